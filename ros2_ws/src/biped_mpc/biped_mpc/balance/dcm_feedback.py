"""DCM (divergent component of motion) PI feedback on the desired ZMP, and support polygons."""
from dataclasses import dataclass
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import check_period, finite_array
from biped_planner.parameter_fields import parameter, validate_fields

_INSIDE_TOLERANCE = 1e-12


def rectangle_vertices(center, yaw: float, length: float, width: float) -> np.ndarray:
    """Corners of a foot rectangle in the ground plane, counter-clockwise.

    :param center: (2,) sole centre (m)
    :param yaw: heading of the foot (rad)
    :param length: extent along the heading (m)
    :param width: extent across the heading (m)
    :return: (4, 2) vertices (m)
    """
    c, s = math.cos(yaw), math.sin(yaw)
    local = 0.5 * np.array([[length, width], [-length, width], [-length, -width],
                            [length, -width]])
    return np.asarray(center, dtype=float)[:2] + local @ np.array([[c, s], [-s, c]])


def convex_hull(points) -> np.ndarray:
    """Convex hull of points in the plane (Andrew's monotone chain), counter-clockwise.

    :param points: (n, 2) points, n >= 1 (m)
    :return: (k, 2) hull vertices without collinear points; 1 or 2 rows when degenerate
    """
    # Python floats: a hull of a few feet corners is built every cycle, and numpy's per-call
    # overhead (np.unique alone) cost more than the chain
    unique = sorted(set(map(tuple, np.asarray(points, dtype=float).reshape(-1, 2).tolist())))
    if len(unique) <= 2:
        return np.array(unique, dtype=float).reshape(-1, 2)

    def half(sequence):
        chain = []
        for p in sequence:
            while len(chain) >= 2 and _turn(chain[-2], chain[-1], p) <= 0.0:
                chain.pop()
            chain.append(p)
        return chain

    lower, upper = half(unique), half(unique[::-1])
    return np.array(lower[:-1] + upper[:-1], dtype=float)


def _turn(origin, a, b) -> float:
    """Cross product of (a - origin) and (b - origin): > 0 for a left turn."""
    return (a[0] - origin[0]) * (b[1] - origin[1]) - (a[1] - origin[1]) * (b[0] - origin[0])


def _closest_on_segment(point: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    edge = b - a
    squared = float(edge @ edge)
    if squared == 0.0:
        return a.copy()
    return a + min(max(float((point - a) @ edge) / squared, 0.0), 1.0) * edge


def project_into_polygon(point, vertices) -> Tuple[np.ndarray, bool]:
    """Nearest point of a convex polygon (its interior included) to a point.

    :param point: (2,) the point (m)
    :param vertices: (n, 2) vertices in any order, n >= 1; their convex hull is used
    :return: the nearest point (2,) and whether the point was already inside
    :raises InputError: if an array is not finite or has the wrong shape
    """
    point = finite_array('point', point, (2,))
    vertices = np.asarray(vertices, dtype=float)
    if vertices.ndim != 2 or vertices.shape[1] != 2 or len(vertices) == 0:
        raise InputError(f'vertices must have shape (n, 2) with n >= 1, got {vertices.shape}')
    hull = convex_hull(finite_array('vertices', vertices, vertices.shape))
    corners = hull.tolist()
    inside_point = point.tolist()
    if len(corners) >= 3 and all(
            _turn(a, b, inside_point) >= -_INSIDE_TOLERANCE
            for a, b in zip(corners, corners[1:] + corners[:1])):
        return point.copy(), True
    edges = list(zip(hull, np.roll(hull, -1, axis=0)))
    candidates = [_closest_on_segment(point, a, b) for a, b in edges]
    best = min(candidates, key=lambda q: float((q - point) @ (q - point)))
    return best, bool(np.allclose(best, point, atol=1e-12, rtol=0.0))


@dataclass(frozen=True)
class DcmFeedbackParams:
    """Gains and limits of the DCM feedback (see DcmFeedback)."""

    com_height: float = parameter(0.497, 'LIPM centre-of-mass height z_c (m)', low=0.05,
                                  high=5.0)
    gravity: float = parameter(9.81, 'gravitational acceleration (m/s^2)', low=0.1, high=100.0)
    proportional_gain: float = parameter(3.0, 'DCM proportional gain k_p (1/s)', low=0.0,
                                         high=50.0)
    integral_gain: float = parameter(2.0, 'DCM integral gain k_i (1/s^2)', low=0.0, high=100.0)
    integral_time_constant: float = parameter(
        5.0, 'leak time constant T_i of the DCM error integral (s)', low=0.01, high=1000.0)
    integral_limit: float = parameter(0.05, 'bound on each axis of the DCM error integral (m s)',
                                      low=0.0, high=10.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)

    @property
    def omega(self) -> float:
        """LIPM natural frequency sqrt(g / z_c) (1/s)."""
        return math.sqrt(self.gravity / self.com_height)


@dataclass(frozen=True)
class DcmFeedbackResult:
    """Output of one DcmFeedback update.

    :param zmp: (2,) desired ZMP, inside the support polygon when one was given (m)
    :param unclamped_zmp: (2,) desired ZMP before the clamp (m)
    :param dcm_error: (2,) xi_ref - xi (m)
    :param integral: (2,) the leaky integral of the DCM error after the update (m s)
    :param clamped: True when the clamp moved the ZMP
    """

    zmp: np.ndarray
    unclamped_zmp: np.ndarray
    dcm_error: np.ndarray
    integral: np.ndarray
    clamped: bool


class DcmFeedback:
    """PI feedback of the DCM around its reference, output as a desired ZMP.

    LIPM with natural frequency omega = sqrt(g / z_c): the DCM xi = c + c_dot / omega obeys
    xi_dot = omega (xi - p), p the ZMP (Englsberger 2015, sec. II). With the DCM error
    e = xi_ref - xi and a reference consistent with the model (xi_ref_dot = omega (xi_ref -
    p_ref)), e_dot = omega (e + p - p_ref). The desired ZMP

        p_d = p_ref - (1 + k_p / omega) e - (k_i / omega) I,      I_dot = e - I / T_i,

    gives e_dot = -k_p e - k_i I: the error decays, with an integral that removes constant
    disturbances (a ZMP offset, a model error). Sign convention: the error is reference minus
    measurement (mc_rtc's lipm_stabilizer: dcmError = dcmTarget - measuredDCM, same formula);
    a DCM ahead of its reference (e < 0) moves the ZMP ahead of p_ref, which pulls
    the DCM back. The integral leaks with T_i (lipm_walking_controller's averaged error) and is
    clamped to +-integral_limit per axis; anti-windup: it does not integrate while the output is
    clamped to the support polygon or the robot is in the air. With the ZMP held over the
    control period dt (exact discretisation), k_i = 0 gives e_{k+1} = lambda e_k with
    lambda = exp(omega dt) - (exp(omega dt) - 1)(1 + k_p / omega).
    """

    def __init__(self, params: DcmFeedbackParams = DcmFeedbackParams()) -> None:
        """Create the feedback with a zero integral.

        :param params: gains and limits
        """
        self.params = params
        self._integral = np.zeros(2)

    @property
    def integral(self) -> np.ndarray:
        """(2,) the DCM error integral (m s), a copy."""
        return self._integral.copy()

    def reset(self, integral: Optional[Sequence[float]] = None) -> None:
        """Zero the integral (or set it).

        :param integral: (2,) new integral (m s), clipped to the limit; None for zero
        :raises InputError: if it is not finite or has the wrong shape
        """
        value = np.zeros(2) if integral is None else finite_array('integral', integral, (2,))
        limit = self.params.integral_limit
        self._integral = np.clip(value, -limit, limit)

    def update(self, dt: float, dcm_reference, dcm, zmp_reference,
               polygon: Optional[np.ndarray] = None,
               in_the_air: bool = False) -> DcmFeedbackResult:
        """One control cycle: the desired ZMP from the DCM error.

        :param dt: control period (s), > 0
        :param dcm_reference: (2,) xi_ref (m)
        :param dcm: (2,) estimated xi = c + c_dot / omega (m)
        :param zmp_reference: (2,) p_ref (m)
        :param polygon: (n, 2) support polygon vertices (m) to clamp to; None: no clamp
        :param in_the_air: True when no foot touches the ground: the integral is held
        :return: the desired ZMP and the error terms
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        error = (finite_array('dcm_reference', dcm_reference, (2,))
                 - finite_array('dcm', dcm, (2,)))
        zmp_reference = finite_array('zmp_reference', zmp_reference, (2,))
        p = self.params
        omega = p.omega
        unclamped = (zmp_reference - (1.0 + p.proportional_gain / omega) * error
                     - (p.integral_gain / omega) * self._integral)
        zmp, clamped = unclamped, False
        if polygon is not None:
            zmp, inside = project_into_polygon(unclamped, polygon)
            clamped = not inside
        if not (clamped or in_the_air):
            decay = math.exp(-dt / p.integral_time_constant)
            integral = decay * self._integral + p.integral_time_constant * (1.0 - decay) * error
            self._integral = np.clip(integral, -p.integral_limit, p.integral_limit)
        return DcmFeedbackResult(zmp, unclamped, error, self._integral.copy(), clamped)
