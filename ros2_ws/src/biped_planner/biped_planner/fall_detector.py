"""Fall detection from the pelvis height and orientation (the state machine's Fallen condition)."""
from dataclasses import dataclass
import math
from typing import Optional

from biped_planner.errors import ConfigError
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.rotations import tilt_of_quaternion


@dataclass(frozen=True)
class FallDetectorParams:
    """Thresholds of the fall detector (ranges in each parameter())."""

    min_base_height: float = parameter(
        0.45, 'pelvis height below which the robot has fallen (m)', low=0.05, high=2.0)
    max_tilt: float = parameter(0.7, 'torso tilt from vertical above which the robot has fallen '
                                '(rad)', low=1e-3, high=math.pi / 2)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


def detect_fall(base_height: float, orientation_xyzw, params: FallDetectorParams) -> Optional[str]:
    """Tell whether the robot has fallen, from its pelvis height and orientation.

    :param base_height: pelvis height above the ground (m)
    :param orientation_xyzw: pelvis orientation quaternion (x, y, z, w)
    :param params: thresholds
    :return: the reason if fallen, else None; non-finite inputs count as no information (None)
    """
    x, y, z, w = (float(v) for v in orientation_xyzw)
    if not all(math.isfinite(v) for v in (base_height, x, y, z, w)):
        return None
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if norm < 1e-9:
        return None
    tilt = tilt_of_quaternion((x / norm, y / norm, z / norm, w / norm))
    if base_height < params.min_base_height:
        return f'pelvis height {base_height:.3f} m below {params.min_base_height} m'
    if tilt > params.max_tilt:
        return f'torso tilt {math.degrees(tilt):.1f} deg above ' \
               f'{math.degrees(params.max_tilt):.1f} deg'
    return None
