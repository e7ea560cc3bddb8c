"""The largest push after which the LIPM can still be stopped, under the step adjuster's limits.

An upper bound for a push table (scripts/experiments/push_capture_bound.py): per horizontal
plane, the DCM of the LIPM of mass m under an external force F on its mass,

    xi_dot = omega (xi - p) + F / (m omega),

is driven with the CoP p anywhere in the extent of the support in that plane (a stance sole, or
both soles' span in double support), by steps that keep the plan's order of feet, each swing
lasting step_time_min or more and landing within the adjuster's reach and width of its stance
foot (no crossing). The walk counts as stopped once, with the push over, the DCM lies inside the
support's extent: the CoP can then hold it there. Each of these is a relaxation (the two planes
choose their step timing each on its own, the double support's hull is its box, weight moves
between the feet at once, the CoP reaches the sole's edge), so no controller of this LIPM with
these limits withstands a push above the bound. Outside the model: angular momentum (a hip
strategy) and the legs' own masses. Pure numpy; time is an argument.
"""
from dataclasses import dataclass
import itertools
import math
from typing import Sequence, Tuple

import numpy as np

from biped_planner.errors import InputError
from biped_planner.sides import LEFT, RIGHT
from biped_planner.step_adjustment import StepAdjustmentParams

AXIS_X = 0
AXIS_Y = 1
# The search over strategies: each step's landing time after its earliest (s), its double
# support before lift-off (s), and its landing point as a fraction of its allowed interval.
# Against a push along one direction the best step lands as early as it may at an end of its
# interval (the support then moves furthest, soonest); the other points check that.
SWING_EXTENSIONS = (0.0, 0.1)
DWELLS = (0.0, 0.1)
PLACEMENTS = (0.0, 0.5, 1.0)
TIME_STEP = 0.002  # s of the DCM integration (exact for a CoP held over the step)


@dataclass(frozen=True)
class PlaneSituation:
    """The walk in one horizontal plane when the push begins.

    :param axis: AXIS_X (along the walk) or AXIS_Y (sideways)
    :param dcm: the DCM (m)
    :param feet: (left, right) sole centres (m)
    :param swinging: the foot in the air now (LEFT or RIGHT), or None in a double support
    :param next_swing: the foot the plan lifts next (in a single support: the swinging one)
    :param swing_elapsed: s since the swinging foot left the ground (0 without one)
    :param half_sole: half the sole's extent along the axis (m)
    """

    axis: int
    dcm: float
    feet: Tuple[float, float]
    swinging: object
    next_swing: int
    swing_elapsed: float
    half_sole: float


def landing_interval(axis: int, side: int, stance: float,
                     limits: StepAdjustmentParams) -> Tuple[float, float]:
    """Where a foot of `side` may land, along the axis, with the other foot at `stance` (m)."""
    if axis == AXIS_X:
        return stance - limits.reach_backward, stance + limits.reach_forward
    if side == LEFT:
        return stance + limits.width_min, stance + limits.width_max
    return stance - limits.width_max, stance - limits.width_min


class PushCaptureBound:
    """Which pushes of one plane some strategy stops (see the module).

    The supports of every strategy searched are laid out once; a push is then one integration
    of all of them at once.

    :param situation: the plane when the push begins
    :param duration: s the push lasts, > 0
    :param mass: the LIPM's mass (kg), > 0
    :param limits: the step adjuster's reach, width, timing and model (com_height, gravity)
    :param steps: landings searched, >= 1
    :param horizon: s simulated after the push begins
    :param min_double_support: s both feet stand before a lift-off, at least (0: the weight
        moves at once)
    :raises InputError: for a non-positive duration, mass, steps or horizon, a negative
        double support
    """

    def __init__(self, situation: PlaneSituation, duration: float, mass: float,
                 limits: StepAdjustmentParams, steps: int = 3, horizon: float = 1.5,
                 min_double_support: float = 0.0) -> None:
        if not (duration > 0.0 and mass > 0.0 and steps >= 1 and horizon > duration
                and min_double_support >= 0.0):
            raise InputError(f'duration, mass and steps must be positive, the horizon past the '
                             f'push and the double support not negative, got {duration!r}, '
                             f'{mass!r}, {steps!r}, {horizon!r}, {min_double_support!r}')
        self.situation, self.duration, self.mass = situation, duration, mass
        self._omega = limits.omega
        self._grid = np.arange(0.0, horizon + 0.5 * TIME_STEP, TIME_STEP)
        choices = [_step_choices(situation, i, min_double_support) for i in range(steps)]
        extents = [_support_extents(situation, plan, self._grid, limits)
                   for plan in itertools.product(*choices)]
        self._low = np.array([low for low, _ in extents])
        self._high = np.array([high for _, high in extents])

    @property
    def strategies(self) -> int:
        """Number of step sequences searched."""
        return self._low.shape[0]

    def stopped(self, force: float) -> bool:
        """Whether some strategy stops the LIPM after a push of `force` N along the axis.

        Over each time step the CoP is on the support's edge on the push's side, which drives
        the DCM against the push as hard as the support can, unless the DCM has reached the
        other edge, where the CoP holds it (a push of 0 N: the CoP holds the DCM where the
        support allows). A strategy stops the walk when, the push over, its DCM is inside its
        support.
        """
        if not math.isfinite(force):
            raise InputError(f'force must be finite, got {force!r}')
        growth = math.exp(self._omega * TIME_STEP)
        push_rate = force / (self.mass * self._omega) * (growth - 1.0) / self._omega
        xi = np.full(self.strategies, float(self.situation.dcm))
        for k, t in enumerate(self._grid):
            low, high = self._low[:, k], self._high[:, k]
            if t >= self.duration - 1e-12 and np.any((low <= xi) & (xi <= high)):
                return True
            if force < 0.0:
                p = np.where(xi >= high, high, low)
            elif force > 0.0:
                p = np.where(xi <= low, low, high)
            else:
                p = np.minimum(np.maximum(xi, low), high)
            xi = p + (xi - p) * growth + (push_rate if t < self.duration - 1e-12 else 0.0)
        return False

    def largest(self, sign: float, high: float = 2000.0, tolerance: float = 1.0) -> float:
        """The largest push along sign * axis that some strategy stops (N), by bisection.

        :param sign: +1 or -1
        :param high: the largest force tried (N), returned when it is stopped too
        :param tolerance: N
        """
        if sign not in (1, -1):
            raise InputError(f'sign must be +1 or -1, got {sign!r}')
        if not self.stopped(0.0):
            return 0.0
        if self.stopped(sign * high):
            return high
        low = 0.0
        while high - low > tolerance:
            middle = 0.5 * (low + high)
            if self.stopped(sign * middle):
                low = middle
            else:
                high = middle
        return low


def direction_bound(plane_bounds: Sequence[Sequence[float]], direction: float) -> float:
    """The bound of a push along `direction` (rad from +x towards +y) from the planes' ones.

    :param plane_bounds: ((x towards -, x towards +), (y towards -, y towards +)) (N)
    :return: the largest force whose components each plane stops (N)
    """
    bound = math.inf
    for axis, component in ((AXIS_X, math.cos(direction)), (AXIS_Y, math.sin(direction))):
        if abs(component) > 1e-9:
            bound = min(bound, plane_bounds[axis][component > 0.0] / abs(component))
    return bound


def _step_choices(situation: PlaneSituation, index: int, min_double_support: float) -> list:
    """(dwell, swing extension, placement) of one step; the first in a single support has
    no dwell (its foot is in the air)."""
    dwells = (0.0,) if index == 0 and situation.swinging is not None else tuple(
        min_double_support + dwell for dwell in DWELLS)
    return list(itertools.product(dwells, SWING_EXTENSIONS, PLACEMENTS))


def _support_extents(situation: PlaneSituation, plan, grid: np.ndarray,
                     limits: StepAdjustmentParams) -> Tuple[np.ndarray, np.ndarray]:
    """The support's extent along the axis at each time of the grid, the steps of `plan`."""
    half = situation.half_sole
    feet = list(situation.feet)
    on_ground = [True, True]
    side = situation.next_swing
    t = 0.0
    low, high = np.empty_like(grid), np.empty_like(grid)

    def fill(begin: float, end: float) -> None:
        span = (grid >= begin - 1e-12) & (grid < end - 1e-12)
        down = [feet[s] for s in (LEFT, RIGHT) if on_ground[s]]
        low[span], high[span] = min(down) - half, max(down) + half

    if situation.swinging is not None:
        on_ground[situation.swinging] = False
    for index, (dwell, extension, placement) in enumerate(plan):
        if on_ground[side]:  # a double support, then the lift-off
            fill(t, t + dwell)
            t += dwell
            on_ground[side] = False
            earliest = limits.step_time_min
        else:  # the swinging foot of the single support the push met
            earliest = max(limits.step_time_min - situation.swing_elapsed,
                           limits.min_remaining_time)
        touchdown = t + min(earliest + extension,
                            max(limits.step_time_max - (situation.swing_elapsed
                                                        if index == 0 else 0.0), earliest))
        fill(t, touchdown)
        lower, upper = landing_interval(situation.axis, side, feet[1 - side], limits)
        feet[side] = lower + placement * (upper - lower)
        on_ground[side] = True
        t = touchdown
        side = 1 - side
    fill(t, grid[-1] + 1.0)
    return low, high

