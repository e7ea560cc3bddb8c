"""Bad inputs of the user's and the planner's side: walk_command, goal_pose, cmd_vel, map,
footstep_plan, walking_state, sole_poses, balance_estimate, step_adjustment, and the services
reset and plan_walk (the graph runs with the step adjuster on: GRAPH_OVERRIDES).

Each Case names the nodes that read the input and what their answer must say
(bad_input_harness). Sent while the robot walks in place.
"""
import math

from biped_msgs.msg import (BalanceEstimate, Footstep, FootstepPlan, StepAdjustment,
                            WalkCommand, WalkingState)
from biped_msgs.srv import PlanWalk
from geometry_msgs.msg import PoseArray, PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid
from std_srvs.srv import Trigger

from biped_planner.errors import BipedPlannerError
from biped_planner.node_support.map_messages import grid_from_msg

from bad_input_harness import Case, logs, refused_response, refused_status, Topic
from ros_harness import goal_pose_msg

NAN, INF, HUGE = math.nan, math.inf, 1e30
INVALID_VALUE, UNKNOWN_COMMAND, NOT_ALLOWED = 1, 2, 3  # biped_msgs/CommandStatus
INVALID_COMMAND, UNKNOWN_FRAME = FootstepPlan.ERROR_INVALID_COMMAND, \
    FootstepPlan.ERROR_UNKNOWN_FRAME



def a_valid_map(msg: OccupancyGrid) -> bool:
    """Whether the nodes take msg (a case copies the newest valid map: a bad map that DDS
    delivers back must not become the base of the next case, whose rejection would then read
    like the one before and be rate-limited as it)."""
    try:
        grid_from_msg(msg)
    except (BipedPlannerError, ValueError):
        return False
    return all(math.isfinite(v) for v in (msg.info.origin.position.x,
                                          msg.info.origin.position.y))


TOPICS = {
    'walk_command': Topic(WalkCommand, flow=False),
    'goal_pose': Topic(PoseStamped, flow=False),
    'cmd_vel': Topic(Twist, flow=False),
    'map': Topic(OccupancyGrid, latched=True, flow=False, usable=lambda m: (
        m.header.frame_id == 'map' and 0.0 < m.info.resolution < 1.0 and
        len(m.data) == m.info.width * m.info.height > 0 and a_valid_map(m))),
    'footstep_plan': Topic(FootstepPlan, latched=True, flow=False, usable=lambda m: (
        m.status == FootstepPlan.STATUS_OK and len(m.footsteps) > 3)),
    'walking_state': Topic(WalkingState),
    'sole_poses': Topic(PoseArray),
    'balance_estimate': Topic(BalanceEstimate),
    'step_adjustment': Topic(StepAdjustment, flow=False),
}
# the reference generator reads balance_estimate only with its step adjuster or its landing
# hold on
GRAPH_OVERRIDES = {'reference_generator': ['step_adjustment.enabled:=true',
                                           'landing_hold.enabled:=true']}
SERVICES = {'reset': Trigger, 'plan_walk': PlanWalk}

SM, PLANNER, REFERENCES, CONTROLLER, SIM = ('state_machine', 'footstep_planner',
                                            'reference_generator', 'mpc_controller', 'simulator')


def mutated(change):
    """A builder that applies change(msg) to the copy of the real message."""
    def build(msg, _fuzzer):
        change(msg)
        return msg
    return build


def setting(path: str, value):
    """A builder setting one (dotted, indexable) field of the real message's copy."""
    def change(msg):
        *parents, last = path.split('.')
        target = msg
        for part in parents:
            target = target[int(part)] if part.isdigit() else getattr(target, part)
        if last.isdigit():
            target[int(last)] = value
        else:
            setattr(target, last, value)
    return mutated(change)


# --- walk_command -------------------------------------------------------------------------
def command(frame_id: str = '', **fields):
    def build(_msg, _fuzzer):
        msg = WalkCommand(**fields)
        msg.header.frame_id = frame_id
        return msg
    return build


GOTO, OMNI, START = WalkCommand.GOTO, WalkCommand.OMNI, WalkCommand.START
WALK_COMMAND = [
    ('command 9', 'enum', command(command=9), UNKNOWN_COMMAND),
    ('GOTO goal_x NaN', 'nan', command(command=GOTO, goal_x=NAN), INVALID_VALUE),
    ('GOTO goal_y inf', 'inf', command(command=GOTO, goal_x=1.0, goal_y=INF), INVALID_VALUE),
    ('GOTO goal_x 1e30', 'huge', command(command=GOTO, goal_x=HUGE), INVALID_VALUE),
    ('GOTO goal_yaw -inf', 'inf', command(command=GOTO, goal_x=1.0, goal_yaw=-INF),
     INVALID_VALUE),
    ('OMNI step_length NaN', 'nan', command(command=OMNI, step_length=NAN), INVALID_VALUE),
    ('OMNI step_length 1e30', 'huge', command(command=OMNI, step_length=HUGE), INVALID_VALUE),
    ('OMNI step_width 5 m', 'bounds', command(command=OMNI, step_width=5.0), INVALID_VALUE),
    ('OMNI step_angle -inf', 'inf', command(command=OMNI, step_angle=-INF), INVALID_VALUE),
    ('START step_time -1 s', 'bounds', command(command=START, step_time=-1.0), INVALID_VALUE),
    ('START step_time NaN', 'nan', command(command=START, step_time=NAN), INVALID_VALUE),
    ('START step_time 1e30', 'huge', command(command=START, step_time=HUGE), INVALID_VALUE),
    ('START start_time NaN', 'nan', command(command=START, start_time=NAN), INVALID_VALUE),
    ('START start_time inf', 'inf', command(command=START, start_time=INF), INVALID_VALUE),
    ('START start_time -1 s', 'bounds', command(command=START, start_time=-1.0),
     INVALID_VALUE),
    ('START start_time 1e30', 'huge', command(command=START, start_time=HUGE), INVALID_VALUE),
    ('STOP start_time NaN', 'nan', command(command=WalkCommand.STOP, start_time=NAN),
     INVALID_VALUE),
    ('STOP start_time 1e30', 'huge', command(command=WalkCommand.STOP, start_time=HUGE),
     INVALID_VALUE),
    ('GOTO in frame odom', 'frame', command(frame_id='odom', command=GOTO, goal_x=1.0),
     INVALID_VALUE),
    ('RESET while walking', 'state', command(command=WalkCommand.RESET), NOT_ALLOWED),
    ('GOTO while walking', 'state', command(command=GOTO, goal_x=1.0), NOT_ALLOWED),
]


# --- goal_pose ----------------------------------------------------------------------------
def goal(frame='map', x=1.0, y=0.0, q=(0.0, 0.0, 0.0, 1.0)):
    return lambda _msg, _fuzzer: goal_pose_msg(x, y, frame, q)


GOAL_POSE = [
    ('empty frame_id', 'frame', goal(frame='')),
    ('frame_id odom', 'frame', goal(frame='odom')),
    ('zero quaternion', 'bounds', goal(q=(0.0, 0.0, 0.0, 0.0))),
    ('quaternion of norm 2', 'bounds', goal(q=(0.0, 0.0, 0.0, 2.0))),
    ('orientation.w NaN', 'nan', goal(q=(0.0, 0.0, 0.0, NAN))),
    ('position.x NaN', 'nan', goal(x=NAN)),
    ('position.y inf', 'inf', goal(y=INF)),
    ('position.x 1e30', 'huge', goal(x=HUGE)),
]


# --- cmd_vel ------------------------------------------------------------------------------
def twist(linear=(0.0, 0.0, 0.0), angular=(0.0, 0.0, 0.0)):
    def build(_msg, _fuzzer):
        msg = Twist()
        msg.linear.x, msg.linear.y, msg.linear.z = linear
        msg.angular.x, msg.angular.y, msg.angular.z = angular
        return msg
    return build


CMD_VEL = [
    ('linear.x NaN', 'nan', twist(linear=(NAN, 0.0, 0.0))),
    ('linear.y inf', 'inf', twist(linear=(0.0, INF, 0.0))),
    ('angular.z 1e30', 'huge', twist(angular=(0.0, 0.0, HUGE))),
    ('linear.x 5 m/s', 'bounds', twist(linear=(5.0, 0.0, 0.0))),
    ('angular.z -inf', 'inf', twist(angular=(0.0, 0.0, -INF))),
    ('linear.z NaN', 'nan', twist(linear=(0.0, 0.0, NAN))),
    ('angular.x NaN', 'nan', twist(angular=(NAN, 0.0, 0.0))),
    ('linear.y -1e30', 'huge', twist(linear=(0.0, -HUGE, 0.0))),
]


# --- map ----------------------------------------------------------------------------------
def a_map(change):
    """The real map (map_server's) changed; without one, a 40 x 40 free map of 0.1 m."""
    def build(msg, _fuzzer):
        if msg is None:
            msg = OccupancyGrid()
            msg.header.frame_id = 'map'
            msg.info.resolution, msg.info.width, msg.info.height = 0.1, 40, 40
            msg.info.origin.position.x = msg.info.origin.position.y = -2.0
            msg.info.origin.orientation.w = 1.0
            msg.data = [0] * 1600
        change(msg)
        return msg
    return build


def drop_last_cell(msg):
    msg.data = list(msg.data)[:-1]


def empty_grid(msg):
    msg.info.width = msg.info.height = 0
    msg.data = []


MAP = [
    ('resolution NaN', 'nan', lambda m: setattr(m.info, 'resolution', NAN)),
    ('resolution inf', 'inf', lambda m: setattr(m.info, 'resolution', INF)),
    ('resolution 0', 'bounds', lambda m: setattr(m.info, 'resolution', 0.0)),
    ('resolution -0.05', 'bounds', lambda m: setattr(m.info, 'resolution', -0.05)),
    ('resolution 1e30', 'huge', lambda m: setattr(m.info, 'resolution', HUGE)),
    ('origin.x NaN', 'nan', lambda m: setattr(m.info.origin.position, 'x', NAN)),
    ('origin.y inf', 'inf', lambda m: setattr(m.info.origin.position, 'y', INF)),
    ('origin.x 1e30', 'huge', lambda m: setattr(m.info.origin.position, 'x', HUGE)),
    ('origin orientation zero', 'bounds', lambda m: setattr(m.info.origin.orientation, 'w', 0.0)),
    ('one cell missing', 'length', drop_last_cell),
    ('no cells, width x height > 0', 'empty', lambda m: setattr(m, 'data', [])),
    ('0 x 0 cells', 'empty', empty_grid),
    ('width 2^32 - 1', 'huge', lambda m: setattr(m.info, 'width', 2 ** 32 - 1)),
    ('a cell of 120', 'bounds', lambda m: m.data.__setitem__(0, 120)),
    ('frame_id odom', 'frame', lambda m: setattr(m.header, 'frame_id', 'odom')),
    ('empty frame_id', 'frame', lambda m: setattr(m.header, 'frame_id', '')),
]


# --- footstep_plan ------------------------------------------------------------------------
def plan(change):
    def build(msg, _fuzzer):
        assert msg is not None, 'no footstep plan to copy'
        change(msg)
        return msg
    return build


def step_field(name, value, index=2):
    return lambda m: setattr(m.footsteps[index], name, value)


def far_last_step(m):
    m.footsteps[-1].x += 5.0


FOOTSTEP_PLAN = [  # (variant, kind, change, readers)
    ('footsteps[2].x NaN', 'nan', step_field('x', NAN), (SM, REFERENCES)),
    ('footsteps[2].y inf', 'inf', step_field('y', INF), (SM, REFERENCES)),
    ('footsteps[2].x 1e30', 'huge', step_field('x', HUGE), (REFERENCES,)),
    ('footsteps[3].yaw NaN', 'nan', step_field('yaw', NAN, 3), (SM, REFERENCES)),
    ('footsteps[2].side 7', 'enum', step_field('side', 7), (SM, REFERENCES)),
    ('status 9', 'enum', lambda m: setattr(m, 'status', 9), (SM, REFERENCES)),
    ('single_support NaN', 'nan', lambda m: setattr(m, 'single_support', NAN),
     (SM, REFERENCES)),
    ('double_support -0.1 s', 'bounds', lambda m: setattr(m, 'double_support', -0.1),
     (SM, REFERENCES)),
    ('single_support 1e30', 'huge', lambda m: setattr(m, 'single_support', HUGE),
     (SM, REFERENCES)),
    ('frame_id odom', 'frame', lambda m: setattr(m.header, 'frame_id', 'odom'), (REFERENCES,)),
    ('last footstep 5 m away', 'bounds', far_last_step, (REFERENCES,)),
    ('no footsteps, status OK', 'empty', lambda m: setattr(m, 'footsteps', []), (REFERENCES,)),
]


# --- walking_state ------------------------------------------------------------------------
def next_epoch(m):
    m.epoch = (m.epoch + 1) % 2 ** 32


WALKING_STATE = [  # readers: the planner (phase, step), references (phase, times, epoch),
    # controller (phase, epoch)
    ('phase 9', 'enum', setting('phase', 9), (PLANNER, REFERENCES, CONTROLLER)),
    ('support_foot 7', 'enum', setting('support_foot', 7), (PLANNER, REFERENCES, CONTROLLER)),
    ('step_index 2^32 - 1', 'huge', setting('step_index', 2 ** 32 - 1), (PLANNER,)),
    ('step_index 1000 ahead', 'bounds', mutated(lambda m: setattr(m, 'step_index',
                                                                  m.step_index + 1000)),
     (PLANNER,)),
    ('walk_start_time NaN', 'nan', setting('walk_start_time', NAN), (REFERENCES,)),
    ('time_in_phase inf', 'inf', setting('time_in_phase', INF), (REFERENCES,)),
    ('phase_duration -1 s', 'bounds', setting('phase_duration', -1.0), (REFERENCES,)),
    ('walk_start_time 1e30', 'huge', setting('walk_start_time', HUGE), (REFERENCES,)),
    ('stop_time NaN', 'nan', setting('stop_time', NAN), (REFERENCES,)),
    ('stop_time -1 s', 'bounds', setting('stop_time', -1.0), (REFERENCES,)),
    ('epoch + 1 while walking', 'state', mutated(next_epoch), (REFERENCES, CONTROLLER)),
]


# --- sole_poses ---------------------------------------------------------------------------
def keep_poses(count):
    def change(m):
        poses = list(m.poses)
        m.poses = (poses * 2)[:count]
    return mutated(change)


SOLE_POSES = [
    ('one pose', 'length', keep_poses(1)),
    ('three poses', 'length', keep_poses(3)),
    ('no poses', 'empty', keep_poses(0)),
    ('poses[0].x NaN', 'nan', setting('poses.0.position.x', NAN)),
    ('poses[1].y inf', 'inf', setting('poses.1.position.y', INF)),
    ('poses[0].x 1e30', 'huge', setting('poses.0.position.x', HUGE)),
    ('poses[0] zero quaternion', 'bounds', setting('poses.0.orientation.w', 0.0)),
    ('poses[1] quaternion of norm 2', 'bounds', setting('poses.1.orientation.w', 2.0)),
    ('frame_id odom', 'frame', setting('header.frame_id', 'odom')),
]


# --- balance_estimate (controller -> the reference generator's step adjuster) ---------------
def far_estimate(m):
    m.com.x += 2.0
    m.dcm.x += 2.0


def ahead(m):
    m.header.stamp.sec += 30


BALANCE_ESTIMATE = [
    ('com.x NaN', 'nan', setting('com.x', NAN)),
    ('dcm.y inf', 'inf', setting('dcm.y', INF)),
    ('dcm.x 1e30', 'huge', setting('dcm.x', HUGE)),
    ('com and dcm 2 m off the plan', 'bounds', mutated(far_estimate)),
    ('stamp 30 s ahead', 'stamp', mutated(ahead)),
    ('frame_id odom', 'frame', setting('header.frame_id', 'odom')),
    # the landing hold's inputs (GRAPH_OVERRIDES turns it on)
    ('landing_modes of one foot', 'mismatched', setting('landing_modes', ['none'])),
    ('no landing_modes', 'empty', setting('landing_modes', [])),
    ('landing_modes flying', 'enum', setting('landing_modes', ['flying', 'none'])),
    ('landing_depths NaN', 'nan', setting('landing_depths', [NAN, 0.0])),
    ('landing_depths inf', 'inf', setting('landing_depths', [0.0, INF])),
    ('landing_depths 1e30', 'huge', setting('landing_depths', [HUGE, 0.0])),
    ('landing_depths -0.1', 'bounds', setting('landing_depths', [0.0, -0.1])),
]


# --- step_adjustment (the reference generator -> planner, state machine) -------------------
def adjustment(change):
    """A StepAdjustment of the walk under way that keeps its plan and touchdown, then change."""
    def build(_msg, fuzzer):
        state = fuzzer.state()
        plans = [p for p in fuzzer.session.series.plans if p.plan_id == state.plan_id and
                 p.status == FootstepPlan.STATUS_OK]
        msg = StepAdjustment(plan_id=state.plan_id, revision=1, step_index=state.step_index,
                             touchdown_time=state.walk_start_time + 1.0,
                             footsteps=[Footstep(side=f.side, x=f.x, y=f.y, yaw=f.yaw)
                                        for f in (plans[-1].footsteps if plans else [])])
        msg.header.frame_id = 'map'
        msg.header.stamp = fuzzer.session.node.get_clock().now().to_msg()
        change(msg)
        return msg
    return build


def held_at(touchdown):
    def change(m):
        m.kind, m.touchdown_time = StepAdjustment.KIND_HELD, touchdown
    return change


def early_at(touchdown):
    def change(m):
        m.kind, m.touchdown_time = StepAdjustment.KIND_EARLY, touchdown
    return change


def moved_walked_footstep(m):
    m.footsteps[0].x += 0.05


STEP_ADJUSTMENT = [  # (variant, kind, change, readers)
    ('footsteps[3].x NaN', 'nan', lambda m: setattr(m.footsteps[3], 'x', NAN), (PLANNER,)),
    ('footsteps[3].y 1e30', 'huge', lambda m: setattr(m.footsteps[3], 'y', HUGE), (PLANNER,)),
    ('no footsteps', 'empty', lambda m: setattr(m, 'footsteps', []), (PLANNER,)),
    ('footsteps[2].side 7', 'enum', lambda m: setattr(m.footsteps[2], 'side', 7), (PLANNER,)),
    ('a walked footstep moved', 'state', moved_walked_footstep, (PLANNER,)),
    ('step_index 2^32 - 1', 'huge', lambda m: setattr(m, 'step_index', 2 ** 32 - 1),
     (PLANNER, SM)),
    ('plan_id 999', 'state', lambda m: setattr(m, 'plan_id', 999), (PLANNER, SM)),
    ('touchdown_time inf', 'inf', lambda m: setattr(m, 'touchdown_time', INF), (SM,)),
    ('touchdown_time NaN', 'nan', lambda m: setattr(m, 'touchdown_time', NAN), (SM,)),
    ('touchdown_time 1e30', 'huge', lambda m: setattr(m, 'touchdown_time', HUGE), (SM,)),
    ('frame_id odom', 'frame', lambda m: setattr(m.header, 'frame_id', 'odom'), (PLANNER,)),
    ('kind 7', 'enum', lambda m: setattr(m, 'kind', 7), (PLANNER, SM)),
    ('kind HELD, touchdown_time NaN', 'nan', held_at(NAN), (SM,)),
    ('kind HELD, touchdown_time 1e30', 'huge', held_at(HUGE), (SM,)),
    ('kind EARLY, touchdown_time NaN', 'nan', early_at(NAN), (SM,)),
    ('kind EARLY, touchdown_time -1e30', 'huge', early_at(-HUGE), (SM,)),
]


# --- services -----------------------------------------------------------------------------
def plan_walk(kind, command_fields=None, goal_fields=None, velocity=None, request_id=900001):
    def build(_msg, _fuzzer):
        request = PlanWalk.Request(request_id=request_id, kind=kind)
        if command_fields is not None:
            request.command = WalkCommand(**command_fields)
        if goal_fields is not None:
            request.goal = goal(**goal_fields)(None, None)
        if velocity is not None:
            request.velocity = twist(*velocity)(None, None)
        return request
    return build


R = PlanWalk.Request
PLAN_WALK = [
    ('kind 9', 'enum', plan_walk(9)),
    ('command 9', 'enum', plan_walk(R.KIND_COMMAND, {'command': 9})),
    ('GOTO goal_x NaN', 'nan', plan_walk(R.KIND_COMMAND, {'command': GOTO, 'goal_x': NAN})),
    ('OMNI step_length 5 m', 'bounds', plan_walk(R.KIND_COMMAND, {'command': OMNI,
                                                                 'step_length': 5.0})),
    ('goal in frame odom', 'frame', plan_walk(R.KIND_GOAL, goal_fields={'frame': 'odom'})),
    ('goal with empty frame_id', 'frame', plan_walk(R.KIND_GOAL, goal_fields={'frame': ''})),
    ('goal zero quaternion', 'bounds', plan_walk(R.KIND_GOAL, goal_fields={
        'q': (0.0, 0.0, 0.0, 0.0)})),
    ('goal position.x inf', 'inf', plan_walk(R.KIND_GOAL, goal_fields={'x': INF})),
    ('goal position.y 1e30', 'huge', plan_walk(R.KIND_GOAL, goal_fields={'y': HUGE})),
    ('velocity linear.x NaN', 'nan', plan_walk(R.KIND_VELOCITY, velocity=((NAN, 0.0, 0.0),))),
    ('velocity angular.z 1e30', 'huge', plan_walk(R.KIND_VELOCITY, velocity=(
        (0.0, 0.0, 0.0), (0.0, 0.0, HUGE)))),
]


def cases() -> list:
    """Every case of this side, in an order that spaces each node's cases apart."""
    groups = [
        [Case('walk_command', v, k, b, {SM: refused_status(code)})
         for v, k, b, code in WALK_COMMAND],
        [Case('goal_pose', v, k, b, {SM: refused_status(INVALID_VALUE)}) for v, k, b in GOAL_POSE],
        [Case('cmd_vel', v, k, b, {SM: refused_status(INVALID_VALUE)}) for v, k, b in CMD_VEL],
        [Case('map', v, k, a_map(change), {PLANNER: logs('map', k, v), SIM: logs('map', k, v)})
         for v, k, change in MAP],
        [Case('footstep_plan', v, k, plan(change), {node: logs('footstep_plan', k, v)
                                                   for node in readers})
         for v, k, change, readers in FOOTSTEP_PLAN],
        [Case('walking_state', v, k, b, {node: logs('walking_state', k, v) for node in readers})
         for v, k, b, readers in WALKING_STATE],
        [Case('sole_poses', v, k, b, {PLANNER: logs('sole_poses', k, v)})
         for v, k, b in SOLE_POSES],
        [Case('balance_estimate', v, k, b, {REFERENCES: logs('balance_estimate', k, v)})
         for v, k, b in BALANCE_ESTIMATE],
        [Case('step_adjustment', v, k, adjustment(change), {node: logs('step_adjustment', k, v)
                                                           for node in readers})
         for v, k, change, readers in STEP_ADJUSTMENT],
        [Case('plan_walk', v, k, b, {PLANNER: refused_response(INVALID_COMMAND, UNKNOWN_FRAME)},
              service=True) for v, k, b in PLAN_WALK],
        [Case('reset', 'while walking', 'state', lambda _m, _f: Trigger.Request(),
              {SM: refused_response()}, service=True)],
    ]
    return interleave(groups)


def interleave(groups) -> list:
    """One case of each group in turn."""
    ordered, index = [], 0
    while any(index < len(group) for group in groups):
        ordered.extend(group[index] for group in groups if index < len(group))
        index += 1
    return ordered
