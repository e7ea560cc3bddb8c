"""The map the graph plans on: a map file, or an empty map around the start."""
import numpy as np
import pytest

from biped_planner.errors import ConfigError, MapError
from biped_planner.example_maps import paper_start_goal_example
from biped_planner.map_file import save_map
from biped_planner.map_source import EmptyMapParams, empty_map, map_from_source


def test_the_empty_map_is_free_and_centred_on_the_start():
    grid = empty_map(EmptyMapParams(size=3.0, resolution=0.25, center_x=-1.0, center_y=2.5))
    assert grid.shape == (12, 12)
    assert grid.extent == pytest.approx((-2.5, 0.5, 1.0, 4.0))
    assert not np.any(grid.values)
    assert grid.contains(-1.0, 2.5)


def test_a_size_that_is_not_a_whole_number_of_cells_is_rounded_up():
    grid = empty_map(EmptyMapParams(size=1.05, resolution=0.1))
    assert grid.shape == (11, 11)
    x0, x1, _, _ = grid.extent
    assert x0 == pytest.approx(-0.55) and x1 == pytest.approx(0.55)


@pytest.mark.parametrize('fields, words', [
    ({'size': 0.0}, 'size'), ({'resolution': float('nan')}, 'resolution'),
    ({'center_x': float('inf')}, 'center_x'), ({'size': 1000.0, 'resolution': 0.01}, 'cells'),
])
def test_bad_empty_map_parameters_are_refused(fields, words):
    with pytest.raises(ConfigError, match=words):
        EmptyMapParams(**fields)


def test_a_map_file_is_loaded_and_an_empty_name_gives_the_empty_map(tmp_path):
    grid, _, _ = paper_start_goal_example()
    path, _ = save_map(grid, tmp_path / 'paper.yaml')
    np.testing.assert_array_equal(map_from_source(path, EmptyMapParams()).values, grid.values)
    assert map_from_source('  ', EmptyMapParams(size=1.0, resolution=0.5)).shape == (2, 2)


def test_a_missing_map_file_names_it():
    with pytest.raises(MapError, match='nowhere.yaml does not exist'):
        map_from_source('/tmp/nowhere.yaml', EmptyMapParams())
