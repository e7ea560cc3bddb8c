"""Joint position limits of a robot (from its URDF), and the check of joint setpoints against them.

The simulator refuses setpoints that no joint can reach (past a limit by more than a margin):
a setpoint of 1e30 rad would otherwise be servoed with the full torque of the joint.
"""
import math
from typing import Sequence, Tuple
import xml.etree.ElementTree as ElementTree

import numpy as np

from biped_planner.input_checks import first_outside_limits
from biped_sim.errors import ConfigError, InputError


def joint_limits_from_urdf(urdf_path: str,
                           names: Sequence[str]) -> Tuple[np.ndarray, np.ndarray]:
    """Lower and upper position limits of the named joints.

    Continuous joints, and joints whose limit element has no bounds, are unbounded (+-inf).

    :param urdf_path: the robot's URDF file
    :param names: joint names, in the order wanted
    :return: (lower, upper), each (len(names),) (rad, or m for prismatic joints)
    :raises ConfigError: when the file cannot be read or a joint is not in it
    """
    try:
        root = ElementTree.parse(urdf_path).getroot()
    except (OSError, ElementTree.ParseError) as error:
        raise ConfigError(f'cannot read the URDF {urdf_path}: {error}') from error
    joints = {joint.get('name'): joint for joint in root.iter('joint')}
    missing = [name for name in names if name not in joints]
    if missing:
        raise ConfigError(f'joints {missing} are not in {urdf_path}')
    lower = np.full(len(names), -np.inf)
    upper = np.full(len(names), np.inf)
    for i, name in enumerate(names):
        joint = joints[name]
        limit = joint.find('limit')
        if joint.get('type') == 'continuous' or limit is None:
            continue
        low, high = limit.get('lower'), limit.get('upper')
        if low is not None and high is not None and float(low) < float(high):
            lower[i], upper[i] = float(low), float(high)
    return lower, upper


def check_setpoints(names: Sequence[str], setpoints: Sequence[float], lower: Sequence[float],
                    upper: Sequence[float], margin: float) -> np.ndarray:
    """Joint setpoints within the joints' limits widened by margin.

    :param names: joint names, for the message
    :param setpoints: (n,) setpoints (rad)
    :param lower: (n,) lower limits (rad), -inf for none
    :param upper: (n,) upper limits (rad), +inf for none
    :param margin: how far past a limit a setpoint may be (rad), >= 0
    :return: the setpoints as a float array
    :raises InputError: naming the first joint whose setpoint is not finite or out of bounds
    """
    if not (isinstance(margin, (int, float)) and math.isfinite(margin) and margin >= 0.0):
        raise ConfigError(f'margin must be a finite number >= 0 (rad), got {margin!r}')
    values = np.asarray(setpoints, dtype=float)
    outside = first_outside_limits(values, lower, upper, margin)
    if outside is not None:
        i, low, high = outside
        raise InputError(f'setpoint {values[i]!r} of {names[i]} is outside [{low:.3f}, '
                         f'{high:.3f}] rad (its limits widened by {margin} rad)')
    return values
