"""The feet state of the paper's footstep planning and its transition s' = t(s, a).

State s = (x_l, y_l, theta_l, phi_l, x_r, y_r, theta_r, phi_r): both soles and which foot swings
next. The body is the point between the feet, in line with the last landing. A transition lands
the swing foot at d = step_width / 2 to its side of a target body pose, clamped to the kinematic
limits relative to the stance foot (biped_planner.kinematic_limits); the body moves beside the
landing, the footstep is saved and the feet swap roles (phi_l, phi_r toggle). Both footstep
generators use it: along a path (biped_planner.footstep_planner) and from step commands
(biped_planner.omnidirectional_stepper).
"""
from typing import List, Tuple

from biped_planner.footsteps import body_beside, feet_beside, foot_beside, Footstep
from biped_planner.kinematic_limits import clamp_step, KinematicLimits
from biped_planner.pose2d import Pose2D
from biped_planner.sides import LEFT, other_side, RIGHT


class FeetState:
    """Both feet, the swing foot, the body pose and the footsteps saved so far."""

    def __init__(self, start: Pose2D, step_width: float, first_swing: int,
                 limits: KinematicLimits) -> None:
        """Feet side by side around the start pose (arguments checked by the caller).

        :param start: body pose between the feet
        :param step_width: distance between the sole centres, 2 d (m)
        :param first_swing: the foot that swings first, LEFT or RIGHT
        :param limits: kinematic limits of every landing
        """
        left, right = feet_beside(start, step_width)
        self.feet = {LEFT: left, RIGHT: right}
        self.half_width = 0.5 * step_width
        self.swing = first_swing
        self.limits = limits
        self.body = start
        self.footsteps: List[Footstep] = [self.feet[other_side(first_swing)],
                                          self.feet[first_swing]]

    @classmethod
    def from_footsteps(cls, footsteps, step_width: float,
                       limits: KinematicLimits) -> 'FeetState':
        """The state after a footstep list (>= 2 footsteps; checked by the caller): each foot
        at its last footstep, the body beside the last landing, the other foot swinging next.

        :param footsteps: initial feet, then landings
        """
        state = cls.__new__(cls)
        state.half_width = 0.5 * step_width
        state.limits = limits
        state.feet = {}
        for step in footsteps:
            state.feet[step.side] = step
        last = footsteps[-1]
        state.swing = other_side(last.side)
        state.body = body_beside(last, state.half_width)
        state.footsteps = list(footsteps)
        return state

    def land(self, x: float, y: float, yaw: float) -> Footstep:
        """The transition: the swing foot lands beside the body pose (x, y, yaw), clamped.

        :return: the landing (also appended to footsteps)
        """
        desired = foot_beside(x, y, yaw, self.swing, self.half_width)
        landing = clamp_step(self.feet[other_side(self.swing)], desired, self.limits)
        self.body = body_beside(landing, self.half_width)
        self.feet[self.swing] = landing
        self.footsteps.append(landing)
        self.swing = other_side(self.swing)
        return landing

    def vector(self) -> Tuple[float, ...]:
        """The paper's s = (x_l, y_l, theta_l, phi_l, x_r, y_r, theta_r, phi_r).

        :return: the 8-tuple; phi is 1 for the foot that swings next and -1 for the other
        """
        left, right = self.feet[LEFT], self.feet[RIGHT]
        return (left.x, left.y, left.yaw, 1.0 if self.swing == LEFT else -1.0,
                right.x, right.y, right.yaw, 1.0 if self.swing == RIGHT else -1.0)
