"""Tests of biped_planner.omnidirectional_stepper, including the paper's omnidirectional run."""
import math

import numpy as np
import pytest

from biped_planner.errors import CommandError, ConfigError
from biped_planner.footsteps import (check_footstep_sequence, LEFT, RIGHT, straight_footsteps)
from biped_planner.kinematic_limits import KinematicLimits, step_violations
from biped_planner.omnidirectional_stepper import (command_from_twist, footsteps_from_commands,
                                                   footsteps_from_schedule,
                                                   OmnidirectionalStepper, StepCommand,
                                                   StepperParams)
from biped_planner.pose2d import Pose2D

STEP_TIME = 0.5
HALF_WIDTH = 0.1


def _check_limits(footsteps, limits=KinematicLimits()):
    check_footstep_sequence(footsteps)
    stance = footsteps[0]
    for landing in footsteps[2:]:
        assert step_violations(stance, landing, limits) == []
        stance = landing


def _bodies(footsteps):
    """Body pose after each landing: the landing moved by d towards the other foot."""
    poses = []
    for step in footsteps[2:]:
        sign = 1.0 if step.side == LEFT else -1.0
        poses.append((step.x + sign * math.sin(step.yaw) * HALF_WIDTH,
                      step.y - sign * math.cos(step.yaw) * HALF_WIDTH, step.yaw))
    return np.array(poses)


def test_walking_in_place_keeps_the_feet():
    steps = footsteps_from_commands(Pose2D(1.0, 2.0, 0.3), [StepCommand()] * 6, STEP_TIME)
    _check_limits(steps)
    for step in steps[2:]:
        initial = steps[0] if step.side == steps[0].side else steps[1]
        assert (step.x, step.y, step.yaw) == pytest.approx((initial.x, initial.y, initial.yaw))


@pytest.mark.parametrize('first_swing', [LEFT, RIGHT])
def test_unfiltered_forward_walk_equals_straight_footsteps(first_swing):
    params = StepperParams(lag_time_constant=0.0)
    steps = footsteps_from_commands(Pose2D(0.0, 0.0, 0.0), [StepCommand(0.12)] * 5, STEP_TIME,
                                    params, first_swing)
    expected = straight_footsteps(5, 0.12, 0.2, first_swing)
    assert len(steps) == len(expected)
    for got, want in zip(steps, expected):
        assert got.side == want.side
        assert (got.x, got.y, got.yaw) == pytest.approx((want.x, want.y, want.yaw), abs=1e-12)


def _paper_schedule(t):
    if t < 2.0:
        return StepCommand()
    if t < 10.0:
        return StepCommand(0.1)
    if t < 20.0:
        return StepCommand(0.1, 0.05)
    if t < 32.0:
        return StepCommand(0.1, 0.05, math.radians(15.0) * STEP_TIME)
    return StepCommand()


def test_paper_omnidirectional_schedule_is_followed():
    """In place, forward 0.1, diagonal 0.1/0.05, plus turning 15 deg/s, back to in place."""
    steps = footsteps_from_schedule(Pose2D(0.0, 0.0, 0.0), _paper_schedule, 40.0, STEP_TIME)
    _check_limits(steps)
    bodies = _bodies(steps)
    start_times = STEP_TIME * np.arange(len(bodies))
    yaw_before = np.concatenate(([0.0], bodies[:-1, 2]))
    turn = bodies[:, 2] - yaw_before
    heading = yaw_before + 0.5 * turn
    delta = np.diff(np.vstack(([0.0, 0.0], bodies[:, :2])), axis=0)
    forward = np.cos(heading) * delta[:, 0] + np.sin(heading) * delta[:, 1]
    sideways = -np.sin(heading) * delta[:, 0] + np.cos(heading) * delta[:, 1]
    settled = 5.0    # s after each change: the lag (tau 0.5 s) has decayed to exp(-10)
    for begin, end, command in ((0.0, 2.0, (0, 0, 0)), (2.0, 10.0, (0.1, 0, 0)),
                                (10.0, 20.0, (0.1, 0.05, 0)),
                                (20.0, 32.0, (0.1, 0.05, math.radians(7.5))),
                                (32.0, 40.0, (0, 0, 0))):
        window = (start_times >= min(begin + settled, end - 1.0)) & (start_times < end)
        assert window.sum() >= 2
        np.testing.assert_allclose(forward[window], command[0], atol=2e-4)
        np.testing.assert_allclose(sideways[window], command[1], atol=2e-4)
        np.testing.assert_allclose(turn[window], command[2], atol=1e-4)
    # the body turned by about 12 s * 15 deg/s = 180 deg in total
    assert bodies[-1, 2] == pytest.approx(math.pi, abs=math.radians(8.0))
    # the closing step puts the feet side by side
    assert abs(steps[-1].yaw - steps[-2].yaw) < 1e-9


def test_filtered_command_follows_the_lag():
    stepper = OmnidirectionalStepper(Pose2D(0.0, 0.0, 0.0), StepperParams(lag_time_constant=1.0))
    for k in range(1, 6):
        stepper.next_footstep(StepCommand(0.1), STEP_TIME)
        assert stepper.filtered_command.step_length == pytest.approx(
            0.1 * (1 - math.exp(-k * STEP_TIME / 1.0)))


def test_incremental_equals_batch_and_state_toggles():
    commands = [StepCommand(0.05 * (k % 3), 0.02 * (k % 2), 0.05 * (k % 4)) for k in range(12)]
    stepper = OmnidirectionalStepper(Pose2D(0.2, -0.1, 0.5))
    phi = []
    for command in commands:
        stepper.next_footstep(command, STEP_TIME)
        phi.append((stepper.state()[3], stepper.state()[7]))
    stepper.close()
    assert stepper.footsteps == footsteps_from_commands(Pose2D(0.2, -0.1, 0.5), commands,
                                                        STEP_TIME)
    assert all(a == -b and abs(a) == 1.0 for a, b in phi)
    assert [a for a, _ in phi[:4]] == [-1.0, 1.0, -1.0, 1.0]


def test_random_commands_respect_the_limits():
    rng = np.random.default_rng(7)
    commands = [StepCommand(*rng.uniform([-0.3, -0.2, -0.6], [0.3, 0.2, 0.6]))
                for _ in range(200)]
    _check_limits(footsteps_from_commands(Pose2D(0.0, 0.0, 0.0), commands, STEP_TIME,
                                          StepperParams(lag_time_constant=0.2)))


def test_twist_conversion():
    command = command_from_twist(0.2, -0.1, 0.3, 0.5)
    assert (command.step_length, command.step_width, command.step_angle) == pytest.approx(
        (0.1, -0.05, 0.15))
    with pytest.raises(CommandError):
        command_from_twist(math.nan, 0.0, 0.0, 0.5)
    with pytest.raises(ConfigError):
        command_from_twist(0.1, 0.0, 0.0, 0.0)


def test_bad_inputs():
    with pytest.raises(CommandError):
        StepCommand(math.inf)
    with pytest.raises(CommandError):
        StepCommand(step_angle='0.1')
    with pytest.raises(ConfigError):
        OmnidirectionalStepper((0.0, 0.0, 0.0))
    with pytest.raises(ConfigError):
        OmnidirectionalStepper(Pose2D(0, 0), first_swing=2)
    with pytest.raises(ConfigError):
        OmnidirectionalStepper(Pose2D(0, 0), params={'step_width': 0.2})
    stepper = OmnidirectionalStepper(Pose2D(0, 0))
    with pytest.raises(CommandError):
        stepper.next_footstep((0.1, 0.0, 0.0), STEP_TIME)
    with pytest.raises(ConfigError):
        stepper.next_footstep(StepCommand(0.1), -0.5)
    with pytest.raises(ConfigError):
        footsteps_from_schedule(Pose2D(0, 0), _paper_schedule, -1.0, STEP_TIME)
    with pytest.raises(ConfigError):
        footsteps_from_schedule(Pose2D(0, 0), _paper_schedule, 4.0, math.nan)
    for kwargs in (dict(step_width=0.0), dict(lag_time_constant=-1.0),
                   dict(max_step_angle=2.0), dict(limits=None)):
        with pytest.raises(ConfigError):
            StepperParams(**kwargs)
    with pytest.raises(ConfigError):
        Pose2D(0.0, math.nan)
