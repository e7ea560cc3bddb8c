"""Closed loop on the model plant: the paper's tracking experiment and its baselines."""
import numpy as np
import pytest

from biped_mpc.linear_mpc import MpcParams
from biped_mpc.lipm_model import lipm_model, LipmParams
from biped_mpc.three_mass_model import three_mass_model, ThreeMassParams
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.model_walk import run_walk, WalkSetup
from biped_sim.walk_log import optimal_fraction, tracking_rms

THREE_MASS = three_mass_model()
LIPM = lipm_model(LipmParams.from_three_mass(ThreeMassParams()))
MARGIN = (0.005, 0.004)


def walk(reference, controller=THREE_MASS, plant=THREE_MASS, **mpc):
    setup = WalkSetup(controller_model=controller, plant_model=plant, mpc=MpcParams(**mpc),
                      polygon_margin=MARGIN)
    return run_walk(reference, setup)


@pytest.fixture(scope='module')
def tracking_log(paper_reference):
    return walk(paper_reference)


def test_tracking_keeps_the_zmp_in_the_scaled_support_polygon_at_every_cycle(tracking_log):
    log = tracking_log
    assert log.t.size == int(round((8.8 - 0.0) / 0.02))
    assert np.all(log.zmp >= log.zmp_min - 1e-9)
    assert np.all(log.zmp <= log.zmp_max + 1e-9)
    assert optimal_fraction(log) == 1.0


def test_tracking_follows_the_references_and_ends_at_rest(tracking_log):
    rms = tracking_rms(tracking_log)
    assert max(rms['left_leg'] + rms['right_leg']) < 0.02
    assert max(rms['zmp']) < 0.02
    np.testing.assert_allclose(tracking_log.com[-1], [4.0, 0.0], atol=1e-3)
    np.testing.assert_allclose(tracking_log.com_velocity[-1], 0.0, atol=1e-3)


def test_torso_has_no_reference_but_stays_near_the_hip(tracking_log):
    assert np.abs(tracking_log.torso - tracking_log.hip).max() < 0.1


def test_lipm_baseline_walks_its_own_lipm_robot(paper_reference):
    log = walk(paper_reference, controller=LIPM, plant=LIPM)
    assert optimal_fraction(log) == 1.0
    assert np.all(log.zmp >= log.zmp_min - 1e-9) and np.all(log.zmp <= log.zmp_max + 1e-9)


def test_lipm_baseline_on_the_three_mass_robot_loses_the_zmp(paper_reference):
    """Ignoring the 30 kg of legs, the baseline's real ZMP leaves the 0.1 m foot by cm."""
    log = walk(paper_reference, controller=LIPM, plant=THREE_MASS)
    assert log.polygon_excursion()[:, 0].max() > 0.05


def test_without_the_terminal_cost_the_paper_outputs_let_the_loop_run_away(paper_reference):
    log = walk(paper_reference, terminal_cost=False, leg_outputs='absolute')
    assert max(tracking_rms(log)['left_leg']) > 1.0


def test_torso_relative_legs_keep_the_loop_bounded_without_the_terminal_cost(paper_reference):
    """Legs measured from the torso make its unstable mode visible in the tracked outputs."""
    log = walk(paper_reference, terminal_cost=False, leg_outputs='torso_relative')
    assert max(tracking_rms(log)['left_leg']) < 0.05


def test_paper_literal_form_is_infeasible_in_the_paper_walk(paper_reference):
    """Hold the last of 20 moves to Np = 80 with hard constraints on all 80 steps."""
    log = walk(paper_reference, move_blocking='hold', constraint_horizon=80,
               terminal_cost=False)
    assert optimal_fraction(log) < 1.0


def test_push_is_applied_on_its_cycles_only(paper_reference):
    setup = WalkSetup(controller_model=THREE_MASS, plant_model=THREE_MASS,
                      push=ExternalPush((100.0, -50.0, 0.0), duration=0.1, start_time=1.6),
                      polygon_margin=MARGIN)
    log = run_walk(paper_reference, setup)
    pushed = np.flatnonzero(np.any(log.force != 0.0, axis=1))
    np.testing.assert_allclose(log.t[pushed], 1.6 + 0.02 * np.arange(5), atol=1e-9)
    np.testing.assert_array_equal(log.force[pushed[0]], [100.0, -50.0])


@pytest.mark.parametrize('kwargs', [dict(force=(1.0,)), dict(force=(np.nan, 0.0, 0.0)),
                                    dict(force=(1.0, 0.0, 0.0), duration=-0.1),
                                    dict(force=(1.0, 0.0, 0.0), start_time=np.inf)])
def test_bad_push_raises(kwargs):
    with pytest.raises(ConfigError):
        ExternalPush(**kwargs)
