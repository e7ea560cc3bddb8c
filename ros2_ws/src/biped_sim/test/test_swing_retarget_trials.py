"""A forward push while walking forward: the moved landing whips the foot unless retargeted.

With the replans that bend the ZMP to join the plan's own state and no DCM leash (the defaults
until 2026-12-07), where the whip was traced."""
from dataclasses import replace

import pytest

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.sides import SIDES
from biped_sim.push_trial import HUMANOID_ADJUSTER, RECOVERY_SWING_LAG, run_push_schedule
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like


@pytest.fixture(scope='module')
def robot():
    return coman_like()


def forward_push(robot, retarget: bool):
    """80 N from behind early in a right single support, walking forward at 0.1 m steps with
    the step adjuster (traced: it moves the left landing 6 cm forward two thirds into the
    swing)."""
    sim = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    try:
        controller = WalkingController(WalkingControllerParams(
            robot=robot.controller_model, balance='stabilizer', swing_target='planned',
            swing_smoothing_time_constant=RECOVERY_SWING_LAG, swing_retarget=retarget,
            adjusted_walk_dcm_leash=0.0))
        return run_push_schedule(sim, controller, robot.controller_model, (80.0,), 0.0,
                                 'early_single',
                                 replace(HUMANOID_ADJUSTER, replan_dcm_from_footsteps=False),
                                 step_length=0.1)
    finally:
        sim.close()


def largest_step_back(footsteps) -> float:
    """The longest move of a foot behind its own previous footstep (m), 0 for none."""
    back = 0.0
    for side in SIDES:
        xs = [step.x for step in footsteps if step.side == side]
        back = max([back] + [before - after for before, after in zip(xs, xs[1:])])
    return back


def test_a_forward_push_is_answered_without_steps_back_once_the_swing_is_retargeted(robot):
    whipped, retargeted = forward_push(robot, False), forward_push(robot, True)
    assert whipped.largest_withstood == retargeted.largest_withstood == 80.0
    assert retargeted.revisions >= 1
    # the whipped foot lands past its footstep and slides on, the DCM behind it, and the
    # next steps come back for it; the retargeted one lands on it and the walk goes on
    assert largest_step_back(whipped.footsteps) > 0.1
    assert largest_step_back(retargeted.footsteps) < 0.005
