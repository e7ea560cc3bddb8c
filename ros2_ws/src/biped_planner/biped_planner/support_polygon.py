"""Axis-aligned ZMP bounds from the feet: the support polygon of the paper's Fig. constraints.

The foot is a rectangle (length along its heading, width across) scaled by support_scale (0.9 in
the paper) so the ZMP stays away from the edges. The MPC bounds each world axis separately, so a
rotated foot is replaced by the axis-aligned box around the rotated scaled rectangle, and double
support by the box spanning both feet's boxes. Both are supersets of the true polygon (equal for
feet aligned with the world axes and side by side or one behind the other): a bound the MPC can
use, at the price of allowing the ZMP into the corners outside the polygon.
"""
import math
from typing import Tuple

import numpy as np


def scaled_foot_box(x: float, y: float, yaw: float, length: float, width: float,
                    scale: float) -> Tuple[np.ndarray, np.ndarray]:
    """Axis-aligned box around a rotated foot rectangle scaled about its centre.

    :param x: sole centre x (m)
    :param y: sole centre y (m)
    :param yaw: foot heading (rad)
    :param length: foot length along its heading (m)
    :param width: foot width (m)
    :param scale: scale factor of the rectangle, (0, 1]
    :return: lower corner (2,) and upper corner (2,) (m)
    """
    cos_yaw = abs(math.cos(yaw))
    sin_yaw = abs(math.sin(yaw))
    half_x = 0.5 * scale * (length * cos_yaw + width * sin_yaw)
    half_y = 0.5 * scale * (length * sin_yaw + width * cos_yaw)
    return np.array([x - half_x, y - half_y]), np.array([x + half_x, y + half_y])


def double_support_box(first: Tuple[np.ndarray, np.ndarray],
                       second: Tuple[np.ndarray, np.ndarray]) -> Tuple[np.ndarray, np.ndarray]:
    """The axis-aligned box spanning two foot boxes.

    :param first: (lower, upper) corners of one foot's box (m)
    :param second: (lower, upper) corners of the other foot's box (m)
    :return: lower corner (2,) and upper corner (2,) (m)
    """
    return np.minimum(first[0], second[0]), np.maximum(first[1], second[1])
