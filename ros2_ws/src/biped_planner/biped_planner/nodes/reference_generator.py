"""The reference generator node: footstep plan + walking state in, MPC references out.

Subscribes: footstep_plan (biped_msgs/FootstepPlan, transient local), walking_state
(biped_msgs/WalkingState: the walk's start time and phase, the reset epoch), sole_poses
(geometry_msgs/PoseArray from the controller: where to stand before the first walk; the
controller sends the measured soles before its first cycle; odom until they arrive only with
standing_from_odom), joint_commands (sensor_msgs/JointState from the controller, on sim time:
see below), balance_estimate (biped_msgs/BalanceEstimate from the controller, with
step_adjustment.enabled, landing_hold.enabled or landing_hold.end_early).
Publishes: reference_trajectory (biped_msgs/ReferenceTrajectory) at the control rate, `horizon`
samples of `dt` from now: ZMP, hip, feet, masses, support polygon and landing bounds;
step_adjustment (biped_msgs/StepAdjustment) when the online step adjuster moved the step under
way; diagnostics (diagnostic_msgs/DiagnosticArray: whether walking_state arrives, adjustments
made) once a second and when that changes.

Step adjustment (biped_planner.step_adjuster, off by default as in the paper): each
balance_estimate of a single support is answered by the adjuster's QP; when it moves the step,
the walk's reference is replanned at once (the next reference_trajectory carries it, with a
higher plan_revision) and step_adjustment tells the planner (which republishes the plan and
plans on from it) and the state machine (which moves the touchdown).

Landing hold (biped_planner.landing_hold, off by default): a swing foot that the controller
reports still seeking the ground past its planned landing holds the single support until it
touches down (WalkingReference.hold_landing); step_adjustment, kind HELD, tells the state
machine the new touchdown; the planner's footsteps do not change. With landing_hold.end_early
a foot reported landed before its planned time ends the single support then (kind EARLY).

On sim time the controller waits for the reference of each period (lockstep). Once it has
answered period t (its joint command stamped t), the simulator steps to t + 1 / rate, so the
reference of that period is sent at once, while physics runs, instead of at its clock tick;
a tick whose reference has not gone out that way (no controller yet) still sends it. A command
that comes before this node's first /clock (across a link the two arrive in either order) is
answered when the clock comes.

The planner's own change of a walk at a step (request_id 0: its extension, or the plan of a STOP
stated for a later time) is stamped with the start of the step that asked for it, and its plan
after a step adjustment with the adjustment's time; each is spliced in from the first reference at
or after stamp + extension_delay, in the order of their times, so a run does not depend on when the
message got through; one that comes later is spliced in at once and logged as late. The reference
of period t answers the balance_estimate of t - 1 and no later one (see _answer_balance_estimates).
On sim time the reference of a time by which a continuous walk's extension is due (and any walk's,
after a step adjustment) waits for it (biped_planner.extension_wait; the controller and, in
lockstep, the simulator wait with it) while the planner's process is alive (DDS liveliness of
footstep_plan/alive), at most extension_wait s of wall time, and not once the clock has passed that
time (a simulator in real time).

A new walking_state.epoch (the state machine reset the robot) drops the walk, its plan and the
standing feet: the references stand where the controller's sole_poses put the feet again. An
epoch change while walking is refused (a reset is refused while walking). Inputs are checked at
the boundary (frames, finite values, the workspace, footsteps farther apart than
max_footstep_distance, a new plan that does not start within max_plan_start_offset of the feet
the references stand on, unknown phases): a refused message is logged and ignored. walking_state
silent for state_timeout (the state machine is gone) is reported ERROR on diagnostics; the
current walk's reference then runs to its plan's end and stands.
"""
import time

import math
from typing import NamedTuple, Optional, Tuple

from biped_msgs.msg import (BalanceEstimate, FootstepPlan, ReferenceTrajectory, StepAdjustment,
                            WalkingState)
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseArray
from nav_msgs.msg import Odometry
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.time import Time
from sensor_msgs.msg import JointState

from biped_planner.errors import BipedPlannerError
from biped_planner.estimate_order import ESTIMATE_WAIT, EstimateOrder
from biped_planner.extension_wait import awaited_extension
from biped_planner.footsteps import feet_beside
from biped_planner.input_watch import InputWatch
from biped_planner.landing_hold import LandingHold, LandingHoldParams
from biped_planner.node_support.dataclass_parameters import (
    declare_dataclass_parameters, declare_live_parameters, declare_node_parameters)
from biped_planner.node_support.latest_message_reader import LatestMessageReader
from biped_planner.node_support.liveliness import LivelinessToken, LivelinessWatch
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.qos import LATCHED_IN
from biped_planner.node_support.reference_messages import reference_trajectory_msg
from biped_planner.node_support.rejection_log import RejectionLog
from biped_planner.node_support.stamps import nanoseconds_of, seconds_of
from biped_planner.node_support.walking_state_checks import walking_state_problem
from biped_planner.nodes.conversions import (checked_pose2d, feet_from_sole_poses,
                                             footstep_msgs, footsteps_from_msgs)
from biped_planner.pose_checks import PoseBounds
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_session import (check_footsteps, check_plan_start, KIND_EARLY,
                                              KIND_HELD, ReferenceSession)
from biped_planner.step_adjuster import OnlineStepAdjuster, OnlineStepAdjusterParams
from biped_planner.step_adjustment import StepAdjustmentParams
from biped_planner.standing_feet import settled_feet
from biped_planner.step_timing import StepTiming
from biped_planner.stop_step import stated_stop_step
from biped_planner.walk_command import MAX_START_LEAD
from biped_planner.walking_state_machine import WALKING_PHASES

WATCH_PERIOD = 0.1  # s of wall time between checks that walking_state still comes
DIAGNOSTICS_PERIOD = 1.0  # s of wall time
MAX_STAMP_LEAD = 1.0  # s: a joint command or walk start farther ahead of the clock is refused
# s of wall time before a reference generator with no feet to stand on says so
STANDING_PATIENCE = 5.0


class ExtensionWait(NamedTuple):
    """A reference held for the planner's extension stamped `stamp` (a step start or a step
    adjustment's time)."""

    stamp: float  # s
    since: Optional[float]  # wall time the wait began; None: given up, the walk goes on
    held_ns: int  # the newest reference time held
    first_ns: int  # the first one: a clock past it runs on without this node (no lockstep)

    @property
    def holding(self) -> bool:
        return self.since is not None


def plan_stamp(record: Optional[Tuple[int, float]], plan_id: int) -> Optional[float]:
    """The stamp (s) of a (plan_id, stamp) record when it is of plan_id, else None."""
    return record[1] if record is not None and record[0] == plan_id else None


def newer_plan_stamp(record: Optional[Tuple[int, float]], plan_id: int,
                     stamp: float) -> Tuple[int, float]:
    """The record to keep after a stamp of plan_id: the newer of the two; another plan's
    record is replaced."""
    known = plan_stamp(record, plan_id)
    return (plan_id, stamp) if known is None or stamp > known else record


class ReferenceGeneratorNode(Node):
    """Thin adapter over biped_planner.reference_session.ReferenceSession."""

    def __init__(self, **kwargs) -> None:
        super().__init__('reference_generator', **kwargs)
        # Descriptions and ranges come from ReferenceParams' parameter() fields.
        self._reference_params = declare_dataclass_parameters(self, ReferenceParams(), {})
        declare_live_parameters(self, PoseBounds(), 'bounds.', '_bounds')
        declare_node_parameters(self, {
            'horizon': (90, 'samples per reference (the MPC needs Np = 80)', (2, 10000)),
            'dt': (0.02, 'sample period of the references, the MPC Ts (s)', (0.001, 1.0)),
            'rate': (50.0, 'references per second without a controller to answer (Hz)',
                     (0.1, 1000.0)),
            'stance_width': (0.2, 'distance between the standing feet before a walk, with '
                             'standing_from_odom (m)', (0.05, 1.0)),
            'standing_from_odom': (False, 'until the controller\'s sole_poses arrive, stand on '
                                   'feet beside the odom pose (a graph without a controller); '
                                   'false: wait for them (the controller sends the measured '
                                   'soles before its first cycle, so a run starts the same '
                                   'whichever message comes first)', None),
            'map_frame': ('map', 'frame of plans, sole poses and odometry', None),
            'max_footstep_distance': (1.0, 'largest distance between consecutive footsteps of '
                                      'a plan (m)', (0.05, 10.0)),
            'max_plan_start_offset': (0.05, 'a new plan whose initial feet are farther than '
                                      'this from where the references stand the feet is '
                                      'refused: the feet would jump there (m)', (0.001, 1.0)),
            'state_timeout': (0.5, 'walking_state silent this long is reported lost (s)',
                              (0.05, 60.0)),
            'extension_delay': (0.35, "the planner's own extension of a walk (request_id 0) "
                                'applies this long after the stamp of the step that asked for '
                                'it, whenever it arrives before then: runs do not depend on '
                                'message timing (s)', (0.0, 5.0)),
            'adjustment_replan_delay': (0.04, "the planner's plan after a step adjustment "
                                        'applies this long after the adjustment: before the '
                                        'next step starts, so that step is not changed while it '
                                        'is walked (s)', (0.0, 1.0)),
            'extension_wait': (2.0, "on sim time, how long (s of wall time) a reference waits "
                               "for the planner's extension due by its time while the planner "
                               'is alive; 0: never waits', (0.0, 60.0))},
            read_only=('horizon', 'dt', 'rate', 'map_frame', 'state_timeout',
                       'standing_from_odom'))
        get = lambda name: self.get_parameter(name).value  # noqa: E731
        self._horizon = max(2, int(get('horizon')))
        self._dt = float(get('dt'))
        self._frame = get('map_frame')
        # Descriptions and ranges from the adjuster's parameter() fields; read at start.
        self._adjuster_params = declare_dataclass_parameters(
            self, OnlineStepAdjusterParams(enabled=False), {}, prefix='step_adjustment.')
        self._hold_params = declare_dataclass_parameters(
            self, LandingHoldParams(), {}, prefix='landing_hold.')
        reference = self._reference_params
        self._step_limits = declare_dataclass_parameters(
            self, StepAdjustmentParams(com_height=reference.com_height), {},
            prefix='step_limits.',
            fixed={'com_height': reference.com_height, 'gravity': reference.gravity})
        self._session = self._new_session()
        self._reject = RejectionLog(self.get_logger().error)
        self._standing = None
        self._phase = None
        # (stop time, when walking_state first said so) of a STOP stated ahead for this walk
        self._stated_stop: Optional[Tuple[float, float]] = None
        self._epoch = None
        self._watch = InputWatch(('walking_state',), timeout=float(get('state_timeout')))
        self._stale = ()
        self._pub = self.create_publisher(ReferenceTrajectory, 'reference_trajectory', 10)
        self._adjustment_pub = self.create_publisher(StepAdjustment, 'step_adjustment', 10)
        # Read when a reference is about to go out, not by a callback: the estimate of period t
        # then always shapes the reference of t + 1 (a callback could run after the command of
        # t had sent it, depending on the load).
        self._balance_reader = LatestMessageReader(
            self, BalanceEstimate, 'balance_estimate', QoSProfile(depth=10)) \
            if self._adjuster_params.enabled or self._hold_params.answers_landings else None
        self._alive = LivelinessToken(self, 'reference_trajectory')  # the controller waits for it
        self._planner_process = LivelinessWatch(self, 'footstep_plan')
        self._continuous = False  # the newest plan used is a teleop plan the planner extends
        self._newest_extension = None  # (plan_id, stamp s) of the planner's newest extension
        # (plan_id, stamp s) of the newest step extension since this node's latest adjustment
        self._refreshed_extension = None
        self._adjustments = (None, [])  # (plan_id, stamps s) of this node's adjustments
        self._waiting: Optional[ExtensionWait] = None
        # an extension did not come in extension_wait: no more waits until one comes in time
        # (a live but hung planner would otherwise cost that much wall time at every step)
        self._planner_behind = False
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, 'diagnostics', 10)
        self.create_subscription(FootstepPlan, 'footstep_plan', self._on_plan, LATCHED_IN)
        self.create_subscription(WalkingState, 'walking_state', self._on_state, 10)
        # Only needed until a walk's reference exists: then unsubscribed (each message costs a
        # wake-up of this process at every control period).
        self._odom_sub = self.create_subscription(Odometry, 'odom', self._on_odom, 10) \
            if get('standing_from_odom') else None
        self._started_at = time.monotonic()
        self._soles_sub = None
        self._subscribe_soles()
        self._soles_seen = False
        self._period_ns = int(round(1e9 / float(get('rate'))))
        self._estimates = EstimateOrder(self._period_ns)  # balance_estimate, in stamp order
        self._sent_ns = None  # stamp of the newest reference sent
        self._held_ns = None  # the clock at the last wall-clock check (_on_held_clock)
        # a joint command that came before any /clock (across a link the two arrive in either
        # order): answered when the clock comes, not refused as ahead of a clock still at 0
        self._command_before_clock: Optional[JointState] = None
        self.create_subscription(JointState, 'joint_commands', self._on_command, 10)
        self.create_timer(1.0 / float(get('rate')), self._on_timer)
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self.create_timer(WATCH_PERIOD, self._check_inputs, clock=wall)
        self.create_timer(DIAGNOSTICS_PERIOD, self._publish_diagnostics, clock=wall)
        self.create_timer(WATCH_PERIOD, self._on_held_clock, clock=wall)
        self.get_logger().info(f'reference generator ready ({self._horizon} samples of '
                               f'{self._dt} s)')

    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _new_session(self) -> ReferenceSession:
        adjuster = OnlineStepAdjuster(self._adjuster_params, self._step_limits) \
            if self._adjuster_params.enabled else None
        return ReferenceSession(self._reference_params, adjuster,
                                LandingHold(self._hold_params))

    def destroy_node(self) -> None:
        if self._balance_reader is not None:
            self._balance_reader.destroy()
        super().destroy_node()

    def _answer_balance_estimates(self, expected_ns: int) -> None:
        """Answer the estimates stamped up to expected_ns (the period before the reference's),
        waiting a little for that one (biped_planner.estimate_order)."""
        if self._balance_reader is None:
            return
        answered, missed = self._estimates.take(
            expected_ns, self._balance_reader.take_all, lambda m: nanoseconds_of(m.header.stamp))
        if missed:
            self.get_logger().warning(
                f'the balance estimate of t={expected_ns * 1e-9:.3f} s did not come within '
                f'{ESTIMATE_WAIT * 1e3:.0f} ms of wall time: the step adjuster answers it '
                'with a later reference (this run may differ from one on a quieter '
                'machine)', throttle_duration_sec=2.0)
        for msg in answered:
            self._on_balance(msg)

    def _on_balance(self, msg: BalanceEstimate) -> None:
        """The controller's balance estimate: the step adjuster answers it."""
        t = seconds_of(msg.header.stamp)
        try:
            if msg.header.frame_id != self._frame:
                raise ValueError(f'frame_id {msg.header.frame_id!r}, expected {self._frame!r}')
            if t > self._now() + MAX_STAMP_LEAD:
                raise ValueError(f'stamp {t:.3f} s is ahead of the clock')
            com = (msg.com.x, msg.com.y)
            dcm = (msg.dcm.x, msg.dcm.y)
            workspace = self._bounds.workspace
            if not all(math.isfinite(v) and abs(v) <= workspace for v in com + dcm):
                raise ValueError(f'com {com} and dcm {dcm} must be finite and within the '
                                 f'workspace ({workspace} m)')
            # The measured ZMP is not used: early in a single support it still lies between the
            # feet (the swing foot unloading), and held there it predicts a DCM that falls
            # inwards, which moved every first step inwards to the crossing limit.
            adjustment = self._session.adjust(t, com, dcm)
            held = None
            if self._hold_params.answers_landings:
                held = self._session.hold_landing(t, msg.landing_modes, msg.landing_depths)
        except (BipedPlannerError, ValueError) as error:
            self._reject('balance_estimate', error)
            return
        for change in (adjustment, held):
            if change is not None:
                self._publish_adjustment(change, msg.header.stamp)

    def _publish_adjustment(self, adjustment, stamp) -> None:
        """:param stamp: the time of the estimate it answers"""
        kind = {KIND_HELD: StepAdjustment.KIND_HELD, KIND_EARLY: StepAdjustment.KIND_EARLY}.get(
            adjustment.kind, StepAdjustment.KIND_MOVED)
        msg = StepAdjustment(kind=kind, plan_id=adjustment.plan_id, revision=adjustment.revision,
                             step_index=adjustment.step_index,
                             touchdown_time=adjustment.touchdown,
                             planned_touchdown_time=adjustment.planned_touchdown,
                             footsteps=footstep_msgs(adjustment.footsteps))
        msg.header.stamp = stamp
        msg.header.frame_id = self._frame
        self._adjustment_pub.publish(msg)
        retimed = {KIND_HELD: 'held for a late landing', KIND_EARLY: 'landed early'}
        if adjustment.kind in retimed:  # the footsteps stay: the planner has nothing to send
            self.get_logger().info(
                f'step {adjustment.step_index} {retimed[adjustment.kind]} (plan '
                f'{adjustment.plan_id}, revision {adjustment.revision}): touchdown at '
                f't={adjustment.touchdown:.3f} s (planned {adjustment.planned_touchdown:.3f} s)')
            return
        # the planner republishes the plan stamped with it: awaited as an extension
        plan_id, stamps = self._adjustments
        if plan_id != adjustment.plan_id:
            stamps = []
        replanned = plan_stamp(self._newest_extension, adjustment.plan_id)
        self._adjustments = (adjustment.plan_id, [t for t in stamps if replanned is None or
                                                  t > replanned] + [seconds_of(stamp)])
        self._refreshed_extension = None
        landing = adjustment.footsteps[adjustment.step_index + 2]
        self.get_logger().info(
            f'step {adjustment.step_index} adjusted (plan {adjustment.plan_id}, revision '
            f'{adjustment.revision}): lands at ({landing.x:.3f}, {landing.y:.3f}) at '
            f't={adjustment.touchdown:.3f} s (planned {adjustment.planned_touchdown:.3f} s), DCM '
            f'{adjustment.dcm_error[0]:+.3f}, {adjustment.dcm_error[1]:+.3f} m off the plan\'s')

    def _on_plan(self, msg: FootstepPlan) -> None:
        if msg.status == FootstepPlan.STATUS_FAILED:
            return
        if msg.status != FootstepPlan.STATUS_OK:
            self._reject('footstep_plan', f'plan {msg.plan_id}: unknown status {msg.status}')
            return
        try:
            if msg.header.frame_id not in ('', self._frame):
                raise ValueError(f'frame_id {msg.header.frame_id!r}, expected {self._frame!r}')
            footsteps = footsteps_from_msgs(msg.footsteps)
            check_footsteps(footsteps, self._bounds.workspace,
                            self.get_parameter('max_footstep_distance').value)
            timing = StepTiming(msg.single_support, msg.double_support)
            standing = self._standing_feet()
            if msg.plan_id != self._session.plan_id and self._phase not in WALKING_PHASES and \
                    standing is not None:
                check_plan_start(footsteps, standing,
                                 self.get_parameter('max_plan_start_offset').value)
            apply_at = stamp = None
            t_out = max(self._now(), (self._sent_ns or 0) * 1e-9)  # newest reference sent
            if msg.request_id == 0:  # the planner's own extension, stamped with its step
                # this node's clock can lag the planner's by a period or two (its /clock
                # callback not yet run): only a stamp farther ahead is not believed
                stamp = seconds_of(msg.header.stamp)
                apply_at = (stamp if stamp <= self._now() + MAX_STAMP_LEAD else self._now()) + \
                    self._change_delay(msg.plan_id, stamp)
            done = self._session.set_plan(msg.plan_id, footsteps, timing, t_out, apply_at)
        except (BipedPlannerError, ValueError) as error:
            self._reject('footstep_plan', f'plan {msg.plan_id} not used: {error}')
            return
        self._continuous = bool(msg.continuous)
        if msg.request_id == 0:
            if self._planner_behind and apply_at > t_out:
                self._planner_behind = False
                self.get_logger().info("the planner's extensions come in time again: "
                                       'references wait for them again')
            self._newest_extension = newer_plan_stamp(self._newest_extension, msg.plan_id, stamp)
            if not self._answers_adjustment(msg.plan_id, stamp):  # a step's extension
                self._refreshed_extension = newer_plan_stamp(self._refreshed_extension,
                                                             msg.plan_id, stamp)
        self._send_held()  # the reference waiting for it goes out now, if it may
        if done == 'queued':
            change = 'extends' if msg.continuous else 'changes'  # a stop, an adjusted walk
            self.get_logger().info(f'plan {msg.plan_id} ({len(msg.footsteps)} footsteps): '
                                   f'{change} the walk at t={apply_at:.3f} s')
            return
        # spliced into the reference of its own stated period is on time (not "0.000 s late")
        late = '' if apply_at is None or done != 'extended' or apply_at > t_out - 1e-6 else \
            (f' {t_out - apply_at:.3f} s late (this run may differ from one on a quieter '
             f'machine) from t={t_out:.3f} s')
        self.get_logger().info(f'plan {msg.plan_id} ({len(msg.footsteps)} footsteps): '
                               f'{done}{late}')

    def _standing_feet(self):
        """Where the references stand the feet between walks: the last walk's final feet, or
        before the first walk the measured ones (None: not known yet)."""
        if self._session.reference is not None:
            return self._session.reference.footsteps[-2:]
        return self._standing

    def _on_state(self, msg: WalkingState) -> None:
        # a scheduled walk (WalkCommand.start_time) starts up to MAX_START_LEAD ahead
        why = walking_state_problem(msg, self._now(), MAX_START_LEAD + MAX_STAMP_LEAD)
        if why is not None:
            self._reject('walking_state', why)
            return
        self._watch.arrived('walking_state', self._now(), time.monotonic())
        if self._epoch is None:
            self._epoch = msg.epoch
        elif msg.epoch != self._epoch:
            if self._phase in WALKING_PHASES:
                self._reject('walking_state', f'epoch {msg.epoch} while walking (a reset is '
                             f'refused while walking)')
                return
            self._restart(msg.epoch)
        self._note_stated_stop(msg)
        if msg.phase in WALKING_PHASES:
            if self._session.start_walk(msg.walk_start_time) and self._phase not in \
                    WALKING_PHASES:
                self.get_logger().info(f'walk from t={msg.walk_start_time:.3f} on plan '
                                       f'{self._session.plan_id}')
        elif self._phase in WALKING_PHASES:
            self._session.end_walk()
        self._phase = msg.phase

    def _note_stated_stop(self, msg: WalkingState) -> None:
        """The walk's STOP stated ahead (walking_state.stop_time): the state machine reports it
        until the walk ends, and 0 once a command dropped it (a STOP without a time too)."""
        if msg.phase not in WALKING_PHASES or msg.stop_time <= 0.0:
            self._stated_stop = None
        elif self._stated_stop is None or self._stated_stop[0] != msg.stop_time:
            self._stated_stop = (msg.stop_time, seconds_of(msg.header.stamp))

    def _stated_stop_step(self, reference) -> Optional[float]:
        """The start of the step whose change the planner makes the stated STOP's plan (s),
        when the planner holds that STOP: it learnt of it with this node, at least a period
        before that step (later, it answers on arrival, which nothing waits for)."""
        timing = self._session.plan_timing
        if self._stated_stop is None or timing is None:
            return None
        stop_time, announced = self._stated_stop
        start = stated_stop_step(reference.phases, stop_time, timing.single_support)
        if start is None or announced > start - self._period_ns * 1e-9:
            return None
        return start

    def _restart(self, epoch: int) -> None:
        """The robot was reset: no walk, no plan, stand where the controller puts the feet."""
        self._epoch = epoch
        self._session = self._new_session()
        self._adjustments = (None, [])
        self._refreshed_extension = None
        self._stated_stop = None
        self._estimates.restart()  # the clock went back
        self._standing = None
        self._soles_seen = False
        self._subscribe_soles()
        self.get_logger().info(f'epoch {epoch}: walk and plan dropped; standing where the '
                               f'sole_poses put the feet')

    def _subscribe_soles(self) -> None:
        if self._soles_sub is None:
            self._soles_sub = self.create_subscription(PoseArray, 'sole_poses', self._on_soles,
                                                       10)

    def _on_soles(self, msg: PoseArray) -> None:
        """Stand where the feet are: standing on feet placed around the pelvis instead would
        make the COM chase its own reference (the COM is not above the pelvis)."""
        if self._session.reference is not None:
            self._unsubscribe_standing_inputs()
            return
        try:
            if msg.header.frame_id != self._frame:
                raise ValueError(f'frame_id {msg.header.frame_id!r}, expected {self._frame!r}')
            measured = feet_from_sole_poses(msg, self._bounds)
            self._standing = settled_feet(self._standing if self._soles_seen else None,
                                          measured)
            self._soles_seen = True
        except (BipedPlannerError, ValueError) as error:
            self._reject('sole_poses', error)
            return
        if self._sent_ns is None:
            self._on_held_clock()  # the controller waits for this first reference

    def _on_odom(self, msg: Odometry) -> None:
        if self._session.reference is not None or self._soles_seen:
            self._unsubscribe_standing_inputs()
            return
        try:
            if msg.header.frame_id != self._frame:
                raise ValueError(f'frame_id {msg.header.frame_id!r}, expected {self._frame!r}')
            pose = checked_pose2d('odom', msg.pose.pose, self._bounds)
            self._standing = feet_beside(pose, self.get_parameter('stance_width').value)
        except (BipedPlannerError, ValueError) as error:
            self._reject('odom', error)

    def _unsubscribe_standing_inputs(self) -> None:
        """odom is read until sole_poses arrive, sole_poses until a walk's reference exists
        (and again after a reset)."""
        if self._odom_sub is not None:
            self.destroy_subscription(self._odom_sub)
            self._odom_sub = None
        if self._soles_sub is not None and self._session.reference is not None:
            self.destroy_subscription(self._soles_sub)
            self._soles_sub = None

    def _answers_adjustment(self, plan_id: int, stamp: float) -> bool:
        """Whether the planner's change of a plan stamped `stamp` (s) is its plan after one of
        this node's step adjustments (else its extension at a step's start)."""
        adjusted_plan, adjusted = self._adjustments
        return adjusted_plan == plan_id and any(abs(stamp - a) < 1e-6 for a in adjusted)

    def _change_delay(self, plan_id: int, stamp: float) -> float:
        """How long after its stamp the planner's change of a plan applies (s): its plan after
        one of this node's step adjustments soon, its extension at a step's start later."""
        if self._answers_adjustment(plan_id, stamp):
            return self.get_parameter('adjustment_replan_delay').value
        return self.get_parameter('extension_delay').value

    def _awaits_extension(self, t_ns: int) -> bool:
        """Whether the reference of t_ns must wait for the planner's extension (see module)."""
        limit = self.get_parameter('extension_wait').value
        reference = self._session.reference
        clock = self.get_clock()
        # the planner extends a walk at the steps the state machine reports: none after a fall
        # or a stop, and the clock must not stand waiting for one then
        if limit <= 0.0 or reference is None or not clock.ros_time_is_active or \
                self._planner_behind or self._phase not in WALKING_PHASES:
            return False
        plan_id = self._session.plan_id
        adjusted_plan, adjusted = self._adjustments
        due = awaited_extension(
            reference.phases, t_ns * 1e-9, self.get_parameter('extension_delay').value,
            plan_stamp(self._newest_extension, plan_id),
            self._continuous, adjusted if adjusted_plan == plan_id else (),
            self.get_parameter('adjustment_replan_delay').value,
            plan_stamp(self._refreshed_extension, plan_id), self._stated_stop_step(reference))
        waiting = self._waiting
        if due is None:
            self._waiting = None
            return False
        if waiting is not None and waiting.stamp == due:
            if not waiting.holding:
                return False  # given up on already
            why = None
            if clock.now().nanoseconds > waiting.first_ns:
                why = 'the clock runs on (no lockstep)'
            elif time.monotonic() - waiting.since >= limit:
                why = (f'it did not come in {limit} s (no more waits until an extension comes '
                       'in time)')
                self._planner_behind = True
            if why is None:
                self._waiting = waiting._replace(held_ns=max(t_ns, waiting.held_ns))
                return True
            self.get_logger().warning(
                f"walking on without the planner's extension stamped t={due:.3f} s: {why} "
                '(this run may differ from another)')
            self._waiting = waiting._replace(since=None, held_ns=t_ns)
            return False
        if not (self._planner_process.alive_count > 0 or self._planner_process.local):
            self.get_logger().warning(
                f"no planner alive: walking on without its extension stamped t={due:.3f} s",
                throttle_duration_sec=5.0)
            self._waiting = ExtensionWait(due, None, t_ns, t_ns)
            return False
        self.get_logger().info(f'reference of t={t_ns * 1e-9:.3f} s waits for the planner\'s '
                               f'extension stamped t={due:.3f} s (a step start or a step '
                               'adjustment)')
        self._waiting = ExtensionWait(due, time.monotonic(), t_ns, t_ns)
        return True

    def _send_held(self) -> None:
        """Send the reference held for an extension, if it may go out now (it came, or the
        wait is over); nothing when none is held."""
        waiting = self._waiting
        if waiting is not None and waiting.holding and (
                self._sent_ns is None or waiting.held_ns > self._sent_ns):
            self._send(waiting.held_ns)

    def _send(self, t_ns: int) -> None:
        """Publish the reference from t_ns (ns of the node's clock), if there is one, after the
        balance estimate of the period before (_answer_balance_estimates): whichever comes
        first, the controller's command or the simulator's clock, sends it."""
        if self._awaits_extension(t_ns):
            return
        self._answer_balance_estimates(t_ns - self._period_ns)
        try:
            if self._session.apply_due(t_ns * 1e-9) == 'extended':
                self.get_logger().info(f'plan {self._session.plan_id}: extended at '
                                       f't={t_ns * 1e-9:.3f} s')
        except BipedPlannerError as error:
            self._reject('footstep_plan', f'plan {self._session.plan_id}: its extension due at '
                         f't={t_ns * 1e-9:.3f} s not used: {error}')
        try:
            window = self._session.window(t_ns * 1e-9, self._horizon, self._dt, self._standing)
        except (BipedPlannerError, ValueError) as error:
            self.get_logger().error(f'no reference at t={t_ns * 1e-9:.3f} s: {error}',
                                    throttle_duration_sec=2.0)
            return
        if window is not None:
            msg = reference_trajectory_msg(window, self._session.plan_id, self._dt,
                                           Time(nanoseconds=t_ns).to_msg(),
                                           self._session.plan_revision,
                                           self._session.walk_adjustments)
            msg.header.frame_id = self._frame
            self._pub.publish(msg)
            self._sent_ns = t_ns

    def _on_command(self, msg: JointState) -> None:
        clock = self.get_clock()
        if not clock.ros_time_is_active:
            return
        if clock.now().nanoseconds == 0:  # no /clock yet
            if self._command_before_clock is None:
                self.get_logger().info('joint_commands came before /clock: answered when the '
                                       'clock comes')
            self._command_before_clock = msg
            return
        stamp = msg.header.stamp
        t_ns = nanoseconds_of(stamp) + self._period_ns
        if t_ns > clock.now().nanoseconds + int(MAX_STAMP_LEAD * 1e9):
            self._reject('joint_commands', f'stamp {stamp.sec}.{stamp.nanosec:09d} s is ahead '
                         f'of the clock')
            return
        if self._sent_ns is None or t_ns > self._sent_ns:
            self._send(t_ns)

    def _answer_command_before_clock(self) -> None:
        msg, self._command_before_clock = self._command_before_clock, None
        if msg is not None:
            self._on_command(msg)

    def _on_timer(self) -> None:
        self._answer_command_before_clock()
        now_ns = self.get_clock().now().nanoseconds
        # sent ahead: this tick's reference or the next one's is out (farther ahead: the clock
        # went back, after a reset of the simulation)
        sent_ahead = self._sent_ns is not None and \
            now_ns - self._period_ns // 2 <= self._sent_ns <= now_ns + 2 * self._period_ns
        if not sent_ahead:
            self._send(now_ns)

    def _on_held_clock(self) -> None:
        """A clock that does not move (lockstep before the controller's first command) fires
        no sim-time timer: the reference of the current time goes out from the wall clock, and
        again while the clock stays there (the first one can go out before the controller's
        subscription is matched)."""
        clock = self.get_clock()
        if not clock.ros_time_is_active:
            return
        self._answer_command_before_clock()
        now_ns = clock.now().nanoseconds
        if self._standing is None and self._session.reference is None and \
                time.monotonic() - self._started_at > STANDING_PATIENCE:
            self.get_logger().warning(
                'no reference: nothing to stand on until the controller\'s sole_poses arrive'
                + ('' if self._odom_sub is not None else ' (standing_from_odom: false)'),
                throttle_duration_sec=5.0)
        self._send_held()  # still waiting for an extension, or the wait is over
        held, self._held_ns = now_ns == self._held_ns, now_ns
        # a moving clock is served by _on_timer and _on_command: no second copy from here
        if self._sent_ns is None or (held and self._sent_ns <= now_ns):
            self._send(now_ns)

    def _check_inputs(self) -> None:
        stale = self._watch.check(self._now(), time.monotonic())
        if stale != self._stale:
            if stale:
                self.get_logger().error(f'{", ".join(stale)} lost (none for '
                                        f'{self._watch.timeout} s): the state machine is gone; '
                                        'the walk runs to the end of its plan and stands')
            else:
                self.get_logger().info(f'{", ".join(self._stale)} back')
            self._stale = stale
            self._publish_diagnostics()

    def _publish_diagnostics(self) -> None:
        if self._stale:
            level = DiagnosticStatus.ERROR
            message = f'{", ".join(self._stale)} lost: no message for {self._watch.timeout} s'
        else:
            level, message = DiagnosticStatus.OK, 'inputs arrive'
        status = DiagnosticStatus(level=level, name='reference_generator: walking_state',
                                  message=message, hardware_id=self.get_name(),
                                  values=[KeyValue(key='stale_inputs',
                                                   value=','.join(self._stale)),
                                          KeyValue(key='step_adjustments',
                                                   value=str(self._session.adjustments)),
                                          KeyValue(key='waiting_for_extension_stamped',
                                                   value=f'{self._waiting.stamp:.3f}'
                                                   if self._waiting is not None and
                                                   self._waiting.holding else '')])
        msg = DiagnosticArray(status=[status])
        msg.header.stamp = self.get_clock().now().to_msg()
        self._diagnostics_pub.publish(msg)


def main(args=None) -> None:
    run_node(ReferenceGeneratorNode, args)


if __name__ == '__main__':
    main()
