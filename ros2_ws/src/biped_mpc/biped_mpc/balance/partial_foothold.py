"""Partial footholds: a sole that rotates about a line under it rests on one side of that line.

A sole across a tile edge, or with its toe over a lower tile, touches the ground on part of
its area only. When the stabilizer asks for pressure beyond that part, the sole rotates about
the edge of what it rests on (the measured centre of pressure sits on that edge) and, with
stiff ankle servos, the body rotates with it. After IHMC's PartialFootholdControlModule
(Wiedebach et al. 2016, "Walking on partial footholds including line contacts"): a loaded
sole turning about a horizontal axis for a while is cut along the line through its measured
CoP parallel to that axis, and the side that sinks is dropped; what remains is the foothold,
which the DCM feedback's support polygon and the wrench distribution's CoP limits then use.
A CoP measured clearly beyond a cut proves ground there and removes the cut; a foot that
leaves the ground gets its whole sole back.

The foothold is kept in the sole frame (x forward, y left, about the sole centre) as the sole
rectangle intersected with the cuts, each a half-plane n . r <= d.
"""
from dataclasses import dataclass
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.validation import check_period
from biped_planner.parameter_fields import parameter, validate_fields

Cut = Tuple[float, float, float]  # (n_x, n_y, d): the foothold keeps n . r <= d, |n| = 1


@dataclass(frozen=True)
class PartialFootholdParams:
    """Detection thresholds of the partial foothold (see PartialFoothold)."""

    sole_length: float = parameter(0.2, 'sole length along the foot (m)', low=0.01, high=1.0)
    sole_width: float = parameter(0.1, 'sole width across the foot (m)', low=0.01, high=1.0)
    rotation_threshold: float = parameter(
        0.5, 'sole angular velocity about a horizontal axis that counts as rotating (rad/s)',
        low=0.0, high=100.0, low_open=True)
    detection_time: float = parameter(0.04, 'time the rotation must last before the cut (s)',
                                      low=0.0, high=1.0)
    velocity_time_constant: float = parameter(
        0.01, 'low-pass of the angular velocity from successive sole attitudes (s)',
        low=0.0, high=1.0)
    min_force: float = parameter(50.0, 'normal force below which a sole is neither cut nor '
                                 'proves ground (N)', low=0.0, high=1e4)
    min_area_fraction: float = parameter(
        0.2, 'smallest foothold a cut may leave, as a share of the sole', low=0.0, high=1.0)
    restore_distance: float = parameter(
        0.01, 'measured CoP this far beyond a cut removes it (m)', low=0.0, high=0.2)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


def sole_rectangle(length: float, width: float) -> List[Tuple[float, float]]:
    """Corners of a sole about its centre, counter-clockwise."""
    x, y = 0.5 * length, 0.5 * width
    return [(x, y), (-x, y), (-x, -y), (x, -y)]


def clip_polygon(vertices: Sequence[Tuple[float, float]], cut: Cut) -> List[Tuple[float, float]]:
    """The part of a convex polygon with n . r <= d (Sutherland-Hodgman, one half-plane).

    :param vertices: counter-clockwise vertices
    :param cut: (n_x, n_y, d)
    :return: counter-clockwise vertices of the part kept (empty when nothing is)
    """
    n_x, n_y, d = cut
    kept = []
    count = len(vertices)
    for i in range(count):
        a, b = vertices[i], vertices[(i + 1) % count]
        side_a = n_x * a[0] + n_y * a[1] - d
        side_b = n_x * b[0] + n_y * b[1] - d
        if side_a <= 0.0:
            kept.append(a)
        if (side_a < 0.0 < side_b) or (side_b < 0.0 < side_a):
            s = side_a / (side_a - side_b)
            kept.append((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])))
    return kept


def polygon_area(vertices: Sequence[Tuple[float, float]]) -> float:
    """Area of a simple polygon (shoelace), positive when counter-clockwise."""
    count = len(vertices)
    return 0.5 * sum(vertices[i][0] * vertices[(i + 1) % count][1]
                     - vertices[(i + 1) % count][0] * vertices[i][1] for i in range(count))


def foothold_polygon(length: float, width: float, cuts: Sequence[Cut],
                     margin: float = 0.0) -> Tuple[List[Tuple[float, float]], List[Cut]]:
    """A sole's foothold in its frame with every edge moved inwards by margin.

    :param length: sole length (m)
    :param width: sole width (m)
    :param cuts: the foothold's cuts, oldest first
    :param margin: inward offset (m), below half the width
    :return: counter-clockwise vertices, and the cuts they used: a cut that the margin would
        leave nothing of is skipped with the ones after it
    """
    polygon = sole_rectangle(length - 2.0 * margin, width - 2.0 * margin)
    used = []
    for n_x, n_y, d in cuts:
        clipped = clip_polygon(polygon, (n_x, n_y, d - margin))
        if len(clipped) < 3 or polygon_area(clipped) <= 0.0:
            break
        polygon = clipped
        used.append((n_x, n_y, d))
    return polygon, used


def angular_velocity(previous: np.ndarray, current: np.ndarray, dt: float) -> np.ndarray:
    """Angular velocity in the current frame from two attitudes dt apart (small rotation).

    :param previous: (3, 3) rotation at t - dt
    :param current: (3, 3) rotation at t
    :param dt: period (s), > 0
    :return: (3,) angular velocity, frame of current (rad/s)
    """
    delta = previous.T @ current
    return np.array([delta[2, 1] - delta[1, 2], delta[0, 2] - delta[2, 0],
                     delta[1, 0] - delta[0, 1]]) / (2.0 * dt)


class PartialFoothold:
    """One sole's foothold: the sole rectangle cut where the sole was seen to rotate.

    :param params: thresholds
    """

    def __init__(self, params: PartialFootholdParams = PartialFootholdParams()) -> None:
        self.params = params
        self._sole_area = polygon_area(sole_rectangle(params.sole_length, params.sole_width))
        self.reset()

    def reset(self) -> None:
        """The whole sole, no rotation seen."""
        self.cuts: List[Cut] = []
        self._rotating_time = 0.0
        self._cut_this_rotation = False
        self._previous: Optional[np.ndarray] = None
        self._velocity = np.zeros(3)

    @property
    def velocity(self) -> np.ndarray:
        """(3,) the low-passed angular velocity of the sole in its own frame (rad/s)."""
        return self._velocity.copy()

    def update(self, dt: float, in_contact: bool, normal_force: float, rotation,
               cop: Optional[Sequence[float]]) -> bool:
        """One control period.

        :param dt: period (s), > 0
        :param in_contact: the foot is a support (its contact state)
        :param normal_force: measured normal force (N)
        :param rotation: (3, 3) measured sole attitude in the world
        :param cop: (2,) measured CoP in the sole frame (m), or None / NaN when not measured
        :return: whether a cut was made this period
        """
        check_period(dt)
        p = self.params
        rotation = np.asarray(rotation, dtype=float)
        if self._previous is not None:
            blend = 1.0 if p.velocity_time_constant == 0.0 else \
                1.0 - math.exp(-dt / p.velocity_time_constant)
            self._velocity += blend * (angular_velocity(self._previous, rotation, dt)
                                       - self._velocity)
        self._previous = rotation.copy()
        if not in_contact:
            self.cuts = []
            self._rotating_time, self._cut_this_rotation = 0.0, False
            return False
        loaded = normal_force >= p.min_force and cop is not None and \
            all(math.isfinite(float(c)) for c in cop)
        if not loaded:
            self._rotating_time = 0.0
            return False
        c_x, c_y = float(cop[0]), float(cop[1])
        self.cuts = [cut for cut in self.cuts
                     if cut[0] * c_x + cut[1] * c_y - cut[2] <= p.restore_distance]
        w_x, w_y = float(self._velocity[0]), float(self._velocity[1])
        speed = math.hypot(w_x, w_y)
        if speed < p.rotation_threshold:
            self._rotating_time, self._cut_this_rotation = 0.0, False
            return False
        self._rotating_time += dt
        if self._cut_this_rotation or self._rotating_time < p.detection_time - 1e-9:
            return False
        self._cut_this_rotation = True
        # The sole turns about (w_x, w_y) through the CoP; a point r moves up at
        # (w x (r - c))_z = w_x (r_y - c_y) - w_y (r_x - c_x): the side moving down has no ground.
        n_x, n_y = w_y / speed, -w_x / speed
        cut = (n_x, n_y, n_x * c_x + n_y * c_y)
        polygon, used = foothold_polygon(p.sole_length, p.sole_width, self.cuts + [cut])
        if len(used) <= len(self.cuts) or \
                polygon_area(polygon) < p.min_area_fraction * self._sole_area:
            return False  # the cut leaves nothing, or too little
        self.cuts.append(cut)
        return True
