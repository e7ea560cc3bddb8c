"""Hip strategy: the trunk's angular momentum takes the part of the ZMP the soles cannot.

When the DCM feedback asks for a ZMP outside the support polygon, the clamp drops the excess
and the ankles can do no more: the robot rolls over a sole edge as one body (a push towards the
stance foot, a sole on a tile corner). A moment about the centre of mass moves the centroidal
moment pivot (CMP) beyond the support polygon, where the CoP cannot go (Popovic, Goswami, Herr
2005; Englsberger et al. 2015 use the CMP as their control input): the trunk is swung about the
hips in the direction of the fall, and its reaction pushes the rest of the body back.

The excess e (world, m) asks for a moment m g e about the centre of mass. The trunk, of
inertia I about the hips, gets the angular acceleration that produces it, and a critically
damped spring brings it back upright once the excess is gone:

    theta_ddot = G m g (R' e)_{y, -x} / I - w^2 theta - 2 z w theta_dot

with theta the (roll, pitch) of the pelvis about its own heading frame (R = R_z(yaw)), rate and
angle limited. Roll is about x (a positive roll moves the trunk's top towards -y), pitch about
y (a positive pitch moves it towards +x): an excess towards -y (the CMP wanted to the right of
the right sole) swings the trunk to the right. The angles are an orientation offset of the IK's
pelvis target: the servos stay stiff, the reference moves. A swing cannot be held (the angle is
limited), so it buys time for the step that catches the robot, and costs nothing while the
ZMP is inside the soles.
"""
from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import finite_array
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class HipStrategyParams:
    """Gain, trunk model and limits of the hip strategy (see HipStrategy)."""

    gain: float = parameter(0.0, 'fraction G of the ZMP beyond the soles produced as a moment '
                            'of the trunk (0 disables the hip strategy)', low=0.0, high=5.0)
    mass: float = parameter(31.0, 'robot mass m (kg)', low=0.0, high=1000.0, low_open=True)
    gravity: float = parameter(9.81, 'gravitational acceleration g (m/s^2)', low=0.0,
                               high=100.0, low_open=True)
    inertia: float = parameter(0.4, 'trunk inertia I about the hips, roll and pitch (kg m^2)',
                               low=0.0, high=100.0, low_open=True)
    return_frequency: float = parameter(6.0, 'natural frequency w of the spring back upright '
                                        '(rad/s)', low=0.0, high=100.0)
    damping_ratio: float = parameter(1.0, 'damping ratio z of that spring', low=0.0,
                                     high=10.0)
    rate_limit: float = parameter(5.0, 'largest trunk speed per axis (rad/s)', low=0.0,
                                  high=50.0, low_open=True)
    angle_limit: float = parameter(0.45, 'largest trunk angle per axis (rad)', low=0.0,
                                   high=1.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


class HipStrategy:
    """Trunk roll and pitch from the ZMP excess, one control cycle at a time.

    :param params: gain, model and limits
    """

    def __init__(self, params: HipStrategyParams = HipStrategyParams()) -> None:
        if not isinstance(params, HipStrategyParams):
            raise ConfigError(f'params must be HipStrategyParams, got '
                              f'{type(params).__name__}')
        self.params = params
        self.reset()

    def reset(self) -> None:
        """Upright and at rest."""
        self.angles = np.zeros(2)
        self.rates = np.zeros(2)

    def update(self, dt: float, zmp_excess, yaw: float) -> np.ndarray:
        """Advance the trunk by one period (semi-implicit Euler).

        :param dt: period (s), > 0
        :param zmp_excess: (2,) desired ZMP before the support-polygon clamp minus after it,
            world x y (m); zero while the ZMP is inside
        :param yaw: heading of the pelvis (rad)
        :return: (2,) roll and pitch of the pelvis target about its heading frame (rad)
        :raises InputError: for a non-finite or non-positive dt, a bad excess or yaw
        """
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0.0):
            raise InputError(f'dt must be a finite number > 0 (s), got {dt!r}')
        excess = finite_array('zmp_excess', zmp_excess, (2,))
        if not math.isfinite(yaw):
            raise InputError(f'yaw must be finite, got {yaw!r}')
        p = self.params
        if p.gain == 0.0 and not self.angles.any() and not self.rates.any():
            return self.angles.copy()
        cos, sin = math.cos(yaw), math.sin(yaw)
        forward, left = cos * excess[0] + sin * excess[1], -sin * excess[0] + cos * excess[1]
        push = p.gain * p.mass * p.gravity / p.inertia * np.array([-left, forward])
        w = p.return_frequency
        acceleration = push - w * w * self.angles - 2.0 * p.damping_ratio * w * self.rates
        self.rates = np.clip(self.rates + acceleration * dt, -p.rate_limit, p.rate_limit)
        angles = self.angles + self.rates * dt
        limited = np.clip(angles, -p.angle_limit, p.angle_limit)
        self.rates[limited != angles] = 0.0  # at the stop: no speed into it
        self.angles = limited
        return self.angles.copy()
