"""Mid-step replans of a walking reference (step adjustment) and the plan data they need."""
import math

import numpy as np
import pytest

from biped_planner.errors import ConfigError
from biped_planner.footsteps import Footstep, straight_footsteps
from biped_planner.plan_adjustment import moved_landings, swing_step_at
from biped_planner.reference_params import ReferenceParams
from biped_planner.sides import LEFT, RIGHT
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference

TIMING = StepTiming(0.4, 0.1)
PARAMS = ReferenceParams()
# initial shift 0 .. 1 s, step 0 single support 1.0 .. 1.4 s, step 1 from 1.5 s
REFERENCE = WalkingReference(straight_footsteps(4, 0.1, 0.2), TIMING, PARAMS)
NAMES = ('zmp', 'hip', 'left_foot', 'right_foot', 'left_mass', 'right_mass', 'zmp_min',
         'zmp_max', 'left_landing_min', 'left_landing_max', 'right_landing_min',
         'right_landing_max', 'support', 'step_index')


def _same(a, b, atol=1e-9):
    for name in NAMES:
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), atol=atol,
                                   err_msg=name)


def test_swing_step_at_reads_the_plan():
    swing = swing_step_at(REFERENCE, 1.6)
    footsteps = REFERENCE.footsteps
    assert swing.step == 1 and swing.landing == footsteps[3] and swing.stance == footsteps[2]
    assert swing.lift_off == pytest.approx(1.5) and swing.touchdown == pytest.approx(1.9)
    assert swing.duration == pytest.approx(0.4)
    np.testing.assert_allclose(swing.zmp, [footsteps[2].x, footsteps[2].y], atol=1e-12)
    np.testing.assert_allclose(swing.zmp_half_size, 0.5 * 0.9 * np.array([0.16, 0.08]))
    np.testing.assert_allclose(swing.dcm, REFERENCE.lipm.state_at(1.6)[1])
    # the first step stands on footsteps[0]
    assert swing_step_at(REFERENCE, 1.2).stance == footsteps[0]
    for t in (0.5, 1.45, 100.0):
        assert swing_step_at(REFERENCE, t) is None


def test_moved_landings_translate_the_rest():
    footsteps = REFERENCE.footsteps
    moved = moved_landings(footsteps, 3, (0.3, -0.25))
    assert len(moved) == len(footsteps) - 3
    for old, new in zip(footsteps[3:], moved):
        assert new.side == old.side and new.yaw == old.yaw
        assert new.x - old.x == pytest.approx(0.3 - footsteps[3].x)
        assert new.y - old.y == pytest.approx(-0.25 - footsteps[3].y)
    with pytest.raises(ConfigError):
        moved_landings(footsteps, 1, (0.0, 0.0))
    with pytest.raises(ConfigError):
        moved_landings(footsteps, 3, (math.nan, 0.0))


def test_unchanged_adjustment_reproduces_the_reference():
    t = 1.62
    same = REFERENCE.adjust_step(t, REFERENCE.footsteps[3:], 1.9)
    assert same.revision == REFERENCE.revision + 1 == 1
    assert same.start_correction == pytest.approx(0.0, abs=1e-12)
    _same(REFERENCE.sample(t, 300, 0.01), same.sample(t, 300, 0.01))


@pytest.mark.parametrize('touchdown', [1.75, 1.9, 2.1])
def test_adjusted_step_lands_where_and_when_asked(touchdown):
    t = 1.62
    hip, dcm = np.array([0.12, -0.08]), np.array([0.2, -0.05])
    landings = moved_landings(REFERENCE.footsteps, 3, (0.3, -0.15))
    adjusted = REFERENCE.adjust_step(t, landings, touchdown, hip, dcm)
    assert adjusted.footsteps[3:] == landings
    assert adjusted.footsteps[:3] == REFERENCE.footsteps[:3]
    # the hip passes through the given state at t_now ...
    now_hip, now_dcm = adjusted.lipm.state_at(t)
    np.testing.assert_allclose(now_hip, hip, atol=1e-9)
    np.testing.assert_allclose(now_dcm, dcm, atol=1e-9)
    # ... the ZMP stays on the stance foot until the new touchdown ...
    stance = REFERENCE.footsteps[2]
    window = adjusted.sample(t, int(round((touchdown - t) / 0.01)), 0.01)
    np.testing.assert_allclose(window.zmp, np.tile([stance.x, stance.y], (len(window.t), 1)),
                               atol=1e-9)
    # ... the swinging (right) foot lands on the new footstep at that time ...
    assert REFERENCE.footsteps[3].side == RIGHT
    landed = adjusted.sample(touchdown, 1, 0.01)
    np.testing.assert_allclose(landed.right_foot[0], [0.3, -0.15, 0.0], atol=1e-9)
    single = adjusted.phases[adjusted.single_support_at(t)]
    assert single.t_end == pytest.approx(touchdown)
    # ... the later phases keep their durations, and the walk ends at rest between the feet
    assert adjusted.t_end == pytest.approx(REFERENCE.t_end + touchdown - 1.9)
    end = adjusted.sample(adjusted.t_end, 1, 0.01)
    final = 0.5 * (np.array([landings[-1].x, landings[-1].y])
                   + [landings[-2].x, landings[-2].y])
    np.testing.assert_allclose(end.hip[0], final, atol=1e-9)
    np.testing.assert_allclose(adjusted.lipm.hip_velocity(np.array([adjusted.t_end])), 0.0,
                               atol=1e-9)


def test_adjust_the_last_step():
    reference = WalkingReference(straight_footsteps(1, 0.1, 0.2), TIMING, PARAMS)
    t = reference.phases[-2].t_begin + 0.1  # the closing step
    swing = swing_step_at(reference, t)
    assert swing.landing == reference.footsteps[-1]
    adjusted = reference.adjust_step(t, moved_landings(reference.footsteps, swing.step + 2,
                                                       (0.15, -0.12)), swing.touchdown)
    end = adjusted.sample(adjusted.t_end + 0.5, 1, 0.01)
    # the hip comes to rest midway between the other foot (0.1, 0.1) and the moved one
    np.testing.assert_allclose(end.hip[0], [0.125, -0.01], atol=1e-9)


def test_adjust_then_extend_counts_revisions():
    adjusted = REFERENCE.adjust_step(1.62, REFERENCE.footsteps[3:], 1.85)
    extended = adjusted.extend([Footstep(RIGHT, 0.4, -0.1)], 1.62)
    assert (REFERENCE.revision, adjusted.revision, extended.revision) == (0, 1, 2)


@pytest.mark.parametrize('t, touchdown, state', [
    (1.45, 1.9, {}),                       # double support
    (0.5, 1.9, {}),                        # initial shift
    (1.62, 1.6, {}),                       # touchdown before now
    (1.62, 1.9, {'hip': (0.0, 0.0)}),      # hip without dcm
    (1.62, 1.9, {'hip': (0.0, 0.0), 'dcm': (math.inf, 0.0)}),
])
def test_adjust_step_rejects(t, touchdown, state):
    with pytest.raises(ConfigError):
        REFERENCE.adjust_step(t, REFERENCE.footsteps[3:], touchdown, **state)


def test_adjust_step_rejects_broken_alternation():
    wrong = (Footstep(LEFT, 0.2, 0.1),) + REFERENCE.footsteps[4:]
    assert REFERENCE.footsteps[3].side == RIGHT
    with pytest.raises(ConfigError):
        REFERENCE.adjust_step(1.62, wrong, 1.9)


def test_reference_session_walks_the_adjusted_plan():
    from biped_planner.reference_session import ReferenceSession
    session = ReferenceSession(PARAMS)
    with pytest.raises(ConfigError):
        session.adjust_step(1.62, REFERENCE.footsteps[3:], 1.85)
    session.set_plan(7, REFERENCE.footsteps, TIMING, 0.0)
    assert session.start_walk(0.0) and session.plan_revision == 0
    landings = moved_landings(session.reference.footsteps, 3, (0.25, -0.12))
    session.adjust_step(1.62, landings, 1.85)
    assert session.plan_revision == 1 and session.reference.footsteps[3:] == landings
    window = session.window(1.85, 1, 0.01, None)
    np.testing.assert_allclose(window.right_foot[0], [0.25, -0.12, 0.0], atol=1e-9)


@pytest.mark.parametrize('t', [1.5, 1.6, 1.75, 1.899])
def test_reference_dcm_closed_form_matches_the_pendulum(t):
    swing = swing_step_at(REFERENCE, 1.55)
    np.testing.assert_allclose(swing.reference_dcm(t), REFERENCE.lipm.state_at(t)[1],
                               atol=1e-9)


def _dcm_run_back(reference, t_from, dt=1e-4):
    """The DCM at t_from by integrating xi_dot = omega (xi - p) backwards from the walk's end at
    rest (xi = the final ZMP), p sampled from the reference (RK4, p linear within a step)."""
    omega = reference.lipm.omega
    n = int(round((reference.t_end - t_from) / dt))
    assert reference.t_end - n * dt == pytest.approx(t_from)
    zmp = reference.sample(t_from, n + 1, dt).zmp[::-1]
    mids = 0.5 * (zmp[:-1] + zmp[1:])

    def rate(x, p):
        return omega * (x - p)
    xi = zmp[0].copy()
    for k in range(n):
        k1 = rate(xi, zmp[k])
        k2 = rate(xi - 0.5 * dt * k1, mids[k])
        k3 = rate(xi - 0.5 * dt * k2, mids[k])
        k4 = rate(xi - dt * k3, zmp[k + 1])
        xi = xi - dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    return xi


@pytest.mark.parametrize('touchdown', [1.75, 1.9, 2.1])
def test_a_step_adjusted_with_the_footsteps_dcm_bends_no_zmp(touchdown):
    t = 1.62
    landings = moved_landings(REFERENCE.footsteps, 3, (0.3, -0.15))
    bent = REFERENCE.adjust_step(t, landings, touchdown)
    straight = REFERENCE.adjust_step(t, landings, touchdown, dcm_from_footsteps=True)
    # the moved step asks for another DCM than the unpushed plan's: the default bends the ZMP
    # of the next double support to join the plan's own state, the option does not (the final
    # settle's free knot takes the hip's lag behind the new DCM, a fraction of a millimetre at
    # the double support's knot) ...
    assert bent.start_correction > 0.05
    assert straight.start_correction < 1e-3
    # ... keeps the hip where it was at t ...
    hip_now, dcm_now = straight.lipm.state_at(t)
    np.testing.assert_allclose(hip_now, REFERENCE.lipm.state_at(t)[0], atol=1e-9)
    # ... and takes the DCM the new footsteps ask for: the pendulum's DCM run back from the
    # walk's end at rest over the new plan's ZMP (an independent integration)
    np.testing.assert_allclose(dcm_now, _dcm_run_back(straight, t), atol=1e-6)
    window = straight.sample(touchdown, 10, 0.01)  # the double support's ZMP: foot to foot
    assert np.all(window.zmp[:, 0] >= REFERENCE.footsteps[2].x - 1e-3)
    assert np.linalg.norm(dcm_now - REFERENCE.lipm.state_at(t)[1]) > 0.01
    # the step lands where and when asked, the walk ends at rest between the last feet
    landed = straight.sample(touchdown, 1, 0.01)
    np.testing.assert_allclose(landed.right_foot[0], [0.3, -0.15, 0.0], atol=1e-9)
    final = 0.5 * (np.array([landings[-1].x, landings[-1].y])
                   + [landings[-2].x, landings[-2].y])
    np.testing.assert_allclose(straight.sample(straight.t_end, 1, 0.01).hip[0], final,
                               atol=1e-6)
    np.testing.assert_allclose(straight.lipm.hip_velocity(np.array([straight.t_end])), 0.0,
                               atol=1e-6)


def test_the_footsteps_dcm_of_an_unmoved_step_is_the_plans_own():
    # within the plan's own bend of its free knots at the start (0.2 mm here)
    t = 1.62
    same = REFERENCE.adjust_step(t, REFERENCE.footsteps[3:], 1.9, dcm_from_footsteps=True)
    _same(REFERENCE.sample(t, 300, 0.01), same.sample(t, 300, 0.01), atol=1e-3)
