"""A planned swing that starts where the foot is: its lift-off offset fades out before landing."""
import math
from typing import Optional, Sequence

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.validation import check_period, check_time_constant, finite_array
from biped_planner.sides import SIDES


class SwingStart:
    """Horizontal offset of each swing foot target from the reference's planned swing.

    The planned swing starts at the footstep the plan put the foot on; the foot stands where
    it was latched, which after a slip or an off-target landing is elsewhere. Jumping the
    target there at lift-off jerks the still loaded leg and pushes the stance foot along the
    ground (on fast gaits it slipped 2-7 cm per step and the robot fell behind its plan). So at
    lift-off the target starts at the latched foot, and the offset (latched - planned) decays
    as e^(-t / time_constant): the foot lands on the planned footstep (e^-4 of the offset is
    left after a 0.4 s swing with 0.1 s). A held foot has no offset; time_constant 0 gives the
    planned swing as it is.
    """

    def __init__(self, time_constant: float) -> None:
        """:param time_constant: decay time of the lift-off offset (s), >= 0
        :raises ConfigError: if it is negative or not finite
        """
        check_time_constant(time_constant)
        self.time_constant = float(time_constant)
        self.reset()

    def reset(self) -> None:
        """Both feet held, no offset."""
        self._held = [True, True]
        self._offsets = np.zeros((2, 2))

    @property
    def offsets(self) -> np.ndarray:
        """(2, 2) current x, y offsets, LEFT then RIGHT (m)."""
        return self._offsets.copy()

    def update(self, dt: float, held: Sequence[bool], latched: Sequence[Optional[np.ndarray]],
               planned: np.ndarray) -> np.ndarray:
        """One control cycle.

        :param dt: control period (s), > 0
        :param held: (2,) the feet held on the ground this cycle (not swinging)
        :param latched: per side the latched sole (x, y, ...) or None (m)
        :param planned: (2, 2) x, y of each foot's planned target this cycle (m)
        :return: (2, 2) x, y offsets to add to the planned targets of the swing feet (m)
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        planned = finite_array('planned', planned, (2, 2))
        if len(held) != 2 or len(latched) != 2:
            raise InputError('held and latched must have one entry per foot')
        decay = math.exp(-dt / self.time_constant) if self.time_constant > 0.0 else 0.0
        for side in SIDES:
            if held[side]:
                self._offsets[side] = 0.0
            elif self._held[side] and latched[side] is not None:  # lift-off
                start = finite_array('latched', np.asarray(latched[side])[:2], (2,))
                self._offsets[side] = (start - planned[side]) if decay > 0.0 else 0.0
            else:
                self._offsets[side] *= decay
            self._held[side] = bool(held[side])
        return self._offsets.copy()
