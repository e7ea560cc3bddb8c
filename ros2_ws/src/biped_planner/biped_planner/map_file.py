"""Occupancy maps in the nav2 map_server format: a YAML file naming a PGM/PNG image.

The YAML holds ``image`` (path, relative to the YAML file), ``resolution`` (m per pixel),
``origin`` [x, y, yaw] (the world pose of the lower-left pixel's corner; yaw must be 0 here, as
our grid is axis aligned), ``negate`` (0 or 1), ``occupied_thresh``, ``free_thresh`` and
``mode`` (trinary, scale or raw), with nav2's meanings: in trinary and scale modes a pixel of
value v (0..255, the mean of the colour channels) is occupied with probability
p = (255 - v) / 255 (v / 255 with negate); p > occupied_thresh is occupied (100),
p < free_thresh free (0), in between unknown (-1) in trinary mode and round(100 p) in scale
mode; a transparent pixel is unknown. In raw mode the value is the occupancy itself (>100:
unknown). The image's top row is the map's last row (images go down, y goes up).
"""
from pathlib import Path
from typing import Tuple

import numpy as np
import yaml

from biped_planner.errors import MapError
from biped_planner.input_checks import check_number
from biped_planner.occupancy_grid import OccupancyGrid, UNKNOWN

MODES = ('trinary', 'scale', 'raw')


def _number(data: dict, key: str, path, default=None) -> float:
    return check_number(f'{path}: {key}', data.get(key, default), error=MapError)


def occupancy_from_pixels(pixels: np.ndarray, alpha, negate: bool, occupied_thresh: float,
                          free_thresh: float, mode: str) -> np.ndarray:
    """nav2's pixel -> occupancy rule for one image (rows top to bottom as in the image).

    :param pixels: (rows, cols) grey values 0..255
    :param alpha: (rows, cols) alpha values 0..255, or None for an opaque image
    :return: (rows, cols) int8 occupancy in -1..100, same row order
    """
    values = np.asarray(pixels, dtype=float)
    if mode == 'raw':
        occupancy = np.where(values > 100, UNKNOWN, values).astype(np.int8)
    else:
        p = values / 255.0 if negate else (255.0 - values) / 255.0
        occupancy = np.full(values.shape, UNKNOWN, dtype=np.int8)
        occupancy[p > occupied_thresh] = 100
        occupancy[p < free_thresh] = 0
        if mode == 'scale':
            between = (p >= free_thresh) & (p <= occupied_thresh)
            occupancy[between] = np.round(100.0 * p[between]).astype(np.int8)
    if alpha is not None and mode != 'raw':
        occupancy[np.asarray(alpha) < 255] = UNKNOWN
    return occupancy


def load_map(yaml_path) -> OccupancyGrid:
    """Read a nav2 map_server map.

    :param yaml_path: the map's YAML file
    :return: the grid (row = y index, origin at the lower-left corner)
    :raises MapError: naming the file and the field that is missing or malformed
    """
    from PIL import Image, UnidentifiedImageError

    path = Path(yaml_path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise MapError(f'cannot read map file {path}: {error}') from error
    if not isinstance(data, dict) or 'image' not in data:
        raise MapError(f'{path}: a nav2 map file needs at least image, resolution and origin')
    resolution = _number(data, 'resolution', path)
    if resolution <= 0.0:
        raise MapError(f'{path}: resolution must be > 0 m, got {resolution}')
    origin = data.get('origin')
    if not isinstance(origin, (list, tuple)) or len(origin) != 3:
        raise MapError(f'{path}: origin must be [x, y, yaw], got {origin!r}')
    x0, y0, yaw = (_number({'origin': v}, 'origin', path) for v in origin)
    if abs(yaw) > 1e-9:
        raise MapError(f'{path}: origin yaw must be 0 (the grid is axis aligned), got {yaw}')
    mode = data.get('mode', 'trinary')
    if mode not in MODES:
        raise MapError(f'{path}: mode must be one of {MODES}, got {mode!r}')
    negate = data.get('negate', 0)
    if negate not in (0, 1, True, False):
        raise MapError(f'{path}: negate must be 0 or 1, got {negate!r}')
    occupied = _number(data, 'occupied_thresh', path, 0.65)
    free = _number(data, 'free_thresh', path, 0.25)
    if not 0.0 <= free <= occupied <= 1.0:
        raise MapError(f'{path}: need 0 <= free_thresh <= occupied_thresh <= 1, got {free}, '
                       f'{occupied}')
    image_path = path.parent / str(data['image'])
    try:
        with Image.open(image_path) as image:
            bands = image.getbands()
            alpha = np.asarray(image.getchannel('A')) if 'A' in bands else None
            if mode == 'raw' or bands[0] in ('L', 'P', '1', 'I'):
                pixels = np.asarray(image.convert('L'))
            else:  # colour: nav2 takes the mean of the channels, not the luminance
                pixels = np.asarray(image.convert('RGB'), dtype=float).mean(axis=2)
    except (OSError, UnidentifiedImageError, ValueError) as error:
        raise MapError(f'{path}: cannot read image {image_path}: {error}') from error
    occupancy = occupancy_from_pixels(pixels, alpha, bool(negate), occupied, free, mode)
    return OccupancyGrid(occupancy[::-1], resolution, (x0, y0))


def save_map(grid: OccupancyGrid, yaml_path, image_name: str = '') -> Tuple[Path, Path]:
    """Write a grid as a nav2 map (trinary PGM: free 254, occupied 0, unknown 205).

    :param grid: the grid
    :param yaml_path: the YAML file to write; the image goes beside it
    :param image_name: the image's file name (default: the YAML's stem + .pgm)
    :return: (yaml path, image path)
    """
    from PIL import Image

    yaml_path = Path(yaml_path)
    image_path = yaml_path.with_name(image_name or yaml_path.stem + '.pgm')
    values = np.asarray(grid.values)
    pixels = np.full(values.shape, 205, dtype=np.uint8)
    pixels[values == 0] = 254
    pixels[values >= 65] = 0
    pixels[(values > 0) & (values < 65)] = 254
    Image.fromarray(pixels[::-1]).save(image_path)
    x0, y0 = (float(v) for v in grid.origin)
    yaml_path.write_text(yaml.safe_dump({
        'image': image_path.name, 'mode': 'trinary', 'resolution': float(grid.resolution),
        'origin': [x0, y0, 0.0], 'negate': 0, 'occupied_thresh': 0.65, 'free_thresh': 0.25},
        sort_keys=False))
    return yaml_path, image_path
