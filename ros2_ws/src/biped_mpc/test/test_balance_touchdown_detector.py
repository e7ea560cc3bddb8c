"""Touchdown detection on 1 kHz synthetic traces: impacts, chatter, inertia, early, late, lift."""
import math

import numpy as np
import pytest

from biped_mpc.balance.ft_filter import compensate_foot_inertia
from biped_mpc.balance.touchdown_detector import (
    ContactEvent, TouchdownDetector, TouchdownParams)
from biped_mpc.errors import ConfigError, InputError

DT = 0.001
SWING = 0.4  # s of planned swing


def landing_trace(t_contact, duration=0.6, load=150.0):
    """Normal force of a landing at t_contact: a 2 ms impact spike, a 5 ms bounce in the air,
    then the load rising over 20 ms with 1 kHz chatter that dips to 5 N for 3 ms."""
    times = np.arange(0.0, duration, DT)
    force = np.zeros_like(times)
    since = times - t_contact
    force[(since >= 0.0) & (since < 0.002)] = 400.0
    rising = since >= 0.007
    force[rising] = load * np.minimum(1.0, (since[rising] - 0.007) / 0.02)
    force[(since >= 0.03) & (since < 0.033)] = 5.0
    force[rising & (since >= 0.04)] += 15.0 * np.sin(2 * np.pi * 200 * since[rising & (since
                                                                                       >= 0.04)])
    return times, force


def run(detector, times, force, phase=None, distance=None):
    events = []
    states = []
    for k, (t, f) in enumerate(zip(times, force)):
        state = detector.update(float(t), float(f),
                                None if phase is None else float(phase[k]),
                                None if distance is None else float(distance[k]))
        states.append(state)
        if state.event != ContactEvent.NONE:
            events.append((state.event, state.event_time, float(t)))
    return events, states


def swing_phase(times):
    return np.minimum(times / SWING, 1.0)


def test_landing_with_impact_bounce_and_chatter_gives_one_touchdown():
    times, force = landing_trace(0.38)
    events, states = run(TouchdownDetector(in_contact=False), times, force, swing_phase(times))
    assert len(events) == 1
    event, started, detected = events[0]
    assert event == ContactEvent.TOUCHDOWN
    # the load passes 50 N 6.7 ms after it starts rising, 7 ms after the spike
    assert started == pytest.approx(0.38 + 0.007 + 0.02 * 50.0 / 150.0, abs=1.5e-3)
    assert detected - started == pytest.approx(0.01, abs=1.5e-3)
    assert states[-1].in_contact


@pytest.mark.parametrize('phase_of_reading', [0.3, 0.7])
def test_mid_air_inertial_reading_does_not_trigger(phase_of_reading):
    times = np.arange(0.0, 0.4, DT)
    force = np.zeros_like(times)
    window = np.abs(times - phase_of_reading * SWING) < 0.02
    force[window] = 38.0
    events, states = run(TouchdownDetector(in_contact=False), times, force, swing_phase(times))
    assert events == [] and not any(s.gated for s in states)


def test_raw_inertial_reading_compensated_does_not_trigger_a_low_threshold():
    # With on_force 20 N the raw 38 N reading of an accelerating foot would count; the
    # compensated force is zero.
    mass, acceleration = 0.75, np.array([0.0, 0.0, 41.0])
    sensor, com = np.array([0.0, 0.0, 0.3]), np.array([0.0, 0.0, 0.27])
    raw = -mass * (acceleration - np.array([0.0, 0.0, -9.81]))
    detector = TouchdownDetector(TouchdownParams(on_force=20.0, off_force=10.0),
                                 in_contact=False)
    for k in range(30):
        force, _ = compensate_foot_inertia(raw, np.zeros(3), sensor, mass, com, acceleration,
                                           sensor)
        state = detector.update(0.3 + k * DT, float(force[2]), 0.9)
        assert not state.in_contact and not state.pending
        assert abs(raw[2]) > 20.0


def test_mid_swing_scuff_is_gated():
    times = np.arange(0.0, 0.4, DT)
    force = np.where(np.abs(times - 0.1) < 0.015, 80.0, 0.0)
    events, states = run(TouchdownDetector(in_contact=False), times, force, swing_phase(times))
    assert events == [] and any(s.gated for s in states)


def test_early_contact_near_the_target_is_accepted_far_is_refused():
    times, force = landing_trace(0.28)  # phase 0.7
    near = np.full_like(times, 0.02)
    events, _ = run(TouchdownDetector(in_contact=False), times, force, swing_phase(times), near)
    assert [e[0] for e in events] == [ContactEvent.TOUCHDOWN] and events[0][2] < SWING
    far = np.full_like(times, 0.08)
    events, states = run(TouchdownDetector(in_contact=False), times, force, swing_phase(times),
                         far)
    assert events == [] and states[-1].gated


def test_late_contact_is_accepted():
    times, force = landing_trace(0.55, duration=0.7)
    events, _ = run(TouchdownDetector(in_contact=False), times, force, swing_phase(times))
    assert [e[0] for e in events] == [ContactEvent.TOUCHDOWN]
    assert events[0][1] > 0.55


def test_liftoff_after_weight_transfer_ignores_a_short_dip():
    times = np.arange(0.0, 0.3, DT)
    force = np.interp(times, [0.0, 0.1, 0.2, 0.3], [150.0, 150.0, 0.0, 0.0])
    force[(times >= 0.05) & (times < 0.055)] = 10.0  # 5 ms dip while standing
    events, _ = run(TouchdownDetector(), times, force)
    assert len(events) == 1 and events[0][0] == ContactEvent.LIFTOFF
    crossing = 0.1 + 0.1 * (1.0 - 25.0 / 150.0)
    assert events[0][1] == pytest.approx(crossing, abs=1.5e-3)
    assert events[0][2] - events[0][1] == pytest.approx(0.01, abs=1.5e-3)


def test_zero_dwell_switches_on_the_sample():
    detector = TouchdownDetector(TouchdownParams(dwell_time=0.0), in_contact=False)
    state = detector.update(0.0, 60.0)
    assert state.event == ContactEvent.TOUCHDOWN and state.event_time == 0.0
    detector.reset(False)
    assert not detector.in_contact


@pytest.mark.parametrize('change', [{'off_force': 60.0}, {'on_force': 0.0},
                                    {'gate_phase': 1.5}, {'dwell_time': -0.01}])
def test_bad_parameters_are_refused(change):
    with pytest.raises(ConfigError):
        TouchdownParams(**change)


def test_bad_inputs_are_refused():
    detector = TouchdownDetector()
    with pytest.raises(InputError):
        detector.update(0.0, math.nan)
    with pytest.raises(InputError):
        detector.update(0.0, 10.0, math.inf)
    detector.update(1.0, 10.0)
    with pytest.raises(InputError, match='backwards'):
        detector.update(0.5, 10.0)
