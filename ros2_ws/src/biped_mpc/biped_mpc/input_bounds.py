"""Physical bounds of what the controller reads: sensors and references it refuses to believe.

A finite number is not necessarily a possible one: odometry at 1e30 m, a wrench of 1e30 N or a
joint angle past its stop are readings of a broken sensor (or of a bad message), and a controller
that takes them as true makes the robot fall. Each check raises InputError naming the input, the
value and the bound; the controller then keeps its previous valid data.
"""
from dataclasses import dataclass
import math
from typing import Sequence

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_planner.input_checks import first_outside_limits
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.sides import SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT

SUPPORTS = (SUPPORT_LEFT, SUPPORT_RIGHT, SUPPORT_DOUBLE)


@dataclass(frozen=True)
class InputBounds:
    """The largest values a reading or a reference may have.

    Each field's description and range are in its parameter().
    """

    workspace: float = parameter(1000.0, 'largest |x|, |y| or |z| of a position the robot or a '
                                 'reference can be at (m)', low=1.0, high=1e6)
    max_speed: float = parameter(20.0, 'largest pelvis speed (m/s)', low=0.1, high=1e3)
    max_angular_speed: float = parameter(50.0, 'largest pelvis angular speed (rad/s)', low=0.1,
                                         high=1e3)
    max_acceleration: float = parameter(500.0, 'largest IMU specific force (m/s^2)', low=1.0,
                                        high=1e5)
    max_force: float = parameter(5000.0, 'largest force an ankle F/T sensor measures (N)',
                                 low=1.0, high=1e6)
    max_torque: float = parameter(1000.0, 'largest torque an ankle F/T sensor measures (N m)',
                                  low=0.1, high=1e6)
    joint_margin: float = parameter(0.2, 'how far a measured joint angle may be past its limit '
                                    '(rad)', low=0.0, high=3.2)
    quaternion_tolerance: float = parameter(0.01, 'largest | |q| - 1 | of an orientation',
                                            low=1e-6, high=0.5)
    max_foot_jump: float = parameter(0.5, 'largest move of a reference foot between two '
                                     'samples (m)', low=0.01, high=10.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


def check_vector(name: str, value: Sequence[float], limit: float, unit: str) -> np.ndarray:
    """A finite vector whose norm is at most limit.

    :raises InputError: for NaN, inf or a norm above limit
    """
    vector = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(vector)):
        raise InputError(f'{name} {vector.tolist()} is not finite')
    norm = float(np.linalg.norm(vector))
    if norm > limit:
        raise InputError(f'{name} {vector.tolist()} has magnitude {norm:.4g} {unit} '
                         f'(> {limit} {unit})')
    return vector


def check_position(name: str, value: Sequence[float], bounds: InputBounds) -> np.ndarray:
    """A finite position inside the workspace box.

    :raises InputError: for NaN, inf or a coordinate beyond bounds.workspace
    """
    position = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(position)):
        raise InputError(f'{name} {position.tolist()} is not finite')
    if np.any(np.abs(position) > bounds.workspace):
        raise InputError(f'{name} {position.tolist()} is outside the workspace '
                         f'(|coordinate| <= {bounds.workspace} m)')
    return position


def check_quaternion(name: str, value: Sequence[float], bounds: InputBounds) -> np.ndarray:
    """A finite unit quaternion (x, y, z, w), its norm within the tolerance of 1.

    :raises InputError: for NaN, inf or a norm off 1 by more than bounds.quaternion_tolerance
    """
    quaternion = np.asarray(value, dtype=float)
    if quaternion.shape != (4,) or not np.all(np.isfinite(quaternion)):
        raise InputError(f'{name} {quaternion.tolist()} is not 4 finite numbers')
    norm = float(np.linalg.norm(quaternion))
    if abs(norm - 1.0) > bounds.quaternion_tolerance:
        raise InputError(f'{name} {quaternion.tolist()} has norm {norm:.6g}, not 1 within '
                         f'{bounds.quaternion_tolerance}')
    return quaternion


def check_joint_angles(names: Sequence[str], angles: Sequence[float], lower: Sequence[float],
                       upper: Sequence[float], bounds: InputBounds) -> np.ndarray:
    """Finite joint angles within their limits, widened by bounds.joint_margin.

    :param names: joint names, for the message
    :param angles: (n,) measured angles (rad)
    :param lower: (n,) lower limits (rad)
    :param upper: (n,) upper limits (rad)
    :raises InputError: naming the first joint out of bounds
    """
    q = np.asarray(angles, dtype=float)
    outside = first_outside_limits(q, lower, upper, bounds.joint_margin)
    if outside is not None:
        i, low, high = outside
        raise InputError(f'joint {names[i]} at {q[i]!r} rad is outside [{low:.3f}, '
                         f'{high:.3f}] (its limits widened by {bounds.joint_margin} rad)')
    return q


REFERENCE_POSITIONS = ('zmp', 'hip', 'left_foot', 'right_foot', 'left_mass', 'right_mass')


def check_reference_window(window, dt: float, bounds: InputBounds) -> None:
    """A reference window the controller can follow.

    :param window: ReferenceWindow (finite already, as its message conversion checks)
    :param dt: the controller's period, the window's sample period (s)
    :raises InputError: for fewer than 2 samples, another sample period, an unknown support
        label, positions outside the workspace or a foot that jumps farther than
        bounds.max_foot_jump between samples
    """
    n = len(window.t)
    if n < 2:
        raise InputError(f'the reference has {n} samples (at least 2 needed)')
    spacing = float(window.t[1] - window.t[0])
    if not math.isclose(spacing, dt, rel_tol=1e-6, abs_tol=1e-9):
        raise InputError(f'the reference samples are {spacing!r} s apart, the controller runs '
                         f'every {dt} s')
    support = np.asarray(window.support)
    known = support == SUPPORTS[0]
    for label in SUPPORTS[1:]:  # np.isin costs 20 us on a window of 81 samples, this 3 us
        known |= support == label
    if not known.all():
        k = int(np.flatnonzero(~known)[0])
        raise InputError(f'reference support[{k}] is {support[k]}: not one of {SUPPORTS} '
                         f'(left, right, double)')
    if np.any(np.asarray(window.step_index) < 0):
        raise InputError('reference step_index must be >= 0')
    for name in REFERENCE_POSITIONS:
        values = np.asarray(getattr(window, name), dtype=float)
        if values.size and np.max(np.abs(values)) > bounds.workspace:
            raise InputError(f'reference {name} leaves the workspace (|coordinate| <= '
                             f'{bounds.workspace} m): {np.max(np.abs(values)):.4g} m')
    for name in ('left_foot', 'right_foot'):
        xy = np.asarray(getattr(window, name), dtype=float)[:, :2]
        jumps = np.hypot(*np.diff(xy, axis=0).T) if n > 1 else np.zeros(0)
        if jumps.size and jumps.max() > bounds.max_foot_jump:
            k = int(np.argmax(jumps))
            raise InputError(f'reference {name} jumps {jumps[k]:.3f} m between samples {k} and '
                             f'{k + 1} (> {bounds.max_foot_jump} m)')
