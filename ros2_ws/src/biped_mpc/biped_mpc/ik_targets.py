"""The IK's targets from the MPC's next state: the paper's mass references inverted.

Section "Masses Reference Trajectories" places each leg mass midway between its foot and the
hip; the controller inverts it on the commanded next state x_cmd(k+1): the hip is the torso
mass, a swinging foot is 2 * leg mass - hip, a stance foot stays where it was latched. Feet
heights and yaws come from the reference window at t + Ts (heights above the stance soles); the
pelvis is upright at pelvis_height above the stance soles (their mean, or the ground under the
commanded ZMP), with the mean heading of the feet.
"""
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from biped_mpc.linear_model import LEFT_LEG, POSITION, RIGHT_LEG, state_index, TORSO
from biped_mpc.model_hip import ModelHip
from biped_mpc.stance_feet import StanceFeet
from biped_planner.rotations import mean_angle, rotation_z
from biped_planner.sides import LEFT, RIGHT, SIDES


def feet_targets_from_masses(hip: np.ndarray, left_mass: np.ndarray,
                             right_mass: np.ndarray) -> tuple:
    """Invert the paper's mass references: a leg mass is midway between its foot and the hip.

    :param hip: (..., 2) model hip (torso mass) (m)
    :param left_mass: (..., 2) left leg mass (m)
    :param right_mass: (..., 2) right leg mass (m)
    :return: (left foot, right foot), each (..., 2) = 2 * leg mass - hip (m)
    """
    hip = np.asarray(hip, dtype=float)
    return 2.0 * np.asarray(left_mass) - hip, 2.0 * np.asarray(right_mass) - hip


@dataclass(frozen=True)
class IkTargets:
    """Pelvis and soles the IK is to reach.

    :param pelvis: (3,) pelvis position (m)
    :param left_foot: (4,) left sole x, y, z (m), yaw (rad)
    :param right_foot: (4,) right sole x, y, z (m), yaw (rad)
    :param yaw: pelvis heading (rad)
    :param foot_tilts: (2, 2) left and right sole roll and pitch about the sole's own x and y
        axes after its yaw (rad): the stabilizer's ankle offsets; zero for flat soles
    :param trunk_tilt: (2,) roll and pitch of the pelvis about its heading frame (rad): the
        stabilizer's hip strategy; zero for an upright trunk
    """

    pelvis: np.ndarray
    left_foot: np.ndarray
    right_foot: np.ndarray
    yaw: float
    foot_tilts: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))
    trunk_tilt: np.ndarray = field(default_factory=lambda: np.zeros(2))


def ik_targets(next_state: np.ndarray, feet_next: np.ndarray, support_next: int,
               stance: StanceFeet, model_hip: ModelHip, pelvis_height: float,
               planned_swing: bool = False, zmp: Optional[np.ndarray] = None) -> IkTargets:
    """Targets of the pelvis and both soles for the commanded next state.

    A swing foot's x and y are 2 * leg mass - hip (the paper), or with planned_swing the
    reference's own swing trajectory: the leg mass lags its reference (the MPC tracks the legs
    loosely), and a foot placed from it landed 2 to 3 cm short of its footstep.

    :param next_state: (2, 9) commanded state at t + Ts
    :param feet_next: (2, 4) left and right sole x, y, z (height above the stance soles), yaw
        of the reference at t + Ts (x and y used with planned_swing only)
    :param support_next: the reference's support label at t + Ts
    :param stance: the latched stance feet
    :param model_hip: the pelvis to model hip map
    :param pelvis_height: pelvis above the stance soles (m)
    :param planned_swing: swing feet x, y from feet_next instead of the masses
    :param zmp: (2,) commanded ZMP: the pelvis stands above the ground under it
        (StanceFeet.ground_height); None: above the held feet's mean height
    :return: the targets
    """
    hip = next_state[:, state_index(TORSO, POSITION)]
    if planned_swing:
        swing_feet = (feet_next[LEFT][:2], feet_next[RIGHT][:2])
    else:
        swing_feet = feet_targets_from_masses(
            hip, next_state[:, state_index(LEFT_LEG, POSITION)],
            next_state[:, state_index(RIGHT_LEG, POSITION)])
    latched = stance.latched
    held = stance.held(support_next)
    ground = stance.ground_height(support_next, zmp)
    feet = [latched[side].copy() if held[side] else
            np.array([swing_feet[side][0], swing_feet[side][1], feet_next[side][2] + ground,
                      feet_next[side][3]])
            for side in SIDES]
    yaw = mean_angle(float(feet_next[LEFT][3]), float(feet_next[RIGHT][3]))
    pelvis_xy = model_hip.pelvis_of(hip, rotation_z(yaw))
    pelvis = np.array([pelvis_xy[0], pelvis_xy[1], ground + pelvis_height])
    return IkTargets(pelvis, feet[LEFT], feet[RIGHT], yaw)
