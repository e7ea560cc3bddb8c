"""Kinematic limits between consecutive footsteps, foot collision, and clamping of a landing.

A step is described in the frame of the stance foot (x along its heading, y to its left):
dx is how far forward the swing foot lands, the lateral distance is measured towards the swing
foot's own side (positive: the feet do not cross), and dyaw is the change of heading.
"""
from dataclasses import dataclass
import math
from typing import List, Tuple

import numpy as np

from biped_planner.errors import ConfigError
from biped_planner.footsteps import Footstep
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.rotations import wrap_angle
from biped_planner.sides import LEFT


@dataclass(frozen=True)
class KinematicLimits:
    """Reachable landings relative to the stance foot, and the foot size for collisions.

    Each field's description and range are in its parameter(); min_width must also lie in
    [foot_width + clearance, max_width].
    """

    max_forward: float = parameter(0.25, 'largest forward distance of a landing (m)',
                                   low=0.0, high=1.0)
    max_backward: float = parameter(0.15, 'largest backward distance of a landing (m)',
                                    low=0.0, high=1.0)
    min_width: float = parameter(0.12, 'smallest lateral distance between the sole centres, '
                                 'towards the swing side (m), at least foot_width + clearance',
                                 low=0.0, high=1.0)
    max_width: float = parameter(0.4, 'largest lateral distance between the sole centres (m)',
                                 low=0.0, high=1.0, low_open=True)
    max_turn: float = parameter(math.radians(30.0), 'largest heading change per step (rad)',
                                low=0.0, high=math.pi / 2)
    foot_length: float = parameter(0.16, 'sole length (m)', low=0.0, high=1.0, low_open=True)
    foot_width: float = parameter(0.08, 'sole width (m)', low=0.0, high=1.0, low_open=True)
    clearance: float = parameter(0.01, 'smallest gap between the two soles (m)',
                                 low=0.0, high=0.2)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        low = self.foot_width + self.clearance
        if not low <= self.min_width <= self.max_width:
            raise ConfigError(f'KinematicLimits.min_width must be in [foot_width + clearance, '
                              f'max_width] = [{low}, {self.max_width}], got {self.min_width!r}')


def relative_step(stance: Footstep, landing: Footstep) -> Tuple[float, float, float]:
    """The landing in the stance foot frame.

    :param stance: the stance foot
    :param landing: the landing of the other foot
    :return: (dx forward (m), lateral distance towards the landing foot's side (m),
        dyaw (rad) wrapped to [-pi, pi))
    """
    cos_yaw, sin_yaw = math.cos(stance.yaw), math.sin(stance.yaw)
    x, y = landing.x - stance.x, landing.y - stance.y
    forward = cos_yaw * x + sin_yaw * y
    left = -sin_yaw * x + cos_yaw * y
    return forward, left if landing.side == LEFT else -left, wrap_angle(landing.yaw - stance.yaw)


def _corners(step: Footstep, length: float, width: float) -> np.ndarray:
    half = np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]]) * [0.5 * length, 0.5 * width]
    cos_yaw, sin_yaw = math.cos(step.yaw), math.sin(step.yaw)
    return half @ np.array([[cos_yaw, sin_yaw], [-sin_yaw, cos_yaw]]) + [step.x, step.y]


def feet_overlap(first: Footstep, second: Footstep, length: float, width: float,
                 clearance: float = 0.0) -> bool:
    """Whether two sole rectangles, each grown by clearance / 2 on every side, intersect
    (separating axis test).

    :param first: one foot
    :param second: the other foot
    :param length: sole length (m)
    :param width: sole width (m)
    :param clearance: required gap (m)
    :return: True if they overlap
    """
    corners = [_corners(step, length + clearance, width + clearance) for step in (first, second)]
    for step in (first, second):
        for angle in (step.yaw, step.yaw + 0.5 * math.pi):
            axis = np.array([math.cos(angle), math.sin(angle)])
            a, b = corners[0] @ axis, corners[1] @ axis
            if a.max() <= b.min() or b.max() <= a.min():
                return False
    return True


def step_violations(stance: Footstep, landing: Footstep, limits: KinematicLimits) -> List[str]:
    """The limits a step breaks (empty when it is feasible).

    :param stance: the stance foot
    :param landing: the landing of the other foot
    :param limits: the limits
    :return: one message per broken limit
    """
    problems = []
    if stance.side == landing.side:
        problems.append('the landing foot is the stance foot')
    forward, lateral, turn = relative_step(stance, landing)
    eps = 1e-9
    if not -limits.max_backward - eps <= forward <= limits.max_forward + eps:
        problems.append(f'forward distance {forward:.3f} m outside [-{limits.max_backward}, '
                        f'{limits.max_forward}]')
    if not limits.min_width - eps <= lateral <= limits.max_width + eps:
        problems.append(f'lateral distance {lateral:.3f} m outside [{limits.min_width}, '
                        f'{limits.max_width}] (negative: crossed feet)')
    if abs(turn) > limits.max_turn + eps:
        problems.append(f'turn {math.degrees(turn):.1f} deg beyond '
                        f'{math.degrees(limits.max_turn):.1f}')
    if feet_overlap(stance, landing, limits.foot_length, limits.foot_width,
                    limits.clearance - eps):
        problems.append('the soles collide')
    return problems


def clamp_step(stance: Footstep, landing: Footstep, limits: KinematicLimits) -> Footstep:
    """The nearest feasible landing: clip the turn, the forward and the lateral distance in the
    stance frame, then widen the step (and finally align the feet) until the soles are clear.

    :param stance: the stance foot
    :param landing: the desired landing of the other foot
    :param limits: the limits
    :return: a landing that step_violations accepts
    """
    forward, lateral, turn = relative_step(stance, landing)
    turn = min(max(turn, -limits.max_turn), limits.max_turn)
    forward = min(max(forward, -limits.max_backward), limits.max_forward)
    lateral = min(max(lateral, limits.min_width), limits.max_width)

    def build(forward: float, lateral: float, turn: float) -> Footstep:
        left = lateral if landing.side == LEFT else -lateral
        cos_yaw, sin_yaw = math.cos(stance.yaw), math.sin(stance.yaw)
        return Footstep(landing.side, stance.x + cos_yaw * forward - sin_yaw * left,
                        stance.y + sin_yaw * forward + cos_yaw * left, stance.yaw + turn)

    candidate = build(forward, lateral, turn)
    while feet_overlap(stance, candidate, limits.foot_length, limits.foot_width,
                       limits.clearance) and lateral < limits.max_width:
        lateral = min(lateral + 0.005, limits.max_width)
        candidate = build(forward, lateral, turn)
    if feet_overlap(stance, candidate, limits.foot_length, limits.foot_width, limits.clearance):
        candidate = build(forward, max(lateral, limits.min_width), 0.0)
    return candidate
