"""Hip (COM) trajectory of the linear inverted pendulum for a piecewise-linear ZMP.

The hip follows the LIPM, x_ddot = omega^2 (x - p), omega = sqrt(g / z_h), in x and y. Within a
segment [T_j, T_j+1] where the ZMP p is linear (constant in single support, a ramp in double
support, eq. zmpEquation), e = x - p satisfies e_ddot = omega^2 e, so the hip is the paper's
analytic solution (eq. com_traj_x0xf) between the boundary positions p_h0 = p_j + e_j and
p_hf = p_j+1 + e_j+1::

    x(t) = p(t) + [e_j sinh(omega (T_j+1 - t)) + e_j+1 sinh(omega (t - T_j))]
                  / sinh(omega (T_j+1 - T_j))

(with a constant ZMP this is exactly eq. com_traj_x0xf). It is evaluated in the equivalent form
x = p + A_j exp(-omega (t - T_j)) + B_j exp(-omega (T_j+1 - t)), whose exponents are never
positive.

Choice of the boundary conditions e_j: the unique bounded solution. The divergent component of
motion xi = x + x_dot / omega obeys xi_dot = omega (xi - p); integrating it backwards from the
end, where the robot stands (xi = p_end), gives the xi that keeps the pendulum from falling, and
the hip then follows x_dot = omega (xi - x) forwards from its start. The resulting hip is C2:
position, velocity and (because the ZMP is continuous) acceleration are continuous at every
boundary. Two extra conditions make the motion start and end at rest (or start from a given
moving state when a plan is extended): xi(t_start) equals the given start DCM and
x(t_end) = p_end. They are met exactly by shifting the ZMP at two "free" knots inside double
support phases (one near the start, one in the final settle); by linearity this is a 2 x 2
solve per plane.
"""
from typing import Optional, Tuple

import numpy as np

from biped_planner.errors import ConfigError
from biped_planner.input_checks import check_number


def _backward_dcm(times: np.ndarray, zmp: np.ndarray, omega: float) -> np.ndarray:
    """DCM at the knots for a piecewise-linear ZMP, with xi = p at the last knot.

    :param times: knot times (M,), strictly increasing (s)
    :param zmp: ZMP at the knots (M, C), any number C of independent columns (m)
    :param omega: LIPM natural frequency (1/s)
    :return: xi at the knots (M, C)
    """
    span = np.diff(times)
    decay = np.exp(-omega * span)[:, None]
    offset = np.diff(zmp, axis=0) / (omega * span[:, None])
    constant = zmp[:-1] + offset - (zmp[1:] + offset) * decay
    xi = np.empty_like(zmp)
    xi[-1] = zmp[-1]
    for j in range(len(times) - 2, -1, -1):
        xi[j] = constant[j] + decay[j] * xi[j + 1]
    return xi


def _forward_offsets(times: np.ndarray, zmp: np.ndarray, xi: np.ndarray, omega: float,
                     e_start: np.ndarray) -> np.ndarray:
    """Hip offsets e = x - p at the knots, integrating x_dot = omega (xi - x) forwards.

    :return: e at the knots (M, C)
    """
    span = np.diff(times)
    decay = np.exp(-omega * span)[:, None]
    offset = np.diff(zmp, axis=0) / (omega * span[:, None])
    unstable = xi[1:] - zmp[1:] - offset
    gain = 0.5 * (1.0 - decay * decay) * unstable
    e = np.empty_like(zmp)
    e[0] = e_start
    for j in range(len(times) - 1):
        e[j + 1] = e[j] * decay[j] + gain[j]
    return e


class PiecewiseLipm:
    """LIPM hip trajectory for a continuous piecewise-linear ZMP (see the module docstring).

    Built from knots (T_j, p_j) and the start state; after the last knot the hip stands at the
    final ZMP, before the first knot at its start position.
    """

    def __init__(self, times: np.ndarray, zmp: np.ndarray, omega: float,
                 hip_start: np.ndarray, dcm_start: Optional[np.ndarray] = None,
                 free_knots: Optional[Tuple[int, int]] = None) -> None:
        """Solve the boundary conditions of every segment.

        :param times: knot times (M,), M >= 2, strictly increasing (s)
        :param zmp: ZMP at the knots (M, 2) (m)
        :param omega: LIPM natural frequency sqrt(g / z_h) (1/s), > 0
        :param hip_start: hip position at times[0] (2,) (m)
        :param dcm_start: DCM x + x_dot / omega at times[0] (2,) (m); with free_knots it is
            matched exactly, without it is the result of the backward pass
        :param free_knots: indices (i_start, i_end) of two interior knots whose ZMP is shifted so
            that xi(times[0]) = dcm_start and the hip reaches zmp[-1] at times[-1] at rest
        :raises ConfigError: if the knots are malformed or the free knots are not interior
        """
        times = np.asarray(times, dtype=float)
        zmp = np.array(zmp, dtype=float)
        if times.ndim != 1 or times.size < 2 or zmp.shape != (times.size, 2):
            raise ConfigError(f'need M >= 2 knot times (M,) and ZMP (M, 2), got {times.shape} '
                              f'and {zmp.shape}')
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(zmp))):
            raise ConfigError('knot times and ZMP must be finite')
        if np.any(np.diff(times) <= 0.0):
            raise ConfigError('knot times must be strictly increasing')
        check_number('omega', omega, low=0.0, low_open=True, unit=' 1/s')
        hip_start = np.asarray(hip_start, dtype=float).reshape(2)
        self.omega = float(omega)
        self.correction = np.zeros(2)
        if free_knots is None:
            xi = _backward_dcm(times, zmp, omega)
        else:
            first, last = free_knots
            if not (0 < first < times.size - 1 and 0 < last < times.size - 1 and first != last):
                raise ConfigError(f'free knots must be two different interior knots of 0..'
                                  f'{times.size - 1}, got {free_knots}')
            if dcm_start is None:
                raise ConfigError('dcm_start is needed with free_knots')
            dcm_start = np.asarray(dcm_start, dtype=float).reshape(2)
            columns = np.zeros((times.size, 4))
            columns[:, :2] = zmp
            columns[first, 2] = 1.0
            columns[last, 3] = 1.0
            xi_all = _backward_dcm(times, columns, omega)
            e_start = np.array([hip_start[0] - zmp[0, 0], hip_start[1] - zmp[0, 1], 0.0, 0.0])
            e_all = _forward_offsets(times, columns, xi_all, omega, e_start)
            # Unit responses are the same in both planes: one 2 x 2 matrix, two right-hand sides.
            response = np.array([[xi_all[0, 2], xi_all[0, 3]], [e_all[-1, 2], e_all[-1, 3]]])
            rhs = np.vstack((dcm_start - xi_all[0, :2], -e_all[-1, :2]))
            shift = np.linalg.solve(response, rhs)
            zmp[first] += shift[0]
            zmp[last] += shift[1]
            self.correction = np.abs(shift).max(axis=1)
            xi = xi_all[:, :2] + np.outer(xi_all[:, 2], shift[0]) + np.outer(xi_all[:, 3],
                                                                             shift[1])
        e = _forward_offsets(times, zmp, xi, omega, hip_start - zmp[0])
        span = np.diff(times)
        decay = np.exp(-omega * span)[:, None]
        slope = np.diff(zmp, axis=0) / span[:, None]
        half_unstable = 0.5 * (xi[1:] - zmp[1:] - slope / omega)
        self.times = times
        self.zmp = zmp
        self.span = span
        self.slope = slope
        self.dcm = xi
        self.offsets = e
        self.coef_stable = e[:-1] - half_unstable * decay
        self.coef_unstable = half_unstable

    @classmethod
    def concatenate(cls, head: 'PiecewiseLipm', cut_knot: int,
                    tail: 'PiecewiseLipm') -> 'PiecewiseLipm':
        """Join the knots of head before cut_knot with tail, which starts at head's knot cut_knot.

        :param head: the earlier trajectory
        :param cut_knot: index of the knot of head where tail starts
        :param tail: the later trajectory; tail.times[0] must equal head.times[cut_knot]
        :return: the joined trajectory (head's segments before the cut, then tail's)
        :raises ConfigError: if the start of tail is not the cut knot of head
        """
        if not 0 <= cut_knot < head.times.size or tail.times[0] != head.times[cut_knot]:
            raise ConfigError('the tail must start at a knot of the head')
        joined = cls.__new__(cls)
        joined.omega = head.omega
        joined.correction = tail.correction
        for name in ('times', 'zmp', 'dcm', 'offsets'):
            setattr(joined, name, np.concatenate((getattr(head, name)[:cut_knot],
                                                  getattr(tail, name))))
        for name in ('span', 'slope', 'coef_stable', 'coef_unstable'):
            setattr(joined, name, np.concatenate((getattr(head, name)[:cut_knot],
                                                  getattr(tail, name))))
        return joined

    def locate(self, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """Segment index and time into the segment, clamped to the knot range.

        :param t: times (N,) (s)
        :return: segment indices (N,) and times since the segment start (N,) (s)
        """
        j = np.searchsorted(self.times, t, side='right') - 1
        np.clip(j, 0, self.span.size - 1, out=j)
        tau = np.minimum(np.maximum(t - self.times[j], 0.0), self.span[j])
        return j, tau

    def evaluate(self, t: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """ZMP and hip positions at the given times.

        :param t: times (N,) (s)
        :return: ZMP (N, 2) and hip (N, 2) (m)
        """
        j, tau = self.locate(t)
        zmp = self.zmp[j] + self.slope[j] * tau[:, None]
        stable = np.exp(-self.omega * tau)[:, None]
        unstable = np.exp(-self.omega * (self.span[j] - tau))[:, None]
        return zmp, zmp + self.coef_stable[j] * stable + self.coef_unstable[j] * unstable

    def hip_velocity(self, t: np.ndarray) -> np.ndarray:
        """Hip velocity at the given times (zero outside the knot range).

        :param t: times (N,) (s)
        :return: hip velocity (N, 2) (m/s)
        """
        t = np.asarray(t, dtype=float)
        j, tau = self.locate(t)
        stable = np.exp(-self.omega * tau)[:, None]
        unstable = np.exp(-self.omega * (self.span[j] - tau))[:, None]
        velocity = self.slope[j] + self.omega * (self.coef_unstable[j] * unstable
                                                 - self.coef_stable[j] * stable)
        outside = (t < self.times[0]) | (t > self.times[-1])
        velocity[outside] = 0.0
        return velocity

    def state_at(self, t: float) -> Tuple[np.ndarray, np.ndarray]:
        """Hip position and DCM at one time.

        :param t: time (s)
        :return: hip (2,) (m) and DCM x + x_dot / omega (2,) (m)
        """
        times = np.array([t], dtype=float)
        hip = self.evaluate(times)[1][0]
        return hip, hip + self.hip_velocity(times)[0] / self.omega
