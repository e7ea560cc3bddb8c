"""Held soles' and the pelvis's height targets that take the ground's steps through a lag."""
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import check_period, check_time_constant, finite_array


class HeightContinuity:
    """The height targets of the held feet and of the pelvis with their large steps lagged.

    A foot is latched where it landed (stance_feet) and the pelvis stands pelvis_height above
    the mean height of the held feet (ik_targets), so on uneven ground every touchdown steps
    the targets by the landing's height. The IK sees the legs' length, sole minus pelvis: a
    foot landing on a tile 13 mm below its swing target had its target dropped 15 mm and the
    pelvis's 7 mm in one period, the stiff leg extended 8 mm at once and the robot hopped
    off both feet (docs/controller_notes.md, "Touchdowns that kick"). Here the part of a held
    foot's or the pelvis's target step beyond a deadband is taken back into an offset that
    decays with a first-order lag; a foot's first held target counts from its swing target of
    the period before. Steps within the deadband pass at once: on flat ground a landing
    steps the targets by under 5 mm (the swing target, itself lagged, still a few millimetres
    above the sole), and the stance leg must press the foot down to take the weight (lagged
    too, the LIPM baseline lost its fastest walks). Both feet and pelvis are lagged: either
    alone crossed fewer tiles than neither. time_constant 0 passes the targets.
    """

    def __init__(self, time_constant: float, deadband: float = 0.0) -> None:
        """:param time_constant: of the lag (s), >= 0
        :param deadband: step passed at once (m), >= 0
        :raises ConfigError: if either is negative or not finite
        """
        check_time_constant(time_constant)
        if not (math.isfinite(deadband) and deadband >= 0.0):
            raise ConfigError(f'deadband must be finite and >= 0, got {deadband!r}')
        self.time_constant = float(time_constant)
        self.deadband = float(deadband)
        self.reset()

    def reset(self) -> None:
        """Forget the targets: the next ones are taken as they are."""
        self._raw: List[Optional[float]] = [None, None, None]  # left, right, pelvis
        self._out: List[Optional[float]] = [None, None, None]
        self._offset = [0.0, 0.0, 0.0]

    def update(self, dt: float, held: Sequence[bool], feet_heights,
               pelvis_height: float) -> Tuple[np.ndarray, float]:
        """One control cycle (exact discretisation of the lag for offsets held over dt).

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
        decay = math.exp(-dt / self.time_constant)
        targets = [float(feet[0]), float(feet[1]), float(pelvis_height)]
        lagged = [bool(held[0]), bool(held[1]), True]
        for i, raw in enumerate(targets):
            if not lagged[i] or self._out[i] is None:
                self._offset[i] = 0.0  # a swinging foot: its target as it is
            else:
                before = self._raw[i] if self._raw[i] is not None else self._out[i]
                step = raw - before
                excess = step - min(max(step, -self.deadband), self.deadband)
                self._offset[i] = (self._offset[i] - excess) * decay
            self._raw[i] = raw if lagged[i] else None
            self._out[i] = raw + self._offset[i]
        return np.array(self._out[:2]), self._out[2]
