"""Where a simulator camera looks from, and the image size, for recording videos."""

from dataclasses import dataclass
from typing import Optional

from biped_planner.parameter_fields import parameter, validate_fields

from biped_sim.errors import ConfigError
from biped_sim.validation import number_tuple


@dataclass(frozen=True)
class CameraView:
    """An orbiting camera looking at a target point.

    :param target: (3,) point looked at (m); None follows the robot's base.
    """

    width: int = parameter(320, 'image width (pixels)', low=16, high=4096)
    height: int = parameter(240, 'image height (pixels)', low=16, high=4096)
    distance: float = parameter(2.0, 'camera distance from the target (m)', low=0.0,
                                high=100.0, low_open=True)
    yaw: float = parameter(50.0, "camera azimuth, as the cameraYaw of PyBullet's debug "
                           'visualiser (deg)', low=-360.0, high=360.0)
    pitch: float = parameter(-20.0, 'camera elevation, negative looks down (deg)', low=-89.0,
                             high=89.0)
    target: Optional[tuple] = None
    fov: float = parameter(60.0, 'vertical field of view (deg), below 180', low=0.0,
                           high=180.0, low_open=True)

    def __post_init__(self):
        validate_fields(self, ConfigError)
        if self.fov >= 180.0:
            raise ConfigError('CameraView.fov = %r deg must be below 180' % (self.fov,))
        if self.target is not None:
            object.__setattr__(self, 'target', number_tuple('CameraView.target', self.target, 3))
