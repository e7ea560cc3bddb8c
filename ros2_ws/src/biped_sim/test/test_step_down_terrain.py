"""The platform the step-down sweep walks off (terrain_trial.step_down_terrain)."""
import numpy as np
import pytest

from biped_planner.landing_hold import LandingHoldParams
from biped_sim.push_trial import HUMANOID_ADJUSTER
from biped_sim.robot_description import coman_like
from biped_sim.terrain_trial import run_trial, step_down_terrain


@pytest.mark.parametrize('height, edge', [(0.025, 0.3), (0.05, 0.47)])
def test_the_platform_ends_at_its_edge(height, edge):
    terrain = step_down_terrain(height, edge)
    on = terrain.height_at(np.array([-0.45, 0.0, edge - 0.005, edge - 0.005]),
                           np.array([0.0, 0.0, 0.07, -0.07]))
    off = terrain.height_at(np.array([edge + 0.005, edge + 0.2, -0.55]),
                            np.array([0.0, 0.07, 0.0]))
    np.testing.assert_allclose(on, height)
    np.testing.assert_allclose(off, 0.0)


def test_a_flat_or_empty_platform_is_refused():
    with pytest.raises(ValueError):
        step_down_terrain(0.0, 0.4)
    with pytest.raises(ValueError):
        step_down_terrain(0.03, -0.6)


def test_a_trial_with_the_step_adjuster_needs_the_robot_and_no_landing_hold():
    with pytest.raises(ValueError, match='robot'):
        run_trial(None, None, 4, 0.1, adjuster=HUMANOID_ADJUSTER)
    with pytest.raises(ValueError, match='landing hold'):
        run_trial(None, None, 4, 0.1, adjuster=HUMANOID_ADJUSTER,
                  robot=coman_like().controller_model,
                  landing_hold=LandingHoldParams(enabled=True, hold_time=0.1))
