"""Where the model's hip (its torso mass) is on the robot: the pelvis plus a fixed offset.

The reference hip is the planner's LIPM centre of mass, and the model's torso mass moves with
it. On the robot the whole-body centre of mass sits com_offset ahead of the pelvis (the knees
bend forward: 1.4 cm for the COMAN-like robot standing), so the controller works in model
coordinates, model hip = pelvis + R hip_centre + R(yaw) com_offset with hip_centre the
midpoint of the hip joints; the pelvis target is the torso mass minus that offset. Without it
the robot's centre of mass, and so its ZMP, would run com_offset ahead of the plan.
"""
from typing import Optional

import numpy as np

from biped_mpc.robot_model import LegGeometry
from biped_planner.rotations import rotation_z, yaw_of_matrix


class ModelHip:
    """The map between the robot's pelvis and the model hip.

    :param geometry: leg dimensions (the hip centres); None puts the hip centre at the pelvis
    :param com_offset: (forward, left) whole-body centre of mass relative to the pelvis in its
        heading frame (m)
    """

    def __init__(self, geometry: Optional[LegGeometry], com_offset: tuple) -> None:
        self._hip_centre = (np.array([geometry.hip_offset[0], 0.0, geometry.hip_offset[2]])
                            if geometry is not None else np.zeros(3))
        self._com_offset = np.array(tuple(com_offset) + (0.0,))
        # Model hip minus pelvis in the heading frame: hip centres plus the COM offset.
        self._pelvis_to_hip = self._com_offset + np.array([self._hip_centre[0], 0.0, 0.0])

    def of_pelvis(self, pelvis: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """(2,) model hip of a pelvis pose (position (3,) (m), rotation (3, 3))."""
        hip = (pelvis + rotation @ self._hip_centre
               + rotation_z(yaw_of_matrix(rotation)) @ self._com_offset)
        return hip[:2]

    def pelvis_of(self, hip: np.ndarray, heading: np.ndarray) -> np.ndarray:
        """(2,) pelvis x, y of an upright pelvis with the model hip (2,) and heading (3, 3)."""
        return hip - (heading @ self._pelvis_to_hip)[:2]
