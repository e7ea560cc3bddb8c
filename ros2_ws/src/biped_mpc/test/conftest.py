"""Fixtures of the biped_mpc tests: the robot model (the paper's walk is in ../../conftest.py)."""
import pytest

from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, load_robot_model


@pytest.fixture(scope='session')
def coman_like_model():
    """The COMAN-like humanoid as the controller sees it (the model file shipped here)."""
    return load_robot_model(COMAN_LIKE_MODEL_FILE)


@pytest.fixture(scope='session')
def coman_like_urdf():
    """Path of the COMAN-like URDF, for the Pinocchio IK: the simulator's file (biped_sim
    builds it from the same leg geometry)."""
    return str(pytest.importorskip('biped_sim.robot_builder').COMAN_LIKE_URDF)
