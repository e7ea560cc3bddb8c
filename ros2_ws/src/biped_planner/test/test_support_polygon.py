"""Tests of biped_planner.support_polygon."""
import math

import numpy as np
import pytest

from biped_planner.support_polygon import double_support_box, scaled_foot_box


def _corners(x, y, yaw, length, width, scale):
    local = 0.5 * scale * np.array([[length, width], [length, -width], [-length, width],
                                    [-length, -width]])
    rotation = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    return local @ rotation.T + [x, y]


@pytest.mark.parametrize('yaw', [0.0, 0.3, math.pi / 4, math.pi / 2, 2.5, -1.0, 7.0])
def test_box_is_the_bounding_box_of_the_rotated_scaled_foot(yaw):
    lower, upper = scaled_foot_box(0.4, -0.2, yaw, 0.16, 0.08, 0.9)
    corners = _corners(0.4, -0.2, yaw, 0.16, 0.08, 0.9)
    np.testing.assert_allclose(lower, corners.min(axis=0), atol=1e-15)
    np.testing.assert_allclose(upper, corners.max(axis=0), atol=1e-15)


def test_aligned_foot_is_scaled_about_its_centre():
    lower, upper = scaled_foot_box(1.0, 2.0, 0.0, 0.2, 0.1, 0.9)
    np.testing.assert_allclose(lower, [0.91, 1.955])
    np.testing.assert_allclose(upper, [1.09, 2.045])


def test_double_support_box_spans_both_feet():
    left = scaled_foot_box(0.1, 0.1, 0.0, 0.2, 0.1, 0.9)
    right = scaled_foot_box(0.0, -0.1, 0.0, 0.2, 0.1, 0.9)
    lower, upper = double_support_box(left, right)
    np.testing.assert_allclose(lower, [-0.09, -0.145])
    np.testing.assert_allclose(upper, [0.19, 0.145])
