"""The timeline of a walking reference: its phases and the ZMP knots, from the footsteps.

A walk from standing is an optional stand, the initial shift (double support, the paper's
Initialize state), then for each step a single support (ZMP at the centre of the stance foot)
and a double support (ZMP moving linearly to the foot that just landed, eq. zmpEquation); the
last step's double support is the final settle, where the ZMP moves to the midpoint of the last
two feet. Each phase also fixes what sampling needs: where the feet start and how far they move,
the swing height, the ZMP box (biped_planner.support_polygon) and the swing landing box.
"""
from dataclasses import dataclass, field
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from biped_planner.footsteps import Footstep
from biped_planner.reference_params import ReferenceParams
from biped_planner.rotations import wrap_angle
from biped_planner.sides import LEFT, RIGHT, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT
from biped_planner.step_timing import StepTiming
from biped_planner.support_polygon import double_support_box, scaled_foot_box

PHASE_STAND = 'stand'
PHASE_INITIAL_SHIFT = 'initial_shift'
PHASE_SINGLE_SUPPORT = 'single_support'
PHASE_DOUBLE_SUPPORT = 'double_support'
PHASE_FINAL_SETTLE = 'final_settle'

NO_SWING = -1
# Where, as fractions of its duration, a double support phase gets its free ZMP knots: one in
# the phase that starts a plan (initial shift, or the first double support after a splice) and
# one in the final settle; two when the final settle is also the first phase after a splice.
FREE_KNOT_FRACTIONS = {1: (0.5,), 2: (1.0 / 3.0, 2.0 / 3.0)}


@dataclass(frozen=True)
class ReferencePhase:
    """One phase of the walking reference.

    :param kind: PHASE_STAND, PHASE_INITIAL_SHIFT, PHASE_SINGLE_SUPPORT, PHASE_DOUBLE_SUPPORT or
        PHASE_FINAL_SETTLE
    :param t_begin: start time (s)
    :param t_end: end time (s)
    :param support: SUPPORT_LEFT, SUPPORT_RIGHT or SUPPORT_DOUBLE
    :param step_index: as in ReferenceWindow.step_index
    :param swing_side: LEFT or RIGHT in single support, NO_SWING otherwise
    """

    kind: str
    t_begin: float
    t_end: float
    support: int
    step_index: int
    swing_side: int


@dataclass
class PhaseRows:
    """Per-phase rows, appended while planning and turned into a PhaseTable for sampling.

    feet_start, feet_delta: (x, y, yaw) of the left then the right foot at the phase start and
    their move over the phase; feet_height: swing heights (left, right); landing: the landing
    box (x_min, y_min, x_max, y_max) of the left then the right foot. knot_times and knot_zmp are
    the ZMP knots of the hip's PiecewiseLipm, free_knots the indices of its free knots.
    """

    phases: List[ReferencePhase] = field(default_factory=list)
    feet_start: List[List[float]] = field(default_factory=list)
    feet_delta: List[List[float]] = field(default_factory=list)
    feet_height: List[List[float]] = field(default_factory=list)
    zmp_min: List[np.ndarray] = field(default_factory=list)
    zmp_max: List[np.ndarray] = field(default_factory=list)
    landing: List[List[float]] = field(default_factory=list)
    knot_times: List[float] = field(default_factory=list)
    knot_zmp: List[np.ndarray] = field(default_factory=list)
    free_knots: List[int] = field(default_factory=list)


def plan_phases(footsteps: Sequence[Footstep], step_timings: Sequence[StepTiming],
                params: ReferenceParams, first_step: int, t_begin: float,
                start_zmp: Optional[np.ndarray], stand_until: Optional[float],
                yaws: Optional[Tuple[float, float]]) -> PhaseRows:
    """Phases and ZMP knots from t_begin to the end of the plan.

    With start_zmp, the plan starts from standing (optional stand until stand_until, then the
    initial shift) before step first_step; without it, it starts with the double support of
    step first_step.

    :param footsteps: the footstep list (checked by the caller)
    :param step_timings: timing of every step k (landing footsteps[k + 2])
    :param params: reference parameters
    :param first_step: the first step planned
    :param t_begin: time the planned phases start (s)
    :param start_zmp: (2,) ZMP when starting from standing, None when rejoining a plan (m)
    :param stand_until: end of a stand before the initial shift (s), None for none
    :param yaws: (left, right) unwrapped foot headings at t_begin (rad); None: those of the
        initial feet
    :return: the rows
    """
    fs = tuple(footsteps)
    swing_order = (fs[1], fs[0]) + fs[2:]
    n_steps = len(fs) - 2
    rows = PhaseRows()
    foot_yaw = list(yaws) if yaws is not None else [0.0, 0.0]
    if yaws is None:
        for step in fs[:2]:
            foot_yaw[step.side] = step.yaw
    no_landing = [-math.inf, -math.inf, math.inf, math.inf]

    def box(step: Footstep) -> Tuple[np.ndarray, np.ndarray]:
        return scaled_foot_box(step.x, step.y, step.yaw, params.foot_length,
                               params.foot_width, params.support_scale)

    def pose(step: Footstep) -> List[float]:
        return [step.x, step.y, foot_yaw[step.side]]

    def add_still(kind: str, t0: float, t1: float, feet: Tuple[Footstep, Footstep],
                  zmp0: np.ndarray, zmp1: np.ndarray, step_index: int, free: int) -> None:
        by_side = {feet[0].side: feet[0], feet[1].side: feet[1]}
        rows.phases.append(ReferencePhase(kind, t0, t1, SUPPORT_DOUBLE, step_index, NO_SWING))
        rows.feet_start.append(pose(by_side[LEFT]) + pose(by_side[RIGHT]))
        rows.feet_delta.append([0.0] * 6)
        rows.feet_height.append([0.0, 0.0])
        lower, upper = double_support_box(box(feet[0]), box(feet[1]))
        rows.zmp_min.append(lower)
        rows.zmp_max.append(upper)
        rows.landing.append(no_landing + no_landing)
        rows.knot_times.append(t0)
        rows.knot_zmp.append(np.asarray(zmp0, dtype=float))
        for fraction in FREE_KNOT_FRACTIONS.get(free, ()):
            rows.free_knots.append(len(rows.knot_times))
            rows.knot_times.append(t0 + fraction * (t1 - t0))
            rows.knot_zmp.append((1.0 - fraction) * np.asarray(zmp0)
                                 + fraction * np.asarray(zmp1))

    def centre(step: Footstep) -> np.ndarray:
        return np.array([step.x, step.y])

    t = t_begin
    if start_zmp is not None:
        feet = (swing_order[first_step], swing_order[first_step + 1])
        if stand_until is not None and stand_until > t:
            add_still(PHASE_STAND, t, stand_until, feet, start_zmp, start_zmp, first_step,
                      free=0)
            t = stand_until
        t1 = t + params.initial_shift_time
        add_still(PHASE_INITIAL_SHIFT, t, t1, feet, start_zmp, centre(feet[1]), first_step,
                  free=1)
        t = t1
        first_single = first_step
    else:
        first_single = first_step + 1
    for k in range(first_step, n_steps):
        stance, landed = swing_order[k + 1], swing_order[k + 2]
        if k >= first_single:
            lift_off = swing_order[k]
            t1 = t + step_timings[k].single_support
            swing_side = lift_off.side
            stance_side = stance.side
            start = pose(lift_off)
            turn = wrap_angle(landed.yaw - foot_yaw[swing_side])
            end_delta = [landed.x - lift_off.x, landed.y - lift_off.y, turn]
            foot_yaw[swing_side] += turn
            swing_rows = (start, end_delta, [params.swing_height])
            stance_rows = (pose(stance), [0.0, 0.0, 0.0], [0.0])
            left_rows, right_rows = ((swing_rows, stance_rows) if swing_side == LEFT
                                     else (stance_rows, swing_rows))
            rows.phases.append(ReferencePhase(
                PHASE_SINGLE_SUPPORT, t, t1,
                SUPPORT_LEFT if stance_side == LEFT else SUPPORT_RIGHT, k + 1, swing_side))
            rows.feet_start.append(left_rows[0] + right_rows[0])
            rows.feet_delta.append(left_rows[1] + right_rows[1])
            rows.feet_height.append(left_rows[2] + right_rows[2])
            lower, upper = box(stance)
            rows.zmp_min.append(lower)
            rows.zmp_max.append(upper)
            landing = [landed.x - params.landing_half_length,
                       landed.y - params.landing_half_width,
                       landed.x + params.landing_half_length,
                       landed.y + params.landing_half_width]
            rows.landing.append(landing + no_landing if swing_side == LEFT
                                else no_landing + landing)
            rows.knot_times.append(t)
            rows.knot_zmp.append(centre(stance))
            t = t1
        if k < n_steps - 1:
            t1 = t + step_timings[k].double_support
            add_still(PHASE_DOUBLE_SUPPORT, t, t1, (stance, landed), centre(stance),
                      centre(landed), k + 1, free=int(k < first_single))
        else:
            t1 = t + params.final_settle_time
            add_still(PHASE_FINAL_SETTLE, t, t1, (stance, landed), centre(stance),
                      0.5 * (centre(stance) + centre(landed)), k + 1,
                      free=1 + int(k < first_single))
            rows.knot_times.append(t1)
            rows.knot_zmp.append(0.5 * (centre(stance) + centre(landed)))
        t = t1
    return rows


@dataclass(frozen=True)
class PhaseTable:
    """The phases of a plan as arrays, one row per phase (columns as in PhaseRows).

    :param phases: the phases in time order
    :param t0: (P,) phase start times (s)
    :param rate: (P,) 1 / phase duration (1/s)
    :param support: (P,) uint8 support labels
    :param step_index: (P,) int64 step indices
    """

    phases: Tuple[ReferencePhase, ...]
    t0: np.ndarray
    rate: np.ndarray
    support: np.ndarray
    step_index: np.ndarray
    feet_start: np.ndarray
    feet_delta: np.ndarray
    feet_height: np.ndarray
    zmp_min: np.ndarray
    zmp_max: np.ndarray
    landing: np.ndarray

    @classmethod
    def from_rows(cls, rows: PhaseRows, keep: int = 0,
                  previous: Optional['PhaseTable'] = None) -> 'PhaseTable':
        """The first keep phases of previous (if any), then the planned rows."""
        def joined(name: str) -> np.ndarray:
            new_array = np.array(getattr(rows, name), dtype=float)
            if previous is None:
                return new_array
            return np.concatenate((getattr(previous, name)[:keep], new_array))

        phases = (previous.phases[:keep] if previous is not None else ()) + tuple(rows.phases)
        return cls(phases=phases,
                   t0=np.array([phase.t_begin for phase in phases]),
                   rate=1.0 / np.array([phase.t_end - phase.t_begin for phase in phases]),
                   support=np.array([phase.support for phase in phases], dtype=np.uint8),
                   step_index=np.array([phase.step_index for phase in phases], dtype=np.int64),
                   feet_start=joined('feet_start'), feet_delta=joined('feet_delta'),
                   feet_height=joined('feet_height'), zmp_min=joined('zmp_min'),
                   zmp_max=joined('zmp_max'), landing=joined('landing'))

    def final_yaws(self) -> Tuple[float, float]:
        """(left, right) unwrapped foot headings at the end of the last phase (rad)."""
        final = self.feet_start[-1] + self.feet_delta[-1]
        return float(final[2]), float(final[5])

    def yaws_at(self, index: int) -> Tuple[float, float]:
        """(left, right) unwrapped foot headings at the start of phase index (rad)."""
        start = self.feet_start[index]
        return float(start[2]), float(start[5])
