"""Tests of the safe stance: finish the step along the last window, then stand between the feet."""
import numpy as np
import pytest

from biped_mpc.errors import ConfigError
from biped_mpc.safe_stance import reference_misfit, SafeStance, SafeStanceParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.sides import SUPPORT_DOUBLE
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference

DT = 0.02
PARAMS = SafeStanceParams()


@pytest.fixture(scope='module')
def walk():
    """10 steps of 0.1 m, 0.4 s single and 0.2 s double support, from t = 0."""
    return WalkingReference(straight_footsteps(10, 0.1, 0.14), StepTiming(0.4, 0.2),
                            ReferenceParams(com_height=0.497, foot_length=0.2, foot_width=0.1))


def mid_single_support(walk) -> float:
    return walk.t_start + 1.0 + 3 * 0.6 + 0.2  # the single support of step 3, half done


def test_it_finishes_the_step_along_the_last_window_then_stands_on_the_landed_feet(walk):
    t_last = mid_single_support(walk) - 0.3   # the last window, 0.3 s before the switch
    last = walk.sample(t_last, 90, DT)
    t = t_last + 0.3
    assert last.support[15] != SUPPORT_DOUBLE   # a foot is in the air now
    stance = SafeStance.finishing_step(PARAMS, last, t)
    assert stance.finishing
    # both feet are down at the first double support of the last window after now
    down = 15 + int(np.flatnonzero(last.support[15:] == SUPPORT_DOUBLE)[0])
    assert stance.t_down == pytest.approx(last.t[down])
    window = stance.window(t, 81, DT)
    before = window.t < stance.t_down - 1e-9
    index = np.round((window.t[before] - last.t[0]) / DT).astype(int)
    for name in ('zmp', 'hip', 'left_foot', 'right_foot', 'support', 'zmp_min', 'zmp_max'):
        np.testing.assert_array_equal(getattr(window, name)[before],
                                      getattr(last, name)[index], err_msg=name)
    after = ~before
    assert np.all(window.support[after] == SUPPORT_DOUBLE)
    np.testing.assert_allclose(window.left_foot[after], np.tile(last.left_foot[down],
                                                                (after.sum(), 1)))
    np.testing.assert_allclose(window.right_foot[after], np.tile(last.right_foot[down],
                                                                 (after.sum(), 1)))
    # ZMP and hip end over the middle of the feet, settle_time after the feet are down
    middle = 0.5 * (last.left_foot[down, :2] + last.right_foot[down, :2])
    late = stance.window(stance.t_down + PARAMS.settle_time, 5, DT)
    np.testing.assert_allclose(late.zmp, np.tile(middle, (5, 1)), atol=1e-12)
    np.testing.assert_allclose(late.hip, np.tile(middle, (5, 1)), atol=1e-12)
    # and the ZMP reference stays inside its bounds on the way
    assert np.all(window.zmp >= window.zmp_min - 1e-9)
    assert np.all(window.zmp <= window.zmp_max + 1e-9)


def test_in_double_support_it_stands_at_once(walk):
    t = walk.t_start + 1.0 + 2 * 0.6 + 0.45  # double support after step 2
    last = walk.sample(t, 90, DT)
    assert last.support[0] == SUPPORT_DOUBLE
    stance = SafeStance.finishing_step(PARAMS, last, t)
    assert not stance.finishing and stance.t_down == pytest.approx(t)
    window = stance.window(t + 1.0, 10, DT)
    np.testing.assert_allclose(window.left_foot[0], last.left_foot[0])


def test_long_after_the_window_it_still_stands(walk):
    last = walk.sample(mid_single_support(walk), 90, DT)
    stance = SafeStance.finishing_step(PARAMS, last, last.t[0])
    window = stance.window(last.t[-1] + 30.0, 3, DT)
    assert np.all(window.support == SUPPORT_DOUBLE)
    assert np.all(np.isfinite(window.zmp))


def test_standing_on_given_feet():
    stance = SafeStance.standing(PARAMS, (1.0, 0.1, 0.0, 0.0), (1.0, -0.1, 0.0, 0.0), 5.0)
    window = stance.window(5.0, 4, DT)
    np.testing.assert_allclose(window.zmp, [[1.0, 0.0]] * 4)
    np.testing.assert_allclose(window.left_mass, [[1.0, 0.05]] * 4)
    assert np.all(np.isinf(window.left_landing_max))


def test_a_reference_fits_only_a_stance_on_the_same_feet(walk):
    stance = SafeStance.standing(PARAMS, (0.0, 0.07, 0.0, 0.0), (0.0, -0.07, 0.0, 0.0), 0.0)
    latched = [np.array([0.0, 0.07, 0.0, 0.0]), np.array([0.0, -0.07, 0.0, 0.0])]
    assert reference_misfit(stance.window(0.0, 5, DT), latched, 0.05) is None
    away = SafeStance.standing(PARAMS, (0.3, 0.07, 0.0, 0.0), (0.3, -0.07, 0.0, 0.0), 0.0)
    assert 'left foot' in reference_misfit(away.window(0.0, 5, DT), latched, 0.05)
    single = walk.sample(mid_single_support(walk), 5, DT)
    assert 'single support' in reference_misfit(single, latched, 0.05)


@pytest.mark.parametrize('field, value', [('settle_time', -1.0), ('feet_tolerance', 0.0),
                                          ('support_scale', 2.0)])
def test_bad_parameters_are_refused(field, value):
    with pytest.raises(ConfigError, match=field):
        SafeStanceParams(**{field: value})
