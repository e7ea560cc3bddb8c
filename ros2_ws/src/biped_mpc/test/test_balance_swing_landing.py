"""Swing landing: late contact at the bounded speed, early contact freeze, missed ground."""
import math

import numpy as np
import pytest

from biped_mpc.balance.swing_landing import (
    FAILED, LANDED, MISSED, RESUME, SEEKING, SHRINK, STRETCH, SupportTimingEvent, SwingLanding,
    SwingLandingParams, SWINGING)
from biped_mpc.balance.touchdown_detector import TouchdownDetector, TouchdownParams
from biped_mpc.errors import ConfigError, InputError

DT = 0.005
LANDING_TIME = 0.4


def planned_height(t):
    """A 4 cm swing landing at height 0 at LANDING_TIME."""
    return 0.04 * math.sin(math.pi * min(t / LANDING_TIME, 1.0))


def walk(landing, ground, duration=1.0, stiffness=2e4):
    """A stiff foot following its target; the ground pushes back once the target is below it.

    The sole sits at max(target, ground), the normal force is stiffness times the penetration
    of the target; the detector has a 10 ms dwell.
    """
    detector = TouchdownDetector(TouchdownParams(dwell_time=0.01), in_contact=False)
    landing.reset(LANDING_TIME, 0.0)
    target = planned_height(0.0)
    log = []
    for k in range(int(round(duration / DT))):
        t = k * DT
        measured = max(target, ground)
        state = detector.update(t, stiffness * max(ground - target, 0.0), min(t / LANDING_TIME,
                                                                                 1.0))
        result = landing.update(t, DT, planned_height(t), state.in_contact, measured)
        target = result.height
        log.append((t, result))
    return log


def events(log):
    return [(r.event.kind, r.event.t) for _, r in log if r.event is not None]


def test_late_contact_descends_at_the_bounded_speed_and_stops_at_contact():
    speed = 0.2
    log = walk(SwingLanding(SwingLandingParams(descent_speed=speed)), ground=-0.03)
    seeking = [(t, r.height) for t, r in log if r.mode == SEEKING]
    assert seeking
    for t, height in seeking:  # the bounded speed, at most max_lead below the held sole
        assert height == pytest.approx(max(-speed * (t - LANDING_TIME), -0.03 - 0.003),
                                       abs=1e-12)
    kinds = events(log)
    assert kinds[0] == (STRETCH, LANDING_TIME)
    assert kinds[1][0] == RESUME
    # the ground is reached at 0.4 + 0.03 / 0.2 s; the force passes 50 N 0.0025 m deeper
    contact = LANDING_TIME + 0.03 / speed
    assert contact < kinds[1][1] < contact + 0.0025 / speed + 0.01 + 2 * DT
    landed = [r for _, r in log if r.mode == LANDED]
    assert len({r.height for r in landed}) == 1
    assert landed[0].height == pytest.approx(-0.03)
    assert not any(r.failed for _, r in log)


def test_early_contact_freezes_the_height_where_the_ground_was_met():
    log = walk(SwingLanding(), ground=0.02)
    kinds = events(log)
    assert len(kinds) == 1 and kinds[0][0] == SHRINK and kinds[0][1] < LANDING_TIME
    after = [r for t, r in log if t >= kinds[0][1]]
    assert all(r.mode == LANDED and r.height == pytest.approx(0.02) for r in after)
    assert all(r.extra_depth == 0.0 for r in after)


def test_missing_ground_reaches_the_max_depth_and_reports_failure():
    params = SwingLandingParams(descent_speed=0.15, max_extra_depth=0.06)
    log = walk(SwingLanding(params), ground=-1.0)
    kinds = events(log)
    assert kinds == [(STRETCH, LANDING_TIME), (MISSED, pytest.approx(LANDING_TIME + 0.4))]
    final = log[-1][1]
    assert final.failed and final.mode == FAILED
    assert final.height == pytest.approx(-0.06) and final.extra_depth == pytest.approx(0.06)
    depths = np.array([r.extra_depth for _, r in log])
    assert np.all(np.diff(depths) <= 0.15 * DT + 1e-12)


def test_a_seeking_target_stays_within_max_lead_of_a_foot_the_ground_holds():
    # The detector has not confirmed yet (in_contact False): the ground at -5 mm holds the sole.
    params = SwingLandingParams(descent_speed=0.15, max_extra_depth=0.06, max_lead=0.003)
    landing = SwingLanding(params)
    landing.reset(LANDING_TIME, 0.0)
    ground, target, heights = -0.005, 0.0, []
    for k in range(int(round(0.3 / DT))):
        t = LANDING_TIME + k * DT
        result = landing.update(t, DT, 0.0, False, max(target, ground))
        target = result.height
        heights.append(target)
    heights = np.array(heights)
    assert heights.min() == pytest.approx(ground - 0.003)
    assert np.all(np.diff(heights) <= 1e-15)  # the target never rises again
    # a free foot (measured = target) follows the bounded speed, as without the bound
    free = SwingLanding(params)
    free.reset(LANDING_TIME, 0.0)
    target = 0.0
    for k in range(20):
        target = free.update(LANDING_TIME + k * DT, DT, 0.0, False, target).height
    assert target == pytest.approx(-0.15 * 20 * DT)  # v dt per update, the first one too



def test_the_descent_starts_from_a_lagging_target_without_a_jump():
    # The planned target reaches the controller through a lag: 6 mm above the landing height
    # at the planned landing time, closing at 0.1 m/s. The seeking target moves down by at most
    # max(v dt, the plan's own step) per cycle, and runs below the lagging plan at v.
    speed = 0.3
    landing = SwingLanding(SwingLandingParams(descent_speed=speed))
    landing.reset(LANDING_TIME, 0.0)

    def lagging(t):
        return max(0.006 - 0.1 * (t - LANDING_TIME), 0.0) if t >= LANDING_TIME else 0.006

    heights = []
    for k in range(-4, 30):
        t = LANDING_TIME + k * DT
        heights.append(landing.update(t, DT, lagging(t), False,
                                      heights[-1] if heights else 0.006).height)
    steps = -np.diff(heights)
    assert heights[4] == pytest.approx(0.006 - speed * DT)  # the first seeking cycle
    assert steps.max() <= speed * DT + 1e-12
    assert heights[-1] == pytest.approx(0.006 - speed * 30 * DT)


def test_a_touching_sole_holds_the_seeking_target():
    landing = SwingLanding(SwingLandingParams(descent_speed=0.3))
    landing.reset(LANDING_TIME, 0.0)
    height = landing.update(LANDING_TIME, DT, 0.0, False, 0.0).height
    for k in range(1, 6):  # force seen, the detector not confirmed yet
        result = landing.update(LANDING_TIME + k * DT, DT, 0.0, False, height, touching=True)
        assert result.mode == SEEKING and result.height == height
    released = landing.update(LANDING_TIME + 6 * DT, DT, 0.0, False, height)
    assert released.height == pytest.approx(height - 0.3 * DT)


def test_a_sole_touching_early_is_not_pushed_into_the_raised_ground():
    # The plan goes on down to 0; the sole met a tile 15 mm up, the detector not confirmed yet.
    params = SwingLandingParams(max_lead=0.003)
    landing = SwingLanding(params)
    landing.reset(LANDING_TIME, 0.0)
    ground = 0.015
    for k in range(4):
        t = LANDING_TIME - 0.05 + k * DT
        result = landing.update(t, DT, planned_height(t), False, ground, touching=True)
        assert result.mode == SWINGING and result.event is None
        assert result.height == pytest.approx(max(planned_height(t), ground - 0.003))
    # untouched, the same cycle follows the plan
    free = SwingLanding(params)
    free.reset(LANDING_TIME, 0.0)
    t = LANDING_TIME - 0.01
    assert free.update(t, DT, planned_height(t), False, 0.02).height == planned_height(t)


def test_without_seeking_a_late_foot_ends_its_planned_swing_and_raises_no_event():
    log = walk(SwingLanding(SwingLandingParams(seek=False)), ground=-0.03)
    assert events(log) == []
    assert all(r.mode == SWINGING and r.height == pytest.approx(planned_height(t))
               for t, r in log)
    early = walk(SwingLanding(SwingLandingParams(seek=False)), ground=0.02)
    kinds = events(early)  # an early contact still freezes the foot where it met the ground
    assert len(kinds) == 1 and kinds[0][0] == SHRINK
    assert early[-1][1].mode == LANDED and early[-1][1].height == pytest.approx(0.02)


def test_contact_on_time_raises_no_event():
    landing = SwingLanding()
    landing.reset(LANDING_TIME, 0.0)
    assert landing.update(0.3, DT, 0.01, False, 0.01).mode == SWINGING
    result = landing.update(LANDING_TIME, DT, 0.0, True, 0.0)
    assert result.event is None and result.mode == LANDED


def test_bad_values_are_refused():
    with pytest.raises(ConfigError):
        SwingLandingParams(descent_speed=0.0)
    with pytest.raises(ConfigError):
        SwingLandingParams(max_extra_depth=-0.01)
    with pytest.raises(ConfigError):
        SwingLandingParams(max_lead=-0.001)
    with pytest.raises(InputError):
        SupportTimingEvent('late', 0.0)
    with pytest.raises(InputError):
        SwingLanding().update(0.0, DT, math.nan, False, 0.0)
    with pytest.raises(InputError, match='dt'):
        SwingLanding().update(0.0, 0.0, 0.0, False, 0.0)
    with pytest.raises(InputError):
        SwingLanding().reset(math.nan, 0.0)


def test_a_retimed_landing_stretches_from_the_new_time():
    landing = SwingLanding(SwingLandingParams(descent_speed=0.2))
    landing.reset(LANDING_TIME, 0.0)
    landing.update(0.1, DT, 0.02, False, 0.02)
    landing.retime(0.6)  # a step adjustment made the step 0.2 s longer
    before = landing.update(0.5, DT, 0.01, False, 0.01)
    assert before.mode == SWINGING and before.event is None
    after = landing.update(0.6, DT, 0.0, False, 0.0)
    assert after.mode == SEEKING
    assert (after.event.kind, after.event.t) == (STRETCH, pytest.approx(0.6))


def test_a_landing_already_seeking_keeps_its_time():
    landing = SwingLanding()
    landing.reset(LANDING_TIME, 0.0)
    first = landing.update(LANDING_TIME, DT, 0.0, False, 0.0)
    assert first.event.kind == STRETCH
    landing.retime(0.6)
    later = landing.update(LANDING_TIME + DT, DT, 0.0, False, 0.0)
    assert later.mode == SEEKING and later.event is None


def test_a_retime_to_nan_is_refused():
    landing = SwingLanding()
    landing.reset(LANDING_TIME, 0.0)
    with pytest.raises(InputError):
        landing.retime(math.nan)
