"""The simulator node: joint setpoints in; clock, joint states, IMU, wrenches, odometry out.

Subscribes: joint_commands (sensor_msgs/JointState: setpoints of some or all joints, stamped
with the sensor time they answer), map (nav_msgs/OccupancyGrid, transient local: obstacles).
Publishes every control period: /clock (rosgraph_msgs/Clock), joint_states
(sensor_msgs/JointState), imu (sensor_msgs/Imu), odom (nav_msgs/Odometry, ground truth pelvis),
left_foot_wrench / right_foot_wrench (geometry_msgs/WrenchStamped, ankle F/T sensors),
zmp (geometry_msgs/PointStamped, measured from the F/T sensors), com (PointStamped, ground truth);
diagnostics (diagnostic_msgs/DiagnosticArray: whether the controller's commands arrive) once a
second and when that changes.
Services: push (biped_msgs/Push), simulator/reset (std_srvs/Trigger: stand the robot at its
start pose; called by the state machine's reset), set_terrain (biped_msgs/SetTerrain),
simulator/resume (std_srvs/Trigger: let a lockstep clock held at hold_at run on; scripted
trials hold it there while they get ready).
Subscribes with paced_by set: that topic (rosgraph_msgs/Clock, the sim time a scripted runner
has acted on); lockstep then holds the clock pace_lead ahead of it while it has a publisher.

Lockstep mode (default): while a controller publishes joint_commands, physics advances one
control period only when the command answering the last sensor time has arrived, so a run is
deterministic and as fast as the graph allows; with no controller it advances in real time.
Real-time mode (lockstep false) always advances at real_time_factor, for watching in the GUI.

Safety: a controller silent for lockstep_timeout of wall time is reported (WARN on diagnostics,
naming joint_commands). While its process is alive (DDS liveliness of joint_commands/alive,
biped_planner.node_support.liveliness) lockstep waits for it, so a loaded machine slows the run
but never changes it, and sends it the period's sensors again every lockstep_timeout; a
controller whose process is gone, one without that token, or one silent for
hung_controller_timeout is lost (ERROR): the robot's safe mode holds its last commanded joint
positions with the servos, and the clock runs in real time until commands come again.
Commands with NaN / inf, past a joint limit by more than command_margin, with unknown joints,
mismatched lengths or a stamp ahead of the simulation are refused (logged) and the previous
setpoints kept; so are malformed maps (frame, resolution, origin, size). After a reset the
servos hold the standing pose for reset_hold, while the controller restarts.
"""
import math
import time

from biped_msgs.srv import Push, SetTerrain
from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PointStamped, WrenchStamped
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Odometry
import numpy as np
from rclpy.clock import Clock as WallClock, ClockType
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState
from std_srvs.srv import Trigger

from biped_planner.node_support.dataclass_parameters import declare_node_parameters
from biped_planner.node_support.liveliness import LivelinessWatch
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.rejection_log import RejectionLog
from biped_planner.node_support.stamps import seconds_of
from biped_sim.camera_view import CameraView
from biped_sim.errors import BipedSimError
from biped_sim.external_push import ExternalPush
from biped_sim.joint_limits import joint_limits_from_urdf
from biped_sim.joint_servo import step_toward
from biped_sim.nodes.conversions import (checked_command, diagnostics_msg, imu_msg,
                                         joint_state_msg, occupied_cells_from_map, odometry_msg,
                                         point_msg, wrench_msg)
from biped_sim.nodes.simulator_parameters import (BACKENDS, READ_ONLY, SIMULATOR_PARAMETERS,
                                                  terrain_from)
from biped_sim.obstacles import boxes_from_occupied_cells
from biped_sim.pybullet_config import PyBulletConfig
from biped_sim.robot_catalogue import load_robot

LATCHED_IN = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                        reliability=ReliabilityPolicy.RELIABLE)
MAX_PUSH_FORCE = 5000.0  # N: beyond any push the robot could feel; larger requests are errors
MAX_PUSH_POINT = 2.0  # m: the point of a push is on the link, not metres away from it
DIAGNOSTICS_PERIOD = 1.0  # s of wall time
DIAGNOSTIC_NAME = 'simulator: joint_commands'


def stamp_of(t: float) -> Time:
    sec = int(math.floor(t))
    return Time(sec=sec, nanosec=int(round((t - sec) * 1e9)) % 1_000_000_000)


class SimulatorNode(Node):
    """Thin adapter over a biped_sim SimulatorBackend (PyBullet or the model plant)."""

    def __init__(self, **kwargs) -> None:
        super().__init__('simulator', **kwargs)
        declare_node_parameters(self, SIMULATOR_PARAMETERS, read_only=READ_ONLY)
        self._frame = self.get_parameter('frame_id').value
        self._period = float(self.get_parameter('control_period').value)
        self._backend = self._make_backend()
        self._names = tuple(self._backend.joint_names)
        self._lower, self._upper = joint_limits_from_urdf(self._backend.description.urdf_path,
                                                          self._names)
        self._reject = RejectionLog(self.get_logger().error)
        self._controller_seen = False  # a command has come since the start
        self._graph_up = False  # the wait_for_publishers topics all had a publisher once
        self._controller_lost = False
        self._hold_until = -math.inf  # sim time until which commands are ignored (reset)
        self._hold_at = float(self.get_parameter('hold_at').value)  # read only
        self._pace_lead = float(self.get_parameter('pace_lead').value)
        self._paced_until = -math.inf  # sim time the pacing runner lets the clock reach
        self._resumed = False  # simulator/resume was called (hold_at)
        self._step_held = False  # a lockstep step is due while hold_at or the pace holds it
        self._setpoints = self._nominal_setpoints()
        self._previous_setpoints = None
        self._velocities = np.zeros(len(self._names))
        self._substeps = max(1, int(round(self._period /
                                          float(self.get_parameter('physics_step').value))))
        self._last_step_wall = time.monotonic()
        self._last_command_wall = self._last_step_wall
        self._last_command_stamp = -math.inf  # sim time a valid command answered last
        self._wall = WallClock(clock_type=ClockType.STEADY_TIME)
        self._map_boxes = []
        self._terrain = None
        # sim time published = offset + backend time: a reset restarts the backend's time, the
        # clock must not go back (every node's timers and the bags follow it)
        self._time_offset = 0.0
        self._camera = self._make_camera()
        get = lambda name: self.get_parameter(name).value  # noqa: E731
        if get('terrain.kind') != SetTerrain.Request.FLAT:
            self._terrain = terrain_from(
                get('terrain.kind'), get('terrain.side_length'), get('terrain.origin_x'),
                get('terrain.origin_y'), get('terrain.tile_size'), get('terrain.min_height'),
                get('terrain.max_height'), get('terrain.seed'))
            self._backend.add_terrain(self._terrain)

        self._clock_pub = self.create_publisher(Clock, '/clock', 10)
        self._joint_pub = self.create_publisher(JointState, 'joint_states', 10)
        self._imu_pub = self.create_publisher(Imu, 'imu', 10)
        self._odom_pub = self.create_publisher(Odometry, 'odom', 10)
        self._wrench_pubs = (self.create_publisher(WrenchStamped, 'left_foot_wrench', 10),
                             self.create_publisher(WrenchStamped, 'right_foot_wrench', 10))
        self._zmp_pub = self.create_publisher(PointStamped, 'zmp', 10)
        self._com_pub = self.create_publisher(PointStamped, 'com', 10)
        self._command_sub = self.create_subscription(JointState, 'joint_commands',
                                                     self._on_command, 10)
        self._controller_process = LivelinessWatch(self, 'joint_commands')
        self._waiting_reported = False  # a late, live controller is on diagnostics
        self.create_subscription(OccupancyGridMsg, 'map', self._on_map, LATCHED_IN)
        self.create_service(Push, 'push', self._on_push)
        # internal: the state machine's user-facing reset calls it and re-initialises the rest
        self.create_service(Trigger, 'simulator/reset', self._on_reset)
        self.create_service(SetTerrain, 'set_terrain', self._on_set_terrain)
        self.create_service(Trigger, 'simulator/resume', self._on_resume)
        paced_by = self.get_parameter('paced_by').value
        self._pace_sub = None if not paced_by else self.create_subscription(
            Clock, paced_by, self._on_pace, 10)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, 'diagnostics', 10)
        self._readings = self._reset_robot()
        self._publish(self._readings)
        # Real time: one step a tick. Lockstep steps run in the command callback, and a tick
        # only times the controller's silence (a faster poll would only cost wake-ups).
        self._timer = self.create_timer(self._real_time_period(), self._on_timer,
                                        clock=self._wall)
        self.create_timer(DIAGNOSTICS_PERIOD, self._publish_diagnostics, clock=self._wall)
        self.get_logger().info(
            f'{self.get_parameter("backend").value} simulator ready: {len(self._names)} joints, '
            f'{"lockstep" if self._lockstep() else "real time"}')

    # --- set-up -----------------------------------------------------------------------------
    def _make_backend(self):
        name = self.get_parameter('backend').value
        robot = load_robot(self.get_parameter('robot').value)
        step = float(self.get_parameter('physics_step').value)
        substeps = max(1, int(round(self._period / step)))
        if name == 'pybullet':
            from biped_sim.pybullet_backend import PyBulletBackend
            config = PyBulletConfig(gui=bool(self.get_parameter('gui').value), time_step=step,
                                    control_substeps=substeps,
                                    control_mode=self.get_parameter('control_mode').value,
                                    leg_kp=float(self.get_parameter('leg_kp').value),
                                    leg_kd=float(self.get_parameter('leg_kd').value),
                                    sole_contact_stiffness=float(
                                        self.get_parameter('sole_contact_stiffness').value),
                                    sole_contact_damping=float(
                                        self.get_parameter('sole_contact_damping').value))
            return PyBulletBackend(robot, config)
        if name == 'model':
            from biped_sim.model_plant_backend import ModelPlantBackend, ModelPlantBackendParams
            return ModelPlantBackend(robot, ModelPlantBackendParams(time_step=step,
                                                                    control_substeps=substeps))
        raise ValueError(f'backend {name!r} unknown: use one of {BACKENDS}')

    def _make_camera(self):
        """(FrameRecorder, CameraView) when camera.frames_dir is set, else None."""
        get = lambda name: self.get_parameter(name).value  # noqa: E731
        if not get('camera.frames_dir'):
            return None
        if not hasattr(self._backend, 'render'):
            raise ValueError('camera frames need the pybullet backend')
        from biped_sim.frame_recorder import FrameRecorder
        view = CameraView(width=int(get('camera.width')), height=int(get('camera.height')),
                          distance=float(get('camera.distance')), yaw=float(get('camera.yaw')),
                          pitch=float(get('camera.pitch')))
        return FrameRecorder(get('camera.frames_dir'), float(get('camera.fps'))), view

    def _now(self) -> float:
        """Sim time of the current readings (s), as published on /clock."""
        return self._time_offset + self._readings.time

    def _nominal_setpoints(self) -> np.ndarray:
        nominal = self._backend.description.nominal_joint_positions
        return np.array([nominal.get(name, 0.0) for name in self._names])

    def _reset_robot(self):
        readings = self._backend.reset(base_yaw=float(self.get_parameter('start_yaw').value),
                                       base_position=None)
        x, y = (float(self.get_parameter(n).value) for n in ('start_x', 'start_y'))
        if x or y:
            base = np.array(readings.base.position, dtype=float)
            base[:2] = (x, y)
            readings = self._backend.reset(base_position=base,
                                           base_yaw=float(self.get_parameter('start_yaw').value))
        self._setpoints = self._nominal_setpoints()
        self._previous_setpoints = None
        self._velocities = np.zeros(len(self._names))
        return readings

    def _lockstep(self) -> bool:
        return bool(self.get_parameter('lockstep').value)

    # --- stepping ---------------------------------------------------------------------------
    def _on_command(self, msg: JointState) -> None:
        stamp = seconds_of(msg.header.stamp)
        now = self._now()
        try:
            # the values first: a bad value is named even when the message also comes late
            setpoints, velocities = checked_command(
                msg, self._names, self._setpoints, (self._lower, self._upper),
                float(self.get_parameter('command_margin').value),
                float(self.get_parameter('max_command_velocity').value))
            if stamp > now + 1e-6:
                raise ValueError(f'stamp {stamp:.3f} s is ahead of the simulation ({now:.3f} s)')
            if stamp < self._last_command_stamp - 1e-6:
                raise ValueError(f'stamp {stamp:.3f} s goes back (the last command answered '
                                 f't={self._last_command_stamp:.3f} s)')
        except (ValueError, BipedSimError) as error:
            self._reject('joint_commands', error)
            if self._lockstep() and abs(stamp - now) < 1e-6 and not self._controller_lost:
                self._step()  # answered, wrongly: the period runs on the previous setpoints
            return
        self._controller_seen = True
        if self._controller_lost:
            if stamp <= self._last_command_stamp:
                return  # not an answer to newer sensors: the servos go on holding
            self._controller_lost = False
            self.get_logger().info(f'joint_commands arrive again at t={now:.2f} s: '
                                   f'{"lockstep" if self._lockstep() else "real time"}')
            self._publish_diagnostics()
        self._last_command_wall = time.monotonic()
        self._last_command_stamp = stamp
        if self._waiting_reported:
            self._waiting_reported = False
            self._publish_diagnostics()
        if now < self._hold_until:
            self.get_logger().info(f'reset: the servos hold the standing pose until '
                                   f't={self._hold_until:.2f} s', throttle_duration_sec=5.0)
        else:
            self._setpoints, self._velocities = setpoints, velocities
        if self._lockstep() and stamp >= now - 1e-6 and self._graph_up:
            self._step()

    def _real_time_period(self) -> float:
        """Wall seconds between steps in real time (s)."""
        return self._period / max(1e-3, float(self.get_parameter('real_time_factor').value))

    def _on_timer(self) -> None:
        period_ns = int(round(self._real_time_period() * 1e9))
        if self._timer.timer_period_ns != period_ns:  # real_time_factor changed
            self._timer.timer_period_ns = period_ns
        timeout = float(self.get_parameter('lockstep_timeout').value)
        now = time.monotonic()
        if self._lockstep() and not self._controller_seen and \
                self.get_parameter('wait_for_controller').value:
            if self._hold_clock(now, timeout):
                self.get_logger().info(f'lockstep holds the clock at t={self._now():.2f} s until '
                                       'a controller answers on joint_commands',
                                       throttle_duration_sec=5.0)
            return
        if self._lockstep() and not self._graph_up:
            missing = self._topics_without_publishers()
            if missing:
                if self._hold_clock(now, timeout):
                    self._last_command_wall = now  # the controller answered what it was sent
                    self.get_logger().info(
                        f'lockstep holds the clock at t={self._now():.2f} s until '
                        f'{", ".join(missing)} have a publisher (wait_for_publishers)',
                        throttle_duration_sec=5.0)
                return
            self._graph_up = True
            if self._controller_seen and self._last_command_stamp >= self._now() - 1e-6:
                self._step()  # the command answering the held time
            return
        if self._holding():
            if self._hold_clock(now, timeout):
                self._last_command_wall = now  # held for the trial, not for the controller
                self.get_logger().info(f'lockstep holds the clock at t={self._now():.2f} s '
                                       'until simulator/resume is called (hold_at)',
                                       throttle_duration_sec=5.0)
            return
        if self._waiting_for_pace():
            # the sensors again, as in every hold: a runner that subscribed after they went out
            # has no sim time to pace by until they come
            self._hold_clock(now, timeout)
            self._last_command_wall = now  # held for the runner, not for the controller
            self.get_logger().info(
                f'lockstep holds the clock at t={self._now():.2f} s until '
                f'{self.get_parameter("paced_by").value} reaches '
                f't={self._now() - self._pace_lead:.2f} s (paced_by)', throttle_duration_sec=5.0)
            return
        if self._step_held:  # the pacing runner is gone: its held step runs now
            self._release_held_step()
            return
        if not self._lockstep() or self._controller_lost or not (
                self._controller_seen or self._command_sub.get_publisher_count() > 0):
            if self._controller_seen and not self._controller_lost and \
                    now - self._last_command_wall >= timeout:
                self._lose_controller(now - self._last_command_wall)
            self._step()
            return
        # lockstep: wait for the command answering the last step (before the first command,
        # since the last step: a controller that does not answer yet)
        silent = now - (self._last_command_wall if self._controller_seen else
                        self._last_step_wall)
        if silent < timeout:
            return
        if self._controller_seen and self._controller_process.alive and \
                silent < float(self.get_parameter('hung_controller_timeout').value):
            self._report_waiting(silent)  # slow, not dead: the run waits for it
            # with this period's sensors again: a controller that lost them, or refused them
            # (held up, its /clock handled after them), answers then
            self._hold_clock(now, timeout)
            return
        if self._controller_seen:
            self._lose_controller(silent)
        else:
            self.get_logger().warning(f'no joint command for t={self._now():.2f} after '
                                      f'{silent:.2f} s: stepping with the last one',
                                      throttle_duration_sec=5.0)
        self._step()

    def _hold_clock(self, now: float, timeout: float) -> bool:
        """While the clock holds (before it starts, at hold_at, for a pacing runner or a late
        live controller): it stays where it is, and every timeout the sensors go out again, for
        a node that subscribed after they were sent, lost them or refused them; :return:
        whether they went out now."""
        if now - self._last_step_wall < timeout:
            return False
        self._last_step_wall = now
        if self._readings is not None:
            self._publish(self._readings)
        return True

    def _topics_without_publishers(self) -> list:
        topics = [t.strip() for t in self.get_parameter('wait_for_publishers').value.split(',')]
        return [t for t in topics if t and self.count_publishers(t) == 0]

    def _report_waiting(self, silent: float) -> None:
        self.get_logger().warning(
            f'lockstep waits for joint_commands at t={self._now():.2f} s: the controller is '
            f'alive but has not answered for {silent:.1f} s', throttle_duration_sec=2.0)
        if not self._waiting_reported:
            self._waiting_reported = True
            self._publish_diagnostics()

    def _lose_controller(self, silent: float) -> None:
        """The robot's safe mode: the servos hold the last commanded positions, at rest."""
        self._controller_lost = True
        self._velocities = np.zeros(len(self._names))
        self._previous_setpoints = self._setpoints.copy()
        self.get_logger().error(f'no valid joint_commands for {silent:.2f} s at '
                                f't={self._now():.2f} s: controller lost; holding its last '
                                'joint positions, running in real time')
        self._publish_diagnostics()

    def _publish_diagnostics(self) -> None:
        if self._controller_lost:
            level, message = DiagnosticStatus.ERROR, (
                'no valid joint_commands: controller lost; holding the last joint positions, '
                'running in real time')
        elif self._waiting_reported:
            level, message = DiagnosticStatus.WARN, (
                'lockstep waits for joint_commands: the controller is alive but late')
        elif self._controller_seen:
            level, message = DiagnosticStatus.OK, 'joint_commands arrive'
        else:
            level, message = DiagnosticStatus.OK, 'no controller yet: running in real time'
        silent = time.monotonic() - self._last_command_wall if self._controller_seen else -1.0
        self._diagnostics_pub.publish(diagnostics_msg(
            stamp_of(self._now()), DIAGNOSTIC_NAME, self.get_parameter('robot').value, level,
            message, {'topic': 'joint_commands', 'seconds_since_last_command': f'{silent:.3f}',
                      'sim_time': f'{self._now():.3f}'}))

    def _holding(self) -> bool:
        """Whether the lockstep clock holds at hold_at, waiting for simulator/resume."""
        return self._lockstep() and not self._resumed and self._hold_at >= 0.0 and \
            self._now() >= self._hold_at - 1e-9

    def _waiting_for_pace(self) -> bool:
        """Whether the lockstep clock waits for the pacing runner: it has run pace_lead ahead
        of it, and the runner's publisher is there (a runner that is gone paces nothing)."""
        return self._pace_sub is not None and self._lockstep() and \
            self._now() >= self._paced_until - 1e-9 and \
            self._pace_sub.get_publisher_count() > 0

    def _on_pace(self, msg: Clock) -> None:
        self._paced_until = max(self._paced_until, seconds_of(msg.clock) + self._pace_lead)
        self._release_held_step()

    def _release_held_step(self) -> None:
        """The step a hold deferred runs now, if nothing holds the clock any more."""
        if self._step_held and not (self._holding() or self._waiting_for_pace()):
            self._step_held = False
            self._last_command_wall = time.monotonic()
            self._step()

    def _on_resume(self, request: Trigger.Request, response: Trigger.Response):
        held = self._holding()
        self._resumed = True
        response.success = True
        response.message = (f'the clock resumes at t={self._now():.2f} s' if held else
                            f'the clock was not held (t={self._now():.2f} s)')
        self.get_logger().info(response.message)
        self._release_held_step()
        return response

    def _step(self) -> None:
        if self._holding() or self._waiting_for_pace():
            self._step_held = True  # resume or the runner's pace steps it
            return
        self._last_step_wall = time.monotonic()
        try:
            self._readings = step_toward(self._backend, self._previous_setpoints,
                                         self._setpoints, self._substeps,
                                         int(self.get_parameter('setpoint_parts').value),
                                         self._velocities)
            self._previous_setpoints = self._setpoints.copy()
        except BipedSimError as error:
            self.get_logger().error(f'simulation step failed: {error}')
            return
        self._publish(self._readings)
        if self._camera is not None:
            recorder, view = self._camera
            recorder.maybe_capture(self._now(), lambda: self._backend.render(view))

    def _publish(self, readings) -> None:
        stamp = stamp_of(self._time_offset + readings.time)
        self._clock_pub.publish(Clock(clock=stamp))
        self._odom_pub.publish(odometry_msg(readings.base, self._frame, 'pelvis', stamp))
        for pub, foot, frame in zip(self._wrench_pubs, (readings.left_foot, readings.right_foot),
                                    ('l_ankle_ft', 'r_ankle_ft')):
            pub.publish(wrench_msg(foot, frame, stamp))
        zmp = readings.zmp if np.all(np.isfinite(readings.zmp)) else (math.nan, math.nan)
        self._zmp_pub.publish(point_msg(zmp, self._frame, stamp))
        # joint_states after the controller's other inputs: it computes when it arrives (and
        # waits for imu only when it reads it); the rest goes out while it computes
        self._joint_pub.publish(joint_state_msg(readings.joints, stamp))
        self._imu_pub.publish(imu_msg(readings.imu, 'imu_link', stamp))
        self._com_pub.publish(point_msg(readings.com_position, self._frame, stamp))

    # --- services ---------------------------------------------------------------------------
    def _on_push(self, request: Push.Request, response: Push.Response) -> Push.Response:
        force = (request.force.x, request.force.y, request.force.z)
        point = (request.point.x, request.point.y, request.point.z)
        values = force + point + (request.duration,)
        if not all(math.isfinite(v) for v in values) or not 0.0 < request.duration <= 60.0 or \
                math.hypot(*force) > MAX_PUSH_FORCE or math.hypot(*point) > MAX_PUSH_POINT:
            response.success = False
            response.message = (f'push rejected: force {force} N (|F| <= {MAX_PUSH_FORCE}), '
                                f'duration {request.duration} s (in (0, 60]) and point {point} '
                                f'm (|p| <= {MAX_PUSH_POINT}) must be finite')
            self.get_logger().warning(response.message)
            return response
        start = seconds_of(request.start) - self._time_offset  # in the backend's time
        start = start if start > self._readings.time else None
        try:
            self._backend.push(ExternalPush(force=force, duration=request.duration,
                                            link=request.link or None, point=point,
                                            start_time=start))
        except BipedSimError as error:
            response.success, response.message = False, f'push rejected: {error}'
            self.get_logger().warning(response.message)
            return response
        response.success = True
        begins = self._time_offset + (self._readings.time if start is None else start)
        response.message = f'pushing {force} N for {request.duration} s from t={begins:.3f} s'
        self.get_logger().info(response.message)
        return response

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        # the clock moves on by one period, spent setting the robot down: PyBullet's force
        # sensors read the last physics step, so without one the first readings after a reset
        # would carry the fallen robot's foot forces (contact and ZMP of a body lying down)
        self._time_offset += self._readings.time
        try:
            self._reset_robot()
            self._readings = self._backend.step(self._setpoints, self._substeps)
            self._previous_setpoints = self._setpoints.copy()
        except (BipedSimError, ValueError) as error:
            response.success, response.message = False, f'reset failed: {error}'
            self.get_logger().error(response.message)
            return response
        self._hold_until = self._now() + float(self.get_parameter('reset_hold').value)
        self._publish(self._readings)
        p = self._readings.base.position
        response.success = True
        response.message = (f'robot standing at its start pose ({p[0]:.2f}, {p[1]:.2f}) from '
                            f't={self._now():.2f} s')
        self.get_logger().info(response.message)
        return response

    def _on_set_terrain(self, request: SetTerrain.Request, response: SetTerrain.Response):
        if not hasattr(self._backend, 'add_terrain'):
            response.success, response.message = False, 'this backend has no terrain'
            return response
        try:
            terrain = terrain_from(request.kind, request.side_length, request.origin_x,
                                   request.origin_y, request.tile_size, request.min_height,
                                   request.max_height, request.seed)
        except (BipedSimError, ValueError, OverflowError) as error:
            response.success, response.message = False, f'terrain rejected: {error}'
            self.get_logger().warning(response.message)
            return response
        self._terrain = terrain
        self._backend.clear_terrain()  # the map's obstacles stay as they are
        if terrain is not None:  # None: flat
            self._backend.add_terrain(terrain)
        response.success, response.message = True, 'terrain set'
        return response

    def _on_map(self, msg: OccupancyGridMsg) -> None:
        if not hasattr(self._backend, 'add_obstacles'):
            return
        try:
            occupied, resolution, origin = occupied_cells_from_map(msg, self._frame)
            boxes = boxes_from_occupied_cells(occupied, resolution, origin)
        except (ValueError, BipedSimError) as error:
            self._reject('map', error)
            return
        if list(boxes) == list(self._map_boxes):
            # Rebuilt, the obstacles' bodies would be new ones, perhaps under a foot at rest:
            # the contact solver starts over, nudging the robot at the moment the latched map
            # happened to arrive, which depends on the machine's load
            self.get_logger().info(f'{len(boxes)} obstacle boxes from the map (unchanged)')
            return
        self._map_boxes = boxes
        # Only the obstacles: rebuilt, the tiles under the standing feet would be new bodies
        # (on the tiles, a run crossed where the same run fell, depending on the load)
        self._backend.clear_obstacles()
        if boxes:
            self._backend.add_obstacles(boxes)
        self.get_logger().info(f'{len(self._map_boxes)} obstacle boxes from the map')

    def destroy_node(self) -> None:
        self._backend.close()
        super().destroy_node()


def main(args=None) -> None:
    run_node(SimulatorNode, args)


if __name__ == '__main__':
    main()
