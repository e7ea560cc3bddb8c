"""A swing foot's IK target corrected for the pelvis attitude the IK does not command.

The IK places both soles relative to the pelvis orientation it is given: the commanded one,
which leans against the measured tilt (posture feedback) and carries the hip strategy's trunk
swing. A stance sole is fixed on the ground, so that difference is what turns the body back
upright. A swing sole is not: with the pelvis really rolled by phi and commanded at -k phi, it
lands rotated by (1 + k) phi about the pelvis, and a robot rolling over its stance sole's edge
holds its swing foot 2-3 cm over the ground it should land on. The correction re-expresses the
swing target so that, with the pelvis at the measured attitude, the sole reaches it.
"""
import numpy as np
from scipy.spatial.transform import Rotation

from biped_planner.rotations import rotation_z, yaw_of_matrix


def attitude_correction(commanded: np.ndarray, measured: np.ndarray, gain: float) -> np.ndarray:
    """Rotation C = R_cmd R_att' with R_att the attitude the swing leg is placed for.

    R_att keeps the commanded heading; its tilt (the rotation after the heading) goes from the
    commanded one (gain 0: C is the identity) to the measured one (gain 1) along the shortest
    rotation between them.

    :param commanded: (3, 3) the IK's pelvis orientation
    :param measured: (3, 3) the measured pelvis orientation
    :param gain: fraction of the attitude difference corrected, [0, 1]
    :return: (3, 3) C
    """
    if gain <= 0.0:
        return np.eye(3)
    heading = rotation_z(yaw_of_matrix(commanded))
    tilt_commanded = heading.T @ commanded
    tilt_measured = rotation_z(yaw_of_matrix(measured)).T @ measured
    difference = Rotation.from_matrix(tilt_commanded.T @ tilt_measured).as_rotvec()
    attitude = heading @ tilt_commanded @ Rotation.from_rotvec(gain * difference).as_matrix()
    return commanded @ attitude.T


def corrected_swing_target(position: np.ndarray, rotation: np.ndarray, pelvis: np.ndarray,
                           correction: np.ndarray) -> tuple:
    """The sole pose to give the IK so that the real pelvis attitude puts the sole at the target.

    With the pelvis really at R_att, a sole the IK places at p + R_cmd r lands at
    p + R_att r; so the IK is given p + C (x - p) and C R for the target x, R.

    :param position: (3,) target sole position, world (m)
    :param rotation: (3, 3) target sole orientation, world
    :param pelvis: (3,) the IK's pelvis position (m)
    :param correction: (3, 3) C of attitude_correction
    :return: (position (3,), rotation (3, 3)) for the IK
    """
    return pelvis + correction @ (np.asarray(position) - pelvis), correction @ rotation
