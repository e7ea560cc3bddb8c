"""The reference window: what the planner hands the MPC, N samples of every reference.

The contract between biped_planner and biped_mpc; its message form is
biped_planner.node_support.reference_messages (biped_msgs/ReferenceTrajectory).
"""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ReferenceWindow:
    """References at N sample times (all positions in the world frame, m).

    :param t: sample times (N,) (s)
    :param zmp: ZMP reference (N, 2)
    :param hip: hip (COM) reference (N, 2)
    :param left_foot: left sole centre x, y, z (N, 3), z > 0 while swinging
    :param right_foot: right sole centre x, y, z (N, 3)
    :param left_yaw: left foot heading (N,) (rad), unwrapped along the plan
    :param right_yaw: right foot heading (N,) (rad)
    :param left_mass: left leg mass, midway between the left sole centre and the hip (N, 2)
    :param right_mass: right leg mass, midway between the right sole centre and the hip (N, 2)
    :param zmp_min: lower corner of the axis-aligned support polygon box (N, 2)
    :param zmp_max: upper corner of the support polygon box (N, 2)
    :param left_landing_min: lower corner of the left swing landing box, -inf in stance (N, 2)
    :param left_landing_max: upper corner of the left swing landing box, +inf in stance (N, 2)
    :param right_landing_min: lower corner of the right swing landing box (N, 2)
    :param right_landing_max: upper corner of the right swing landing box (N, 2)
    :param support: SUPPORT_LEFT, SUPPORT_RIGHT or SUPPORT_DOUBLE of biped_planner.sides (N,)
        uint8
    :param step_index: 0 before the first step, k + 1 during step k (which lands footsteps[k + 2])
        (N,) int
    """

    t: np.ndarray
    zmp: np.ndarray
    hip: np.ndarray
    left_foot: np.ndarray
    right_foot: np.ndarray
    left_yaw: np.ndarray
    right_yaw: np.ndarray
    left_mass: np.ndarray
    right_mass: np.ndarray
    zmp_min: np.ndarray
    zmp_max: np.ndarray
    left_landing_min: np.ndarray
    left_landing_max: np.ndarray
    right_landing_min: np.ndarray
    right_landing_max: np.ndarray
    support: np.ndarray
    step_index: np.ndarray
