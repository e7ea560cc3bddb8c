"""Foot damping control: ankle roll / pitch admittance on the ankle torque error."""
from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.validation import check_period, finite_array
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class FootDampingParams:
    """Gains and limits of one foot's damping control (see FootDamping)."""

    roll_gain: float = parameter(0.01, 'roll admittance K_d (rad/(N m s))', low=0.0, high=1.0)
    pitch_gain: float = parameter(0.01, 'pitch admittance K_d (rad/(N m s))', low=0.0,
                                  high=1.0)
    single_support_gain: float = parameter(
        0.01, 'roll and pitch admittance of the only supporting foot (rad/(N m s))', low=0.0,
        high=1.0)
    spring_time_constant: float = parameter(
        1.0, 'time constant T_s of the weak spring back to the nominal sole angle (s)',
        low=0.01, high=1000.0)
    rate_limit: float = parameter(0.2, 'largest offset speed per axis (rad/s)', low=0.0,
                                  high=10.0, low_open=True)
    angle_limit: float = parameter(0.15, 'largest offset per axis (rad)', low=0.0, high=0.6)
    release_rate: float = parameter(1.0, 'speed of the return to nominal while the foot is '
                                    'off the ground (rad/s)', low=0.0, high=100.0,
                                    low_open=True)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


@dataclass(frozen=True)
class FootDampingResult:
    """Output of one FootDamping update.

    :param offset: (2,) roll and pitch offsets of the sole orientation target (rad), about the
        sole frame's x and y axes
    :param rate: (2,) their speed over the update (rad/s)
    :param torque_error: (2,) measured - desired roll and pitch torques (N m); zero off the
        ground
    :param rate_limited: True when the rate limit cut the update
    :param angle_limited: True when an offset sits at the angle limit
    """

    offset: np.ndarray
    rate: np.ndarray
    torque_error: np.ndarray
    rate_limited: bool
    angle_limited: bool


class FootDamping:
    """Ankle admittance of one foot: the sole gives way to the torque it did not ask for.

    Torques are the ground reaction on the foot about the sole centre in the sole frame
    (ft_filter.FootWrench.local_torque[:2]): tau_x = y_cop f_z, tau_y = -x_cop f_z. The roll
    and pitch offsets theta of the sole orientation target follow

        theta_dot = K_d (tau_measured - tau_desired) - theta / T_s

    rate limited to +-rate_limit and angle limited to +-angle_limit per axis (Kajita 2010 foot
    damping control; lipm_walking_controller's CoP admittance, K_d 0.01 rad/(N m s) and
    0.2 rad/s on HRP-4). Sign: with ground reaction torques, a measured tau_x above the desired
    means the CoP is too far towards +y; a positive roll lifts the +y edge, which moves it back
    (the same for pitch: a positive pitch lifts the heel). Written with the torque the foot
    exerts on the ground the law reads K_d (tau_d - tau). On a tile tilted by alpha the sole
    settles at theta = alpha instead of the robot tipping over the edge.

    Discretisation: exact for a held error, theta_k+1 = a theta_k + (1 - a) K_d e T_s with
    a = exp(-dt / T_s), then the rate and angle limits. While the foot is off the ground the
    offsets return to zero at release_rate (no jump of the swing foot target at lift-off) and
    the next contact starts from there; reset() zeroes them at once.
    """

    def __init__(self, params: FootDampingParams = FootDampingParams()) -> None:
        """Create the control with zero offsets.

        :param params: gains and limits
        """
        self.params = params
        self._offset = np.zeros(2)

    @property
    def offset(self) -> np.ndarray:
        """(2,) the current roll and pitch offsets (rad), a copy."""
        return self._offset.copy()

    def reset(self) -> None:
        """Zero the offsets at once."""
        self._offset = np.zeros(2)

    def update(self, dt: float, in_contact: bool, desired_torque,
               measured_torque, single_support: bool = False) -> FootDampingResult:
        """One control cycle.

        :param dt: control period (s), > 0
        :param in_contact: the foot supports (touchdown_detector's state)
        :param single_support: it is the only supporting foot: single_support_gain applies
        :param desired_torque: (2,) desired roll and pitch ground torques, sole frame (N m)
        :param measured_torque: (2,) measured ones, sole frame (N m)
        :return: the offsets and what limited them
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        error = (finite_array('measured_torque', measured_torque, (2,))
                 - finite_array('desired_torque', desired_torque, (2,)))
        p = self.params
        previous = self._offset
        if not in_contact:
            step = p.release_rate * dt
            self._offset = previous - np.clip(previous, -step, step)
            return FootDampingResult(self._offset.copy(), (self._offset - previous) / dt,
                                     np.zeros(2), False, False)
        decay = math.exp(-dt / p.spring_time_constant)
        gains = (np.full(2, p.single_support_gain) if single_support
                 else np.array([p.roll_gain, p.pitch_gain]))
        free = decay * previous + (1.0 - decay) * gains * error * p.spring_time_constant
        step = p.rate_limit * dt
        limited = np.clip(free - previous, -step, step)
        offset = np.clip(previous + limited, -p.angle_limit, p.angle_limit)
        self._offset = offset
        return FootDampingResult(offset.copy(), (offset - previous) / dt, error,
                                 bool(np.any(limited != free - previous)),
                                 bool(np.any(np.abs(offset) >= p.angle_limit)))
