"""Partial foothold: polygon clipping and attitude rates in closed form, the cut's detection."""
import math

import numpy as np
import pytest

from biped_mpc.balance.partial_foothold import (
    angular_velocity, clip_polygon, foothold_polygon, PartialFoothold, PartialFootholdParams,
    polygon_area, sole_rectangle)
from biped_mpc.errors import ConfigError
from biped_planner.rotations import rotation_x, rotation_y

DT = 0.02
SOLE = sole_rectangle(0.2, 0.1)


def test_clipping_a_sole_keeps_the_closed_form_part():
    heel = clip_polygon(SOLE, (1.0, 0.0, 0.03))  # x <= 0.03
    assert polygon_area(heel) == pytest.approx(0.13 * 0.1)
    assert max(x for x, _ in heel) == pytest.approx(0.03)
    corner = clip_polygon(SOLE, (math.sqrt(0.5), math.sqrt(0.5), 0.0))  # x + y <= 0
    # the line through the centre at -45 deg halves the rectangle
    assert polygon_area(corner) == pytest.approx(0.5 * 0.02)
    assert clip_polygon(SOLE, (1.0, 0.0, -0.2)) == []
    assert polygon_area(clip_polygon(SOLE, (1.0, 0.0, 0.2))) == pytest.approx(0.02)


def test_the_angular_velocity_of_a_known_rotation():
    for axis, rotation in ((0, rotation_x), (1, rotation_y)):
        angle = 0.01
        previous = rotation(0.3)
        omega = angular_velocity(previous, previous @ rotation(angle), DT)
        expected = np.zeros(3)
        expected[axis] = math.sin(angle) / DT  # the vee of the skew part of R(angle)
        np.testing.assert_allclose(omega, expected, atol=1e-12)


def test_a_margin_moves_every_edge_inwards_and_drops_a_cut_it_would_empty():
    vertices, used = foothold_polygon(0.2, 0.1, [(1.0, 0.0, 0.03)], margin=0.01)
    assert used == [(1.0, 0.0, 0.03)]
    xs, ys = [v[0] for v in vertices], [v[1] for v in vertices]
    assert (min(xs), max(xs), min(ys), max(ys)) == pytest.approx((-0.09, 0.02, -0.04, 0.04))
    vertices, used = foothold_polygon(0.2, 0.1, [(1.0, 0.0, -0.085)], margin=0.01)
    assert used == []
    assert polygon_area(vertices) == pytest.approx(0.18 * 0.08)


def pitch_toe_down(foothold, rate, periods, cop=(0.02, 0.0), force=300.0, start=0.0):
    """The sole pitching toe down (about +y) at rate for periods control periods."""
    angle = start
    cuts = []
    for _ in range(periods):
        angle += rate * DT
        cuts.append(foothold.update(DT, True, force, rotation_y(angle), cop))
    return angle, cuts


def test_a_sole_pitching_toe_down_about_its_cop_keeps_the_heel_side():
    foothold = PartialFoothold(PartialFootholdParams(velocity_time_constant=0.0))
    foothold.update(DT, True, 300.0, np.eye(3), (0.02, 0.0))
    _, cuts = pitch_toe_down(foothold, 1.0, 3)
    # the rotation must last detection_time (two periods) before the cut
    assert cuts == [False, True, False]
    assert len(foothold.cuts) == 1
    n_x, n_y, d = foothold.cuts[0]
    assert (n_x, n_y, d) == pytest.approx((1.0, 0.0, 0.02))
    vertices, _ = foothold_polygon(0.2, 0.1, foothold.cuts)
    assert max(v[0] for v in vertices) == pytest.approx(0.02)
    assert min(v[0] for v in vertices) == pytest.approx(-0.1)


def test_a_rolling_sole_keeps_the_side_that_rises():
    foothold = PartialFoothold(PartialFootholdParams(velocity_time_constant=0.0))
    foothold.update(DT, True, 300.0, np.eye(3), (0.0, -0.01))
    angle = 0.0
    for _ in range(3):
        angle -= DT  # roll -1 rad/s about the CoP: the left (y > 0) edge goes down
        foothold.update(DT, True, 300.0, rotation_x(angle), (0.0, -0.01))
    (n_x, n_y, d), = foothold.cuts
    assert (n_x, n_y, d) == pytest.approx((0.0, 1.0, -0.01))  # keeps y <= -0.01


def test_slow_or_brief_rotation_and_light_feet_are_not_cut():
    params = PartialFootholdParams(velocity_time_constant=0.0)
    slow = PartialFoothold(params)
    slow.update(DT, True, 300.0, np.eye(3), (0.02, 0.0))
    pitch_toe_down(slow, 0.45, 10)
    assert slow.cuts == []
    brief = PartialFoothold(params)
    brief.update(DT, True, 300.0, np.eye(3), (0.02, 0.0))
    angle, _ = pitch_toe_down(brief, 2.0, 1)
    brief.update(DT, True, 300.0, rotation_y(angle), (0.02, 0.0))  # stops
    pitch_toe_down(brief, 2.0, 1, start=angle)
    assert brief.cuts == []
    light = PartialFoothold(params)
    light.update(DT, True, 30.0, np.eye(3), (0.02, 0.0))
    pitch_toe_down(light, 1.0, 5, force=30.0)
    assert light.cuts == []
    unmeasured = PartialFoothold(params)
    unmeasured.update(DT, True, 300.0, np.eye(3), None)
    pitch_toe_down(unmeasured, 1.0, 5, cop=(math.nan, 0.0))
    assert unmeasured.cuts == []


def test_a_cut_that_leaves_too_little_of_the_sole_is_not_made():
    foothold = PartialFoothold(PartialFootholdParams(velocity_time_constant=0.0,
                                                     min_area_fraction=0.2))
    foothold.update(DT, True, 300.0, np.eye(3), (-0.07, 0.0))
    pitch_toe_down(foothold, 1.0, 4, cop=(-0.07, 0.0))  # would keep 0.03 of 0.2 m
    assert foothold.cuts == []


def test_one_cut_per_rotation_and_a_new_rotation_cuts_again():
    foothold = PartialFoothold(PartialFootholdParams(velocity_time_constant=0.0))
    foothold.update(DT, True, 300.0, np.eye(3), (0.02, 0.0))
    angle, _ = pitch_toe_down(foothold, 1.0, 8)
    assert len(foothold.cuts) == 1
    foothold.update(DT, True, 300.0, rotation_y(angle), (0.0, 0.0))  # at rest
    pitch_toe_down(foothold, 1.0, 3, cop=(0.0, 0.0), start=angle)
    assert [cut[2] for cut in foothold.cuts] == pytest.approx([0.02, 0.0])


def test_ground_proven_beyond_a_cut_and_a_lifted_foot_restore_the_sole():
    params = PartialFootholdParams(velocity_time_constant=0.0, restore_distance=0.01)
    foothold = PartialFoothold(params)
    foothold.update(DT, True, 300.0, np.eye(3), (0.02, 0.0))
    angle, _ = pitch_toe_down(foothold, 1.0, 3)
    assert len(foothold.cuts) == 1
    foothold.update(DT, True, 300.0, rotation_y(angle), (0.029, 0.0))  # within the distance
    assert len(foothold.cuts) == 1
    foothold.update(DT, True, 300.0, rotation_y(angle), (0.031, 0.0))  # beyond it
    assert foothold.cuts == []
    pitch_toe_down(foothold, 1.0, 3, start=angle)
    assert len(foothold.cuts) == 1
    foothold.update(DT, False, 0.0, rotation_y(angle), None)
    assert foothold.cuts == []


def test_the_angular_velocity_is_low_passed():
    foothold = PartialFoothold(PartialFootholdParams(velocity_time_constant=0.02))
    foothold.update(DT, True, 300.0, np.eye(3), (0.0, 0.0))
    foothold.update(DT, True, 300.0, rotation_y(0.02), (0.0, 0.0))  # 1 rad/s for a period
    assert foothold.velocity[1] == pytest.approx((1.0 - math.exp(-1.0)) * math.sin(0.02) / DT)


@pytest.mark.parametrize('change', [{'rotation_threshold': 0.0}, {'min_area_fraction': 1.5},
                                    {'detection_time': -0.1}, {'restore_distance': math.nan}])
def test_bad_parameters_are_refused(change):
    with pytest.raises(ConfigError):
        PartialFootholdParams(**change)
