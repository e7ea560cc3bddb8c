"""The paper's MATLAB push test with online step adjustment, and the paper's own criterion."""
import numpy as np
import pytest

from biped_planner.step_adjuster import OnlineStepAdjusterParams
from biped_planner.step_adjustment import StepAdjustmentParams
from biped_mpc.state_estimator import EstimatorParams
from biped_mpc.three_mass_model import three_mass_model
from biped_sim.external_push import ExternalPush
from biped_sim.model_plant import PlantParams
from biped_sim.model_walk import walk, WalkSetup
from biped_sim.push_recovery import evaluate_push, evaluate_push_paper

MODEL = three_mass_model()
# scripts/experiments/model_experiments.py PAPER_STEP_ADJUSTMENT: limits around 0.8 m steps
QP = StepAdjustmentParams(reach_forward=1.1, reach_backward=0.3, step_time_min=0.4,
                          step_time_max=1.2)


def walk_pushed(reference, force, adjuster, noise_seed=None):
    """The experiment's walk with a push at 1.6 s (none for 0 N); with noise_seed, the paper's
    noise level on the measurements and the Kalman filter."""
    push = None if force == 0.0 else ExternalPush((force, 0.0, 0.0), duration=0.1,
                                                  start_time=1.6)
    noise = {} if noise_seed is None else dict(plant=PlantParams.paper_noise(noise_seed),
                                               estimator=EstimatorParams())
    setup = WalkSetup(controller_model=MODEL, plant_model=MODEL, push=push,
                      polygon_margin=(0.005, 0.004), step_adjuster=adjuster,
                      step_adjustment=QP, **noise)
    return walk(reference, setup), push


def pushed_walk(reference, force, adjust, replan_hip_from_estimate=True):
    return walk_pushed(reference, force, OnlineStepAdjusterParams(
        enabled=adjust, replan_hip_from_estimate=replan_hip_from_estimate))


def test_unpushed_walk_is_not_adjusted(paper_reference):
    on, _ = pushed_walk(paper_reference, 0.0, True)
    off, _ = pushed_walk(paper_reference, 0.0, False)
    assert on.revisions == 0 and on.adjustments == ()
    assert on.reference.footsteps == paper_reference.footsteps
    np.testing.assert_allclose(on.log.state, off.log.state, atol=1e-12)


def test_paper_criterion_is_weaker_than_ours(paper_reference):
    """435 N: the ZMP returns and the walk completes, but a leg mass strays 0.25 m."""
    run, push = pushed_walk(paper_reference, 435.0, False)
    assert evaluate_push_paper(run.log, push).withstood
    strict = evaluate_push(run.log, push)
    assert not strict.withstood
    assert any('leg mass' in failure for failure in strict.failures)


def test_step_adjustment_recovers_a_push_the_fixed_plan_does_not(paper_reference):
    """-500 N: without adjustment the robot is still moving at the end; with it, it stands."""
    fixed, push = pushed_walk(paper_reference, -500.0, False)
    verdict = evaluate_push_paper(fixed.log, push)
    assert not verdict.withstood and 'not standing' in verdict.failures[0]
    adjusted, _ = pushed_walk(paper_reference, -500.0, True)
    assert evaluate_push_paper(adjusted.log, push).withstood
    assert adjusted.revisions == len(adjusted.adjustments) > 0
    # a backward push shortens the steps: the walk ends behind the planned end
    assert adjusted.reference.footsteps[-1].x < paper_reference.footsteps[-1].x - 0.05
    # the plant walked the adjusted plan: it stands at its end
    final = adjusted.reference.sample(adjusted.reference.t_end, 1, 0.02).hip[0]
    np.testing.assert_allclose(adjusted.log.com[-1], final, atol=0.05)


def test_replans_from_the_reference_hip_keep_a_pushed_walk_going_forward(paper_reference):
    """550 N forward, the adjuster's defaults replanning from the reference's hip (the
    experiment's adjuster until 2026-12-07, model_experiments.PAPER_ADJUSTER): every
    landing after the push is ahead of the one before, and the walk completes. Replanned from
    the estimate instead, the step's second replan undid the first (landing 1.43 -> 0.5 m) and
    the walk went backwards (0.5, 0.32, 0.02 ... -0.58 m)."""
    run, push = pushed_walk(paper_reference, 550.0, True, replan_hip_from_estimate=False)
    assert run.revisions > 0
    landings = [step.x for step in run.reference.footsteps[2:]]
    assert all(later > earlier for earlier, later in zip(landings, landings[1:-1]))
    assert landings[-1] > paper_reference.footsteps[-1].x - 0.1
    assert evaluate_push_paper(run.log, push).withstood


@pytest.mark.parametrize('seed', [0, 1])
@pytest.mark.parametrize('force', [435.0, -395.0])
def test_the_graphs_adjuster_withstands_the_papers_pushes_by_its_criterion(paper_reference,
                                                                          force, seed):
    """The paper's +435 / -395 N with its noise level, judged by its criterion (the fictitious
    ZMP back inside the support polygon before the walk ends, which ends standing), with the
    graph's adjuster (push_trial.HUMANOID_ADJUSTER, model_experiments.PAPER_ADJUSTER)."""
    from biped_sim.push_trial import HUMANOID_ADJUSTER
    run, push = walk_pushed(paper_reference, force, HUMANOID_ADJUSTER, seed)
    assert run.revisions > 0
    verdict = evaluate_push_paper(run.log, push)
    assert verdict.withstood, verdict.failures


def test_with_the_adjusters_defaults_the_papers_forward_push_is_not_withstood(paper_reference):
    """The dataclass's defaults (0.05 m deadband, half the ankle's authority, frozen 0.2 s
    before touchdown): the same +435 N ends with the ZMP outside after the walk's end or the
    robot not standing (the experiment's figure was +384 N)."""
    adjuster = OnlineStepAdjusterParams(replan_hip_from_estimate=False)
    run, push = walk_pushed(paper_reference, 435.0, adjuster, 0)
    assert not evaluate_push_paper(run.log, push).withstood
