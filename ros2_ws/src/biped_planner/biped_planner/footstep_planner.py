"""Footsteps along a collision-free path: the second stage of the paper's A* footstep planning.

Feet state s = (x_l, y_l, theta_l, phi_l, x_r, y_r, theta_r, phi_r), action a = (R, sigma):
the body (the point between the feet, in line with the last landing) advances R along its new
heading after turning by sigma, and the swing foot lands on the line parallel to the path at
d = step_width / 2 on its side (the paper's Fig. footstep: two lines at +-d, footsteps R apart).
R is the constant step size (0.1 m), reduced only to stop exactly at the goal; sigma is the
inverse tangent of the direction from the body to a look-ahead point on the path minus the
current heading. The action passes through a first-order lag filter (one update per step), is
clipped to the largest turn per step, and the landing is clamped to the kinematic limits
(biped_planner.kinematic_limits: reach, width range so the feet never cross, turn, no sole
collision). Once at the goal the robot turns in place to the goal heading and a last step puts
the feet side by side.

The A* path of an 8-connected grid zig-zags; before stepping it is shortened by line of sight
(a vertex is dropped when the straight segment that skips it stays on free cells of the
inflated map), so the footsteps follow straight lines and real turns only.
"""
from dataclasses import dataclass
import math
from typing import List, Optional, Sequence

import numpy as np

from biped_planner.astar import AStarPlanner, GridPath
from biped_planner.errors import ConfigError, PlanningError
from biped_planner.feet_state import FeetState
from biped_planner.footsteps import Footstep
from biped_planner.input_checks import check_finite_array, check_side, check_type
from biped_planner.kinematic_limits import KinematicLimits
from biped_planner.lag_filter import FirstOrderLag
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.pose2d import Pose2D
from biped_planner.rotations import wrap_angle
from biped_planner.sides import LEFT, RIGHT


@dataclass(frozen=True)
class FootstepPlannerParams:
    """Parameters of the path-following footstep planner (ranges in each parameter()).

    :param limits: kinematic limits between consecutive footsteps
    """

    step_length: float = parameter(0.1, 'R: advance of the body per step along the path (m)',
                                   low=0.0, high=0.5, low_open=True)
    step_width: float = parameter(0.2, '2 d: distance between the two feet lines (m)',
                                  low=0.0, high=1.0, low_open=True)
    lookahead: float = parameter(0.3, 'distance along the path of the point sigma aims at (m)',
                                 low=0.0, high=5.0, low_open=True)
    lag_time_constant: float = parameter(
        0.5, 'tau of the first-order lag filter on the action (s)', low=0.0, high=100.0)
    step_time: float = parameter(0.5, 'update interval of the lag filter, one step (s)',
                                 low=0.0, high=5.0, low_open=True)
    goal_tolerance: float = parameter(0.01, 'distance at which the body has reached the goal (m)',
                                      low=0.0, high=0.5, low_open=True)
    heading_tolerance: float = parameter(
        1e-6, 'heading error at which the final turn stops (rad)', low=1e-6, high=0.5)
    max_steps: int = parameter(5000, 'the planner gives up after this many steps',
                               low=1, high=100000)
    limits: KinematicLimits = KinematicLimits()

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        check_type('FootstepPlannerParams.limits', self.limits, KinematicLimits)


@dataclass(frozen=True)
class FootstepPlan:
    """The result of planning on a map.

    :param grid_path: the optimal A* path
    :param path: the shortened path the footsteps follow (K, 2) (m)
    :param footsteps: the footstep list (initial feet, then landings, ending side by side)
    """

    grid_path: GridPath
    path: np.ndarray
    footsteps: List[Footstep]


def shortcut_path(points: np.ndarray, planner: AStarPlanner) -> np.ndarray:
    """Drop path vertices while the straight segment that skips them stays on free cells.

    :param points: (K, 2) path points (m), on free cells of the planner's inflated map
    :param planner: the planner whose inflated map the segments must avoid
    :return: (L, 2) the kept points, the first and last included
    """
    points = np.asarray(points, dtype=float)
    if len(points) <= 2:
        return points.copy()
    grid = planner.grid
    blocked = planner.blocked
    height, width = blocked.shape
    spacing = 0.25 * grid.resolution

    def clear(a: np.ndarray, b: np.ndarray) -> bool:
        count = max(2, int(math.ceil(np.linalg.norm(b - a) / spacing)) + 1)
        samples = a + np.linspace(0.0, 1.0, count)[:, None] * (b - a)
        cols = np.floor((samples[:, 0] - grid.origin[0]) / grid.resolution).astype(int)
        rows = np.floor((samples[:, 1] - grid.origin[1]) / grid.resolution).astype(int)
        inside = (rows >= 0) & (rows < height) & (cols >= 0) & (cols < width)
        return bool(inside.all() and not blocked[rows, cols].any())

    kept = [0]
    anchor = 0
    while anchor < len(points) - 1:
        low, high = anchor + 1, len(points) - 1
        if clear(points[anchor], points[high]):
            kept.append(high)
            break
        # the farthest visible vertex, found by scanning back from the end in halves
        best = low
        while low <= high:
            middle = (low + high) // 2
            if clear(points[anchor], points[middle]):
                best, low = middle, middle + 1
            else:
                high = middle - 1
        kept.append(best)
        anchor = best
    return points[kept]


def shortened_path(planner: AStarPlanner, start: Pose2D, goal: Pose2D):
    """The A* path from start to goal, its ends on the exact poses, shortened (shortcut_path).

    :return: (the grid path, the shortened (K, 2) path)
    :raises PlanningError: (a subclass) if A* finds no path
    """
    grid_path = planner.plan((start.x, start.y), (goal.x, goal.y))
    points = grid_path.points.copy()
    points[0] = (start.x, start.y)
    points[-1] = (goal.x, goal.y)
    return grid_path, shortcut_path(points, planner)


class _Polyline:
    """Arc-length parameterised polyline."""

    def __init__(self, points: np.ndarray) -> None:
        self.points = points
        segments = np.diff(points, axis=0)
        self.lengths = np.hypot(segments[:, 0], segments[:, 1])
        self.cumulative = np.concatenate(([0.0], np.cumsum(self.lengths)))
        self.total = float(self.cumulative[-1])

    def at(self, s: float) -> np.ndarray:
        s = min(max(s, 0.0), self.total)
        if self.total == 0.0:
            return self.points[0].copy()
        j = int(np.clip(np.searchsorted(self.cumulative, s, side='right') - 1, 0,
                        len(self.lengths) - 1))
        if self.lengths[j] == 0.0:
            return self.points[j].copy()
        return self.points[j] + (s - self.cumulative[j]) / self.lengths[j] * (
            self.points[j + 1] - self.points[j])

    def project(self, point: np.ndarray, s_min: float, window: float) -> float:
        """Arc length of the nearest point of the polyline within [s_min, s_min + window]."""
        start = self.points[:-1]
        delta = self.points[1:] - start
        u = np.clip(np.einsum('ij,ij->i', point - start, delta)
                    / np.maximum(self.lengths ** 2, 1e-18), 0.0, 1.0)
        s = self.cumulative[:-1] + u * self.lengths
        distance = np.hypot(*(start + u[:, None] * delta - point).T)
        behind = s < s_min
        if behind.any():
            distance[behind] = np.hypot(*(self.at(s_min) - point))
            s[behind] = s_min
        distance[s > s_min + window] = np.inf
        return float(s[int(np.argmin(distance))])


class FootstepPlanner:
    """Plans footsteps along a path (the paper's footstep planning second stage)."""

    def __init__(self, params: FootstepPlannerParams = FootstepPlannerParams()) -> None:
        """Create the planner.

        :param params: planner parameters
        :raises ConfigError: if params has the wrong type
        """
        self._params = check_type('params', params, FootstepPlannerParams)

    @property
    def params(self) -> FootstepPlannerParams:
        """The planner parameters."""
        return self._params

    def plan_on_map(self, planner: AStarPlanner, start: Pose2D, goal: Pose2D) -> FootstepPlan:
        """A* path from start to goal, shortened, then footsteps along it.

        :param planner: A* planner of the map
        :param start: body pose between the initial feet
        :param goal: body pose between the final feet
        :return: the path and the footsteps
        :raises ConfigError: if start or goal is not a Pose2D
        :raises PlanningError: (a subclass) if A* finds no path or the steps do not converge
        """
        check_type('start', start, Pose2D)
        check_type('goal', goal, Pose2D)
        grid_path, path = shortened_path(planner, start, goal)
        return FootstepPlan(grid_path, path, self.plan_along_path(path, start, goal))

    def plan_along_path(self, path: np.ndarray, start: Pose2D, goal: Pose2D,
                        first_swing: Optional[int] = None) -> List[Footstep]:
        """Footsteps that follow a path from the start pose to the goal pose.

        :param path: (K, 2) path points from near the start to the goal (m), K >= 1, finite
        :param start: body pose between the initial feet
        :param goal: body pose between the final feet (its position should be the path end)
        :param first_swing: the foot that swings first (default: the side the path turns to)
        :return: the footstep list (initial feet, then landings, ending side by side)
        :raises ConfigError: if an argument is malformed
        :raises PlanningError: if the goal is not reached within max_steps steps
        """
        path = check_finite_array('path', path)
        if path.ndim != 2 or path.shape[1] != 2 or len(path) < 1:
            raise ConfigError(f'path must be a finite (K, 2) array with K >= 1, got shape '
                              f'{path.shape}')
        check_type('start', start, Pose2D)
        check_type('goal', goal, Pose2D)
        params = self._params
        goal_xy = np.array([goal.x, goal.y])
        line = _Polyline(np.vstack(([start.x, start.y], path, goal_xy)))
        if first_swing is None:
            direction = line.at(params.lookahead) - [start.x, start.y]
            turn = wrap_angle(math.atan2(direction[1], direction[0]) - start.yaw) if np.hypot(
                *direction) > 1e-9 else wrap_angle(goal.yaw - start.yaw)
            first_swing = LEFT if turn >= 0.0 else RIGHT
        else:
            check_side('first_swing', first_swing)
        state = FeetState(start, params.step_width, first_swing, params.limits)
        return self._walk_to(state, line, goal, FirstOrderLag(params.lag_time_constant,
                                                              [0.0, 0.0]))

    def plan_from_footsteps(self, planner: AStarPlanner, footsteps: Sequence[Footstep],
                            goal: Pose2D) -> FootstepPlan:
        """Go on to the goal from footsteps already walked or committed (a step adjuster moved
        a landing): A* from the body beside the last footstep, then footsteps along the path,
        walking on at the nominal step length.

        :param footsteps: >= 2 footsteps, initial feet first; kept as they are
        :return: the path and the whole footstep list (footsteps, then the new landings)
        :raises PlanningError: (a subclass) if A* finds no path or the steps do not converge
        """
        check_type('goal', goal, Pose2D)
        if len(footsteps) < 2:
            raise ConfigError(f'at least 2 footsteps are needed, got {len(footsteps)}')
        params = self._params
        state = FeetState.from_footsteps(tuple(footsteps), params.step_width, params.limits)
        start = state.body
        grid_path, path = shortened_path(planner, start, goal)
        line = _Polyline(np.vstack(([start.x, start.y], path, [goal.x, goal.y])))
        walking = FirstOrderLag(params.lag_time_constant, [params.step_length, 0.0])
        return FootstepPlan(grid_path, path, self._walk_to(state, line, goal, walking))

    def _walk_to(self, state: FeetState, line: '_Polyline', goal: Pose2D,
                 action: FirstOrderLag) -> List[Footstep]:
        """Land footsteps from state along line until the body stands at the goal."""
        params = self._params
        goal_xy = np.array([goal.x, goal.y])
        progress = 0.0
        for _ in range(params.max_steps):
            body = np.array([state.body.x, state.body.y])
            remaining = float(np.hypot(*(goal_xy - body)))
            if remaining <= params.goal_tolerance:
                break
            progress = line.project(body, progress,
                                    3.0 * params.lookahead + params.step_length)
            target = line.at(progress + params.lookahead)
            if np.hypot(*(target - body)) < 1e-9 or remaining < params.lookahead:
                target = goal_xy
            sigma_raw = wrap_angle(math.atan2(target[1] - body[1], target[0] - body[0])
                                   - state.body.yaw)
            step, sigma = action.update([params.step_length, sigma_raw], params.step_time)
            sigma = min(max(float(sigma), -params.limits.max_turn), params.limits.max_turn)
            if remaining < params.step_length:
                # final approach: aim straight at the goal, unfiltered, so the body stops on it
                sigma = min(max(sigma_raw, -params.limits.max_turn), params.limits.max_turn)
                step = remaining if abs(wrap_angle(sigma_raw - sigma)) < 1e-9 else 0.0
                action.reset([step, sigma])
            _advance(state, float(min(step, remaining)), sigma)
        else:
            raise PlanningError(f'the footsteps did not reach the goal within '
                                f'{params.max_steps} steps')
        for _ in range(params.max_steps):
            error = wrap_angle(goal.yaw - state.body.yaw)
            if abs(error) <= params.heading_tolerance:
                break
            _advance(state, 0.0, min(max(error, -params.limits.max_turn), params.limits.max_turn))
        else:
            raise PlanningError('the final turn did not converge')
        _advance(state, 0.0, wrap_angle(goal.yaw - state.body.yaw))
        return state.footsteps


def _advance(state: FeetState, advance: float, turn: float) -> None:
    """The action a = (R, sigma): the body turns by sigma and advances R along its new heading,
    and the swing foot lands beside it."""
    body = state.body
    yaw = body.yaw + turn
    state.land(body.x + advance * math.cos(yaw), body.y + advance * math.sin(yaw), yaw)
