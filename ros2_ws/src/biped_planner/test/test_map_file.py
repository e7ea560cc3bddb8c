"""nav2 map_server files: the pixel rule, the row order, round trips and refusals."""
from pathlib import Path

import numpy as np
import pytest

from biped_planner.errors import MapError
from biped_planner.example_maps import paper_start_goal_example
from biped_planner.map_file import load_map, occupancy_from_pixels, save_map

SHIPPED = Path(__file__).resolve().parent.parent / 'maps' / 'paper_start_goal.yaml'


def write_map(folder: Path, pgm_rows, **fields) -> Path:
    """An ASCII PGM (P2) and its YAML, as a user writes them by hand."""
    rows = [list(r) for r in pgm_rows]
    text = f'P2\n{len(rows[0])} {len(rows)}\n255\n' + '\n'.join(
        ' '.join(str(v) for v in row) for row in rows) + '\n'
    (folder / 'm.pgm').write_text(text)
    data = {'image': 'm.pgm', 'resolution': 0.05, 'origin': [-1.0, 2.0, 0.0],
            'occupied_thresh': 0.65, 'free_thresh': 0.196, 'negate': 0, **fields}
    lines = [f'{k}: {v}' for k, v in data.items()]
    (folder / 'm.yaml').write_text('\n'.join(lines) + '\n')
    return folder / 'm.yaml'


def test_nav2_trinary_rule_and_row_order(tmp_path):
    # top image row = last map row; 0 black = occupied, 254 white = free, 205 grey = unknown
    grid = load_map(write_map(tmp_path, [[0, 254, 205], [254, 254, 0]]))
    np.testing.assert_array_equal(grid.values, [[0, 0, 100], [100, 0, -1]])
    assert grid.resolution == 0.05
    assert tuple(grid.origin) == (-1.0, 2.0)


def test_thresholds_by_hand():
    # p = (255 - v) / 255: v = 90 -> 0.647 (unknown), v = 89 -> 0.651 (occupied),
    # v = 205 -> 0.196 (unknown at free_thresh 0.196: not below it), v = 206 -> 0.192 (free)
    values = occupancy_from_pixels(np.array([[90, 89, 205, 206]]), None, False, 0.65, 0.196,
                                   'trinary')
    np.testing.assert_array_equal(values, [[-1, 100, -1, 0]])


def test_negate_and_scale_and_raw():
    negated = occupancy_from_pixels(np.array([[0, 255]]), None, True, 0.65, 0.25, 'trinary')
    np.testing.assert_array_equal(negated, [[0, 100]])
    scaled = occupancy_from_pixels(np.array([[128]]), None, False, 0.65, 0.25, 'scale')
    assert scaled[0, 0] == round(100 * (255 - 128) / 255)
    raw = occupancy_from_pixels(np.array([[0, 57, 100, 101, 255]]), None, False, 0.65, 0.25,
                                'raw')
    np.testing.assert_array_equal(raw, [[0, 57, 100, -1, -1]])


def test_transparent_pixels_are_unknown():
    values = occupancy_from_pixels(np.array([[0, 254]]), np.array([[255, 0]]), False, 0.65,
                                   0.25, 'trinary')
    np.testing.assert_array_equal(values, [[100, -1]])


def test_round_trip_of_the_paper_map(tmp_path):
    grid, _, _ = paper_start_goal_example()
    yaml_path, image_path = save_map(grid, tmp_path / 'paper.yaml')
    assert image_path.suffix == '.pgm' and image_path.is_file()
    loaded = load_map(yaml_path)
    np.testing.assert_array_equal(loaded.values, grid.values)
    assert loaded.resolution == grid.resolution


def test_the_shipped_paper_map_is_the_example():
    grid, _, _ = paper_start_goal_example()
    np.testing.assert_array_equal(load_map(SHIPPED).values, grid.values)


@pytest.mark.parametrize('fields, message', [
    ({'origin': [0.0, 0.0]}, 'origin must be'),
    ({'origin': [0.0, 0.0, 0.5]}, 'origin yaw must be 0'),
    ({'origin': [0.0, 'a', 0.0]}, 'must be a finite number'),
    ({'resolution': 0}, 'resolution must be > 0'),
    ({'resolution': '.nan'}, 'must be a finite number'),
    ({'occupied_thresh': 0.1}, 'free_thresh <= occupied_thresh'),
    ({'mode': 'fancy'}, 'mode must be one of'),
    ({'negate': 3}, 'negate must be 0 or 1'),
    ({'image': 'missing.pgm'}, 'cannot read image'),
])
def test_malformed_files_are_refused_with_the_field_named(tmp_path, fields, message):
    with pytest.raises(MapError, match=message):
        load_map(write_map(tmp_path, [[0, 254]], **fields))


def test_not_a_map_file(tmp_path):
    (tmp_path / 'x.yaml').write_text('just: text\n')
    with pytest.raises(MapError, match='needs at least image'):
        load_map(tmp_path / 'x.yaml')
    (tmp_path / 'y.yaml').write_text('{{{')
    with pytest.raises(MapError, match='cannot read map file'):
        load_map(tmp_path / 'y.yaml')
    with pytest.raises(MapError, match='cannot read map file'):
        load_map(tmp_path / 'none.yaml')
