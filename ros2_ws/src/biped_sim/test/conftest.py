"""The COMAN-like humanoid in PyBullet with the stack's stiff servos, shared by the closed-loop
tests of this package (a test module may define its own `robot` or `sim`)."""
import pytest

from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like


@pytest.fixture(scope='module')
def robot():
    return coman_like()


@pytest.fixture(scope='module')
def sim(robot):
    backend = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    yield backend
    backend.close()
