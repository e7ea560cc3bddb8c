"""Held soles' and the pelvis's height targets that take the ground's steps through a lag."""
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.validation import check_period, check_time_constant, finite_array
from biped_planner.sides import SIDES


class HeightContinuity:
    """The height targets of the held feet and of the pelvis, low-passed; a swing foot's as is.

    A foot is latched where it landed (stance_feet) and the pelvis stands pelvis_height above
    the mean height of the held feet (ik_targets), so on uneven ground every touchdown steps
    the targets by the landing's height. The IK sees the legs' length, sole minus pelvis: a
    foot landing on a tile 13 mm below its swing target had its target dropped 15 mm and the
    pelvis's 7 mm in one period, the stiff leg extended 8 mm at once and the robot hopped
    off both feet (docs/controller_notes.md, "Touchdowns that kick"). Here a held foot's
    height target starts from its swing target of the period before and reaches the latched
    height with a first-order lag, and the pelvis's follows the held feet's mean with the
    same lag, so the legs' length changes smoothly. Both are needed: either alone crossed
    fewer tiles than neither. On flat ground the targets barely step; time_constant 0 passes
    them.
    """

    def __init__(self, time_constant: float) -> None:
        """:param time_constant: of the lag (s), >= 0
        :raises ConfigError: if it is negative or not finite
        """
        check_time_constant(time_constant)
        self.time_constant = float(time_constant)
        self.reset()

    def reset(self) -> None:
        """Forget the targets: the next ones are taken as they are."""
        self._feet: list = [None, None]
        self._pelvis: Optional[float] = None

    def update(self, dt: float, held: Sequence[bool], feet_heights,
               pelvis_height: float) -> Tuple[np.ndarray, float]:
        """One control cycle (exact discretisation of the lag for targets held over dt).

        :param dt: control period (s), > 0
        :param held: (2,) the feet held on the ground this cycle
        :param feet_heights: (2,) sole height targets (m), LEFT then RIGHT
        :param pelvis_height: pelvis height target (m)
        :return: the sole height targets (2,) and the pelvis height target to follow (m)
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        feet = finite_array('feet_heights', feet_heights, (2,))
        if len(held) != 2:
            raise InputError('held must have one entry per foot')
        if not math.isfinite(pelvis_height):
            raise InputError(f'pelvis_height must be finite, got {pelvis_height!r}')
        if self.time_constant == 0.0:
            return feet.copy(), float(pelvis_height)
        gain = 1.0 - math.exp(-dt / self.time_constant)
        for side in SIDES:
            previous = self._feet[side]
            if held[side] and previous is not None:
                feet[side] = previous + gain * (feet[side] - previous)
            self._feet[side] = float(feet[side])
        pelvis = float(pelvis_height) if self._pelvis is None else \
            self._pelvis + gain * (float(pelvis_height) - self._pelvis)
        self._pelvis = pelvis
        return feet, pelvis
