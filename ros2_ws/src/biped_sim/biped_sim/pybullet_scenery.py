"""What stands around the robot in PyBullet: tiled terrain, obstacles, and a camera to film it.

Terrain tiles and obstacles are static bodies with the feet's friction. Tiles are grouped by
height into colour bins, blue for the lowest to red for the highest, as bodies of at most
MAX_SHAPES_PER_BODY tiles (one compound shape each: createVisualShapeArray crashes PyBullet
3.2.7 beyond 16 shapes). Frames are rendered with the tiny software renderer (no GPU needed).
"""

import numpy as np

from biped_sim.camera_view import CameraView
from biped_sim.errors import ConfigError
from biped_sim.obstacles import as_sim_obstacle, BoxObstacle
from biped_sim.terrain import Terrain

try:
    import pybullet
except ImportError as error:  # pragma: no cover - pybullet is a hard dependency of biped_sim
    raise ImportError('biped_sim.pybullet_scenery needs pybullet (Python <= 3.11 wheels): '
                      'pip install pybullet==3.2.7') from error

MAX_SHAPES_PER_BODY = 16  # createVisualShapeArray segfaults with more (PyBullet 3.2.7)


class PyBulletScenery:
    """The static bodies added to a PyBullet world, and their removal: the terrain's and the
    obstacles' apart, so a new map leaves the tiles under the feet as they are.

    :param client: PyBullet physics client id.
    :param friction: lateral friction coefficient of the bodies.
    """

    def __init__(self, client: int, friction: float) -> None:
        self._client = client
        self._friction = friction
        self._terrain_bodies: list = []
        self._obstacle_bodies: list = []

    @property
    def bodies(self) -> list:
        """The body ids of the terrain's tiles, then of the obstacles."""
        return self._terrain_bodies + self._obstacle_bodies

    def add_terrain(self, terrain: Terrain, colour_bins: int = 8) -> list:
        """Build the tiles of a terrain as static boxes, coloured by height.

        A tile of height 0 is no tile: the ground plane is there.

        :param terrain: the generated terrain.
        :param colour_bins: number of height colours, >= 1.
        :return: the PyBullet body ids.
        :raises ConfigError: for a bad colour_bins.
        """
        if not (isinstance(colour_bins, int) and colour_bins >= 1):
            raise ConfigError('colour_bins = %r must be an int >= 1' % (colour_bins,))
        heights = terrain.heights.ravel()
        centres = terrain.tile_centres()
        low, high = terrain.params.min_height, terrain.params.max_height
        span = max(high - low, 1e-9)
        bins = np.minimum(((heights - low) / span * colour_bins).astype(int), colour_bins - 1)
        half_side = 0.5 * terrain.tile_side
        ids = []
        for b in range(colour_bins):
            members = np.flatnonzero((bins == b) & (heights > 0.0))
            if members.size == 0:
                continue
            level = (b + 0.5) / colour_bins
            colour = [level, 0.3, 1.0 - level, 1.0]
            for chunk in np.array_split(members, -(-members.size // MAX_SHAPES_PER_BODY)):
                half_extents = [[half_side, half_side, 0.5 * heights[k]] for k in chunk]
                frames = [[centres[k, 0], centres[k, 1], 0.5 * heights[k]] for k in chunk]
                ids.append(self._static_compound(half_extents, frames, colour))
        self._terrain_bodies.extend(ids)
        return ids

    def _static_compound(self, half_extents: list, frames: list, colour: list) -> int:
        client = self._client
        count = len(half_extents)
        collision = pybullet.createCollisionShapeArray(
            shapeTypes=[pybullet.GEOM_BOX] * count, halfExtents=half_extents,
            collisionFramePositions=frames, physicsClientId=client)
        visual = pybullet.createVisualShapeArray(
            shapeTypes=[pybullet.GEOM_BOX] * count, halfExtents=half_extents,
            visualFramePositions=frames, rgbaColors=[colour] * count, physicsClientId=client)
        body = pybullet.createMultiBody(0.0, collision, visual, [0.0, 0.0, 0.0],
                                        physicsClientId=client)
        pybullet.changeDynamics(body, -1, lateralFriction=self._friction,
                                physicsClientId=client)
        return body

    def add_obstacles(self, obstacles) -> list:
        """Add static obstacles from a planner-like list of boxes and discs.

        :param obstacles: BoxObstacle, DiscObstacle or duck-typed equivalents
            (biped_sim.obstacles.as_sim_obstacle).
        :return: the PyBullet body ids, one per obstacle.
        """
        client, ids = self._client, []
        for item in obstacles:
            obstacle = as_sim_obstacle(item)
            if isinstance(obstacle, BoxObstacle):
                half = [0.5 * obstacle.size_x, 0.5 * obstacle.size_y, 0.5 * obstacle.height]
                collision = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=half,
                                                          physicsClientId=client)
                visual = pybullet.createVisualShape(pybullet.GEOM_BOX, halfExtents=half,
                                                    rgbaColor=[0.6, 0.4, 0.3, 1.0],
                                                    physicsClientId=client)
                yaw = obstacle.yaw
            else:
                collision = pybullet.createCollisionShape(
                    pybullet.GEOM_CYLINDER, radius=obstacle.radius, height=obstacle.height,
                    physicsClientId=client)
                visual = pybullet.createVisualShape(
                    pybullet.GEOM_CYLINDER, radius=obstacle.radius, length=obstacle.height,
                    rgbaColor=[0.3, 0.5, 0.6, 1.0], physicsClientId=client)
                yaw = 0.0
            body = pybullet.createMultiBody(
                0.0, collision, visual, [obstacle.x, obstacle.y, 0.5 * obstacle.height],
                pybullet.getQuaternionFromEuler([0.0, 0.0, yaw]), physicsClientId=client)
            ids.append(body)
        self._obstacle_bodies.extend(ids)
        return ids

    def clear(self) -> None:
        """Remove every terrain tile and obstacle added so far."""
        self.clear_terrain()
        self.clear_obstacles()

    def clear_terrain(self) -> None:
        """Remove the terrain's tiles; the obstacles stay."""
        self._remove(self._terrain_bodies)
        self._terrain_bodies = []

    def clear_obstacles(self) -> None:
        """Remove the obstacles; the terrain's tiles stay."""
        self._remove(self._obstacle_bodies)
        self._obstacle_bodies = []

    def _remove(self, bodies: list) -> None:
        for body in bodies:
            pybullet.removeBody(body, physicsClientId=self._client)


def render(client: int, view: CameraView, target) -> np.ndarray:
    """Render a camera frame with the tiny software renderer.

    :param client: PyBullet physics client id.
    :param view: camera placement and image size.
    :param target: (3,) point looked at when the view has none (m).
    :return: (height, width, 3) uint8 RGB image.
    """
    target = list(view.target) if view.target is not None else list(target)
    view_matrix = pybullet.computeViewMatrixFromYawPitchRoll(
        target, view.distance, view.yaw, view.pitch, 0.0, 2, physicsClientId=client)
    projection = pybullet.computeProjectionMatrixFOV(
        view.fov, view.width / view.height, 0.02, 50.0, physicsClientId=client)
    image = pybullet.getCameraImage(view.width, view.height, view_matrix, projection,
                                    renderer=pybullet.ER_TINY_RENDERER, physicsClientId=client)[2]
    rgba = np.asarray(image, dtype=np.uint8).reshape(view.height, view.width, 4)
    return rgba[:, :, :3].copy()
