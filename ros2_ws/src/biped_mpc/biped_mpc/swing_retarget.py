"""A swing whose landing the plan moves mid-air: the target's jump fades out by the touchdown."""
import math
from typing import Optional, Sequence

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.validation import check_period, finite_array
from biped_planner.sides import SIDES
from biped_planner.swing_trajectory import swing_progress

# s over which a jump fades when the window shows no touchdown of that foot
FALLBACK_FADE = 0.1


class SwingRetarget:
    """Horizontal offset that keeps a swing foot's target continuous across a replan.

    The step adjuster replans a step mid-swing by stretching the swing curve from its lift-off
    to the new landing and time (WalkingReference.adjust_step), so the planned target jumps by
    up to three quarters of the move in one period, and the stiff servos whip the foot after it
    (docs/controller_notes.md, "A moved landing whips the swing foot"). Each cycle the planned
    target is compared with the one the previous window planned for the same time (a cycle
    whose time is not one period after the last compares nothing); a difference beyond
    `threshold` is a replan, and its negative joins an offset that fades as 1 - h(tau), h the
    swing's own quintic (zero speed at both ends), tau from 0 at the replan to 1 at the planned
    touchdown: the foot leaves its path without a jump and lands on the new footstep at rest.

    :param threshold: the smallest difference taken for a replan (m), >= 0
    """

    def __init__(self, threshold: float = 1e-3) -> None:
        if not math.isfinite(threshold) or threshold < 0.0:
            raise InputError(f'threshold must be finite and >= 0 (m), got {threshold!r}')
        self.threshold = float(threshold)
        self.reset()

    def reset(self) -> None:
        """Both feet held: no offset, nothing expected."""
        self._expected: list = [None, None]   # (time, x y) the last window planned
        self._start = np.zeros((2, 2))
        self._fade = [(0.0, 1.0), (0.0, 1.0)]   # (start time, touchdown) of each offset

    def offset_at(self, side: int, t: float) -> np.ndarray:
        """The offset of one foot at time t (m), fading from its last replan."""
        begin, end = self._fade[side]
        tau = min(max((t - begin) / (end - begin), 0.0), 1.0)
        return self._start[side] * (1.0 - float(swing_progress(tau)))

    def update(self, t: float, dt: float, held: Sequence[bool], planned: np.ndarray,
               planned_after: np.ndarray, touchdowns: Sequence[Optional[float]]) -> np.ndarray:
        """One control cycle.

        :param t: time of the planned targets (s)
        :param dt: control period (s), > 0
        :param held: (2,) the feet held on the ground at t (not swinging)
        :param planned: (2, 2) x, y of each foot's planned target at t (m)
        :param planned_after: (2, 2) the same plan's targets at t + dt (m), which the next
            cycle compares its own with
        :param touchdowns: per foot the planned touchdown time after t (s), None if the plan
            shows none (biped_mpc.balance.balance_loop.planned_landing)
        :return: (2, 2) x, y offsets to add to the planned targets of the swing feet (m)
        :raises InputError: for a non-finite or misshaped input
        """
        check_period(dt)
        planned = finite_array('planned', planned, (2, 2))
        planned_after = finite_array('planned_after', planned_after, (2, 2))
        if len(held) != 2 or len(touchdowns) != 2:
            raise InputError('held and touchdowns must have one entry per foot')
        offsets = np.zeros((2, 2))
        for side in SIDES:
            if held[side]:
                self._expected[side] = None
                self._start[side] = 0.0
                continue
            offset = self.offset_at(side, t)
            expected = self._expected[side]
            if expected is not None and abs(t - expected[0]) <= 0.25 * dt:
                jump = planned[side] - expected[1]
                if float(np.hypot(*jump)) > self.threshold:
                    touchdown = touchdowns[side]
                    if touchdown is None or not touchdown > t:
                        touchdown = t + FALLBACK_FADE
                    offset = offset - jump
                    self._start[side] = offset
                    self._fade[side] = (t, float(touchdown))
            self._expected[side] = (t + dt, planned_after[side].copy())
            offsets[side] = offset
        return offsets
