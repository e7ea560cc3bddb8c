"""Bad inputs of the controller's and the simulator's side: reference_trajectory, joint_states,
odom, the foot wrenches, zmp, joint_commands, and the services push and set_terrain.

Each sensor case is a copy of the next real message with one field made bad (its stamp is the
current period's, so the value checks are reached), published as a second publisher would.
imu has no reader in the default graph (the controller takes the pelvis from odom,
pelvis_source ground_truth), so it has no case.
"""
import math

from biped_msgs.msg import ReferenceTrajectory
from biped_msgs.srv import Push, SetTerrain
from geometry_msgs.msg import PointStamped, WrenchStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState

from bad_input_commands_cases import CONTROLLER, interleave, mutated, REFERENCES, setting, SIM, \
    SM
from bad_input_harness import Case, logs, refused_response, Topic

NAN, INF, HUGE = math.nan, math.inf, 1e30

TOPICS = {
    'reference_trajectory': Topic(ReferenceTrajectory),
    'joint_states': Topic(JointState),
    'odom': Topic(Odometry),
    'left_foot_wrench': Topic(WrenchStamped),
    'right_foot_wrench': Topic(WrenchStamped),
    'zmp': Topic(PointStamped, usable=lambda m: math.isfinite(m.point.x)),
    'joint_commands': Topic(JointState),
}
SERVICES = {'push': Push, 'set_terrain': SetTerrain}


def shifted(seconds: float, change=None):
    """The real message stamped seconds later (earlier when negative), then changed."""
    def apply(msg):
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9 + seconds
        msg.header.stamp.sec = int(math.floor(t))
        msg.header.stamp.nanosec = int((t - math.floor(t)) * 1e9) % 1_000_000_000
        if change is not None:
            change(msg)
    return mutated(apply)


def array_item(name: str, index: int, value):
    return mutated(lambda m: getattr(m, name).__setitem__(index, value))


def drop_last(name: str):
    return mutated(lambda m: setattr(m, name, list(getattr(m, name))[:-1]))


def empty_reference(msg):
    """Every array empty (the scalar fields keep their values: a setter takes anything, and a
    list in an integer field aborts the message's conversion to C)."""
    for name, kind in msg.get_fields_and_field_types().items():
        if kind.startswith('sequence<'):
            setattr(msg, name, [])


def foot_jump(msg):
    msg.left_foot_x = [x + (0.8 if i >= 40 else 0.0) for i, x in enumerate(msg.left_foot_x)]


REFERENCE = [
    ('all arrays empty', 'empty', mutated(empty_reference)),
    ('zmp_x one sample short', 'length', drop_last('zmp_x')),
    ('zmp_x[3] NaN', 'nan', array_item('zmp_x', 3, NAN)),
    ('hip_y[10] inf', 'inf', array_item('hip_y', 10, INF)),
    ('left_foot_x[0] 1e30', 'huge', array_item('left_foot_x', 0, HUGE)),
    ('support[5] 7', 'enum', array_item('support', 5, 7)),
    ('step_index one sample short', 'length', drop_last('step_index')),
    ('zmp_max_y[0] NaN', 'nan', array_item('zmp_max_y', 0, NAN)),
    ('dt NaN', 'nan', setting('dt', NAN)),
    ('dt 0.1 s (the controller runs at 0.02 s)', 'bounds', setting('dt', 0.1)),
    ('frame_id odom', 'frame', setting('header.frame_id', 'odom')),
    ('left foot jumps 0.8 m', 'bounds', mutated(foot_jump)),
    ('stamp 1 s back', 'stamp', shifted(-1.0)),
    ('stamp 100 s ahead', 'stamp', shifted(100.0)),
]


def leg_joint(fuzzer) -> str:
    """A leg joint the controller commands (the names of its joint_commands)."""
    command = fuzzer.latest('joint_commands')
    return command.name[3] if command is not None and len(command.name) > 3 else 'l_knee'


def joint_value(value, velocity: bool = False):
    """The real JointState with a leg joint's position (or velocity) set to value."""
    def build(msg, fuzzer):
        index = list(msg.name).index(leg_joint(fuzzer)) if leg_joint(fuzzer) in msg.name else 0
        (msg.velocity if velocity else msg.position)[index] = value
        return msg
    return build


def rename_joints(msg):
    msg.name = [f'joint_{i}' for i in range(len(msg.name))]


def no_joints(msg):
    msg.name, msg.position, msg.velocity, msg.effort = [], [], [], []


JOINT_STATES = [
    ('a leg joint NaN', 'nan', joint_value(NAN)),
    ('a leg joint inf', 'inf', joint_value(INF)),
    ('a leg joint 1e30', 'huge', joint_value(HUGE)),
    ('a leg joint -1e30', 'huge', joint_value(-HUGE)),
    ('a leg joint at 10 rad', 'bounds', joint_value(10.0)),
    ('one position short', 'length', drop_last('position')),
    ('no joints', 'empty', mutated(no_joints)),
    ('unknown joint names', 'enum', mutated(rename_joints)),
    ('stamp 1 s back', 'stamp', shifted(-1.0)),
    ('stamp 100 s ahead', 'stamp', shifted(100.0)),
]

ODOM = [  # (variant, kind, builder, readers besides the controller)
    ('position.x NaN', 'nan', setting('pose.pose.position.x', NAN), (SM,)),
    ('position.z inf', 'inf', setting('pose.pose.position.z', INF), (SM,)),
    ('position.y -inf', 'inf', setting('pose.pose.position.y', -INF), (SM,)),
    ('position.x 1e30', 'huge', setting('pose.pose.position.x', HUGE), (SM,)),
    ('zero quaternion', 'bounds', mutated(lambda m: setattr(
        m.pose.pose, 'orientation', type(m.pose.pose.orientation)(w=0.0))), (SM,)),
    ('quaternion of norm 2', 'bounds', mutated(lambda m: setattr(
        m.pose.pose, 'orientation', type(m.pose.pose.orientation)(w=2.0))), (SM,)),
    ('frame_id odom', 'frame', setting('header.frame_id', 'odom'), (SM,)),
    ('child_frame_id base_link', 'frame', setting('child_frame_id', 'base_link'), ()),
    ('linear velocity 1e30', 'huge', setting('twist.twist.linear.x', HUGE), ()),
    ('angular velocity NaN', 'nan', setting('twist.twist.angular.z', NAN), ()),
    ('stamp 1 s back', 'stamp', shifted(-1.0), (SM,)),
    ('stamp 100 s ahead', 'stamp', shifted(100.0), (SM,)),
    ('position.x NaN, stamped 0.5 s ahead', 'stamp', shifted(0.5, lambda m: setattr(
        m.pose.pose.position, 'x', NAN)), (SM,)),
]

WRENCH = [  # (topic, variant, kind, builder)
    ('left_foot_wrench', 'force.z NaN', 'nan', setting('wrench.force.z', NAN)),
    ('left_foot_wrench', 'torque.x inf', 'inf', setting('wrench.torque.x', INF)),
    ('left_foot_wrench', 'force.z 1e30', 'huge', setting('wrench.force.z', HUGE)),
    ('left_foot_wrench', 'frame_id r_ankle_ft', 'frame', setting('header.frame_id',
                                                                  'r_ankle_ft')),
    ('left_foot_wrench', 'stamp 1 s back', 'stamp', shifted(-1.0)),
    ('right_foot_wrench', 'force.x -inf', 'inf', setting('wrench.force.x', -INF)),
    ('right_foot_wrench', 'torque.y 1e30', 'huge', setting('wrench.torque.y', HUGE)),
    ('right_foot_wrench', 'force.z 1e5 N', 'bounds', setting('wrench.force.z', 1e5)),
    ('right_foot_wrench', 'empty frame_id', 'frame', setting('header.frame_id', '')),
    ('right_foot_wrench', 'stamp 100 s ahead', 'stamp', shifted(100.0)),
]

ZMP = [
    ('point.x NaN', 'nan', setting('point.x', NAN)),
    ('point.y inf', 'inf', setting('point.y', INF)),
    ('point.x 1e30', 'huge', setting('point.x', HUGE)),
    ('frame_id odom', 'frame', setting('header.frame_id', 'odom')),
    ('stamp 1 s back', 'stamp', shifted(-1.0)),
]


def unknown_joint(msg):
    msg.name = list(msg.name)
    msg.name[0] = 'no_such_joint'


def velocities_short(msg):
    msg.velocity = list(msg.velocity)[:-1] if len(msg.velocity) else [0.0]


JOINT_COMMANDS = [  # (variant, kind, builder, readers)
    ('a position NaN', 'nan', array_item('position', 2, NAN), (SIM,)),
    ('a position inf', 'inf', array_item('position', 2, INF), (SIM,)),
    ('a position 1e30', 'huge', array_item('position', 2, HUGE), (SIM,)),
    ('a position at 10 rad', 'bounds', array_item('position', 2, 10.0), (SIM,)),
    ('one position short', 'length', drop_last('position'), (SIM,)),
    ('an unknown joint', 'enum', mutated(unknown_joint), (SIM,)),
    ('no joints', 'empty', mutated(no_joints), (SIM,)),
    ('a velocity 1e30', 'huge', array_item('velocity', 2, HUGE), (SIM,)),
    ('one velocity short', 'length', mutated(velocities_short), (SIM,)),
    ('stamp 100 s ahead', 'stamp', shifted(100.0), (SIM, REFERENCES)),
    ('stamp 1 s back', 'stamp', shifted(-1.0), (SIM,)),
]


def push(force=(1.0, 0.0, 0.0), duration=0.1, link='', point=(0.0, 0.0, 0.0)):
    def build(_msg, _fuzzer):
        request = Push.Request(duration=duration, link=link)
        request.force.x, request.force.y, request.force.z = force
        request.point.x, request.point.y, request.point.z = point
        return request
    return build


PUSH = [
    ('force.x NaN', 'nan', push(force=(NAN, 0.0, 0.0))),
    ('force.y inf', 'inf', push(force=(0.0, INF, 0.0))),
    ('force.x 1e30', 'huge', push(force=(HUGE, 0.0, 0.0))),
    ('duration -1 s', 'bounds', push(duration=-1.0)),
    ('duration 0 s', 'bounds', push(duration=0.0)),
    ('duration NaN', 'nan', push(duration=NAN)),
    ('duration 1e30 s', 'huge', push(duration=HUGE)),
    ('unknown link', 'enum', push(link='no_such_link')),
    ('point 1e30 m from the link', 'huge', push(point=(HUGE, 0.0, 0.0))),
    ('point.z NaN', 'nan', push(point=(0.0, 0.0, NAN))),
]


def terrain(**fields):
    def build(_msg, _fuzzer):
        return SetTerrain.Request(**{'kind': SetTerrain.Request.TILES, **fields})
    return build


SET_TERRAIN = [
    ('kind 7', 'enum', terrain(kind=7)),
    ('side_length NaN', 'nan', terrain(side_length=NAN)),
    ('tile_size inf', 'inf', terrain(tile_size=INF)),
    ('tile_size 0', 'bounds', terrain(tile_size=0.0)),
    ('min_height above max_height', 'bounds', terrain(min_height=0.05, max_height=0.01)),
    ('side_length 1e30', 'huge', terrain(side_length=HUGE)),
    ('min_height -1 m', 'bounds', terrain(min_height=-1.0)),
    ('max_height 1e30', 'huge', terrain(max_height=HUGE)),
    ('origin_x NaN', 'nan', terrain(origin_x=NAN)),
]
# sent last: a simulator that tries to build them hangs, and every later case would fail
TOO_MANY_TILES = ('1e8 tiles (100 m side, 1 cm tiles)', 'huge',
                  terrain(side_length=100.0, tile_size=0.01))


def cases() -> list:
    """Every case of this side, each node's cases spaced apart by the others'."""
    groups = [
        [Case('reference_trajectory', v, k, b, {CONTROLLER: logs('reference_trajectory', k, v)})
         for v, k, b in REFERENCE],
        [Case('joint_states', v, k, b, {CONTROLLER: logs('joint_states', k, v)})
         for v, k, b in JOINT_STATES],
        [Case('odom', v, k, b, {node: logs('odom', k, v) for node in (CONTROLLER, *readers)})
         for v, k, b, readers in ODOM],
        [Case(topic, v, k, b, {CONTROLLER: logs(topic, k, v)}) for topic, v, k, b in WRENCH],
        [Case('zmp', v, k, b, {CONTROLLER: logs('zmp', k, v)}) for v, k, b in ZMP],
        [Case('joint_commands', v, k, b, {node: logs('joint_commands', k, v) for node in readers})
         for v, k, b, readers in JOINT_COMMANDS],
        [Case('push', v, k, b, {SIM: refused_response()}, service=True) for v, k, b in PUSH],
        [Case('set_terrain', v, k, b, {SIM: refused_response()}, service=True)
         for v, k, b in SET_TERRAIN],
    ]
    return interleave(groups) + [Case('set_terrain', *TOO_MANY_TILES, {SIM: refused_response()},
                                      service=True)]
