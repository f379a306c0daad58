"""An occupancy grid cut to a rectangle of its map, or coarsened to larger cells: what makes a
map of a large building small enough to learn in.

Grids are (rows, columns) of bool, True where free, top row first, placed in their map by a
GridPlace. Coarsening never opens a wall: a large cell is free only where every cell of the
grid it overlaps is free, so a wall one pixel thick still closes a room.
"""

from __future__ import annotations

import math

import numpy as np

from tvl_cli.sim.maps.grid_world import GridPlace, metres

# Rounding left in a ratio of cell sizes (0.06 / 0.03 = 2.0000000000000004): a large cell's
# edge this near a small cell's edge lies on it.
_EDGE_SLACK = 1e-9


def crop(
    free: np.ndarray, place: GridPlace, box: tuple[float, float, float, float]
) -> tuple[np.ndarray, GridPlace]:
    """The cells whose centres lie within box (map-frame x0, y0, x1, y1 metres, x0 < x1 and
    y0 < y1), and where they lie; ValueError if none does."""
    x0, y0, x1, y1 = box
    rows, columns = free.shape
    half = place.cell_m / 2.0
    # Centre of column c: left + (c + 1/2) cell; of row r (from the top): bottom + (rows - r
    # - 1/2) cell.
    first_column = max(math.ceil((x0 - place.left_x_m - half) / place.cell_m), 0)
    last_column = min(math.floor((x1 - place.left_x_m - half) / place.cell_m), columns - 1)
    first_from_bottom = max(math.ceil((y0 - place.bottom_y_m - half) / place.cell_m), 0)
    last_from_bottom = min(math.floor((y1 - place.bottom_y_m - half) / place.cell_m), rows - 1)
    if first_column > last_column or first_from_bottom > last_from_bottom:
        raise ValueError("holds no cell of the map")
    top, bottom = rows - 1 - last_from_bottom, rows - 1 - first_from_bottom
    kept = free[top : bottom + 1, first_column : last_column + 1]
    return kept, GridPlace(
        place.cell_m,
        metres(place.left_x_m + first_column * place.cell_m),
        metres(place.bottom_y_m + first_from_bottom * place.cell_m),
    )


def coarsen(free: np.ndarray, place: GridPlace, cell_m: float) -> tuple[np.ndarray, GridPlace]:
    """The grid at cells of cell_m (at least the grid's), from the same bottom-left corner:
    a cell free only where every grid cell it overlaps is; one reaching past the grid's far
    edges, a wall. Each large cell counts the cells not free under it from a summed-area
    table."""
    rows, columns = free.shape
    ratio = cell_m / place.cell_m
    blocked = np.zeros((rows + 1, columns + 1), dtype=np.int64)  # (rows + 1, columns + 1)
    # Counted from the bottom, as the large cells are laid: row 0 of this table's cells is
    # the grid's bottom row.
    blocked[1:, 1:] = (~free[::-1]).cumsum(axis=0).cumsum(axis=1)
    row_low, row_high = _spans(rows, ratio)
    column_low, column_high = _spans(columns, ratio)
    low_r, high_r = row_low[:, None], np.minimum(row_high, rows)[:, None]
    low_c, high_c = column_low[None, :], np.minimum(column_high, columns)[None, :]
    under = blocked[high_r, high_c] - blocked[low_r, high_c] - blocked[high_r, low_c]
    under += blocked[low_r, low_c]  # (new rows, new columns) cells not free under each
    within = (row_high <= rows)[:, None] & (column_high <= columns)[None, :]
    coarse = (under == 0) & within
    return coarse[::-1], GridPlace(cell_m, place.left_x_m, place.bottom_y_m)


def _spans(cells: int, ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """For each large cell along an axis of `cells` small ones (enough large cells to cover
    them), the first and one past the last small cell it overlaps (perhaps past the end)."""
    count = math.ceil(cells / ratio - _EDGE_SLACK)
    index = np.arange(count)
    low = np.floor(index * ratio + _EDGE_SLACK).astype(np.int64)
    high = np.ceil((index + 1) * ratio - _EDGE_SLACK).astype(np.int64)
    return low, high
