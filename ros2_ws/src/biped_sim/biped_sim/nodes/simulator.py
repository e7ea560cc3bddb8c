"""The simulator node: joint setpoints in; clock, joint states, IMU, wrenches, odometry out.

Subscribes: joint_commands (sensor_msgs/JointState: setpoints of some or all joints, stamped
with the sensor time they answer), map (nav_msgs/OccupancyGrid, transient local: obstacles).
Publishes every control period: /clock (rosgraph_msgs/Clock), joint_states
(sensor_msgs/JointState), imu (sensor_msgs/Imu), odom (nav_msgs/Odometry, ground truth pelvis),
left_foot_wrench / right_foot_wrench (geometry_msgs/WrenchStamped, ankle F/T sensors),
zmp (geometry_msgs/PointStamped, measured from the F/T sensors), com (PointStamped, ground truth).
Services: push (biped_msgs/Push), reset (std_srvs/Trigger), set_terrain (biped_msgs/SetTerrain).

Lockstep mode (default): while a controller publishes joint_commands, physics advances one
control period only when the command answering the last sensor time has arrived, so a run is
deterministic and as fast as the graph allows; with no controller (or after lockstep_timeout
of wall time) it advances in real time with the last setpoints. Real-time mode (lockstep false)
always advances at real_time_factor, for watching in the GUI.
"""
import math
import time

from biped_msgs.srv import Push, SetTerrain
from builtin_interfaces.msg import Time
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
from biped_planner.node_support.node_runner import run_node
from biped_planner.parameter_fields import field_specs
from biped_sim.camera_view import CameraView
from biped_sim.closed_loop import ClosedLoopParams
from biped_sim.errors import BipedSimError
from biped_sim.external_push import ExternalPush
from biped_sim.frame_recorder import FPS_RANGE
from biped_sim.joint_servo import step_toward
from biped_sim.nodes.conversions import (imu_msg, joint_state_msg, odometry_msg, point_msg,
                                         setpoints_from_joint_state, wrench_msg)
from biped_sim.obstacles import boxes_from_occupied_cells
from biped_sim.pybullet_config import PyBulletConfig
from biped_sim.robot_catalogue import load_robot, ROBOTS
from biped_sim.terrain import generate_terrain, TerrainParams

LATCHED_IN = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                        reliability=ReliabilityPolicy.RELIABLE)
MAX_PUSH_FORCE = 5000.0  # N: beyond any push the robot could feel; larger requests are errors
BACKENDS = ('pybullet', 'model')


def from_library(cls, field: str, default=None, description: str = None,
                 transform=None) -> tuple:
    """(default, description, range) of a node parameter that sets a library dataclass field.

    The range is the field's own (biped_planner.parameter_fields), so the node cannot restate
    it; default None takes the library's default.

    :param transform: maps the field's bounds to the parameter's (a tile area to its side)
    """
    spec = field_specs(cls)[field]
    bounds = spec.bounds
    if transform is not None:
        bounds = tuple(transform(b) for b in bounds)
    value = cls.__dataclass_fields__[field].default if default is None else default
    return value, description or spec.description, bounds


SIMULATOR_PARAMETERS = {
    'backend': ('pybullet', 'physics: PyBullet humanoid or the three-mass model plant',
                BACKENDS),
    'robot': ('coman_like', 'the simulated humanoid (biped_sim.robot_catalogue)',
              tuple(ROBOTS)),
    'gui': from_library(PyBulletConfig, 'gui'),
    'control_mode': from_library(PyBulletConfig, 'control_mode'),
    'control_period': (0.02, 'one controller cycle: sensor publication period (s)', (0.001, 1.0)),
    'physics_step': from_library(PyBulletConfig, 'time_step'),
    'leg_kp': from_library(PyBulletConfig, 'leg_kp', 2000.0),
    'leg_kd': from_library(PyBulletConfig, 'leg_kd'),
    'setpoint_parts': from_library(ClosedLoopParams, 'setpoint_interpolation', 4,
                                   'parts of a period with interpolated setpoints (servo ramp)'),
    'lockstep': (True, 'physics waits for the command answering the last sensor time', None),
    'lockstep_timeout': (0.5, 'wall time without a command after which it steps anyway (s)',
                         (0.01, 60.0)),
    'real_time_factor': (1.0, 'speed of the clock without lockstep (or controller)',
                         (0.01, 100.0)),
    'start_x': (0.0, 'pelvis start x (m)', (-1e4, 1e4)),
    'start_y': (0.0, 'pelvis start y (m)', (-1e4, 1e4)),
    'start_yaw': (0.0, 'pelvis start heading (rad)', (-7.0, 7.0)),
    'frame_id': ('map', 'frame of odom, zmp and com', None),
    'terrain.kind': (0, 'terrain at start, the robot standing on it: 0 flat, 1 tiles', (0, 1)),
    'terrain.side_length': from_library(TerrainParams, 'side_length'),
    'terrain.origin_x': from_library(TerrainParams, 'origin', -2.0, 'x of the area corner with '
                                     'the smallest coordinates (m)'),
    'terrain.origin_y': from_library(TerrainParams, 'origin', -2.0, 'y of the area corner with '
                                     'the smallest coordinates (m)'),
    'terrain.tile_size': from_library(TerrainParams, 'tile_area', 0.2, 'side of a square tile '
                                      '(m): 0.1, 0.2, 0.25 in the paper', math.sqrt),
    'terrain.min_height': from_library(TerrainParams, 'min_height'),
    'terrain.max_height': from_library(TerrainParams, 'max_height'),
    'terrain.seed': from_library(TerrainParams, 'seed'),
    'camera.frames_dir': ('', 'directory for PNG camera frames (pybullet); empty: off', None),
    'camera.fps': (12.5, 'camera frames per second of sim time', FPS_RANGE),
    'camera.width': from_library(CameraView, 'width'),
    'camera.height': from_library(CameraView, 'height'),
    'camera.distance': from_library(CameraView, 'distance', 2.5,
                                    'camera distance from the pelvis (m)'),
    'camera.yaw': from_library(CameraView, 'yaw', description='camera azimuth (deg)'),
    'camera.pitch': from_library(CameraView, 'pitch'),
}


def stamp_of(t: float) -> Time:
    sec = int(math.floor(t))
    return Time(sec=sec, nanosec=int(round((t - sec) * 1e9)) % 1_000_000_000)


def seconds_of(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def terrain_from(kind: int, side_length: float, origin_x: float, origin_y: float,
                 tile_size: float, min_height: float, max_height: float, seed: int):
    """The terrain of a SetTerrain request or of the terrain.* parameters (None: flat).

    :raises ValueError, BipedSimError: for an unknown kind or invalid tiles
    """
    if kind == SetTerrain.Request.FLAT:
        return None
    if kind != SetTerrain.Request.TILES:
        raise ValueError(f'kind {kind} unknown: 0 flat, 1 tiles')
    return generate_terrain(TerrainParams(
        tile_area=tile_size ** 2, side_length=side_length, min_height=min_height,
        max_height=max_height, origin=(origin_x, origin_y), seed=int(seed)))


class SimulatorNode(Node):
    """Thin adapter over a biped_sim SimulatorBackend (PyBullet or the model plant)."""

    def __init__(self, **kwargs) -> None:
        super().__init__('simulator', **kwargs)
        declare_node_parameters(self, SIMULATOR_PARAMETERS)
        self._frame = self.get_parameter('frame_id').value
        self._period = float(self.get_parameter('control_period').value)
        self._backend = self._make_backend()
        self._names = tuple(self._backend.joint_names)
        self._setpoints = self._nominal_setpoints()
        self._previous_setpoints = None
        self._velocities = np.zeros(len(self._names))
        self._substeps = max(1, int(round(self._period /
                                          float(self.get_parameter('physics_step').value))))
        self._last_step_wall = time.monotonic()
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
            self._rebuild_scenery()

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
        self.create_subscription(OccupancyGridMsg, 'map', self._on_map, LATCHED_IN)
        self.create_service(Push, 'push', self._on_push)
        self.create_service(Trigger, 'reset', self._on_reset)
        self.create_service(SetTerrain, 'set_terrain', self._on_set_terrain)
        self._readings = self._reset_robot()
        self._publish(self._readings)
        # Real time: one step a tick. Lockstep steps run in the command callback, and a tick
        # only times the controller's silence (a faster poll would only cost wake-ups).
        self._timer = self.create_timer(self._real_time_period(), self._on_timer,
                                        clock=self._wall)
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
                                    leg_kd=float(self.get_parameter('leg_kd').value))
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
        try:
            self._setpoints = setpoints_from_joint_state(msg, self._names, self._setpoints)
            if len(msg.velocity) == len(msg.name):
                self._velocities = setpoints_from_joint_state(
                    JointState(name=msg.name, position=msg.velocity), self._names,
                    np.zeros(len(self._names)))
        except ValueError as error:
            self.get_logger().error(f'joint_commands rejected: {error}',
                                    throttle_duration_sec=2.0)
            return
        if self._lockstep() and seconds_of(msg.header.stamp) >= self._now() - 1e-6:
            self._step()

    def _real_time_period(self) -> float:
        """Wall seconds between steps in real time (s)."""
        return self._period / max(1e-3, float(self.get_parameter('real_time_factor').value))

    def _on_timer(self) -> None:
        period_ns = int(round(self._real_time_period() * 1e9))
        if self._timer.timer_period_ns != period_ns:  # real_time_factor changed
            self._timer.timer_period_ns = period_ns
        if self._lockstep() and self._command_sub.get_publisher_count() > 0:
            waited = time.monotonic() - self._last_step_wall
            if waited >= float(self.get_parameter('lockstep_timeout').value):
                self.get_logger().warning(f'no joint command for t={self._now():.2f} '
                                          f'after {waited:.2f} s: stepping with the last one',
                                          throttle_duration_sec=5.0)
                self._step()
            return
        self._step()

    def _step(self) -> None:
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
        if not all(math.isfinite(v) for v in values) or request.duration <= 0.0 or \
                math.hypot(*force) > MAX_PUSH_FORCE:
            response.success = False
            response.message = (f'push rejected: force {force} N (|F| <= {MAX_PUSH_FORCE}), '
                                 f'duration {request.duration} s (> 0) and point must be finite')
            return response
        start = seconds_of(request.start) - self._time_offset  # in the backend's time
        start = start if start > self._readings.time else None
        try:
            self._backend.push(ExternalPush(force=force, duration=request.duration,
                                            link=request.link or None, point=point,
                                            start_time=start))
        except BipedSimError as error:
            response.success, response.message = False, f'push rejected: {error}'
            return response
        response.success = True
        begins = self._time_offset + (self._readings.time if start is None else start)
        response.message = f'pushing {force} N for {request.duration} s from t={begins:.3f} s'
        self.get_logger().info(response.message)
        return response

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        self._time_offset += self._readings.time + self._period
        self._readings = self._reset_robot()
        self._publish(self._readings)
        response.success, response.message = True, 'robot reset to its start pose'
        return response

    def _on_set_terrain(self, request: SetTerrain.Request, response: SetTerrain.Response):
        if not hasattr(self._backend, 'add_terrain'):
            response.success, response.message = False, 'this backend has no terrain'
            return response
        try:
            terrain = terrain_from(request.kind, request.side_length, request.origin_x,
                                   request.origin_y, request.tile_size, request.min_height,
                                   request.max_height, request.seed)
        except (BipedSimError, ValueError) as error:
            response.success, response.message = False, f'terrain rejected: {error}'
            return response
        self._terrain = terrain
        self._rebuild_scenery()
        response.success, response.message = True, 'terrain set'
        return response

    def _on_map(self, msg: OccupancyGridMsg) -> None:
        if not hasattr(self._backend, 'add_obstacles'):
            return
        values = np.asarray(msg.data, dtype=np.int16)
        if values.size != msg.info.width * msg.info.height or msg.info.resolution <= 0.0:
            self.get_logger().error('map ignored: data size or resolution malformed')
            return
        occupied = values.reshape(msg.info.height, msg.info.width) >= 50
        origin = (msg.info.origin.position.x, msg.info.origin.position.y)
        self._map_boxes = boxes_from_occupied_cells(occupied, msg.info.resolution, origin)
        self._rebuild_scenery()
        self.get_logger().info(f'{len(self._map_boxes)} obstacle boxes from the map')

    def _rebuild_scenery(self) -> None:
        """Obstacles from the map and the terrain, both kept when either changes."""
        self._backend.clear_scenery()
        if self._map_boxes:
            self._backend.add_obstacles(self._map_boxes)
        if self._terrain is not None:
            self._backend.add_terrain(self._terrain)

    def destroy_node(self) -> None:
        self._backend.close()
        super().destroy_node()


def main(args=None) -> None:
    run_node(SimulatorNode, args)


if __name__ == '__main__':
    main()
