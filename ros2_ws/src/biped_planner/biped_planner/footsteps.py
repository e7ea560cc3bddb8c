"""Footsteps: the pose of a foot's sole centre on the ground, and simple footstep lists.

A footstep list follows one convention everywhere in the stack: element 0 is the first support
foot, element 1 is the first swing foot's initial place, and each later element is the landing of
the next swing foot (feet alternate). This is the paper's sequence of saved footsteps f_i.
"""
from dataclasses import dataclass
import math
from typing import List, Sequence

from biped_planner.errors import ConfigError

LEFT = 0
RIGHT = 1
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
        if isinstance(self.side, bool) or self.side not in (LEFT, RIGHT):
            raise ConfigError(f'Footstep.side must be LEFT (0) or RIGHT (1), got {self.side!r}')
        for name in ('x', 'y', 'yaw'):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ConfigError(f'Footstep.{name} must be a finite number, got {value!r}')


def other_side(side: int) -> int:
    """Return the other foot's label.

    :param side: LEFT or RIGHT
    :return: RIGHT for LEFT and LEFT for RIGHT
    :raises ConfigError: if side is neither LEFT nor RIGHT
    """
    if side == LEFT:
        return RIGHT
    if side == RIGHT:
        return LEFT
    raise ConfigError(f'side must be LEFT (0) or RIGHT (1), got {side!r}')


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
    if isinstance(n_steps, bool) or not isinstance(n_steps, int) or n_steps < 0:
        raise ConfigError(f'n_steps must be an integer >= 0, got {n_steps!r}')
    for name, value in (('step_length', step_length), ('step_width', step_width), ('x0', x0),
                        ('y0', y0)):
        if not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ConfigError(f'{name} must be a finite number, got {value!r}')
    if not -1.0 <= step_length <= 1.0:
        raise ConfigError(f'step_length must be in [-1, 1] m, got {step_length!r}')
    if not 0.0 < step_width <= 1.0:
        raise ConfigError(f'step_width must be in (0, 1] m, got {step_width!r}')
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
