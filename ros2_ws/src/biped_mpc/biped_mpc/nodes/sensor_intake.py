"""The controller's sensor messages checked at the boundary, the newest valid one kept per topic.

A message is refused (and the previous valid one kept) when its frame is not the expected one,
its stamp goes back, jumps ahead of the stream's (unless the node's clock has run through the gap
or the stream had been silent in wall time: this node or its producer held up), or lies in the
future of the node's clock (when it follows /clock), or a value is not finite or
beyond the physical bounds of biped_mpc.input_bounds (positions outside the workspace, joints
past their limits, forces beyond what an F/T sensor measures, quaternions that are not unit).
"""
from dataclasses import dataclass
import math
import time
from typing import Callable, Dict, Optional, Sequence, Tuple

import numpy as np

from biped_mpc.controller_io import ControllerFeedback
from biped_mpc.controller_params import PELVIS_GROUND_TRUTH
from biped_mpc.errors import InputError
from biped_mpc.input_bounds import (check_joint_angles, check_position, check_quaternion,
                                    check_vector, InputBounds)
from biped_mpc.nodes.conversions import world_velocity
from biped_planner.node_support.stamps import seconds_of

Stamp = Tuple[int, int]
CLOCK_JUMP = 0.1  # s: a stamp this close to a clock that went back follows the clock
CLOCK_LAG = 0.1  # s: how far a stream may run ahead of the node's clock (its /clock handled later)
MAX_JUMP = 0.25  # s: a stream's stamps move on by a period; farther ahead is refused
SILENCE = 0.25  # s of wall time: a stream silent this long (its node or this one held up) may jump
NEW_TIMELINE = 25  # stamps off the timeline that run on steadily this long become the time


@dataclass(frozen=True)
class SensorFrames:
    """The frame ids the controller expects on its sensor messages."""

    world: str = 'map'
    pelvis: str = 'pelvis'
    imu: str = 'imu_link'
    left_foot_wrench: str = 'l_ankle_ft'
    right_foot_wrench: str = 'r_ankle_ft'


class SensorIntake:
    """Checks sensor messages and keeps, per topic, the newest valid one.

    :param bounds: physical bounds of the readings
    :param frames: expected frame ids
    :param leg_names: the 12 leg joints joint_states must carry
    :param joint_lower: (12,) their lower limits (rad)
    :param joint_upper: (12,) their upper limits (rad)
    :param clock: now (s) of the node's clock when it is sim time, else None (no future check)
    :param max_lead: how far a stamp may be ahead of that clock (s)
    :param wall: now (s) of a steady wall clock (how long a stream has been silent)
    """

    def __init__(self, bounds: InputBounds, frames: SensorFrames, leg_names: Sequence[str],
                 joint_lower: Sequence[float], joint_upper: Sequence[float],
                 clock: Callable[[], Optional[float]], max_lead: float = 1.0,
                 wall: Callable[[], float] = time.monotonic) -> None:
        self.bounds = bounds
        self._frames = frames
        self._legs = list(leg_names)
        self._lower, self._upper = joint_lower, joint_upper
        self._clock = clock
        self._max_lead = max_lead
        self._wall = wall
        self._moved_on: Dict[str, float] = {}  # wall time each topic's newest stamp came
        self.valid: Dict[str, object] = {}
        self.rejected: Dict[str, Tuple[Stamp, str]] = {}  # topic -> (stamp, why), newest
        self._newest: Dict[str, float] = {}  # newest valid stamp per topic (s)
        self._timelines: Dict[str, Tuple[float, int]] = {}  # off-timeline stamps: last, count
        self._checks = {'joint_states': self._joint_states, 'odom': self._odom, 'imu': self._imu,
                        'zmp': self._zmp, 'left_foot_wrench': self._left_wrench,
                        'right_foot_wrench': self._right_wrench}

    def reset(self) -> None:
        """Forget the stamps seen (a clock that starts again, e.g. a new simulator)."""
        self._newest.clear()

    def accept(self, topic: str, msg) -> Tuple[bool, Optional[str]]:
        """Check a message of topic; keep it when valid.

        :return: (it was kept, why the message was refused or None)
        """
        stamp = msg.header.stamp
        seconds = seconds_of(stamp)
        wall = self._wall()
        # since the stream last moved on (a repeat of its newest stamp, as a simulator holding
        # its clock sends, is not a sign that it runs)
        silent = wall - self._moved_on.get(topic, -math.inf)
        try:
            self._checks[topic](msg)
        except (InputError, ValueError, TypeError) as error:
            self.rejected[topic] = ((stamp.sec, stamp.nanosec), str(error))
            return False, str(error)
        why = self._stamp_problem(topic, seconds, silent)
        if why is not None:
            self.rejected[topic] = ((stamp.sec, stamp.nanosec), why)
            return False, why
        # only a valid message moves the stamps on: a refused one stamped ahead must not make
        # the valid ones that follow look old
        if seconds > self._newest.get(topic, -math.inf):
            self._moved_on[topic] = wall
        self._newest[topic] = seconds
        self.valid[topic] = msg
        return True, None

    def has_period(self, topic: str, period: Stamp) -> bool:
        """Whether the topic's message of this period came (valid or refused)."""
        msg = self.valid.get(topic)
        if msg is not None and (msg.header.stamp.sec, msg.header.stamp.nanosec) == period:
            return True
        return topic in self.rejected and self.rejected[topic][0] == period

    def age(self, topic: str, t: float) -> Optional[float]:
        """How old the newest valid message of topic is at t (s), None without one."""
        msg = self.valid.get(topic)
        return None if msg is None else t - seconds_of(msg.header.stamp)

    def why_stale(self, topic: str) -> str:
        """What the last refused message of topic was refused for ('' when none was)."""
        return self.rejected[topic][1] if topic in self.rejected else ''

    def stale(self, topics: Sequence[str], t: float, timeout: float) -> str:
        """Why the sensor data of time t cannot be trusted ('' when it can): the topics whose
        newest valid message is older than timeout (s)."""
        stale = []
        for topic in topics:
            age = self.age(topic, t)
            if age is not None and age > timeout + 1e-9:
                why = self.why_stale(topic)
                stale.append(f'{topic} {age:.2f} s old' + (f' (refused: {why})' if why else ''))
        return f'sensors stale: {"; ".join(stale)}' if stale else ''

    def feedback(self, pelvis_source: str, contact_force: float) -> ControllerFeedback:
        """The controller's feedback from the newest valid messages.

        :param pelvis_source: PELVIS_GROUND_TRUTH (odom) or the IMU orientation only
        :param contact_force: foot normal force above which it is in contact (N)
        :raises KeyError: naming a topic that has had no valid message yet
        """
        sensors = self.valid
        position = dict(zip(sensors['joint_states'].name, sensors['joint_states'].position))
        legs = [position[name] for name in self._legs]
        contacts = tuple(sensors[topic].wrench.force.z > contact_force
                         for topic in ('left_foot_wrench', 'right_foot_wrench'))
        zmp = (sensors['zmp'].point.x, sensors['zmp'].point.y)
        wrenches = [[w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z]
                    for w in (sensors[topic].wrench
                              for topic in ('left_foot_wrench', 'right_foot_wrench'))]
        if pelvis_source == PELVIS_GROUND_TRUTH:
            odom = sensors['odom']
            pose = odom.pose.pose
            q = pose.orientation
            return ControllerFeedback(
                legs, (q.x, q.y, q.z, q.w), zmp, contacts,
                (pose.position.x, pose.position.y, pose.position.z), world_velocity(odom),
                foot_wrenches=wrenches)
        q = sensors['imu'].orientation
        return ControllerFeedback(legs, (q.x, q.y, q.z, q.w), zmp, contacts,
                                  foot_wrenches=wrenches)

    # --- checks -----------------------------------------------------------------------------
    def _stamp_problem(self, topic: str, seconds: float, silent: float) -> Optional[str]:
        """:param silent: wall time since the topic's stamps last moved on (s)"""
        now = self._clock()
        if now is not None and seconds > now + self._max_lead:
            return f'stamp {seconds:.3f} s is ahead of the clock ({now:.3f} s)'
        newest = self._newest.get(topic)
        if newest is None or newest - 1e-9 <= seconds <= newest + MAX_JUMP:
            self._timelines.pop(topic, None)
            return None
        # the clock itself went back (a new simulator): follow it
        if now is not None and now < newest - CLOCK_JUMP and abs(seconds - now) <= CLOCK_JUMP:
            return None
        # a gap in the stream: one the clock has run through (messages lost), or a silence in
        # wall time (this node held up while a simulator that gave up on it ran on; the node's
        # /clock may be handled after the sensors): the stamp is the time. A stamp ahead within
        # a steady stream is refused (bad input would make the valid ones that follow look old).
        if seconds > newest and ((now is not None and seconds <= now + CLOCK_LAG) or
                                 silent >= SILENCE):
            self._timelines.pop(topic, None)
            return None
        if self._new_timeline(topic, seconds):
            return None
        if seconds < newest:
            return f'stamp {seconds:.3f} s goes back (newest {newest:.3f} s)'
        return f'stamp {seconds:.3f} s jumps ahead of the newest ({newest:.3f} s)'

    def _new_timeline(self, topic: str, seconds: float) -> bool:
        """Whether stamps off the current timeline have run on steadily for NEW_TIMELINE
        messages (a restarted simulator, without a clock to tell): then they are the time."""
        last, count = self._timelines.get(topic, (None, 0))
        steady = last is not None and last < seconds <= last + MAX_JUMP
        count = count + 1 if steady else 1
        if count >= NEW_TIMELINE:
            self._timelines.pop(topic, None)
            return True
        self._timelines[topic] = (seconds, count)
        return False

    def _frame(self, name: str, actual: str, expected: str) -> None:
        if actual != expected:
            raise InputError(f'{name} is {actual!r}, expected {expected!r}')

    def _joint_states(self, msg) -> None:
        if len(msg.name) != len(msg.position):
            raise InputError(f'{len(msg.name)} joint names but {len(msg.position)} positions')
        position = dict(zip(msg.name, msg.position))
        missing = [name for name in self._legs if name not in position]
        if missing:
            raise InputError(f'leg joints {missing} missing')
        check_joint_angles(self._legs, [position[name] for name in self._legs], self._lower,
                           self._upper, self.bounds)

    def _odom(self, msg) -> None:
        self._frame('odom frame_id', msg.header.frame_id, self._frames.world)
        self._frame('odom child_frame_id', msg.child_frame_id, self._frames.pelvis)
        pose, twist = msg.pose.pose, msg.twist.twist
        check_position('odom position', (pose.position.x, pose.position.y, pose.position.z),
                       self.bounds)
        q = pose.orientation
        check_quaternion('odom orientation', (q.x, q.y, q.z, q.w), self.bounds)
        check_vector('odom linear velocity', (twist.linear.x, twist.linear.y, twist.linear.z),
                     self.bounds.max_speed, 'm/s')
        check_vector('odom angular velocity', (twist.angular.x, twist.angular.y,
                                               twist.angular.z),
                     self.bounds.max_angular_speed, 'rad/s')

    def _imu(self, msg) -> None:
        self._frame('imu frame_id', msg.header.frame_id, self._frames.imu)
        q = msg.orientation
        check_quaternion('imu orientation', (q.x, q.y, q.z, q.w), self.bounds)
        w, a = msg.angular_velocity, msg.linear_acceleration
        check_vector('imu angular velocity', (w.x, w.y, w.z), self.bounds.max_angular_speed,
                     'rad/s')
        check_vector('imu linear acceleration', (a.x, a.y, a.z), self.bounds.max_acceleration,
                     'm/s^2')

    def _zmp(self, msg) -> None:
        self._frame('zmp frame_id', msg.header.frame_id, self._frames.world)
        xy = np.array([msg.point.x, msg.point.y], dtype=float)
        if np.all(np.isnan(xy)):
            return  # no foot on the ground: the sensors have no ZMP
        check_position('zmp', xy, self.bounds)

    def _wrench(self, msg, side: str, frame: str) -> None:
        self._frame(f'{side} foot wrench frame_id', msg.header.frame_id, frame)
        f, m = msg.wrench.force, msg.wrench.torque
        check_vector(f'{side} foot force', (f.x, f.y, f.z), self.bounds.max_force, 'N')
        check_vector(f'{side} foot torque', (m.x, m.y, m.z), self.bounds.max_torque, 'N m')

    def _left_wrench(self, msg) -> None:
        self._wrench(msg, 'left', self._frames.left_foot_wrench)

    def _right_wrench(self, msg) -> None:
        self._wrench(msg, 'right', self._frames.right_foot_wrench)
