"""The simulator node's parameters: each with its description and range (library ranges are the
library's own), and the terrain they describe."""
import math

from biped_msgs.srv import SetTerrain

from biped_planner.parameter_fields import field_specs
from biped_sim.camera_view import CameraView
from biped_sim.closed_loop import ClosedLoopParams
from biped_sim.frame_recorder import FPS_RANGE
from biped_sim.pybullet_config import PyBulletConfig
from biped_sim.robot_catalogue import ROBOTS
from biped_sim.terrain import generate_terrain, TerrainParams

BACKENDS = ('pybullet', 'model')
MAX_TILES = 40_000  # terrain tiles at most (the paper's 4 m of 10 cm tiles: 1,600)


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
    'sole_contact_stiffness': from_library(PyBulletConfig, 'sole_contact_stiffness'),
    'sole_contact_damping': from_library(PyBulletConfig, 'sole_contact_damping'),
    'setpoint_parts': from_library(ClosedLoopParams, 'setpoint_interpolation', 4,
                                   'parts of a period with interpolated setpoints (servo ramp)'),
    'lockstep': (True, 'physics waits for the command answering the last sensor time', None),
    'lockstep_timeout': (0.5, 'wall time without a command after which the controller is '
                         'reported late; one whose process is gone (DDS liveliness of '
                         'joint_commands/alive), or without that token, is then lost: the servos '
                         'hold its last positions, the clock runs in real time (s)',
                         (0.01, 60.0)),
    'wait_for_controller': (False, 'lockstep: hold the clock at its start (publishing the '
                            'first sensor readings again every lockstep_timeout) until the '
                            'first joint command, so that a run does not depend on how long '
                            'the controller took to start', None),
    'wait_for_publishers': ('', 'lockstep: comma-separated topics (e.g. walking_state,'
                            'footstep_plan) that must each have a publisher before the clock '
                            'starts: a user\'s command then reaches a graph that started at '
                            'the same sim time however slowly its processes came up', None),
    'hold_at': (-1.0, 'lockstep: the clock holds at this sim time until simulator/resume is '
                'called: a scripted trial gets ready there, so its commands meet the same sim '
                'time however long that took on the wall clock (s); negative: no hold',
                (-1.0, 1e6)),
    'paced_by': ('', 'lockstep: a topic (rosgraph_msgs/Clock) on which a scripted runner '
                 'publishes the sim time it has acted on; while it has a publisher, the clock '
                 'never runs more than pace_lead ahead of it, so the runner\'s commands meet '
                 'the same sim time however slowly it runs; empty: no pacing', None),
    'pace_lead': (0.1, 'lockstep: how far the clock may run ahead of paced_by (s)',
                  (0.0, 1e3)),
    'hung_controller_timeout': (10.0, 'wall time without a command after which a controller '
                                'whose process is alive is lost all the same (hung) (s)',
                                (0.1, 3600.0)),
    'command_margin': (0.1, 'how far past a joint limit a commanded position may be (rad)',
                       (0.0, 3.2)),
    'max_command_velocity': (1000.0, 'largest feed-forward joint speed of a command (rad/s)',
                             (0.1, 1e6)),
    'reset_hold': (0.5, 'after a reset, time the servos hold the standing pose and ignore '
                   'commands, while the controller restarts (s)', (0.0, 10.0)),
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


# Read at start only (declared read-only): the rest can change while running.
LIVE_PARAMETERS = ('lockstep', 'lockstep_timeout', 'hung_controller_timeout', 'real_time_factor',
                   'wait_for_controller', 'wait_for_publishers',
                   'setpoint_parts', 'command_margin', 'max_command_velocity', 'reset_hold',
                   'start_x', 'start_y', 'start_yaw')
READ_ONLY = tuple(name for name in SIMULATOR_PARAMETERS if name not in LIVE_PARAMETERS)


def terrain_from(kind: int, side_length: float, origin_x: float, origin_y: float,
                 tile_size: float, min_height: float, max_height: float, seed: int):
    """The terrain of a SetTerrain request or of the terrain.* parameters (None: flat).

    :raises ValueError, BipedSimError: for an unknown kind or invalid tiles
    """
    if kind == SetTerrain.Request.FLAT:
        return None
    if kind != SetTerrain.Request.TILES:
        raise ValueError(f'kind {kind} unknown: 0 flat, 1 tiles')
    if not (math.isfinite(side_length) and math.isfinite(tile_size) and tile_size > 0.0):
        raise ValueError(f'side_length {side_length} and tile_size {tile_size} must be finite, '
                         'the tile size > 0')
    tiles = math.ceil(side_length / tile_size) ** 2 if side_length > 0.0 else 0
    if tiles > MAX_TILES:
        raise ValueError(f'{tiles:.3g} tiles ({side_length} m side, {tile_size} m tiles): at '
                         f'most {MAX_TILES}')
    return generate_terrain(TerrainParams(
        tile_area=tile_size ** 2, side_length=side_length, min_height=min_height,
        max_height=max_height, origin=(origin_x, origin_y), seed=int(seed)))
