"""Wall segments bucketed by the square cells of a uniform grid, so that a ray asks only the
walls of the cells it crosses, and a point only those of the cells round it, rather than
every wall of a large world.

A wall is put in every cell its line passes through or comes within `SLACK_M` of (a few
more where a piece of it crosses a cell's corner), so that a crossing or a nearest point
computed in floating point is never in a cell that does not list its wall. Within a cell
the walls keep their order (increasing numbers), and each entry carries its wall's normal
and start side by side, in the order a ray reads them.

A world of fewer than `MIN_WALLS_TO_BUCKET` walls is one cell holding every wall: testing
them all costs less than walking cells, and is exactly what the queries did before any
grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

# Below this many wall segments one cell holds them all (every shipped and generated world).
MIN_WALLS_TO_BUCKET = 256
# A cell's side: about a tenth of the sonar's range, so that a ray crosses some 10 to 20
# cells and each holds a few of a scanned map's short walls (benchmarks/large_worlds.py)...
CELL_M = 0.5
# ... or less where walls crowd closer (a checkerboard of walls): a side of this many times
# the mean spacing of the walls, about nine walls a cell, but never under MIN_CELL_M.
WALL_SPACINGS_A_CELL = 3.0
MIN_CELL_M = 0.05
# A grid of no more cells than this (8 bytes each): a larger world gets larger cells.
MAX_CELLS = 1 << 22
# How near a wall may come to a cell to be listed in it: far above the rounding of any
# coordinate in metres, far below any size that matters.
SLACK_M = 1e-6


@dataclass(frozen=True, slots=True, eq=False)
class WallGrid:
    """Cells of side `cell_m` from (x0_m, y0_m), `columns` across and `rows` up; cell
    (row, column) is number row * columns + column. Its walls are
    `walls[first[cell]:first[cell + 1]]`."""

    x0_m: float
    y0_m: float
    cell_m: float
    columns: int
    rows: int
    first: np.ndarray  # (columns * rows + 1,) int64
    walls: np.ndarray  # (k,) int64 wall numbers, increasing within each cell
    # (4, k) for each entry its wall's normal x, normal y, start x, start y (metres): what a
    # ray screens every wall of a cell by, read side by side.
    lines: np.ndarray

    # The grid as the ring and clearance kernels take it (sim.ring_kernel documents it).
    kernel_input: tuple[object, ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        inputs = (self.x0_m, self.y0_m, self.cell_m, self.columns, self.rows, self.first,
                  self.walls, self.lines)  # fmt: skip
        object.__setattr__(self, "kernel_input", inputs)


def wall_grid(
    segments: np.ndarray, normal: np.ndarray, start: np.ndarray, cell_m: float = CELL_M
) -> WallGrid:
    """The grid over segments (n, 4) x1, y1, x2, y2 metres, with their normals (2, n) and
    starts (2, n) as sim.geometry.StaticGeometry keeps them: cells of cell_m, or smaller where
    the walls crowd (WALL_SPACINGS_A_CELL), or larger in a world too wide for MAX_CELLS."""
    n = len(segments)
    ends = segments.reshape(-1, 2)
    low = ends.min(axis=0) - SLACK_M if n else np.zeros(2)
    high = ends.max(axis=0) + SLACK_M if n else np.ones(2)
    if n < MIN_WALLS_TO_BUCKET:
        extent = float(max(high[0] - low[0], high[1] - low[1]))
        return _grid(low, extent, 1, 1, np.zeros(n, np.int64), np.arange(n), normal, start)
    size = high - low  # (2,) metres
    area_m2 = float(size[0] * size[1])
    spacing_m = math.sqrt(area_m2 / n)  # as if the walls stood evenly over the world
    cell_m = min(cell_m, max(MIN_CELL_M, WALL_SPACINGS_A_CELL * spacing_m))
    cell_m = max(cell_m, math.sqrt(area_m2 / MAX_CELLS))
    columns, rows = (max(1, math.ceil(float(s) / cell_m)) for s in size)
    cells, walls = _cells_of(segments, low, cell_m, columns, rows)
    return _grid(low, cell_m, columns, rows, cells, walls, normal, start)


def _cells_of(
    segments: np.ndarray, low: np.ndarray, cell_m: float, columns: int, rows: int
) -> tuple[np.ndarray, np.ndarray]:
    """Every (cell, wall) pair, once each: each wall cut into pieces no longer than half a
    cell, and each piece listed in the cells its box, grown by SLACK_M, meets."""
    length = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    pieces = np.maximum(1, np.ceil(length / (cell_m / 2.0)).astype(np.int64))  # (n,)
    wall = np.repeat(np.arange(len(segments)), pieces)  # (p,) each piece's wall
    first_piece = np.cumsum(pieces) - pieces
    index = np.arange(len(wall)) - np.repeat(first_piece, pieces)  # (p,) piece within wall
    share = pieces[wall].astype(np.float64)
    a, b = segments[wall, :2], segments[wall, 2:] - segments[wall, :2]  # (p, 2) metres
    piece_start = a + b * (index / share)[:, None]
    piece_end = a + b * ((index + 1) / share)[:, None]
    lo = (np.minimum(piece_start, piece_end) - SLACK_M - low) / cell_m  # (p, 2) in cells
    hi = (np.maximum(piece_start, piece_end) + SLACK_M - low) / cell_m
    lo_cell = np.clip(np.floor(lo).astype(np.int64), 0, [columns - 1, rows - 1])
    hi_cell = np.clip(np.floor(hi).astype(np.int64), 0, [columns - 1, rows - 1])
    # A piece spans at most two cells each way: half a cell long, grown by a hair.
    pairs = []
    for dx in (0, 1):
        for dy in (0, 1):
            column, row = lo_cell[:, 0] + dx, lo_cell[:, 1] + dy
            keep = (column <= hi_cell[:, 0]) & (row <= hi_cell[:, 1])
            pairs.append((row[keep] * columns + column[keep]) * len(segments) + wall[keep])
    unique = _sorted_unique(np.concatenate(pairs))  # by cell, then wall
    return unique // len(segments), unique % len(segments)


def _sorted_unique(values: np.ndarray) -> np.ndarray:
    """np.unique of integers (k,), by sorting them and keeping each first of a run: what
    np.unique gives, in a small part of its time on the thousands of pairs a step's grid of
    remembered patches lists (numpy 2's np.unique seeks by hash before it sorts)."""
    ordered = np.sort(values)
    first = np.ones(len(ordered), dtype=bool)
    np.not_equal(ordered[1:], ordered[:-1], out=first[1:])
    return ordered[first]


def _grid(
    low: np.ndarray,
    cell_m: float,
    columns: int,
    rows: int,
    cells: np.ndarray,
    walls: np.ndarray,
    normal: np.ndarray,
    start: np.ndarray,
) -> WallGrid:
    counts = np.bincount(cells, minlength=columns * rows)
    first = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    walls = np.ascontiguousarray(walls, dtype=np.int64)
    lines = np.ascontiguousarray(np.concatenate([normal[:, walls], start[:, walls]]))
    return WallGrid(float(low[0]), float(low[1]), float(cell_m), columns, rows, first, walls,
                    lines.reshape(4, -1))  # fmt: skip
