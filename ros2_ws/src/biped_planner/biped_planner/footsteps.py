"""Footsteps: the pose of a foot's sole centre on the ground, and simple footstep lists.

A footstep list follows one convention everywhere in the stack: element 0 is the first support
foot, element 1 is the first swing foot's initial place, and each later element is the landing of
the next swing foot (feet alternate). This is the paper's sequence of saved footsteps f_i.
"""
from dataclasses import dataclass
import math
from typing import List, Sequence, Tuple

from biped_planner import sides
from biped_planner.errors import ConfigError
from biped_planner.input_checks import check_integer, check_number, check_side
from biped_planner.pose2d import Pose2D
# RIGHT is importable from here for the packages that still find it here (biped_planner.sides).
from biped_planner.sides import LEFT, RIGHT  # noqa: F401

SIDE_NAMES = ('left', 'right')


@dataclass(frozen=True)
class Footstep:
    """Pose of one foot's sole centre in the world frame.

    :param side: LEFT (0) or RIGHT (1)
    :param x: sole centre x (m)
    :param y: sole centre y (m)
    :param yaw: heading of the foot about z, counter-clockwise from world x (rad)
    """

    side: int
    x: float
    y: float
    yaw: float = 0.0

    def __post_init__(self) -> None:
        check_side('Footstep.side', self.side)
        for name in ('x', 'y', 'yaw'):
            check_number(f'Footstep.{name}', getattr(self, name))


def other_side(side: int) -> int:
    """biped_planner.sides.other_side for a side given by a caller: checked first.

    :param side: LEFT or RIGHT
    :return: RIGHT for LEFT and LEFT for RIGHT
    :raises ConfigError: if side is neither LEFT nor RIGHT
    """
    return sides.other_side(check_side('side', side))


def foot_beside(x: float, y: float, yaw: float, side: int, distance: float) -> Footstep:
    """The sole of one foot at a distance to its own side of a pose, with the pose's heading.

    :param x: pose x (m)
    :param y: pose y (m)
    :param yaw: pose heading (rad)
    :param side: LEFT (placed to the pose's left) or RIGHT
    :param distance: lateral distance from the pose (m)
    :return: the footstep
    """
    sign = 1.0 if side == LEFT else -1.0
    cos_yaw, sin_yaw = math.cos(yaw), math.sin(yaw)
    return Footstep(side, x - sign * sin_yaw * distance, y + sign * cos_yaw * distance, yaw)


def feet_beside(body: Pose2D, step_width: float) -> Tuple[Footstep, Footstep]:
    """Left and right soles side by side around a body pose, step_width apart.

    :return: (left, right)
    """
    half = 0.5 * step_width
    return (foot_beside(body.x, body.y, body.yaw, LEFT, half),
            foot_beside(body.x, body.y, body.yaw, RIGHT, half))


def body_beside(foot: Footstep, distance: float) -> Pose2D:
    """The pose at a distance from a foot towards the other foot's side, with its heading:
    the body between the feet, in line with the foot that landed last.
    """
    sign = 1.0 if foot.side == LEFT else -1.0
    return Pose2D(foot.x + sign * math.sin(foot.yaw) * distance,
                  foot.y - sign * math.cos(foot.yaw) * distance, foot.yaw)


def check_footstep_sequence(footsteps: Sequence[Footstep], minimum: int = 3) -> None:
    """Check the footstep-list convention: Footstep items, two different initial feet, alternation.

    The swing sequence is (footsteps[1], footsteps[0], footsteps[2], footsteps[3], ...): the
    first landing uses the same foot as footsteps[1] and every later landing the other foot than
    the previous landing.

    :param footsteps: the footstep list
    :param minimum: the smallest allowed length (3: two initial feet and one step)
    :raises ConfigError: if the list is too short, holds a non-Footstep or feet do not
        alternate
    """
    if len(footsteps) < minimum:
        raise ConfigError(
            f'a footstep list needs at least {minimum} footsteps (two initial feet and the '
            f'steps), got {len(footsteps)}')
    for index, step in enumerate(footsteps):
        if not isinstance(step, Footstep):
            raise ConfigError(f'footsteps[{index}] must be a Footstep, got {type(step).__name__}')
    if footsteps[0].side == footsteps[1].side:
        raise ConfigError('footsteps[0] and footsteps[1] (the initial feet) must be different '
                          f'feet, both are {SIDE_NAMES[footsteps[0].side]}')
    if len(footsteps) > 2 and footsteps[2].side != footsteps[1].side:
        raise ConfigError('footsteps[2] must land the first swing foot (the side of '
                          f'footsteps[1], {SIDE_NAMES[footsteps[1].side]}), got '
                          f'{SIDE_NAMES[footsteps[2].side]}')
    for index in range(3, len(footsteps)):
        if footsteps[index].side == footsteps[index - 1].side:
            raise ConfigError(f'feet must alternate: footsteps[{index}] and '
                              f'footsteps[{index - 1}] are both '
                              f'{SIDE_NAMES[footsteps[index].side]}')


def straight_footsteps(n_steps: int, step_length: float, step_width: float,
                       first_swing: int = LEFT, x0: float = 0.0,
                       y0: float = 0.0) -> List[Footstep]:
    """Footsteps of a straight walk along world x, ending with the feet side by side.

    The two initial feet stand at (x0, y0 +- step_width / 2); landing k (k = 1..n_steps) is at
    x0 + k * step_length (consecutive footsteps, and so consecutive ZMP points, are step_length
    apart); a final step brings the trailing foot next to the leading one.

    :param n_steps: number of steps forward, >= 0 (0 gives one step in place)
    :param step_length: distance along x between consecutive footsteps (m), in [-1, 1]
    :param step_width: distance between the left and right sole centres (m), in (0, 1]
    :param first_swing: the foot that swings first, LEFT or RIGHT
    :param x0: x of the initial feet (m)
    :param y0: y of the point midway between the initial feet (m)
    :return: n_steps + 3 footsteps in the footstep-list convention
    :raises ConfigError: if an argument is out of range or not finite
    """
    check_integer('n_steps', n_steps, low=0)
    check_number('step_length', step_length, -1.0, 1.0, unit=' m')
    check_number('step_width', step_width, 0.0, 1.0, low_open=True, unit=' m')
    check_number('x0', x0)
    check_number('y0', y0)
    support = other_side(first_swing)
    half_width = 0.5 * step_width

    def foot(side: int, x: float) -> Footstep:
        return Footstep(side, float(x), float(y0 + (half_width if side == LEFT else -half_width)))

    footsteps = [foot(support, x0), foot(first_swing, x0)]
    side = first_swing
    for k in range(1, n_steps + 1):
        footsteps.append(foot(side, x0 + k * step_length))
        side = other_side(side)
    footsteps.append(foot(side, x0 + n_steps * step_length))
    return footsteps
