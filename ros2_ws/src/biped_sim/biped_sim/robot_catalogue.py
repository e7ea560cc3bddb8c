"""The humanoids the simulator loads by name: the COMAN-like robot and the optional others.

A node names its robot with a parameter; the descriptions themselves are built by
biped_sim.robot_description (the COMAN-like robot, from biped_mpc/robots/coman_like.yaml) and
biped_sim.other_robots (G1 and TALOS, from the optional example-robot-data).
"""
from biped_sim import other_robots
from biped_sim.errors import ConfigError
from biped_sim.robot_description import coman_like, RobotDescription

ROBOTS = {'coman_like': coman_like, **other_robots.ROBOTS}


def load_robot(name: str) -> RobotDescription:
    """Return the description of the robot of that name (a key of ROBOTS).

    :raises ConfigError: for an unknown name
    :raises MissingRobotDataError: if an optional robot's data is not installed
    """
    if name not in ROBOTS:
        raise ConfigError(f'robot {name!r} is not one of {sorted(ROBOTS)}')
    return ROBOTS[name]()
