"""Late and early touchdowns walked through in PyBullet (biped_sim.terrain_trial).

Two steps of 0.2 m; the left foot's lane changes height just ahead of its toe
(terrain_trial.lane_step_terrain), so its first landing meets the ground 20 mm below the
plan (late touchdown) or 15 mm above it (early touchdown). The references are blind (flat).

The late walk-through is marked xfail: it passed in a run of several trials on one backend
and failed on a fresh one (docs/simulator_notes.md): the landing works step by step but the
walk after it is marginal (its foot lands on the lane's edge, heel on the platform). The early
one was too, until a seeking foot was no longer refused by the touchdown detector's distance
gate (2026-12-05, late): it walks through on fresh backends. The hip strategy is off: with
it, the late touchdown is walked through without the contact-aware landing too, and the
landing is what is tested here.
So is the swing lag (swing_smoothing_time_constant, 0.07 s by default): with it the late
touchdown is walked through without the landing as well (one run, 2026-12-04), and so is the
ground conformance (with it the late touchdown is walked through without the landing too,
2026-12-05), and so is the pelvis over the ground under the ZMP (pelvis_ground_at_zmp, the
default since 2026-12-06). One run each with the landing (2026-12-06): with every default on,
both touchdowns are walked through; the same with the pelvis over the held feet's mean, the
early one fell; with the ZMP ground the only one of these four on, the early one fell.
"""
import pytest

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_sim.terrain_trial import lane_step_terrain, run_trial


def walk(sim, robot, terrain, contact_aware_landing):
    controller = WalkingController(WalkingControllerParams(
        robot=robot.controller_model, balance='stabilizer', swing_target='planned',
        contact_aware_landing=contact_aware_landing, hip_strategy_gain=0.0,
        swing_smoothing_time_constant=0.0, ground_conformance=False,
        pelvis_ground_at_zmp=False))
    modes = []

    def on_cycle(t, window, output, readings):
        modes.append(output.landing_modes[0])

    result = run_trial(sim, controller, 2, 0.2, lane_step_terrain(*terrain),
                       on_cycle=on_cycle)
    return result, modes


MARGINAL = pytest.mark.xfail(reason='walked through once, fell on a fresh backend: marginal',
                             strict=False)


@MARGINAL
def test_a_late_touchdown_seeks_the_ground_and_walks_through(sim, robot):
    result, modes = walk(sim, robot, (-0.02, 0.02), contact_aware_landing=True)
    assert not result.fallen
    assert result.max_tilt < 15.0
    assert 'seeking' in modes and 'landed' in modes
    assert modes.index('seeking') < modes.index('landed')
    # the left sole rests on the lowered lane, the right one on the 20 mm platform
    assert result.log.left_sole[-1, 2] == pytest.approx(0.0, abs=0.005)
    assert result.log.right_sole[-1, 2] == pytest.approx(0.02, abs=0.005)
    assert result.log.left_sole[-1, 0] == pytest.approx(0.4, abs=0.05)


def test_without_contact_aware_landing_the_late_touchdown_falls(sim, robot):
    result, _ = walk(sim, robot, (-0.02, 0.02), contact_aware_landing=False)
    assert result.fallen


def test_an_early_touchdown_stops_the_foot_and_walks_through(sim, robot):
    result, modes = walk(sim, robot, (0.015, 0.0), contact_aware_landing=True)
    assert not result.fallen
    assert result.max_tilt < 15.0
    assert 'landed' in modes
    # the left sole ends on the raised lane, the right one on the ground
    assert result.log.left_sole[-1, 2] == pytest.approx(0.015, abs=0.005)
    assert result.log.right_sole[-1, 2] == pytest.approx(0.0, abs=0.005)
