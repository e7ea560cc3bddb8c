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

When the step adjuster moves a step, the plan follows the measured DCM; an MPC that keeps its
own unpushed DCM then drives its model against the adjusted footholds (a pushed robot's
commanded hip stays behind it, and with the ZMP bounded to the step placed ahead the model can
only fall back). The DCM leash brings the commanded DCM within a radius of the measured one by
changing every mass's commanded velocity alike: the positions stay, so the targets do not jump,
and the model's divergent motion is the robot's. The controller applies it once per adjustment:
every cycle, command and robot chase each other through the stiff servos.
"""
import math

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.linear_model import LEFT_LEG, POSITION, RIGHT_LEG, state_index, TORSO, VELOCITY
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


def dcm_leash_excess(commanded_dcm: np.ndarray, measured_dcm: np.ndarray,
                     radius: float) -> np.ndarray:
    """How far the commanded DCM is outside the circle of the measured DCM.

    :param commanded_dcm: (2,) the commanded state's DCM (m)
    :param measured_dcm: (2,) the measured DCM (m)
    :param radius: radius of the circle (m), > 0
    :return: (2,) the commanded DCM minus its nearest point in the circle (m); zero inside
    :raises InputError: for a radius that is not > 0 and finite, or non-finite or misshaped DCMs
    """
    if not (math.isfinite(radius) and radius > 0.0):
        raise InputError(f'the DCM leash radius must be > 0 m, got {radius!r}')
    error = (finite_array('commanded_dcm', commanded_dcm, (2,))
             - finite_array('measured_dcm', measured_dcm, (2,)))
    distance = float(np.hypot(*error))
    if distance <= radius:
        return np.zeros(2)
    return error * (1.0 - radius / distance)


def shift_velocities(command: np.ndarray, dcm_excess: np.ndarray, omega: float) -> None:
    """Move the commanded DCM back by dcm_excess through the velocities, in place.

    Every mass's velocity changes by -omega dcm_excess, so the centre of mass velocity does,
    and the DCM c + c_dot / omega moves by -dcm_excess with the positions untouched.

    :param command: (2, 9) commanded state
    :param dcm_excess: (2,) from dcm_leash_excess (m)
    :param omega: the pendulum's natural frequency (1/s)
    """
    for mass in MASSES:
        command[:, state_index(mass, VELOCITY)] -= omega * dcm_excess
