"""Exact zero-order-hold discretisation of linear models driven by piecewise-constant inputs."""
import math

import numpy as np

from biped_mpc.errors import ConfigError


def discretize_exact(a: np.ndarray, b: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Discretise dx/dt = A x + B u with u held constant over each period dt.

    The exact solution is A_d = e^{A dt}, B_d = (integral_0^dt e^{A s} ds) B. The models of this
    package are chains of integrators, so A is nilpotent (A^n = 0) and both series end after n
    terms: A_d = sum_{k<n} (A dt)^k / k!, B_d = sum_{k<n} A^k B dt^{k+1} / (k+1)!. This is exact
    (no truncation) and needs no matrix exponential. A matrix that is not nilpotent falls back
    to the exponential of the augmented matrix [[A, B], [0, 0]] (scipy).

    :param a: continuous state matrix A, shape (n, n)
    :param b: continuous input matrix B, shape (n, m)
    :param dt: sampling period (s), finite and > 0
    :return: (A_d, B_d) with shapes (n, n) and (n, m)
    :raises ConfigError: if the shapes do not match or dt is not a finite positive number
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ConfigError(f'A must be square, got shape {a.shape}')
    if b.ndim != 2 or b.shape[0] != a.shape[0]:
        raise ConfigError(f'B must have {a.shape[0]} rows, got shape {b.shape}')
    if not np.all(np.isfinite(a)) or not np.all(np.isfinite(b)):
        raise ConfigError('A and B must be finite')
    if not isinstance(dt, (int, float)) or not math.isfinite(dt) or dt <= 0.0:
        raise ConfigError(f'dt must be a finite number > 0 (s), got {dt!r}')
    n = a.shape[0]
    if np.any(np.linalg.matrix_power(a, n)):
        return _discretize_by_expm(a, b, dt)
    a_d = np.eye(n)
    b_d = b * dt
    power = np.eye(n)
    for k in range(1, n):
        power = power @ a
        if not np.any(power):
            break
        a_d = a_d + power * dt ** k / math.factorial(k)
        b_d = b_d + power @ b * dt ** (k + 1) / math.factorial(k + 1)
    return a_d, b_d


def _discretize_by_expm(a: np.ndarray, b: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    from scipy.linalg import expm

    n, m = b.shape
    augmented = np.zeros((n + m, n + m))
    augmented[:n, :n] = a
    augmented[:n, n:] = b
    exponential = expm(augmented * dt)
    return exponential[:n, :n], exponential[:n, n:]
