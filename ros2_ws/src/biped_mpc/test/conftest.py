"""Shared fixtures of the biped_mpc tests: the paper's walk from the planner, the robot model."""
import pytest

from biped_mpc.lipm_model import LipmParams
from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, load_robot_model
from biped_mpc.three_mass_model import ThreeMassParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference


@pytest.fixture(scope='session')
def paper_reference():
    """Five 0.8 m steps of 1 s (0.8 s single, 0.2 s double support), 0.1 m long feet."""
    params = ReferenceParams(
        com_height=LipmParams.from_three_mass(ThreeMassParams()).com_height,
        foot_length=0.1, foot_width=0.08, support_scale=0.9)
    return WalkingReference(straight_footsteps(5, 0.8, 0.2),
                            StepTiming(single_support=0.8, double_support=0.2), params)


@pytest.fixture(scope='session')
def coman_like_model():
    """The COMAN-like humanoid as the controller sees it (the model file shipped here)."""
    return load_robot_model(COMAN_LIKE_MODEL_FILE)


@pytest.fixture(scope='session')
def coman_like_urdf():
    """Path of the COMAN-like URDF, for the Pinocchio IK: the simulator's file (biped_sim
    builds it from the same leg geometry)."""
    return str(pytest.importorskip('biped_sim.robot_builder').COMAN_LIKE_URDF)
