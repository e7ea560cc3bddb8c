"""Node-level tests of the reference generator's safety: a reset (a new walking_state epoch)
drops the walk, refused plans and inputs, and a lost state machine reported. Real rclpy and DDS,
sim time driven by the test."""
import math

from biped_msgs.msg import Footstep as FootstepMsg, FootstepPlan, ReferenceTrajectory, \
    WalkingState
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Pose, PoseArray
import numpy as np
import pytest
import rclpy
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile

from biped_planner.footsteps import straight_footsteps
from biped_planner.node_support.reference_messages import window_from_reference_msg
from biped_planner.nodes.reference_generator import ReferenceGeneratorNode
from biped_planner.sides import SUPPORT_DOUBLE
from ros_harness import (Collector, RosoutLines, SimClock, spin_until,
                         wait_for_subscribers)

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


@pytest.fixture
def gen(ros_context, executor):
    executor.track(ReferenceGeneratorNode(context=ros_context, parameter_overrides=[
        Parameter('use_sim_time', value=True)]))
    client = executor.track(rclpy.create_node('reference_test_client', context=ros_context))
    g = dict(client=client, executor=executor, clock=SimClock(client, executor),
             rosout=RosoutLines(client))
    g['refs'] = Collector(client, ReferenceTrajectory, 'reference_trajectory', 50)
    g['diagnostics'] = Collector(client, DiagnosticArray, 'diagnostics', 50)
    g['plan'] = client.create_publisher(FootstepPlan, 'footstep_plan', LATCHED)
    g['state'] = client.create_publisher(WalkingState, 'walking_state', 10)
    g['soles'] = client.create_publisher(PoseArray, 'sole_poses', 10)
    for name in ('plan', 'state', 'soles'):
        assert wait_for_subscribers(executor, g[name], timeout=15), name
    assert wait_for_subscribers(executor, g['clock'].publisher, timeout=15)
    g['clock'].advance(0.05)
    return g


def sole_poses(x: float, frame: str = 'map') -> PoseArray:
    msg = PoseArray()
    msg.header.frame_id = frame
    for y in (0.07, -0.07):
        pose = Pose()
        pose.position.x, pose.position.y, pose.orientation.w = x, y, 1.0
        msg.poses.append(pose)
    return msg


def plan_msg(plan_id: int, footsteps) -> FootstepPlan:
    msg = FootstepPlan(status=FootstepPlan.STATUS_OK, plan_id=plan_id, single_support=0.4,
                       double_support=0.2)
    msg.header.frame_id = 'map'
    msg.footsteps = [FootstepMsg(side=int(f.side), x=float(f.x), y=float(f.y),
                                 yaw=float(f.yaw)) for f in footsteps]
    return msg


def state(g, phase: int, epoch: int = 0, walk_start: float = 0.0) -> None:
    g['state'].publish(WalkingState(phase=phase, epoch=epoch, walk_start_time=walk_start,
                                    plan_id=1))
    g['clock'].advance(0.05)


def newest_window(g):
    count = len(g['refs'].messages)
    g['clock'].advance(0.1)
    assert len(g['refs'].messages) > count, 'no reference'
    return window_from_reference_msg(g['refs'].messages[-1]), g['refs'].messages[-1].plan_id


def test_a_new_epoch_drops_the_walk_and_stands_where_the_controller_puts_the_feet(gen):
    g = gen
    g['soles'].publish(sole_poses(0.0))
    state(g, WalkingState.IDLE)
    g['plan'].publish(plan_msg(1, straight_footsteps(6, 0.1, 0.14)))
    state(g, WalkingState.INITIALIZE, walk_start=g['clock'].t)
    g['clock'].advance(2.0)
    window, plan_id = newest_window(g)
    assert plan_id == 1 and window.hip[-1, 0] > 0.05  # walking forward on plan 1
    # an epoch change while walking is refused: a reset is refused while walking
    state(g, WalkingState.SINGLE_SUPPORT, epoch=1, walk_start=g['clock'].t - 2.0)
    assert g['rosout'].has('walking_state rejected', 'while walking')
    assert newest_window(g)[1] == 1
    # the robot fell; the state machine resets it (epoch 1, Idle) and it stands elsewhere
    state(g, WalkingState.FALLEN)
    state(g, WalkingState.IDLE, epoch=1)
    g['soles'].publish(sole_poses(2.0))
    g['clock'].advance(0.1)
    window, plan_id = newest_window(g)
    assert plan_id == 0
    assert np.all(window.support == SUPPORT_DOUBLE)
    assert window.left_foot[0, :2] == pytest.approx([2.0, 0.07])
    assert window.hip[-1] == pytest.approx([2.0, 0.0])
    assert g['rosout'].has('epoch 1', 'dropped')
    # the old plan is not walked again: a walk waits for a plan of the new epoch
    state(g, WalkingState.INITIALIZE, epoch=1, walk_start=g['clock'].t)
    assert newest_window(g)[1] == 0


def test_the_planners_extension_applies_at_its_step_stamp_plus_the_delay(gen):
    """request_id 0 (the planner's own extension), stamped with the start of the step that
    asked for it: spliced in at stamp + extension_delay, not on arrival; a user's change
    (another request_id) at once."""
    from builtin_interfaces.msg import Time
    g = gen
    g['soles'].publish(sole_poses(0.0))
    state(g, WalkingState.IDLE)
    steps = straight_footsteps(10, 0.1, 0.14)
    g['plan'].publish(plan_msg(1, steps[:8]))
    state(g, WalkingState.INITIALIZE, walk_start=g['clock'].t)
    g['clock'].advance(1.0)
    step_start = round(g['clock'].t - 0.3, 2)
    extension = plan_msg(1, steps[:9])
    extension.header.stamp = Time(sec=int(step_start),
                                  nanosec=round((step_start % 1) * 1e9))
    g['plan'].publish(extension)
    g['clock'].advance(0.02)
    due = step_start + 0.35
    assert g['rosout'].has('9 footsteps', f'extends the walk at t={due:.3f}')
    assert not g['rosout'].has('plan 1: extended')
    g['clock'].advance(0.2)
    assert g['rosout'].has('plan 1: extended at')
    user = plan_msg(1, steps)
    user.request_id = 7
    g['plan'].publish(user)
    g['clock'].advance(0.05)
    assert g['rosout'].has(f'{len(steps)} footsteps): extended')


@pytest.mark.parametrize('change, words', [
    (lambda steps: steps[3].__class__(steps[3].side, 1e30, steps[3].y), 'workspace'),
    (lambda steps: steps[3].__class__(steps[3].side, steps[3].x + 5.0, steps[3].y),
     'from footstep'),
])
def test_a_plan_the_robot_cannot_walk_is_refused(gen, change, words):
    g = gen
    g['soles'].publish(sole_poses(0.0))
    state(g, WalkingState.IDLE)
    steps = list(straight_footsteps(6, 0.1, 0.14))
    steps[3] = change(steps)
    g['plan'].publish(plan_msg(1, steps))
    state(g, WalkingState.INITIALIZE, walk_start=g['clock'].t)
    g['clock'].advance(0.5)
    assert g['rosout'].has('footstep_plan rejected', words)
    window, plan_id = newest_window(g)
    assert plan_id == 0 and np.all(np.abs(window.left_foot) < 1.0)  # stands, walks nothing


def test_malformed_standing_inputs_are_refused(gen):
    g = gen
    g['soles'].publish(sole_poses(0.0))
    g['clock'].advance(0.1)
    g['soles'].publish(sole_poses(math.nan))
    g['soles'].publish(sole_poses(0.5, frame='odom'))
    g['state'].publish(WalkingState(phase=9))
    g['clock'].advance(0.2)
    for words in (('sole_poses rejected', 'outside'), ('sole_poses rejected', "'odom'"),
                  ('walking_state rejected', 'phase 9')):
        assert g['rosout'].has(*words), words
    window, _ = newest_window(g)
    assert window.left_foot[0, :2] == pytest.approx([0.0, 0.07])  # the valid one kept


def test_a_silent_state_machine_is_reported_on_diagnostics(gen):
    g = gen
    g['soles'].publish(sole_poses(0.0))
    for _ in range(10):
        state(g, WalkingState.IDLE)
    count = len(g['diagnostics'].messages)
    g['clock'].advance(1.5, pace=1.0)  # silent for 1.5 s of sim and wall time
    assert spin_until(g['executor'], lambda: any(
        s.level == DiagnosticStatus.ERROR and 'walking_state' in s.message
        for d in g['diagnostics'].messages[count:] for s in d.status), 5)
    state(g, WalkingState.IDLE)  # back
    count = len(g['diagnostics'].messages)
    assert spin_until(g['executor'], lambda: any(
        s.level == DiagnosticStatus.OK
        for d in g['diagnostics'].messages[count:] for s in d.status), 5)
