"""References of a robot standing still on two feet, for any horizon."""
import numpy as np

from biped_planner.footsteps import Footstep
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_window import ReferenceWindow
from biped_planner.sides import SUPPORT_DOUBLE
from biped_planner.support_polygon import double_support_box, scaled_foot_box


def standing_window(left: Footstep, right: Footstep, params: ReferenceParams, t0: float, n: int,
                    dt: float) -> ReferenceWindow:
    """ZMP and hip midway between the feet, feet on the ground, double-support bounds.

    :param left: left sole pose
    :param right: right sole pose
    :param params: foot size and support scale
    :param t0: time of the first sample (s)
    :param n: number of samples, >= 1
    :param dt: sample period (s), > 0
    :return: the window of n identical standing samples
    """
    def repeat(row) -> np.ndarray:
        return np.tile(np.asarray(row, dtype=float), (n, 1))

    middle = 0.5 * np.array([left.x + right.x, left.y + right.y])
    lower, upper = double_support_box(
        scaled_foot_box(left.x, left.y, left.yaw, params.foot_length, params.foot_width,
                        params.support_scale),
        scaled_foot_box(right.x, right.y, right.yaw, params.foot_length, params.foot_width,
                        params.support_scale))
    left_xy, right_xy = np.array([left.x, left.y]), np.array([right.x, right.y])
    return ReferenceWindow(
        t=t0 + dt * np.arange(n), zmp=repeat(middle), hip=repeat(middle),
        left_foot=repeat([left.x, left.y, 0.0]), right_foot=repeat([right.x, right.y, 0.0]),
        left_yaw=np.full(n, float(left.yaw)), right_yaw=np.full(n, float(right.yaw)),
        left_mass=repeat(0.5 * (left_xy + middle)), right_mass=repeat(0.5 * (right_xy + middle)),
        zmp_min=repeat(lower), zmp_max=repeat(upper),
        left_landing_min=np.full((n, 2), -np.inf), left_landing_max=np.full((n, 2), np.inf),
        right_landing_min=np.full((n, 2), -np.inf), right_landing_max=np.full((n, 2), np.inf),
        support=np.full(n, SUPPORT_DOUBLE, dtype=np.uint8), step_index=np.zeros(n, dtype=np.int64))
