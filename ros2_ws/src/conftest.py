"""Fixtures shared by the unit tests of every biped package: the paper's MATLAB walk."""
import pytest

from biped_mpc.lipm_model import LipmParams
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
