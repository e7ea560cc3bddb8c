"""Tests of biped_planner.fall_detector."""
import math

import pytest

from biped_planner.fall_detector import detect_fall, FallDetectorParams


def quat_about_x(angle):
    return (math.sin(angle / 2), 0.0, 0.0, math.cos(angle / 2))


@pytest.mark.parametrize('height, tilt, fallen', [
    (0.8, 0.0, False), (0.3, 0.0, True), (0.8, 0.5, False), (0.8, 0.9, True),
    (0.8, math.pi, True), (math.nan, 0.0, False)])
def test_fall_detector(height, tilt, fallen):
    reason = detect_fall(height, quat_about_x(tilt), FallDetectorParams(0.45, 0.7))
    assert (reason is not None) == fallen
