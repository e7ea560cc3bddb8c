"""An external push on the robot: a constant force applied at a point of a link for a while.

The one push type of every simulator backend and of the model plant's closed loop; a backend
turns its start time and duration into the physics steps it acts on (:meth:`ExternalPush.steps`).
"""

from dataclasses import dataclass
import math
from typing import Optional

from biped_sim.errors import ConfigError
from biped_sim.validation import number_tuple


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
            object.__setattr__(self, name,
                               number_tuple('ExternalPush.%s' % name, getattr(self, name), 3))
        if not (math.isfinite(self.duration) and self.duration > 0.0):
            raise ConfigError('ExternalPush.duration = %r s must be finite and > 0'
                              % (self.duration,))
        if self.start_time is not None and not math.isfinite(self.start_time):
            raise ConfigError('ExternalPush.start_time = %r s must be finite or None'
                              % (self.start_time,))

    def steps(self, now: int, time_step: float, time_origin: float = 0.0) -> tuple:
        """The physics steps the push acts on: [start, end), at least one.

        :param now: the step about to run (the start of a push without start_time).
        :param time_step: physics step (s).
        :param time_origin: simulated time of step 0 (s).
        :return: (start, end) step indices.
        """
        start = now if self.start_time is None else int(round((self.start_time - time_origin)
                                                              / time_step))
        return start, start + max(1, int(round(self.duration / time_step)))
