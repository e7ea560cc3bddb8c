"""Where a simulator camera looks from, and the image size, for recording videos."""

from dataclasses import dataclass
import math
from typing import Optional

from biped_sim.errors import ConfigError


@dataclass(frozen=True)
class CameraView:
    """An orbiting camera looking at a target point.

    :param width: image width (pixels), 16..4096.
    :param height: image height (pixels), 16..4096.
    :param distance: camera distance from the target (m), > 0.
    :param yaw: camera azimuth (deg), as the cameraYaw of PyBullet's debug visualiser.
    :param pitch: camera elevation (deg), negative looks down, in (-90, 90).
    :param target: (3,) point looked at (m); None follows the robot's base.
    :param fov: vertical field of view (deg), in (0, 180).
    """

    width: int = 320
    height: int = 240
    distance: float = 2.0
    yaw: float = 50.0
    pitch: float = -20.0
    target: Optional[tuple] = None
    fov: float = 60.0

    def __post_init__(self):
        for name in ('width', 'height'):
            value = getattr(self, name)
            if not (isinstance(value, int) and 16 <= value <= 4096):
                raise ConfigError('CameraView.%s = %r must be an int in [16, 4096]'
                                  % (name, value))
        if not (math.isfinite(self.distance) and self.distance > 0.0):
            raise ConfigError('CameraView.distance = %r m must be finite and > 0'
                              % (self.distance,))
        if not (math.isfinite(self.yaw) and -90.0 < self.pitch < 90.0):
            raise ConfigError('CameraView yaw = %r, pitch = %r deg: yaw finite, pitch in '
                              '(-90, 90)' % (self.yaw, self.pitch))
        if not 0.0 < self.fov < 180.0:
            raise ConfigError('CameraView.fov = %r deg must be in (0, 180)' % (self.fov,))
        if self.target is not None:
            if len(self.target) != 3 or not all(math.isfinite(v) for v in self.target):
                raise ConfigError('CameraView.target = %r must be 3 finite numbers or None'
                                  % (self.target,))
