"""A planned swing target followed through a first-order lag: softer lift-off and landing."""
import math
from typing import Sequence

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.validation import check_period, check_time_constant, finite_array
from biped_planner.sides import SIDES


class SwingSmoothing:
    """Each swing foot's target (x, y, z) low-passed with a time constant; a held foot's as is.

    The feed-forward default swings the foot to 2 * leg mass - hip, which lags the planned swing
    through the MPC's dynamics, and walks fast turns the planned swing falls in (library omni
    course, docs/controller_notes.md); a first-order lag of the planned target gives the same
    soft start and landing while the foot still ends on the planned footstep (the target stops
    moving there; e^-(T / time_constant) of the last move is left at touchdown). The filter
    restarts from the target whenever the foot is held; time_constant 0 passes the target.
    """

    def __init__(self, time_constant: float) -> None:
        """:param time_constant: of the lag (s), >= 0
        :raises ConfigError: if it is negative or not finite
        """
        check_time_constant(time_constant)
        self.time_constant = float(time_constant)
        self._filtered = [None, None]

    def reset(self) -> None:
        self._filtered = [None, None]

    def update(self, dt: float, held: Sequence[bool], targets: np.ndarray) -> np.ndarray:
        """One control cycle (the exact discretisation of the lag for a target held over dt).

        :param dt: control period (s), > 0
        :param held: (2,) the feet held on the ground this cycle
        :param targets: (2, 3) x, y, z of each foot's target (m), LEFT then RIGHT
        :return: (2, 3) the targets to follow
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        targets = finite_array('targets', targets, (2, 3))
        if len(held) != 2:
            raise InputError('held must have one entry per foot')
        if self.time_constant == 0.0:  # the target exactly, not previous + (target - previous)
            return targets.copy()
        gain = 1.0 - math.exp(-dt / self.time_constant)
        for side in SIDES:
            previous = self._filtered[side]
            self._filtered[side] = targets[side].copy() if held[side] or previous is None \
                else previous + gain * (targets[side] - previous)
        return np.array(self._filtered)
