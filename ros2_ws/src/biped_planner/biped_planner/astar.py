"""A* search for a collision-free body path on the inflated occupancy grid (first planning stage).

Graph: the free cells of the inflated grid, 8-connected, a move costing its Euclidean length
(1 or sqrt(2) cells); a diagonal move needs both cells it passes by free (no corner cutting).
Heuristic: Euclidean distance to the goal, which is admissible and consistent on this graph, so
the returned path is optimal. Reachability is checked first with a connected-component labelling
(with no corner cutting the 8-connected graph has the 4-connected components), so an unreachable
goal fails at once instead of exhausting the search.

Two searches over the same graph return the same optimal cost:

* 'jump' (default): A* with jump-point pruning (JPS, Harabor and Grastien 2011, with the
  no-corner-cutting rules of their 2014 paper; diagonal moves have no forced neighbours, a
  straight move has one where an obstacle ends beside it). Jumps take O(1) time with per-map
  tables (JPS+): for every cell and direction, the free run length and the distance to the next
  jump point. A* then expands only jump points, typically tens to hundreds instead of tens of
  thousands of cells.
* 'plain': textbook A* expanding cells one by one (the reference the tests compare with).
"""
from dataclasses import dataclass
import heapq
import math
from typing import Tuple

import numpy as np
from scipy import ndimage

from biped_planner.errors import (ConfigError, GoalOccupiedError, GoalOutsideMapError,
                                  NoPathError, StartOccupiedError, StartOutsideMapError)
from biped_planner.input_checks import check_type, is_finite_number
from biped_planner.occupancy_grid import InflationParams, OccupancyGrid

SQRT2 = math.sqrt(2.0)
# (row step, column step, cost in cells); the first four are the orthogonal moves.
MOVES = ((0, 1, 1.0), (1, 0, 1.0), (0, -1, 1.0), (-1, 0, 1.0),
         (1, 1, SQRT2), (1, -1, SQRT2), (-1, 1, SQRT2), (-1, -1, SQRT2))


@dataclass(frozen=True)
class GridPath:
    """An optimal path on the grid.

    :param cells: (K, 2) int (row, col) from start to goal
    :param points: (K, 2) world centres of the cells (m)
    :param cost: path length (m)
    :param expanded: number of cells A* expanded
    """

    cells: np.ndarray
    points: np.ndarray
    cost: float
    expanded: int


INFINITE = 1 << 40
SEARCH_METHODS = ('jump', 'plain')
# Candidate directions after arriving at a jump point in a direction (indices into MOVES): a
# straight arrival may continue straight or turn to either side (forced or not: a superset of
# the pruned set keeps the search optimal); a diagonal arrival continues with its two straight
# components and the diagonal itself.
_CANDIDATES = {0: (0, 1, 3, 4, 6), 1: (1, 0, 2, 4, 5), 2: (2, 1, 3, 5, 7), 3: (3, 0, 2, 6, 7),
               4: (0, 1, 4), 5: (2, 1, 5), 6: (0, 3, 6), 7: (2, 3, 7)}
# Straight components (column direction, row direction) of each diagonal move.
_COMPONENTS = {4: (0, 1), 5: (2, 1), 6: (0, 3), 7: (2, 3)}


class AStarPlanner:
    """A* on one occupancy grid; inflation, move masks, regions and jump tables are precomputed."""

    def __init__(self, grid: OccupancyGrid, params: InflationParams = InflationParams(),
                 method: str = 'jump') -> None:
        """Precompute everything that depends only on the map.

        :param grid: the occupancy grid
        :param params: inflation parameters
        :param method: 'jump' (A* with jump-point pruning) or 'plain' (cell-by-cell A*)
        :raises ConfigError: if grid or params has the wrong type or method is unknown
        """
        check_type('grid', grid, OccupancyGrid)
        check_type('params', params, InflationParams)
        if method not in SEARCH_METHODS:
            raise ConfigError(f'method must be one of {SEARCH_METHODS}, got {method!r}')
        self._grid = grid
        self._params = params
        self._method = method
        self._occupied = grid.occupied(params)
        self._blocked = grid.inflated(params)
        height, width = self._blocked.shape
        self._padded_width = width + 2
        free = np.zeros((height + 2, width + 2), dtype=bool)
        free[1:-1, 1:-1] = ~self._blocked
        self._free = free
        mask = np.zeros(free.shape, dtype=np.int64)
        for bit, (d_row, d_col, _) in enumerate(MOVES):
            mask[1:-1, 1:-1] |= self._allowed(d_row, d_col)[1:-1, 1:-1].astype(np.int64) << bit
        self._mask_array = mask
        self._mask = mask.ravel().tolist()
        self._offsets = [d_row * self._padded_width + d_col for d_row, d_col, _ in MOVES]
        self._moves_by_mask = [tuple((self._offsets[bit], MOVES[bit][2]) for bit in range(8)
                                     if value >> bit & 1) for value in range(256)]
        self._regions, self._region_count = ndimage.label(~self._blocked)
        if method == 'jump':
            self._build_jump_tables()

    def _allowed(self, d_row: int, d_col: int) -> np.ndarray:
        """(H + 2, W + 2) bool: the move (d_row, d_col) from each padded cell is allowed."""
        free = self._free
        shifted = _shift(free, d_row, d_col)
        allowed = free & shifted
        if d_row and d_col:
            allowed &= _shift(free, d_row, 0) & _shift(free, 0, d_col)
        return allowed

    def _build_jump_tables(self) -> None:
        """Per-cell run lengths and jump distances for the 4 straight and 4 diagonal moves."""
        free = self._free
        blocked = ~free
        runs = {}
        jumps = {}
        for direction in range(4):
            d_row, d_col, _ = MOVES[direction]
            side_row, side_col = d_col, d_row
            forced = free & (
                (_shift(free, side_row, side_col)
                 & _shift(blocked, side_row - d_row, side_col - d_col))
                | (_shift(free, -side_row, -side_col)
                   & _shift(blocked, -side_row - d_row, -side_col - d_col)))
            run = np.zeros(free.shape, dtype=np.int64)
            jump = np.full(free.shape, INFINITE, dtype=np.int64)
            for line in _sweep_order(free.shape, d_row, d_col):
                ahead = _ahead(line, d_row, d_col)
                run[line] = np.where(free[line], 1 + run[ahead], 0)
                jump[line] = np.where(~free[line], INFINITE,
                                      np.where(forced[line], 0,
                                               np.minimum(jump[ahead] + 1, INFINITE)))
            runs[direction] = run
            jumps[direction] = jump
        for direction in range(4, 8):
            d_row, d_col, _ = MOVES[direction]
            col_dir, row_dir = _COMPONENTS[direction]
            hit = free & (
                (_shift(free, 0, d_col) & (_shift(jumps[col_dir], 0, d_col, INFINITE)
                                           < INFINITE))
                | (_shift(free, d_row, 0) & (_shift(jumps[row_dir], d_row, 0, INFINITE)
                                             < INFINITE)))
            allowed = self._allowed(d_row, d_col)
            run = np.zeros(free.shape, dtype=np.int64)
            jump = np.full(free.shape, INFINITE, dtype=np.int64)
            for line in _sweep_order(free.shape, d_row, d_col):
                ahead = _ahead(line, d_row, d_col)
                run[line] = np.where(free[line], 1 + np.where(allowed[line], run[ahead], 0), 0)
                jump[line] = np.where(~free[line], INFINITE,
                                      np.where(hit[line], 0,
                                               np.where(allowed[line],
                                                        np.minimum(jump[ahead] + 1, INFINITE),
                                                        INFINITE)))
            runs[direction] = run
            jumps[direction] = jump
        self._runs = [runs[d].ravel().tolist() for d in range(8)]
        self._jumps = [jumps[d].ravel().tolist() for d in range(8)]

    @property
    def grid(self) -> OccupancyGrid:
        """The occupancy grid."""
        return self._grid

    @property
    def method(self) -> str:
        """The search method, 'jump' or 'plain'."""
        return self._method

    @property
    def blocked(self) -> np.ndarray:
        """(height, width) bool: the inflated obstacles the planner avoids."""
        return self._blocked

    @property
    def occupied(self) -> np.ndarray:
        """(height, width) bool: the obstacles before inflation."""
        return self._occupied

    def plan(self, start: Tuple[float, float], goal: Tuple[float, float]) -> GridPath:
        """Optimal path between the cells that contain two world points.

        :param start: world (x, y) of the start (m)
        :param goal: world (x, y) of the goal (m)
        :return: the path
        :raises ConfigError: if a coordinate is not a finite number
        :raises StartOutsideMapError: if the start is not on the map (GoalOutsideMapError
            likewise)
        :raises StartOccupiedError: if the start cell is blocked (GoalOccupiedError likewise)
        :raises NoPathError: if no path joins them
        """
        cells = []
        for name, point, outside in (('start', start, StartOutsideMapError),
                                     ('goal', goal, GoalOutsideMapError)):
            if len(point) != 2 or not all(is_finite_number(v) for v in point):
                raise ConfigError(f'{name} must be two finite numbers (x, y), got {point!r}')
            if not self._grid.contains(point[0], point[1]):
                x_min, x_max, y_min, y_max = self._grid.extent
                raise outside(f'{name} ({point[0]:.3f}, {point[1]:.3f}) is outside the map '
                              f'[{x_min:.3f}, {x_max:.3f}) x [{y_min:.3f}, {y_max:.3f})')
            cells.append(self._grid.world_to_cell(point[0], point[1]))
        return self.plan_cells(cells[0], cells[1])

    def plan_cells(self, start: Tuple[int, int], goal: Tuple[int, int]) -> GridPath:
        """Optimal path between two cells.

        :param start: (row, col) of the start cell
        :param goal: (row, col) of the goal cell
        :return: the path, every cell of it (consecutive cells are neighbours)
        :raises StartOutsideMapError: if the start cell is not on the grid (GoalOutsideMapError
            likewise)
        :raises StartOccupiedError: if the start cell is blocked (GoalOccupiedError likewise)
        :raises NoPathError: if no path joins them
        """
        height, width = self._blocked.shape
        for name, cell, outside, occupied in (
                ('start', start, StartOutsideMapError, StartOccupiedError),
                ('goal', goal, GoalOutsideMapError, GoalOccupiedError)):
            row, col = int(cell[0]), int(cell[1])
            if not (0 <= row < height and 0 <= col < width):
                raise outside(f'{name} cell {tuple(cell)} is outside the grid [0, {height}) x '
                              f'[0, {width})')
            if self._blocked[row, col]:
                reason = ('inside an obstacle' if self._occupied[row, col] else
                          f'within the inflated margin of an obstacle (scale '
                          f'{self._params.scale}, robot radius {self._params.robot_radius} m)')
                raise occupied(f'{name} cell {tuple(cell)} is {reason}')
        start = (int(start[0]), int(start[1]))
        goal = (int(goal[0]), int(goal[1]))
        if self._regions[start] != self._regions[goal]:
            raise NoPathError(f'no path: the goal cell {goal} is not reachable from the start '
                              f'cell {start}; obstacles separate them (the inflated map has '
                              f'{self._region_count} free regions)')
        padded = self._padded_width
        source = (start[0] + 1) * padded + start[1] + 1
        target = (goal[0] + 1) * padded + goal[1] + 1
        search = self._search_jump if self._method == 'jump' else self._search_plain
        parent, cost, expanded = search(source, target)
        nodes = [target]
        while nodes[-1] != source:
            nodes.append(parent[nodes[-1]])
        nodes.reverse()
        flat = np.array(nodes)
        corners = np.column_stack((flat // padded - 1, flat % padded - 1))
        cells = _fill_lines(corners)
        return GridPath(cells=cells, points=self._grid.cell_centres(cells),
                        cost=cost * self._grid.resolution, expanded=expanded)

    def _search_plain(self, source: int, target: int) -> Tuple[dict, float, int]:
        """Cell-by-cell A* on flat indices of the padded grid: parents, cost (cells), count."""
        padded = self._padded_width
        goal_row, goal_col = divmod(target, padded)
        g_score = {source: 0.0}
        parent = {}
        closed = bytearray(len(self._mask))
        mask = self._mask
        moves_by_mask = self._moves_by_mask
        hypot = math.hypot
        push = heapq.heappush
        pop = heapq.heappop
        infinity = math.inf
        heap = [(0.0, source)]
        expanded = 0
        while heap:
            _, node = pop(heap)
            if closed[node]:
                continue
            if node == target:
                return parent, g_score[target], expanded
            closed[node] = 1
            expanded += 1
            g_node = g_score[node]
            for offset, step in moves_by_mask[mask[node]]:
                neighbour = node + offset
                g_new = g_node + step
                if g_new < g_score.get(neighbour, infinity):
                    g_score[neighbour] = g_new
                    parent[neighbour] = node
                    row, col = divmod(neighbour, padded)
                    push(heap, (g_new + hypot(row - goal_row, col - goal_col), neighbour))
        raise NoPathError(f'no path: A* exhausted {expanded} cells without reaching the goal')

    def _search_jump(self, source: int, target: int) -> Tuple[dict, float, int]:
        """A* over jump points (O(1) jumps from the tables): parents, cost (cells), count."""
        padded = self._padded_width
        goal_row, goal_col = divmod(target, padded)
        mask = self._mask
        offsets = self._offsets
        runs = self._runs
        jumps = self._jumps
        hypot = math.hypot
        push = heapq.heappush
        pop = heapq.heappop
        infinity = math.inf
        g_score = {source: 0.0}
        parent = {}
        arrival = {source: -1}
        closed = set()
        heap = [(0.0, source)]
        expanded = 0
        all_moves = tuple(range(8))
        while heap:
            _, node = pop(heap)
            if node in closed:
                continue
            if node == target:
                return parent, g_score[target], expanded
            closed.add(node)
            expanded += 1
            g_node = g_score[node]
            allowed = mask[node]
            came = arrival[node]
            for direction in (all_moves if came < 0 else _CANDIDATES[came]):
                if not allowed >> direction & 1:
                    continue
                offset = offsets[direction]
                first = node + offset
                row, col = divmod(first, padded)
                d_row, d_col, step = MOVES[direction]
                reach = runs[direction][first]
                distance = jumps[direction][first]
                if direction < 4:
                    ahead = ((goal_col - col) * d_col if d_row == 0 and row == goal_row else
                             (goal_row - row) * d_row if d_col == 0 and col == goal_col else -1)
                    if 0 <= ahead < reach and ahead < distance:
                        distance = ahead
                else:
                    distance = min(distance, self._diagonal_goal_distance(
                        first, row, col, direction, reach, goal_row, goal_col))
                if distance >= reach:
                    continue
                point = first + distance * offset
                g_new = g_node + (distance + 1) * step
                if g_new < g_score.get(point, infinity):
                    g_score[point] = g_new
                    parent[point] = node
                    arrival[point] = direction
                    point_row, point_col = divmod(point, padded)
                    push(heap, (g_new + hypot(point_row - goal_row, point_col - goal_col),
                                point))
        raise NoPathError(f'no path: A* exhausted {expanded} jump points without reaching the '
                          'goal')

    def _diagonal_goal_distance(self, first: int, row: int, col: int, direction: int,
                                reach: int, goal_row: int, goal_col: int) -> int:
        """Smallest k < reach such that the diagonal cell k steps from first is the goal or has
        the goal on its straight sweep along the row or the column; INFINITE if none."""
        d_row, d_col, _ = MOVES[direction]
        col_dir, row_dir = _COMPONENTS[direction]
        padded = self._padded_width
        best = INFINITE
        k_row = (goal_row - row) * d_row
        if 0 <= k_row < reach:
            cell = first + k_row * self._offsets[direction]
            gap = (goal_col - (col + k_row * d_col)) * d_col
            if gap == 0 or (gap > 0 and gap - 1 < self._runs[col_dir][cell + d_col]):
                best = k_row
        k_col = (goal_col - col) * d_col
        if 0 <= k_col < min(reach, best):
            cell = first + k_col * self._offsets[direction]
            gap = (goal_row - (row + k_col * d_row)) * d_row
            if gap == 0 or (gap > 0 and gap - 1 < self._runs[row_dir][cell + d_row * padded]):
                best = k_col
        return best


def _shift(array: np.ndarray, d_row: int, d_col: int, fill=False) -> np.ndarray:
    """result[r, c] = array[r + d_row, c + d_col], fill outside."""
    result = np.full(array.shape, fill, dtype=array.dtype)
    height, width = array.shape
    rows_to = slice(max(0, -d_row), min(height, height - d_row))
    cols_to = slice(max(0, -d_col), min(width, width - d_col))
    rows_from = slice(max(0, d_row), min(height, height + d_row))
    cols_from = slice(max(0, d_col), min(width, width + d_col))
    result[rows_to, cols_to] = array[rows_from, cols_from]
    return result


def _sweep_order(shape: Tuple[int, int], d_row: int, d_col: int):
    """Index lines (rows or columns) of the padded grid in the order a recurrence along
    (d_row, d_col) needs: the line ahead first. The outermost line ahead is the blocked border
    and is skipped."""
    height, width = shape
    if d_row:
        order = range(height - 2, 0, -1) if d_row > 0 else range(1, height - 1)
        return [(index, slice(1, width - 1)) for index in order]
    order = range(width - 2, 0, -1) if d_col > 0 else range(1, width - 1)
    return [(slice(1, height - 1), index) for index in order]


def _ahead(line, d_row: int, d_col: int):
    """The cells one move ahead of the cells of a line."""
    rows, cols = line
    if isinstance(rows, int):
        return rows + d_row, slice(cols.start + d_col, cols.stop + d_col)
    return slice(rows.start + d_row, rows.stop + d_row), cols + d_col


def _fill_lines(corners: np.ndarray) -> np.ndarray:
    """Every cell on the straight or diagonal segments between consecutive corner cells."""
    cells = [corners[:1]]
    for first, second in zip(corners[:-1], corners[1:]):
        delta = second - first
        count = int(np.abs(delta).max())
        steps = np.arange(1, count + 1)[:, None]
        cells.append(first + steps * np.sign(delta))
    return np.concatenate(cells).astype(np.int64)
