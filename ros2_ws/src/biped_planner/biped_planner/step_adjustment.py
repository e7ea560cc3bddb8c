"""Online adjustment of the next step's location and timing from the estimated DCM.

A small QP solved each control cycle, after Khadiv et al. 2020 ("Walking control based on step
timing adaptation", arXiv 1704.01271) with the remaining time of the step as the timing
variable. Pure numpy: no rclpy, no clock; time is an argument.
"""
from dataclasses import dataclass, field
import importlib
import math
from typing import Sequence, Tuple

import numpy as np

from biped_planner.errors import ConfigError, InputError, SolverUnavailableError
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.sides import LEFT, SIDES

STATUS_OPTIMAL = 'optimal'
STATUS_SATURATED = 'saturated'
STATUS_BLOCKED = 'blocked'
STATUS_FAILED = 'failed'
SOLVERS = ('daqp', 'quadprog')

_BOUND_NAMES = (('reach_backward', 'reach_forward'), ('width_min', 'width_max'),
                ('time_min', 'time_max'))
_DAQP_OPTIMAL = (1, 2)
_DAQP_INFINITY = 1e9
_EQUALITY = 5
# A location this far inside a keep-out box counts as in it, and the face half-plane is moved
# out by as much, so that a solution on the face (within the solver's 1e-6 m) counts as out.
_KEEP_OUT_TOLERANCE = 1e-5


@dataclass(frozen=True)
class StepAdjustmentParams:
    """Model, weights and limits of the step adjustment QP (see StepAdjuster)."""

    com_height: float = parameter(0.5, 'LIPM centre-of-mass height z_c (m)', low=0.0,
                                  high=10.0, low_open=True)
    gravity: float = parameter(9.81, 'gravitational acceleration (m/s^2)', low=0.0, high=100.0,
                               low_open=True)
    location_weight: float = parameter(
        1.0, 'cost of the step location deviating from nominal (1/m^2)', low=0.0, high=1e9,
        low_open=True)
    timing_weight: float = parameter(
        5.0, 'cost of tau = exp(omega T_remaining) deviating from nominal (1, tau has no unit)',
        low=0.0, high=1e9, low_open=True)
    offset_weight: float = parameter(
        1000.0, 'cost of the DCM offset at touchdown deviating from nominal (1/m^2)', low=0.0,
        high=1e9, low_open=True)
    step_time_min: float = parameter(0.2, 'shortest step, lift-off to touchdown (s)', low=0.0,
                                     high=10.0, low_open=True)
    step_time_max: float = parameter(0.8, 'longest step, lift-off to touchdown (s)', low=0.0,
                                     high=10.0, low_open=True)
    min_remaining_time: float = parameter(
        0.02, 'shortest time left to touchdown the QP may choose (s)', low=0.0, high=1.0,
        low_open=True)
    reach_forward: float = parameter(
        0.35, 'longest step ahead of the stance ankle, stance yaw frame (m)', low=0.0, high=5.0)
    reach_backward: float = parameter(
        0.25, 'longest step behind the stance ankle, stance yaw frame (m)', low=0.0, high=5.0)
    width_min: float = parameter(
        0.1, 'smallest lateral ankle distance towards the swing side, no crossing (m)',
        low=-1.0, high=5.0)
    width_max: float = parameter(
        0.4, 'largest lateral ankle distance towards the swing side (m)', low=-1.0, high=5.0)
    adjustment_tolerance: float = parameter(
        1e-3, 'change of location (m) or duration (s) beyond which a step counts as adjusted',
        low=0.0, high=1.0)
    solver: str = parameter('daqp', 'QP solver of the adjustment', choices=SOLVERS)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        for low, high in (('step_time_min', 'step_time_max'), ('width_min', 'width_max')):
            if getattr(self, low) > getattr(self, high):
                raise ConfigError(f'{low} ({getattr(self, low)}) must not exceed {high} '
                                  f'({getattr(self, high)})')

    @property
    def omega(self) -> float:
        """Natural frequency sqrt(g / z_c) of the LIPM (1/s)."""
        return math.sqrt(self.gravity / self.com_height)


@dataclass(frozen=True)
class StepAdjustment:
    """The adjusted next step.

    :param location: touchdown position of the swing ankle (2,), world frame (m)
    :param duration: whole step duration, lift-off to touchdown (s)
    :param remaining_time: time left to touchdown from now (s)
    :param dcm_offset: predicted DCM at touchdown minus location (2,), world frame (m)
    :param status: STATUS_OPTIMAL (no limit binds), STATUS_SATURATED (a reach, width, timing
        or keep-out limit binds: the offset absorbs what the step cannot), STATUS_BLOCKED (no
        reachable location outside a keep-out box: the solution inside it is returned),
        STATUS_FAILED (solver failure: the nominal step and duration are returned)
    :param adjusted: location or duration differs from nominal by more than the tolerance
    :param active_limits: names of the binding limits ('reach_forward', 'width_min',
        'time_min', 'keep_out_2', ...)
    """

    location: np.ndarray
    duration: float
    remaining_time: float
    dcm_offset: np.ndarray
    status: str
    adjusted: bool
    active_limits: Tuple[str, ...] = field(default=())


class StepAdjuster:
    """Next step location u, remaining time T and DCM offset b from the DCM, each cycle.

    With the ZMP p held on the stance foot, the LIPM's DCM obeys xi_dot = omega (xi - p), so
    at touchdown, T from now, xi(T) = p + (xi_0 - p) tau with tau = exp(omega T). Taking tau
    instead of T as the variable makes this linear (Khadiv et al.'s key step). The QP, in the
    stance foot's yaw frame R (d = R'(u - s), beta = R' b, s the stance ankle), over
    z = (d, tau, beta):

        min  w_u |d - d_nom|^2 + w_tau (tau - tau_nom)^2 + w_b |beta - beta_nom|^2
        s.t. d + beta - R'(xi_0 - p) tau = R'(p - s)          (xi(T) = u + b)
             -reach_backward <= d_x <= reach_forward
             width_min <= sigma d_y <= width_max               (sigma = +1 if the swing foot is
                                                                the left one, no crossing)
             exp(omega T_lo) <= tau <= exp(omega T_hi),
             T_lo = max(T_min - t, T_rem_min),  T_hi = max(T_max - t, T_lo)

    tau_nom = exp(omega (T_nom - t)) clipped to the bounds. beta_nom is the caller's, or that
    of periodic walking with the nominal step (per axis, derived as Khadiv et al. do for
    their nominal offset): forward d_x / (exp(omega T_nom) - 1), lateral
    -d_y / (1 + exp(omega T_nom)), the lateral step alternating in sign.

    The default weights (1, 5, 1000) make the offset the stiffest: a disturbance moves the
    location first, since a centimetre of it costs far less than a change of tau; the timing
    moves noticeably once a reach or width limit binds. The QP is always feasible when no
    keep-out box is given (the offset is free), so a push beyond the limits yields a
    saturated step, never a failure.

    Keep-out boxes (axis-aligned in the world, already inflated by half the foot size) make
    the feasible set a non-convex complement of a union. The QP is solved without them; if the
    location falls in a box, the half-plane beyond the box's face nearest to that location is
    added and the QP solved again (the next-nearest face if that is infeasible), repeated for
    each box the new location falls in. This picks one convex piece, the one nearest the
    unobstructed optimum, and needs one extra solve only when a box is hit; it may miss a
    cheaper piece behind a farther face, a price paid for a fixed cost per cycle.
    """

    def __init__(self, params: StepAdjustmentParams = StepAdjustmentParams()) -> None:
        """Prepare the fixed parts of the QP.

        :param params: weights and limits
        :raises SolverUnavailableError: if the solver's Python package is not installed
        """
        try:
            self._solver = importlib.import_module(params.solver)
        except ImportError as error:
            raise SolverUnavailableError(f'the step adjuster needs the Python package '
                                         f'{params.solver!r}: pip install {params.solver}'
                                         ) from error
        self.params = params
        self._omega = params.omega
        self._weights = ((params.location_weight,) * 2 + (params.timing_weight,)
                         + (params.offset_weight,) * 2)
        self._hessian = np.diag(self._weights)
        self._multiplier_tolerance = 1e-7 * max(self._weights)

    def solve(self, t_in_step: float, stance_foot: Sequence[float], nominal_next_step,
              nominal_duration: float, dcm, zmp, nominal_offset=None,
              keep_out_boxes: Sequence[Sequence[float]] = ()) -> StepAdjustment:
        """Adjust the next step for the DCM estimated now.

        :param t_in_step: time since the swing foot lifted off (s), >= 0
        :param stance_foot: (x, y, yaw, side) of the stance ankle (m, m, rad, LEFT/RIGHT)
        :param nominal_next_step: planned touchdown of the swing ankle (2,), world (m)
        :param nominal_duration: planned step duration, lift-off to touchdown (s), > 0
        :param dcm: estimated DCM xi_0 (2,), world (m)
        :param zmp: ZMP p held until touchdown (2,), world (m), usually the stance CoP
        :param nominal_offset: planned DCM at touchdown minus nominal_next_step (2,), world
            (m); None for that of periodic walking with the nominal step
        :param keep_out_boxes: (xmin, ymin, xmax, ymax) boxes the location must avoid (m)
        :return: the adjusted step
        :raises InputError: for wrong shapes, non-finite values or an unknown side
        """
        params, omega = self.params, self._omega
        # 2D geometry in Python floats: numpy's per-call overhead would dominate the solve
        x, y, yaw, side = _floats('stance_foot', stance_foot, 4)
        if side not in SIDES:
            raise InputError(f'stance_foot side must be one of {SIDES}, got {side!r}')
        nominal = _floats('nominal_next_step', nominal_next_step, 2)
        xi, p = _floats('dcm', dcm, 2), _floats('zmp', zmp, 2)
        boxes = _boxes(keep_out_boxes)
        if not math.isfinite(t_in_step) or t_in_step < 0.0:
            raise InputError(f't_in_step must be finite and >= 0, got {t_in_step!r}')
        if not math.isfinite(nominal_duration) or nominal_duration <= 0.0:
            raise InputError(f'nominal_duration must be finite and > 0, got '
                             f'{nominal_duration!r}')
        cos, sin = math.cos(yaw), math.sin(yaw)
        d_nominal = _rotate(cos, -sin, nominal[0] - x, nominal[1] - y)
        if nominal_offset is None:
            tau_step = math.exp(omega * nominal_duration)
            beta_nominal = (d_nominal[0] / (tau_step - 1.0), -d_nominal[1] / (1.0 + tau_step))
        else:
            beta_nominal = _rotate(cos, -sin, *_floats('nominal_offset', nominal_offset, 2))
        t_low = max(params.step_time_min - t_in_step, params.min_remaining_time)
        t_high = max(params.step_time_max - t_in_step, t_low)
        t_nominal = min(max(nominal_duration - t_in_step, t_low), t_high)
        sigma = 1.0 if side != LEFT else -1.0
        widths = (sigma * params.width_min, sigma * params.width_max)
        lower = [-params.reach_backward, min(widths), math.exp(omega * t_low)]
        upper = [params.reach_forward, max(widths), math.exp(omega * t_high)]
        target = [*d_nominal, math.exp(omega * t_nominal), *beta_nominal]
        spread = _rotate(cos, -sin, xi[0] - p[0], xi[1] - p[1])
        problem = _Problem([-w * value for w, value in zip(self._weights, target)], lower,
                           upper, [[1.0, 0.0, -spread[0], 1.0, 0.0],
                                   [0.0, 1.0, -spread[1], 0.0, 1.0]],
                           list(_rotate(cos, -sin, p[0] - x, p[1] - y)))

        row_names = []
        z, active = self._qp(problem)
        status = STATUS_OPTIMAL
        for _ in range(len(boxes)):
            if z is None:
                break
            location = _rotate(cos, sin, z[0], z[1])
            location = (location[0] + x, location[1] + y)
            hit = next((i for i, box in enumerate(boxes) if _inside(location, box)), None)
            if hit is None:
                break
            for normal, bound in _faces_nearest_first(location, boxes[hit]):
                problem.rows.append([*_rotate(cos, -sin, *normal), 0.0, 0.0, 0.0])
                problem.row_lower.append(bound - normal[0] * x - normal[1] * y)
                candidate = self._qp(problem)
                if candidate[0] is not None:
                    break
                problem.rows.pop()
                problem.row_lower.pop()
            else:
                status = STATUS_BLOCKED
                break
            row_names.append(f'keep_out_{hit}')
            z, active = candidate
        if z is None:
            return StepAdjustment(np.array(nominal), nominal_duration,
                                  nominal_duration - t_in_step,
                                  np.array(_rotate(cos, sin, *beta_nominal)), STATUS_FAILED,
                                  False)
        # towards the right (sigma = -1) the width bounds of d_y swap ends
        flips = (False, sigma < 0.0, False)
        names = tuple(_BOUND_NAMES[i][int((sign > 0) != flips[i])]
                      for i, sign in enumerate(active[:3]) if sign)
        names += tuple(name for name, sign in zip(row_names, active[3:]) if sign)
        if status == STATUS_OPTIMAL and names:
            status = STATUS_SATURATED
        location = _rotate(cos, sin, z[0], z[1])
        location = (location[0] + x, location[1] + y)
        remaining = math.log(z[2]) / omega
        tolerance = params.adjustment_tolerance
        adjusted = (math.hypot(location[0] - nominal[0], location[1] - nominal[1]) > tolerance
                    or abs(t_in_step + remaining - nominal_duration) > tolerance)
        return StepAdjustment(np.array(location), t_in_step + remaining, remaining,
                              np.array(_rotate(cos, sin, z[3], z[4])), status, adjusted, names)

    def _qp(self, problem: '_Problem'):
        """Solve the QP; (z, signs of the binding bounds then rows) or (None, None)."""
        if self.params.solver == 'daqp':
            return self._daqp(problem)
        return self._quadprog(problem)

    def _daqp(self, problem: '_Problem'):
        n_rows = len(problem.rows)
        fixed = [lo == hi for lo, hi in zip(problem.lower, problem.upper)]
        sense = np.array([_EQUALITY if f else 0 for f in fixed] + [_EQUALITY] * 2
                         + [0] * n_rows, dtype=np.int32)
        z, _, exitflag, info = self._solver.solve(
            self._hessian, np.array(problem.linear), np.array(problem.equality + problem.rows),
            np.array(problem.upper + problem.equality_rhs + [_DAQP_INFINITY] * n_rows),
            np.array(problem.lower + problem.equality_rhs + problem.row_lower), sense)
        if exitflag not in _DAQP_OPTIMAL:
            return None, None
        # daqp's multipliers: positive at an upper bound, negative at a lower one
        tolerance = self._multiplier_tolerance
        multipliers = info['lam'].tolist()
        del multipliers[3:5]
        signs = [0.0 if abs(m) <= tolerance or (i < 3 and fixed[i]) else math.copysign(1.0, m)
                 for i, m in enumerate(multipliers)]
        return z.tolist(), signs

    def _quadprog(self, problem: '_Problem'):
        identity = [[1.0 if i == j else 0.0 for j in range(5)] for i in range(3)]
        negated = [[-value for value in row] for row in identity]
        # quadprog takes C' z >= b with the equalities first
        constraints = np.array(problem.equality + identity + negated + problem.rows).T.copy()
        rhs = np.array(problem.equality_rhs + problem.lower + [-v for v in problem.upper]
                       + problem.row_lower)
        try:
            z, _, _, _, multipliers, _ = self._solver.solve_qp(
                self._hessian, -np.array(problem.linear), constraints, rhs, 2)
        except ValueError:
            return None, None
        binding = [m > self._multiplier_tolerance for m in multipliers.tolist()]
        signs = [0.0 if lo == hi else float(binding[5 + i]) - float(binding[2 + i])
                 for i, (lo, hi) in enumerate(zip(problem.lower, problem.upper))]
        return z.tolist(), signs + [-float(b) for b in binding[8:]]


@dataclass
class _Problem:
    """One QP in lists: linear cost, bounds of (d, tau), equality rows, keep-out rows."""

    linear: list
    lower: list
    upper: list
    equality: list
    equality_rhs: list
    rows: list = field(default_factory=list)
    row_lower: list = field(default_factory=list)


def _rotate(cos: float, sin: float, x: float, y: float) -> Tuple[float, float]:
    """(x, y) rotated by the angle of (cos, sin); (cos, -sin) rotates back."""
    return cos * x - sin * y, sin * x + cos * y


def _floats(name: str, value, size: int) -> tuple:
    try:
        values = tuple(float(element) for element in value)
    except (TypeError, ValueError):
        values = ()
    if len(values) != size or not all(map(math.isfinite, values)):
        raise InputError(f'{name} must be {size} finite numbers, got {value!r}')
    return values


def _boxes(boxes) -> list:
    result = [_floats('keep_out_boxes entry', box, 4) for box in boxes]
    for box in result:
        if box[0] >= box[2] or box[1] >= box[3]:
            raise InputError(f'a keep-out box must be (xmin, ymin, xmax, ymax) with '
                             f'xmin < xmax and ymin < ymax, got {box}')
    return result


def _inside(point: Tuple[float, float], box: tuple) -> bool:
    return (box[0] + _KEEP_OUT_TOLERANCE < point[0] < box[2] - _KEEP_OUT_TOLERANCE
            and box[1] + _KEEP_OUT_TOLERANCE < point[1] < box[3] - _KEEP_OUT_TOLERANCE)


def _faces_nearest_first(point: Tuple[float, float], box: tuple) -> list:
    """Half-planes normal . u >= bound beyond each face of box, nearest to point first."""
    margin = 2.0 * _KEEP_OUT_TOLERANCE
    faces = ((point[0] - box[0], (-1.0, 0.0), -box[0] + margin),
             (box[2] - point[0], (1.0, 0.0), box[2] + margin),
             (point[1] - box[1], (0.0, -1.0), -box[1] + margin),
             (box[3] - point[1], (0.0, 1.0), box[3] + margin))
    return [(normal, bound) for _, normal, bound in sorted(faces, key=lambda face: face[0])]
