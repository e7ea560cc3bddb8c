"""The MPC's commanded state kept on a leash of the measured robot.

The MPC runs from its own commanded state (feed-forward, as in the paper); the stabilizer
feeds the measured DCM back around it. The stiff joint servos pull the robot towards the
commanded hip. After a push the measured hip is centimetres from it, and that pull, far more
than the stance sole's centre of pressure can hold, rolls the whole robot over the sole's edge
and lifts the swing foot off the ground it should land on. Keeping the commanded hip within a
box of the measured one, in the pelvis heading frame (translating every mass's commanded
position by the excess, the velocities untouched), bounds the pull: the servos then pull a
pushed robot back by at most the box's half size, the stabilizer and the step adjuster answer
the rest. The sole is half as wide as it is long, so the box may be narrower across the
heading than along it; a side of 0 leaves that axis unbounded.
"""
import math

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.linear_model import LEFT_LEG, POSITION, RIGHT_LEG, state_index, TORSO
from biped_mpc.validation import finite_array
from biped_planner.rotations import rotation_z

MASSES = (LEFT_LEG, TORSO, RIGHT_LEG)


def leash_shift(command: np.ndarray, measured_hip: np.ndarray, along: float, across: float,
                heading: float) -> np.ndarray:
    """The translation that brings the commanded hip into the leash box of the measured hip.

    :param command: (2, 9) commanded state, one row per plane (x, y)
    :param measured_hip: (2,) measured model hip (m)
    :param along: half size of the box along the heading (m), >= 0; 0: unbounded
    :param across: half size of the box across the heading (m), >= 0; 0: unbounded
    :param heading: pelvis yaw (rad)
    :return: (2,) world shift to subtract from every mass's commanded position (m); zero while
        the commanded hip is inside the box
    :raises InputError: for negative or non-finite sizes, a non-finite heading or misshaped
        arrays
    """
    for name, value in (('along', along), ('across', across)):
        if not (math.isfinite(value) and value >= 0.0):
            raise InputError(f'the leash half size {name} must be >= 0 m, got {value!r}')
    if not math.isfinite(heading):
        raise InputError(f'heading must be finite, got {heading!r}')
    command = np.asarray(command, dtype=float)
    if command.ndim != 2 or command.shape[0] != 2:
        raise InputError(f'expected a (2, n) commanded state, got {command.shape}')
    measured_hip = finite_array('measured_hip', measured_hip, (2,))
    to_world = rotation_z(heading)[:2, :2]
    local = to_world.T @ (command[:, state_index(TORSO, POSITION)] - measured_hip)
    excess = np.zeros(2)
    for axis, half in enumerate((along, across)):
        if half > 0.0:
            excess[axis] = local[axis] - min(max(local[axis], -half), half)
    return to_world @ excess


def shift_positions(command: np.ndarray, shift: np.ndarray) -> None:
    """Subtract the shift from every mass's commanded position, in place.

    :param command: (2, 9) commanded state
    :param shift: (2,) translation (m)
    """
    for mass in MASSES:
        command[:, state_index(mass, POSITION)] -= shift
