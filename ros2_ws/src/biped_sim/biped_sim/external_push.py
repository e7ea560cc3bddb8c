"""An external push on the robot: a constant force applied at a point of a link for a while."""

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

from biped_sim.errors import ConfigError


@dataclass(frozen=True)
class ExternalPush:
    """A constant world-frame force applied at a point fixed on a link for a duration.

    The paper pushes the middle of the hip for 100 ms with 80..150 N (section "Push Recovery").

    :param force: (3,) force in the world frame (N).
    :param duration: how long the force lasts (s), > 0.
    :param link: name of the pushed link; None pushes the floating base (pelvis).
    :param point: (3,) application point in the link frame (m).
    :param start_time: simulated time the push starts (s); None starts it at the next step.
    """

    force: tuple
    duration: float = 0.1
    link: Optional[str] = None
    point: tuple = (0.0, 0.0, 0.0)
    start_time: Optional[float] = None

    def __post_init__(self):
        for name in ('force', 'point'):
            array = np.asarray(getattr(self, name), dtype=float)
            if array.shape != (3,) or not np.all(np.isfinite(array)):
                raise ConfigError('ExternalPush.%s = %r must be 3 finite numbers'
                                  % (name, getattr(self, name)))
            object.__setattr__(self, name, tuple(float(v) for v in array))
        if not (math.isfinite(self.duration) and self.duration > 0.0):
            raise ConfigError('ExternalPush.duration = %r s must be finite and > 0'
                              % (self.duration,))
        if self.start_time is not None and not math.isfinite(self.start_time):
            raise ConfigError('ExternalPush.start_time = %r s must be finite or None'
                              % (self.start_time,))
