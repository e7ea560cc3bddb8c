"""Parameters of the walking references: LIPM height, foot size, swing height, bounds, timing."""
from dataclasses import dataclass
import math

from biped_planner.errors import ConfigError
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class ReferenceParams:
    """Parameters of the reference trajectories (each field's range is in its parameter())."""

    com_height: float = parameter(0.5, 'LIPM height of the hip z_h, omega = sqrt(g / z_h) (m)',
                                  low=0.05, high=5.0, low_open=True)
    swing_height: float = parameter(0.04, 'highest point of the swing foot above the ground (m)',
                                    low=0.0, high=0.5)
    foot_length: float = parameter(0.16, 'sole length along the foot heading (m)',
                                   low=0.0, high=1.0, low_open=True)
    foot_width: float = parameter(0.08, 'sole width (m)', low=0.0, high=1.0, low_open=True)
    support_scale: float = parameter(0.9, 'scale of the foot in the ZMP bounds (paper: 0.9)',
                                     low=0.0, high=1.0, low_open=True)
    gravity: float = parameter(9.81, 'gravitational acceleration g (m/s^2)',
                               low=0.0, high=30.0, low_open=True)
    landing_half_length: float = parameter(
        0.05, 'half size along world x of the swing landing box (m)', low=0.0, high=2.0)
    landing_half_width: float = parameter(
        0.05, 'half size along world y of the swing landing box (m)', low=0.0, high=2.0)
    initial_shift_time: float = parameter(
        1.0, 'double support that shifts the hip from standing over the first support foot, '
        "the paper's Initialize state; = the state machine's initialize_duration (s)",
        low=0.1, high=10.0)
    final_settle_time: float = parameter(
        1.0, 'final double support that brings the hip to rest midway between the last two '
        'feet (s)', low=0.1, high=10.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)

    @property
    def omega(self) -> float:
        """LIPM natural frequency sqrt(g / z_h) (1/s)."""
        return math.sqrt(self.gravity / self.com_height)
