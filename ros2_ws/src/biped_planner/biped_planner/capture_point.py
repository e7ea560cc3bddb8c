"""Closed forms of the linear inverted pendulum (LIPM) around the capture point.

The LIPM of constant height z_c has the natural frequency omega = sqrt(g / z_c). Its divergent
component of motion (DCM, Englsberger et al. 2015, eq. 2; the instantaneous capture point of
Pratt et al. 2006 on flat ground) is

    xi = c + c_dot / omega,          xi_dot = omega (xi - p),          c_dot = -omega (c - xi),

with c the centre of mass (COM) and p the zero moment point (ZMP). Under a fixed ZMP the DCM
diverges from it, xi(t) = p + (xi_0 - p) exp(omega t), while the COM converges to the DCM: a
step placed at the DCM (the ZMP jumping onto it) stops the pendulum over the new foot.

Every function is pure numpy, works per plane on arrays of any shape (x, y, or (x, y) pairs),
and is used by the step adjuster, its tests and diagnostics.
"""
import math
from typing import Tuple

import numpy as np

from biped_planner.errors import InputError


def natural_frequency(com_height: float, gravity: float = 9.81) -> float:
    """Natural frequency omega = sqrt(g / z_c) of the LIPM (1/s).

    :param com_height: constant COM height above the ground z_c (m), > 0
    :param gravity: gravitational acceleration g (m/s^2), > 0
    :return: omega (1/s)
    :raises InputError: if a value is not finite and positive
    """
    for name, value in (('com_height', com_height), ('gravity', gravity)):
        if not math.isfinite(value) or value <= 0.0:
            raise InputError(f'{name} must be a finite positive number, got {value!r}')
    return math.sqrt(gravity / com_height)


def dcm(com, com_velocity, omega: float) -> np.ndarray:
    """DCM of a COM state, xi = c + c_dot / omega (m).

    :param com: COM position c, any shape (m)
    :param com_velocity: COM velocity c_dot, the shape of com (m/s)
    :param omega: natural frequency (1/s), > 0
    :return: xi, the shape of com (m)
    """
    return np.asarray(com, dtype=float) + np.asarray(com_velocity, dtype=float) / omega


def instantaneous_capture_point(com, com_velocity, omega: float) -> np.ndarray:
    """Instantaneous capture point: where to put the ZMP now to come to rest over it (m).

    On flat ground with a constant COM height it is the horizontal DCM.

    :param com: horizontal COM position (2,) (m); a 3D position's z is ignored
    :param com_velocity: horizontal COM velocity (2,) (m/s); a 3D velocity's z is ignored
    :param omega: natural frequency (1/s), > 0
    :return: the capture point (2,) (m)
    """
    return dcm(np.asarray(com, dtype=float)[:2], np.asarray(com_velocity, dtype=float)[:2],
               omega)


def dcm_at(dcm_now, zmp, omega: float, duration: float) -> np.ndarray:
    """DCM after duration under a fixed ZMP: xi(T) = p + (xi_0 - p) exp(omega T) (m).

    :param dcm_now: DCM now xi_0, any shape (m)
    :param zmp: the fixed ZMP p, the shape of dcm_now (m)
    :param omega: natural frequency (1/s)
    :param duration: T (s), may be negative (the DCM T seconds ago)
    :return: xi(T), the shape of dcm_now (m)
    """
    zmp = np.asarray(zmp, dtype=float)
    return zmp + (np.asarray(dcm_now, dtype=float) - zmp) * math.exp(omega * duration)


def lipm_state_at(com, com_velocity, zmp, omega: float,
                  duration: float) -> Tuple[np.ndarray, np.ndarray]:
    """Exact LIPM state after duration under a fixed ZMP (per plane, cosh/sinh form).

    c(t) - p = (c_0 - p) cosh(omega t) + c_dot_0 / omega sinh(omega t).

    :param com: COM position c_0, any shape (m)
    :param com_velocity: COM velocity c_dot_0, the shape of com (m/s)
    :param zmp: the fixed ZMP p, the shape of com (m)
    :param omega: natural frequency (1/s)
    :param duration: t (s)
    :return: (c(t), c_dot(t)) (m, m/s)
    """
    offset = np.asarray(com, dtype=float) - np.asarray(zmp, dtype=float)
    velocity = np.asarray(com_velocity, dtype=float)
    cosh, sinh = math.cosh(omega * duration), math.sinh(omega * duration)
    position = np.asarray(zmp, dtype=float) + offset * cosh + velocity / omega * sinh
    return position, offset * omega * sinh + velocity * cosh


def n_step_capture_bound(steps: int, max_step_length: float, min_step_duration: float,
                         omega: float, foot_radius: float = 0.0) -> float:
    """Largest DCM-to-ankle distance from which the LIPM can stop in `steps` steps (m).

    After Koolen et al. 2012 (capturability-based analysis, the LIPM with a finite foot),
    derived here per plane in the worst direction: with the CoP held at the sole's edge r
    towards the DCM, one step of the shortest duration dt reaching
    at most l_max maps a distance d to r + (d - r) exp(omega dt) - l_max, so
    d_N = r + (d_{N-1} - r + l_max) exp(-omega dt), d_0 = r, that is
    d_N = r + l_max sum_{i=1..N} exp(-i omega dt). steps < 0 means infinitely many steps.

    :param steps: number of steps N (0: stop on the stance foot alone; < 0: N -> infinity)
    :param max_step_length: l_max, the longest step from ankle to ankle (m), >= 0
    :param min_step_duration: dt, the shortest step (s), > 0
    :param omega: natural frequency (1/s), > 0
    :param foot_radius: r, the distance the CoP can move from the ankle (m), >= 0
    :return: d_N (m)
    :raises InputError: for negative lengths or non-positive durations
    """
    if max_step_length < 0.0 or foot_radius < 0.0:
        raise InputError(f'max_step_length and foot_radius must be >= 0, got '
                         f'{max_step_length!r} and {foot_radius!r}')
    if min_step_duration <= 0.0 or omega <= 0.0:
        raise InputError(f'min_step_duration and omega must be > 0, got '
                         f'{min_step_duration!r} and {omega!r}')
    decay = math.exp(-omega * min_step_duration)
    if steps < 0:
        return foot_radius + max_step_length * decay / (1.0 - decay)
    return foot_radius + max_step_length * decay * (1.0 - decay ** steps) / (1.0 - decay)
