"""Ground conformance: the sole of a single support takes the tilt of the ground under it.

The ankle servos are stiff and position controlled, so a sole that tips onto where it rests (the
edge of a tile under its middle, its toe on a lower tile) tips the whole robot with it: the
foot damping (foot_damping) moves the ankle only for the torque the stabilizer asks, which on a
partial foothold points the same way as the tipping. Here the tilt of the loaded sole in the
world (the IMU's attitude and the leg kinematics) beyond a deadband becomes an offset of
its orientation target, reached with a first-order lag: the ankle joint takes the ground's tilt
and the body stays upright. The deadband leaves the few degrees of a sole settling on flat
ground, and the ankle regulation working there, alone; a foot that is not loaded goes back to
its nominal attitude with the same lag.
"""
from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.validation import check_period
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.rotations import roll_pitch_of_zxy_matrix
from biped_planner.sides import SIDES


@dataclass(frozen=True)
class GroundConformanceParams:
    """Deadband, lag and limit of the ground conformance (see GroundConformance)."""

    deadband: float = parameter(0.035, 'sole tilt (roll or pitch) the ankle leaves to the '
                                'rest of the stabilizer (rad)', low=0.0, high=0.5)
    time_constant: float = parameter(0.04, 'lag of the offset behind the tilt beyond the '
                                     'deadband (s)', low=0.001, high=10.0)
    angle_limit: float = parameter(0.3, 'largest offset per axis (rad)', low=0.0, high=0.6)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


class GroundConformance:
    """Roll and pitch offsets (2, 2) of both sole targets: each loaded sole's tilt beyond the
    deadband, low-passed.

    :param params: deadband, time constant and limit
    """

    def __init__(self, params: GroundConformanceParams = GroundConformanceParams()) -> None:
        self.params = params
        self.reset()

    def reset(self) -> None:
        """Both offsets zero."""
        self.offsets = np.zeros((2, 2))

    def update(self, dt: float, sole_rotations, loaded) -> np.ndarray:
        """One control period.

        :param dt: period (s), > 0
        :param sole_rotations: (left, right) measured sole rotations in the world (3, 3)
        :param loaded: (left, right) True for a foot to conform (the balance loop: the only
            support foot, in contact)
        :return: the offsets (2, 2): left roll, left pitch, right roll, right pitch (rad)
        """
        check_period(dt)
        p = self.params
        blend = 1.0 - math.exp(-dt / p.time_constant)
        for side in SIDES:
            goal = np.zeros(2)
            if loaded[side]:
                tilt = roll_pitch_of_zxy_matrix(np.asarray(sole_rotations[side], dtype=float))
                goal = np.sign(tilt) * np.maximum(np.abs(tilt) - p.deadband, 0.0)
            goal = np.clip(goal, -p.angle_limit, p.angle_limit)
            self.offsets[side] += blend * (goal - self.offsets[side])
        return self.offsets.copy()
