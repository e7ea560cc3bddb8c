"""Swing foot trajectory: Bezier curves for a smooth lift-off and touch-down.

With s = (t - t_ss_start) / T_ss in [0, 1], the swing foot moves along quintic Bezier curves:

* horizontal position and yaw: control points (P0, P0, P0, P1, P1, P1), i.e.
  P(s) = P0 + (P1 - P0) h(s), h(s) = 10 s^3 - 15 s^4 + 6 s^5;
* height: control points (0, 0, 1.6 H, 1.6 H, 0, 0), i.e. z(s) = 16 H s^2 (1 - s)^2, whose
  maximum is the swing height H at s = 1/2.

Velocity is zero at lift-off and touch-down in all directions (and the horizontal acceleration
too), so the foot leaves and reaches the ground without impact velocity.
"""
import numpy as np

HEIGHT_CONTROL_SCALE = 1.6


def bernstein_curve(control_points: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Evaluate a Bezier curve of any degree (de Casteljau's algorithm).

    :param control_points: control points (K + 1, D) of a degree-K curve
    :param s: curve parameters (N,) in [0, 1]
    :return: points (N, D)
    """
    points = np.broadcast_to(np.asarray(control_points, dtype=float)[None],
                             (np.size(s),) + np.shape(control_points)).copy()
    s = np.asarray(s, dtype=float).reshape(-1, 1, 1)
    for count in range(points.shape[1] - 1, 0, -1):
        points = (1.0 - s) * points[:, :count] + s * points[:, 1:count + 1]
    return points[:, 0]


def swing_progress(s: np.ndarray) -> np.ndarray:
    """Fraction of the horizontal move done, h(s) = 10 s^3 - 15 s^4 + 6 s^5.

    :param s: phase of the swing (N,), clipped to [0, 1] by the caller
    :return: h(s) (N,), from 0 to 1
    """
    return s * s * s * (10.0 + s * (6.0 * s - 15.0))


def swing_lift(s: np.ndarray) -> np.ndarray:
    """Height profile 16 s^2 (1 - s)^2 of a unit swing height.

    :param s: phase of the swing (N,), clipped to [0, 1] by the caller
    :return: height / swing height (N,), 0 at both ends and 1 at s = 1/2
    """
    r = s * (1.0 - s)
    return 16.0 * r * r
