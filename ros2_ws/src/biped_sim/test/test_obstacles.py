"""Tests of the obstacle list conversion (planner-like boxes and discs)."""

from dataclasses import dataclass
import math

import pytest

from biped_sim.errors import ConfigError
from biped_sim.obstacles import as_sim_obstacle, BoxObstacle, DiscObstacle


@dataclass
class PlannerDisc:
    center: tuple
    radius: float


@dataclass
class PlannerBox:
    x_min: float
    y_min: float
    x_max: float
    y_max: float


@dataclass
class CentredBox:
    x: float
    y: float
    size_x: float
    size_y: float
    yaw: float
    height: float


def test_duck_typed_disc():
    disc = as_sim_obstacle(PlannerDisc((1.8, 0.0), 1.35))
    assert disc == DiscObstacle(1.8, 0.0, 1.35)


def test_duck_typed_boxes():
    box = as_sim_obstacle(PlannerBox(1.0, -0.5, 1.5, 0.5), height=0.3)
    assert box == BoxObstacle(1.25, 0.0, 0.5, 1.0, 0.0, 0.3)
    rotated = as_sim_obstacle(CentredBox(1.0, 2.0, 0.5, 0.2, 0.3, 0.8))
    assert rotated == BoxObstacle(1.0, 2.0, 0.5, 0.2, 0.3, 0.8)


def test_own_types_pass_through():
    box = BoxObstacle(0.0, 0.0, 1.0, 1.0)
    assert as_sim_obstacle(box) is box


def test_bad_obstacles_raise():
    with pytest.raises(ConfigError, match='neither a disc'):
        as_sim_obstacle(object())
    with pytest.raises(ConfigError, match='radius'):
        DiscObstacle(0.0, 0.0, -1.0)
    with pytest.raises(ConfigError, match='size_x'):
        BoxObstacle(0.0, 0.0, 0.0, 1.0)
    with pytest.raises(ConfigError, match='x'):
        BoxObstacle(math.nan, 0.0, 1.0, 1.0)
    with pytest.raises(ConfigError, match='height'):
        as_sim_obstacle(PlannerBox(1.0, 0.0, 2.0, 1.0), height=0.0)
