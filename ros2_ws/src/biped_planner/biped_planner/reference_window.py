"""The reference window: what the planner hands the MPC, N samples of every reference.

The contract between biped_planner and biped_mpc; its message form is
biped_planner.node_support.reference_messages (biped_msgs/ReferenceTrajectory).
"""
from dataclasses import dataclass, fields

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


def joined_at(before: ReferenceWindow, after: ReferenceWindow, t_join: float) -> ReferenceWindow:
    """The samples of `before` at times < t_join, those of `after` from t_join on.

    :param before: a window
    :param after: a window at the same sample times
    :param t_join: time of the first sample taken from `after` (s)
    :return: the joined window
    """
    early = np.asarray(before.t) < t_join
    values = {}
    for field in fields(ReferenceWindow):
        first, second = getattr(before, field.name), getattr(after, field.name)
        mask = early.reshape((-1,) + (1,) * (np.ndim(second) - 1))
        values[field.name] = np.where(mask, first, second).astype(np.asarray(second).dtype)
    return ReferenceWindow(**values)
