"""Graph tests of the command flow, with real node processes (biped_tools.graph_session) and the
PyBullet humanoid (the model plant diverged under these start-and-stop walks).

The state machine is the one subscriber of the user's topics and forwards each request to the
planner over plan_walk, so a publisher that sends once, as soon as it has matched a subscriber
(`ros2 topic pub --once`), is never lost; a walk driven by cmd_vel stops when cmd_vel falls
silent; a robot pushed over is reset and walks again.
"""
import math
import time

from biped_msgs.msg import CommandStatus, FootstepPlan, WalkCommand, WalkingState
from geometry_msgs.msg import PoseStamped, Twist
import numpy as np
import pytest
from std_srvs.srv import Trigger

from biped_planner.occupancy_grid import OccupancyGrid
from biped_tools.graph_session import GraphSession
from ros_harness import domain_id_for_worker, goal_pose_msg

REPEATS = 20


class Watch:
    """Every walking_state, walk_command_status and footstep_plan the session's client sees."""

    def __init__(self, session: GraphSession) -> None:
        from rclpy.qos import DurabilityPolicy, QoSProfile
        self.session = session
        self.states, self.statuses, self.plans = [], [], []
        self._publishers = []
        node = session.node
        node.create_subscription(WalkingState, 'walking_state', self.states.append, 100)
        node.create_subscription(CommandStatus, 'walk_command_status', self.statuses.append, 100)
        node.create_subscription(FootstepPlan, 'footstep_plan', self.plans.append, QoSProfile(
            depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        assert session.spin_until(lambda: self.states, 30.0), 'no walking_state'

    def walks(self) -> set:
        """Start times of the walks seen so far."""
        return {s.walk_start_time for s in self.states if s.phase != WalkingState.IDLE and
                s.phase != WalkingState.FALLEN}

    def phase(self) -> int:
        return self.states[-1].phase

    def publish_once(self, msg_type, topic: str, msg) -> None:
        """A fresh publisher that sends msg exactly once, right after its first match (as
        `ros2 topic pub --once` does). It stays until drop_publishers(): a reliable writer
        delivers to a reader that matches it after the send only while it exists."""
        publisher = self.session.node.create_publisher(msg_type, topic, 10)
        self._publishers.append(publisher)
        assert self.session.spin_until(lambda: publisher.get_subscription_count() > 0, 30.0)
        publisher.publish(msg)

    def drop_publishers(self) -> None:
        while self._publishers:
            self.session.node.destroy_publisher(self._publishers.pop())


def at_rate(period: float, action):
    """A callable that runs action at most once every period s of wall time (a teleop)."""
    due = [0.0]

    def tick() -> None:
        if time.monotonic() >= due[0]:
            action()
            due[0] = time.monotonic() + period
    return tick


def stamp(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def only_subscriber_of_user_topics(session) -> None:
    for topic in ('/walk_command', '/goal_pose', '/cmd_vel'):
        session.wait_for_nodes_on(topic, ('state_machine',))  # names known: discovery done
        names = [i.node_name for i in session.node.get_subscriptions_info_by_topic(topic)]
        assert names == ['state_machine'], (topic, names)


@pytest.mark.parametrize('user_topic', ['walk_command', 'goal_pose', 'cmd_vel'])
def test_commands_sent_once_right_after_the_first_match_take_effect_every_time(user_topic):
    """Each command from a fresh publisher that sends it once, as soon as it matches; then the
    walk it started is carried into its first step and ended (STOP, or cmd_vel falling silent
    after a teleop took it over), so that every walk is a whole one."""
    with GraphSession(domain_id_for_worker(), log=print) as session:
        session.wait_until_ready()
        watch = Watch(session)
        only_subscriber_of_user_topics(session)
        if user_topic == 'goal_pose':
            session.publish_map(OccupancyGrid(np.zeros((400, 400), dtype=np.int8), 0.05,
                                              (-10.0, -10.0)))
        teleop = session.node.create_publisher(Twist, 'cmd_vel', 10)
        started = ended = 0
        for attempt in range(REPEATS):
            walks = watch.walks()
            answered = len(watch.statuses)
            if user_topic == 'walk_command':
                watch.publish_once(WalkCommand, 'walk_command',
                                   WalkCommand(command=WalkCommand.START))
            elif user_topic == 'goal_pose':
                x, y = session.series.pelvis[-1][1:3]
                watch.publish_once(PoseStamped, 'goal_pose', goal_pose_msg(x + 0.5, y))
            else:
                watch.publish_once(Twist, 'cmd_vel', Twist())
            if session.spin_until(lambda: watch.walks() - walks, 60.0):
                started += 1
            else:
                print(f'[test] {user_topic} {attempt + 1} did not start: statuses '
                      f'{[(s.command, s.error_msg) for s in watch.statuses[answered:]]}')
            if user_topic == 'cmd_vel':  # a teleop at 10 Hz takes the walk into its step
                tick = at_rate(0.1, lambda: teleop.publish(Twist()))
                session.spin_until(lambda: tick() or watch.phase() in (
                    WalkingState.SINGLE_SUPPORT, WalkingState.IDLE), 60.0)
            else:
                session.spin_until(lambda: watch.phase() in (
                    WalkingState.SINGLE_SUPPORT, WalkingState.IDLE), 60.0)
                watch.publish_once(WalkCommand, 'walk_command',
                                   WalkCommand(command=WalkCommand.STOP))
            if session.spin_until(lambda: watch.phase() == WalkingState.IDLE, 60.0):
                ended += 1
            watch.drop_publishers()
            print(f'[test] {user_topic} {attempt + 1}: started {started}, ended {ended}')
            # fail at the fall: every later command is refused only after its waits time out
            assert not session.fallen(), f'fell in walk {attempt + 1}'
        assert not session.fallen()
    assert (started, ended) == (REPEATS, REPEATS)
    rejected = [s for s in watch.statuses if not s.accepted]
    assert not rejected, [(s.command, s.error_msg) for s in rejected]
    if user_topic == 'cmd_vel':
        ends = [b for a, b in zip(watch.states, watch.states[1:])
                if a.phase != WalkingState.IDLE and b.phase == WalkingState.IDLE]
        reasons = [(s.step_index, s.reason) for s in ends]  # (steps, why) of each walk's end
        assert len(ends) == REPEATS and all(s.reason == 'plan finished' for s in ends), reasons
        assert sum('cmd_vel timeout' in s.reason for s in watch.states) >= REPEATS


def test_a_teleop_walk_stops_finishing_its_step_when_cmd_vel_falls_silent():
    with GraphSession(domain_id_for_worker(), log=print) as session:
        session.wait_until_ready()
        watch = Watch(session)
        publisher = session.node.create_publisher(Twist, 'cmd_vel', 10)
        assert session.spin_until(lambda: publisher.get_subscription_count() > 0, 30.0)
        forward = Twist()
        forward.linear.x = 0.1
        sent = []  # sim time of each cmd_vel, as this node's clock has it (not ahead of it)

        def send() -> None:
            publisher.publish(forward)
            sent.append(session.sim_time())
        tick = at_rate(0.1, send)  # a teleop at 10 Hz of wall time
        assert session.spin_until(lambda: tick() or watch.states[-1].step_index >= 5, 120.0), \
            'the teleop walk did not go on'
        walking = [s for s in watch.states if s.phase != WalkingState.IDLE]
        assert not any(s.stop_requested for s in walking)
        # the last cmd_vel went out up to 0.1 s of wall time (several periods of a lockstep
        # clock) before the loop ended: the timeout counts from it, not from the loop's end
        last_sent = sent[-1]
        assert session.spin_until(lambda: watch.phase() == WalkingState.IDLE, 60.0)
        assert session.wait_sim_time(1.0, 30.0)
        assert not session.fallen()
    stop = next(s for s in watch.states if 'cmd_vel timeout' in s.reason)
    assert stamp(stop) >= last_sent + 0.5 - 0.03  # one control period of slack
    plan = [p for p in watch.plans if p.plan_id == watch.states[-1].plan_id][-1]
    assert not plan.continuous  # the planner's stop plan: the step taken, then closing
    last, closing = plan.footsteps[-2:]
    assert closing.side != last.side and math.hypot(closing.x - last.x, closing.y - last.y) < 0.2
    end = watch.states[-1]
    assert end.reason == 'plan finished' and end.step_index == len(plan.footsteps) - 2


def test_a_robot_pushed_over_is_reset_and_walks_ten_steps():
    with GraphSession(domain_id_for_worker(), log=print) as session:
        session.wait_until_ready()
        watch = Watch(session)
        assert session.push(400.0, duration=0.3)
        assert session.spin_until(lambda: watch.phase() == WalkingState.FALLEN, 60.0), \
            'the push did not make it fall'
        reset = session.node.create_client(Trigger, 'reset')
        assert reset.wait_for_service(timeout_sec=10.0)
        future = reset.call_async(Trigger.Request())
        assert session.spin_until(future.done, 30.0)
        assert future.result().success, future.result().message
        assert 'simulator' in future.result().message
        assert session.spin_until(lambda: watch.states[-1].epoch == 1 and
                                  watch.phase() == WalkingState.IDLE, 30.0)
        reset_at = session.sim_time()
        assert session.wait_sim_time(2.0, 60.0)
        assert watch.phase() == WalkingState.IDLE, 'it fell again after the reset'
        watch.publish_once(WalkCommand, 'walk_command', WalkCommand(command=WalkCommand.START))
        assert session.spin_until(lambda: watch.states[-1].step_index >= 10 or
                                  watch.phase() == WalkingState.FALLEN, 300.0)
        watch.publish_once(WalkCommand, 'walk_command', WalkCommand(command=WalkCommand.STOP))
        assert session.spin_until(lambda: watch.phase() in (WalkingState.IDLE,
                                                             WalkingState.FALLEN), 120.0)
        pelvis = session.series.pelvis[-1]
    after = [s for s in watch.states if stamp(s) > reset_at]
    assert not any(s.fallen for s in after)
    assert max(s.step_index for s in after) >= 10
    assert pelvis[3] > 0.5  # standing
