"""Vertical drift compensation: slow correction of the mean height of the feet."""
from dataclasses import dataclass
import math

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import check_period
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class VerticalDriftParams:
    """Rate and limit of the vertical drift compensation (see VerticalDrift)."""

    frequency: float = parameter(1.0, 'correction rate f: the closed-loop time constant is '
                                 '1 / f (1/s)', low=0.0, high=50.0)
    max_offset: float = parameter(0.05, 'largest common offset of the feet (m)', low=0.0,
                                  high=0.3)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


@dataclass(frozen=True)
class VerticalDriftResult:
    """Output of one VerticalDrift update.

    :param offset: common vertical offset added to both sole targets (m)
    :param error: desired - measured mean feet height (m); zero when inactive
    :param limited: True when the offset sits at +-max_offset
    """

    offset: float
    error: float
    limited: bool


class VerticalDrift:
    """Keeps the mean height of the feet at its reference while other loops move them.

    The force difference control moves the feet by +-dz/2, and tracking errors of the stiff
    servos accumulate: the mean leg length drifts. A common offset o of both sole targets
    integrates the error of the measured mean height (lipm_walking_controller's vertical drift
    compensation, vdc_frequency 1 on HRP-4):

        o_dot = f (z_mean_desired - z_mean_measured),

    in double support (active), held otherwise. Heights are sole heights relative to the
    pelvis along the world z axis (z_sole - z_pelvis, the IK's frame), so that the loop keeps
    the legs' mean length, not a world height the terrain decides. With the measured height
    following the offset (z_measured = z_0 + o), the error decays as (1 - f dt)^k
    (exp(-f t) for small dt). |o| <= max_offset.
    """

    def __init__(self, params: VerticalDriftParams = VerticalDriftParams()) -> None:
        """Create the compensation with a zero offset.

        :param params: rate and limit
        """
        self.params = params
        self._offset = 0.0

    @property
    def offset(self) -> float:
        """The current common offset (m)."""
        return self._offset

    def reset(self) -> None:
        """Zero the offset."""
        self._offset = 0.0

    def update(self, dt: float, active: bool, desired_height: float,
               measured_height: float) -> VerticalDriftResult:
        """One control cycle.

        :param dt: control period (s), > 0
        :param active: integrate (double support); otherwise the offset is held
        :param desired_height: reference mean height of the soles (m)
        :param measured_height: measured mean height of the soles (m)
        :return: the common offset
        :raises InputError: for a non-finite input or dt <= 0
        """
        check_period(dt)
        for name, value in (('desired_height', desired_height),
                            ('measured_height', measured_height)):
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise InputError(f'{name} must be a finite number (m), got {value!r}')
        error = float(desired_height - measured_height) if active else 0.0
        limit = self.params.max_offset
        self._offset = min(max(self._offset + self.params.frequency * error * dt, -limit), limit)
        return VerticalDriftResult(self._offset, error, abs(self._offset) >= limit)
