"""Tests of biped_planner.walking_reference: eq. zmpEquation, hip, swing, masses, bounds."""
import math

import numpy as np
import pytest

from biped_planner.errors import ConfigError
from biped_planner.footsteps import Footstep, LEFT, RIGHT, straight_footsteps
from biped_planner.step_timing import StepTiming
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_phases import (PHASE_DOUBLE_SUPPORT, PHASE_FINAL_SETTLE,
                                            PHASE_INITIAL_SHIFT, PHASE_SINGLE_SUPPORT,
                                            PHASE_STAND)
from biped_planner.reference_window import ReferenceWindow
from biped_planner.sides import SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT
from biped_planner.walking_reference import WalkingReference

TIMING = StepTiming(0.4, 0.1)
PARAMS = ReferenceParams()
DT = 0.002


def _all_samples(reference, dt=DT, margin=0.5):
    n = int((reference.duration + 2 * margin) / dt) + 1
    return reference.sample(reference.t_start - margin, n, dt)


def _turning_footsteps():
    """Walk along an arc turning 15 degrees per step, then close the feet."""
    steps = [Footstep(RIGHT, 0.0, -0.1), Footstep(LEFT, 0.0, 0.1)]
    heading, x, y = 0.0, 0.0, 0.0
    side = LEFT
    for _ in range(8):
        heading += math.radians(15.0)
        x += 0.08 * math.cos(heading)
        y += 0.08 * math.sin(heading)
        offset = 0.1 if side == LEFT else -0.1
        steps.append(Footstep(side, x - offset * math.sin(heading),
                              y + offset * math.cos(heading), heading))
        side = 1 - side
    offset = 0.1 if side == LEFT else -0.1
    steps.append(Footstep(side, x - offset * math.sin(heading), y + offset * math.cos(heading),
                          heading))
    return steps


@pytest.fixture(name='straight')
def fixture_straight():
    return WalkingReference(straight_footsteps(6, 0.1, 0.2), TIMING, PARAMS)


def _phase_mask(reference, window, kind):
    mask = np.zeros(window.t.size, dtype=bool)
    for phase in reference.phases:
        if phase.kind == kind:
            mask |= (window.t > phase.t_begin + 1e-9) & (window.t < phase.t_end - 1e-9)
    return mask


def test_window_shapes_and_types(straight):
    window = straight.sample(0.3, 80, 0.02)
    assert isinstance(window, ReferenceWindow)
    np.testing.assert_allclose(window.t, 0.3 + 0.02 * np.arange(80))
    for name in ('zmp', 'hip', 'left_mass', 'right_mass', 'zmp_min', 'zmp_max',
                 'left_landing_min', 'left_landing_max', 'right_landing_min',
                 'right_landing_max'):
        assert getattr(window, name).shape == (80, 2), name
    for name in ('left_foot', 'right_foot'):
        assert getattr(window, name).shape == (80, 3)
    for name in ('left_yaw', 'right_yaw', 'support', 'step_index'):
        assert getattr(window, name).shape == (80,)
    assert window.support.dtype == np.uint8
    assert np.issubdtype(window.step_index.dtype, np.integer)
    assert straight.sample(0.0, 2000, 0.01).t.shape == (2000,)


def test_timeline(straight):
    phases = straight.phases
    assert phases[0].kind == PHASE_INITIAL_SHIFT and phases[-1].kind == PHASE_FINAL_SETTLE
    assert [p.kind for p in phases[1:-1]] == [PHASE_SINGLE_SUPPORT, PHASE_DOUBLE_SUPPORT] * 6 + [
        PHASE_SINGLE_SUPPORT]
    for before, after in zip(phases[:-1], phases[1:]):
        assert after.t_begin == before.t_end
    assert straight.duration == pytest.approx(
        PARAMS.initial_shift_time + 7 * TIMING.single_support + 6 * TIMING.double_support
        + PARAMS.final_settle_time)
    assert straight.n_steps == 7


def test_zmp_follows_eq_zmp_equation(straight):
    """Single support: the stance sole centre; double support: f_i + SL (t - T_ss) / T_ds."""
    steps = straight.footsteps
    swing_order = [steps[1], steps[0]] + list(steps[2:])
    checked = 0
    for phase in straight.phases:
        if phase.kind not in (PHASE_SINGLE_SUPPORT, PHASE_DOUBLE_SUPPORT):
            continue
        k = phase.step_index - 1
        stance, landed = swing_order[k + 1], swing_order[k + 2]
        t = np.linspace(phase.t_begin, phase.t_end, 11)[:-1]
        window = straight.sample(float(t[0]), 10, float(t[1] - t[0]))
        f_i = np.array([stance.x, stance.y])
        if phase.kind == PHASE_SINGLE_SUPPORT:
            expected = np.tile(f_i, (10, 1))
            assert np.all(window.support == (SUPPORT_LEFT if stance.side == LEFT
                                             else SUPPORT_RIGHT))
        else:
            step = np.array([landed.x - stance.x, landed.y - stance.y])
            expected = f_i + np.outer(window.t - phase.t_begin, step) / TIMING.double_support
            assert np.all(window.support == SUPPORT_DOUBLE)
        np.testing.assert_allclose(window.zmp, expected, atol=1e-12)
        checked += 1
    assert checked == 13


@pytest.mark.parametrize('make', ['straight', 'turning', 'sideways', 'backward'])
def test_zmp_is_continuous_and_inside_the_support_polygon(make):
    steps = {'straight': lambda: straight_footsteps(6, 0.1, 0.2),
             'turning': _turning_footsteps,
             'sideways': lambda: [Footstep(RIGHT, 0.0, -0.1), Footstep(LEFT, 0.0, 0.1)] + [
                 Footstep(LEFT if k % 2 == 0 else RIGHT, 0.0,
                          (0.1 if k % 2 == 0 else -0.1) + 0.05 * (k // 2 + 1))
                 for k in range(8)],
             'backward': lambda: straight_footsteps(5, -0.08, 0.2, first_swing=RIGHT)}[make]()
    reference = WalkingReference(steps, TIMING, PARAMS)
    window = _all_samples(reference)
    assert np.all(window.zmp >= window.zmp_min - 1e-12)
    assert np.all(window.zmp <= window.zmp_max + 1e-12)
    # continuity: the ZMP never moves faster than its steepest ramp
    steepest = 0.45 / TIMING.double_support
    assert np.abs(np.diff(window.zmp, axis=0)).max() <= steepest * DT


def test_hip_satisfies_the_lipm_ode_and_is_smooth(straight):
    h = 1e-4
    t = np.arange(0.0, straight.duration, 0.013) + 0.0007
    knots = straight.lipm.times
    t = t[np.min(np.abs(t[:, None] - knots[None, :]), axis=1) > 3 * h]
    hips = [np.concatenate([straight.sample(float(ti + d), 1, 1.0).hip for ti in t])
            for d in (-h, 0.0, h)]
    zmp = np.concatenate([straight.sample(float(ti), 1, 1.0).zmp for ti in t])
    acceleration = (hips[2] - 2 * hips[1] + hips[0]) / h ** 2
    np.testing.assert_allclose(acceleration, straight.omega ** 2 * (hips[1] - zmp), atol=5e-5)
    velocity = straight.lipm.hip_velocity(np.concatenate((knots - 1e-9, knots + 1e-9)))
    half = knots.size
    np.testing.assert_allclose(velocity[:half], velocity[half:], atol=1e-6)


def test_hip_starts_and_ends_at_rest(straight):
    hip0 = np.array([0.0, 0.0])
    before = straight.sample(-1.0, 50, 0.02)
    np.testing.assert_allclose(before.hip, np.tile(hip0, (50, 1)), atol=1e-15)
    np.testing.assert_allclose(before.zmp, np.tile(hip0, (50, 1)), atol=1e-15)
    velocity = straight.lipm.hip_velocity(np.array([1e-9, straight.t_end - 1e-9]))
    np.testing.assert_allclose(velocity, 0.0, atol=1e-8)
    after = straight.sample(straight.t_end, 50, 0.1)
    np.testing.assert_allclose(after.hip, np.tile([0.6, 0.0], (50, 1)), atol=1e-12)
    np.testing.assert_allclose(after.zmp, np.tile([0.6, 0.0], (50, 1)), atol=1e-12)


def test_custom_hip0_and_t_start():
    reference = WalkingReference(straight_footsteps(2, 0.1, 0.2), TIMING, PARAMS,
                                 hip0=[0.01, 0.02], t_start=10.0)
    window = reference.sample(9.0, 10, 0.1)
    np.testing.assert_allclose(window.hip, np.tile([0.01, 0.02], (10, 1)), atol=1e-15)
    assert reference.phases[0].t_begin == 10.0
    np.testing.assert_allclose(reference.lipm.hip_velocity(np.array([10.0 + 1e-9])), 0.0,
                               atol=1e-8)


def test_swing_foot_follows_the_bezier_curve(straight):
    steps = straight.footsteps
    swing_order = [steps[1], steps[0]] + list(steps[2:])
    for phase in straight.phases:
        if phase.kind != PHASE_SINGLE_SUPPORT:
            continue
        k = phase.step_index - 1
        lift_off, landing = swing_order[k], swing_order[k + 2]
        duration = phase.t_end - phase.t_begin
        window = straight.sample(phase.t_begin, 101, duration / 100)
        foot = window.left_foot if phase.swing_side == LEFT else window.right_foot
        stance = window.right_foot if phase.swing_side == LEFT else window.left_foot
        s = np.linspace(0.0, 1.0, 101)
        progress = 10 * s ** 3 - 15 * s ** 4 + 6 * s ** 5
        np.testing.assert_allclose(foot[:, 0], lift_off.x + (landing.x - lift_off.x) * progress,
                                   atol=1e-12)
        np.testing.assert_allclose(foot[:, 2], 16 * PARAMS.swing_height * (s * (1 - s)) ** 2,
                                   atol=1e-12)
        assert foot[50, 2] == pytest.approx(PARAMS.swing_height)
        assert np.all(stance[:, 2] == 0.0)
        np.testing.assert_allclose(foot[[0, -1], :2], [[lift_off.x, lift_off.y],
                                                       [landing.x, landing.y]], atol=1e-12)
        h = 1e-7
        for t, sign in ((phase.t_begin, 1.0), (phase.t_end, -1.0)):
            pair = straight.sample(t, 2, sign * h) if sign > 0 else straight.sample(t - h, 2, h)
            swing = pair.left_foot if phase.swing_side == LEFT else pair.right_foot
            assert np.abs(np.diff(swing, axis=0)).max() / h < 1e-4


def test_feet_are_still_and_on_the_ground_outside_single_support(straight):
    window = _all_samples(straight)
    still = window.support == SUPPORT_DOUBLE
    assert np.all(window.left_foot[still, 2] == 0.0)
    assert np.all(window.right_foot[still, 2] == 0.0)
    swinging = window.support != SUPPORT_DOUBLE
    assert np.all((window.left_foot[swinging, 2] > 0) | (window.right_foot[swinging, 2] > 0)
                  | np.isclose(np.mod(window.t[swinging] - 1.0, 0.5), 0.0))


def test_masses_follow_the_geometric_relations(straight):
    window = _all_samples(straight)
    np.testing.assert_allclose(window.left_mass, 0.5 * (window.left_foot[:, :2] + window.hip))
    np.testing.assert_allclose(window.right_mass, 0.5 * (window.right_foot[:, :2] + window.hip))
    single = _phase_mask(straight, window, PHASE_SINGLE_SUPPORT)
    left_stance = single & (window.support == SUPPORT_LEFT)
    right_stance = single & (window.support == SUPPORT_RIGHT)
    # the paper: stance leg mass midway between the ZMP and the hip
    np.testing.assert_allclose(window.left_mass[left_stance],
                               0.5 * (window.zmp + window.hip)[left_stance], atol=1e-12)
    np.testing.assert_allclose(window.right_mass[right_stance],
                               0.5 * (window.zmp + window.hip)[right_stance], atol=1e-12)
    assert np.abs(np.diff(window.left_mass, axis=0)).max() < 0.01


def test_bounds_per_phase(straight):
    window = _all_samples(straight)
    half = 0.5 * PARAMS.support_scale * np.array([PARAMS.foot_length, PARAMS.foot_width])
    single = window.support != SUPPORT_DOUBLE
    stance = np.where((window.support == SUPPORT_LEFT)[:, None], window.left_foot[:, :2],
                      window.right_foot[:, :2])
    np.testing.assert_allclose(window.zmp_min[single], stance[single] - half, atol=1e-12)
    np.testing.assert_allclose(window.zmp_max[single], stance[single] + half, atol=1e-12)
    double = ~single
    lower = np.minimum(window.left_foot[:, :2], window.right_foot[:, :2]) - half
    upper = np.maximum(window.left_foot[:, :2], window.right_foot[:, :2]) + half
    np.testing.assert_allclose(window.zmp_min[double], lower[double], atol=1e-12)
    np.testing.assert_allclose(window.zmp_max[double], upper[double], atol=1e-12)
    landing_half = np.array([PARAMS.landing_half_length, PARAMS.landing_half_width])
    steps = straight.footsteps
    for phase in straight.phases:
        inside = (window.t > phase.t_begin) & (window.t < phase.t_end)
        for side, low, high in ((LEFT, window.left_landing_min, window.left_landing_max),
                                (RIGHT, window.right_landing_min, window.right_landing_max)):
            if phase.swing_side == side:
                target = steps[phase.step_index + 1]
                np.testing.assert_allclose(low[inside], np.tile([target.x, target.y], (
                    inside.sum(), 1)) - landing_half)
                np.testing.assert_allclose(high[inside], np.tile([target.x, target.y], (
                    inside.sum(), 1)) + landing_half)
            else:
                assert np.all(np.isneginf(low[inside])) and np.all(np.isposinf(high[inside]))


def test_step_index(straight):
    for phase in straight.phases:
        window = straight.sample((phase.t_begin + phase.t_end) / 2, 1, 1.0)
        assert window.step_index[0] == phase.step_index
    assert straight.phases[0].step_index == 0
    assert straight.phases[-1].step_index == straight.n_steps


def test_yaw_is_unwrapped_and_continuous():
    steps = [Footstep(RIGHT, 0.0, -0.1, 3.0), Footstep(LEFT, 0.0, 0.1, 3.0),
             Footstep(LEFT, 0.0, 0.1, -3.0), Footstep(RIGHT, 0.0, -0.1, -2.9),
             Footstep(LEFT, 0.0, 0.1, -2.9)]
    reference = WalkingReference(steps, TIMING, PARAMS)
    window = _all_samples(reference)
    assert np.abs(np.diff(window.left_yaw)).max() < 0.01
    assert window.left_yaw[-1] == pytest.approx(2 * math.pi - 2.9)
    assert window.right_yaw[-1] == pytest.approx(2 * math.pi - 2.9)


def _continue_straight(reference, count, length=0.1):
    last = reference.footsteps[-1]
    x = last.x
    side = 1 - last.side
    new = []
    for _ in range(count):
        x += length
        new.append(Footstep(side, x, 0.1 if side == LEFT else -0.1))
        side = 1 - side
    new.append(Footstep(side, x, 0.1 if side == LEFT else -0.1))
    return new


@pytest.mark.parametrize('t_now', [0.5, 1.2, 2.0, 2.6, 5.0, 8.0])
def test_extension_keeps_the_past_and_the_hip_smooth(straight, t_now):
    extended = straight.extend(_continue_straight(straight, 4), t_now)
    assert extended.n_steps == straight.n_steps + 5
    old = _all_samples(straight, margin=0.0)
    new = extended.sample(old.t[0], old.t.size, DT)
    past = old.t < t_now
    for name in ('zmp', 'hip', 'left_foot', 'right_foot', 'zmp_min', 'support'):
        np.testing.assert_array_equal(getattr(new, name)[past], getattr(old, name)[past])
    knots = extended.lipm.times
    velocity = extended.lipm.hip_velocity(np.concatenate((knots - 1e-9, knots + 1e-9)))
    np.testing.assert_allclose(velocity[:knots.size], velocity[knots.size:], atol=1e-6)
    whole = _all_samples(extended)
    assert np.all(whole.zmp >= whole.zmp_min - 1e-12) and np.all(whole.zmp <= whole.zmp_max
                                                                 + 1e-12)
    np.testing.assert_allclose(whole.hip[-1], [1.0, 0.0], atol=1e-12)
    if t_now > straight.t_end:
        kinds = [phase.kind for phase in extended.phases]
        assert PHASE_STAND in kinds and kinds.count(PHASE_INITIAL_SHIFT) == 2


def test_extension_replacing_the_preview_changes_little():
    preview = WalkingReference(straight_footsteps(10, 0.1, 0.2), TIMING, PARAMS)
    t_now = 2.05
    cut = next(p for p in preview.phases
               if p.t_begin >= t_now and p.kind == PHASE_DOUBLE_SUPPORT)
    keep = cut.step_index + 2
    last = preview.footsteps[keep - 1]
    sides = [(1 - last.side + i) % 2 for i in range(7)]
    new = [Footstep(side, last.x + 0.12 * min(i + 1, 6), 0.1 if side == LEFT else -0.1)
           for i, side in enumerate(sides)]
    extended = preview.extend(new, t_now, replace_from=keep)
    assert extended.start_correction < 0.02
    assert extended.footsteps[:keep] == preview.footsteps[:keep]
    assert extended.footsteps[keep:] == tuple(new)
    with pytest.raises(ConfigError, match='too early'):
        preview.extend(new, t_now, replace_from=keep - 1)


def test_extension_with_new_timing():
    reference = WalkingReference(straight_footsteps(2, 0.1, 0.2), TIMING, PARAMS)
    slow = StepTiming(0.6, 0.2)
    extended = reference.extend(_continue_straight(reference, 2), 0.0, timing=slow)
    assert extended.step_timing(0) == TIMING and extended.step_timing(4) == slow
    singles = [p for p in extended.phases if p.kind == PHASE_SINGLE_SUPPORT]
    assert singles[-1].t_end - singles[-1].t_begin == pytest.approx(0.6)
    with pytest.raises(ConfigError):
        extended.step_timing(99)


def test_extension_without_change_returns_itself(straight):
    assert straight.extend([], 1.0) is straight


@pytest.mark.parametrize('kwargs, match', [
    (dict(t_now=math.nan), 't_now'),
    (dict(timing=(0.4, 0.1)), 'timing'),
    (dict(replace_from=1), 'replace_from'),
    (dict(replace_from=99), 'replace_from'),
    (dict(replace_from=True), 'replace_from'),
])
def test_extension_rejects_bad_arguments(straight, kwargs, match):
    arguments = dict(footsteps=_continue_straight(straight, 2), t_now=1.0)
    arguments.update(kwargs)
    with pytest.raises(ConfigError, match=match):
        straight.extend(**arguments)


def test_extension_rejects_feet_that_do_not_alternate(straight):
    last = straight.footsteps[-1]
    with pytest.raises(ConfigError, match='alternate'):
        straight.extend([Footstep(last.side, last.x + 0.1, last.y)], 1.0)


@pytest.mark.parametrize('t0, n, dt', [(math.nan, 80, 0.02), (0.0, 0, 0.02), (0.0, 80, 0.0),
                                       (0.0, 80, -0.02), (0.0, 80, math.inf), (0.0, True, 0.02),
                                       (0.0, 2.5, 0.02), (math.inf, 80, 0.02)])
def test_sample_rejects_bad_arguments(straight, t0, n, dt):
    with pytest.raises(ConfigError):
        straight.sample(t0, n, dt)


@pytest.mark.parametrize('change', ['timing', 'params', 'hip0_shape', 'hip0_nan', 'hip0_text',
                                    't_start', 'footsteps'])
def test_constructor_rejects_bad_arguments(change):
    arguments = dict(footsteps=straight_footsteps(2, 0.1, 0.2), timing=TIMING, params=PARAMS)
    arguments.update({'timing': dict(timing=(0.4, 0.1)),
                      'params': dict(params={'com_height': 0.5}),
                      'hip0_shape': dict(hip0=[0.0, 0.0, 0.0]),
                      'hip0_nan': dict(hip0=[0.0, math.nan]),
                      'hip0_text': dict(hip0=['a', 'b']),
                      't_start': dict(t_start=math.inf),
                      'footsteps': dict(footsteps=straight_footsteps(2, 0.1, 0.2)[:2])}[change])
    with pytest.raises(ConfigError):
        WalkingReference(**arguments)
