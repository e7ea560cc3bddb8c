"""A 200 N push from the front, late in a single support while walking in place (the issue's
sagittal target), on the PyBullet humanoid with the step adjuster: walked through when the
replanned reference takes the moved steps' own DCM and the MPC's commanded DCM is brought to
the measured one (the defaults since 2026-12-07), where the adjuster whose replans bend the ZMP
to join the plan's own state, without the DCM leash, falls (docs/controller_notes.md, "A moved
step replanned with its own DCM")."""
from dataclasses import replace
import math

import pytest

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_sim.push_trial import HUMANOID_ADJUSTER, RECOVERY_SWING_LAG, run_push_trial
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like


@pytest.fixture(scope='module')
def robot():
    return coman_like()


def push_from_the_front(robot, force: float, replanned_dcm: bool):
    sim = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    try:
        controller = WalkingController(WalkingControllerParams(
            robot=robot.controller_model, balance='stabilizer', swing_target='planned',
            swing_smoothing_time_constant=RECOVERY_SWING_LAG,
            adjusted_walk_dcm_leash=0.05 if replanned_dcm else 0.0))
        adjuster = replace(HUMANOID_ADJUSTER, replan_dcm_from_footsteps=replanned_dcm)
        return run_push_trial(sim, controller, robot.controller_model, force,
                              math.radians(180.0), 'late_single', adjuster)
    finally:
        sim.close()


def test_the_defaults_are_the_replanned_dcm_and_its_leash():
    assert HUMANOID_ADJUSTER.replan_dcm_from_footsteps
    assert WalkingControllerParams(
        robot=coman_like().controller_model).adjusted_walk_dcm_leash == pytest.approx(0.05)


@pytest.mark.parametrize('force', [200.0, 230.0])
def test_a_push_from_the_front_is_walked_through_on_the_replanned_dcm(robot, force):
    assert push_from_the_front(robot, force, replanned_dcm=False).fallen
    walked = push_from_the_front(robot, force, replanned_dcm=True)
    assert not walked.fallen and walked.revisions >= 1
