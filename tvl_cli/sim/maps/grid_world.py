"""An occupancy grid -> the text of a world: free cells are floor, every other cell a wall.

A cell that is not known to be free is a wall, so that the robot never drives into the
unknown. The world keeps only the free cells' bounding box and one cell round it, which is
all a robot inside can reach or hear (a wall hides what lies behind it); where that ring
would lie past the grid's edge it is padded with walls, so the world is always enclosed.

The world keeps the grid's frame: its `origin:` line places its bottom-left corner where that
corner lies in the map, so every coordinate of the world (walls, the start, goals, the paths
a robot drives) is the map's. Its `start:` line puts the robot exactly where it was asked to
stand, facing any way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tvl_cli.sim.maps.text_grid import WALL
from tvl_cli.sim.worldheader import FORMAT_VERSION

FLOOR = "."


@dataclass(frozen=True, slots=True)
class GridPlace:
    """Where a grid lies in its map's frame (metres)."""

    cell_m: float
    left_x_m: float  # x of the grid's left edge
    bottom_y_m: float  # y of its bottom edge

    def centre(self, rows: int, row: int, column: int) -> tuple[float, float]:
        """The map-frame x, y (m) of a cell's centre in a grid of `rows` rows, counted from
        the top; to the nanometre, so that no float noise is printed."""
        return (
            metres(self.left_x_m + (column + 0.5) * self.cell_m),
            metres(self.bottom_y_m + (rows - row - 0.5) * self.cell_m),
        )

    def cell(self, rows: int, x_m: float, y_m: float) -> tuple[int, int]:
        """The (row, column) of the cell holding map-frame (x, y), perhaps off the grid."""
        column = math.floor((x_m - self.left_x_m) / self.cell_m)
        return rows - 1 - math.floor((y_m - self.bottom_y_m) / self.cell_m), column


def metres(value: float) -> float:
    """To the nanometre: 0.35, not the 0.35000000000000003 that summing cells gives."""
    return round(value, 9)


@dataclass(frozen=True, slots=True, eq=False)
class GridWorld:
    """A world made from a grid, and where it lies in the map's frame."""

    text: str
    columns: int
    rows: int
    place: GridPlace  # where the world's grid lies: its bottom-left corner is its origin
    start: tuple[float, float, float]  # map-frame x, y (m) and heading (degrees)
    floor: np.ndarray  # (rows, columns) bool, top row first: the world's free cells


def grid_world(
    free: np.ndarray,
    place: GridPlace,
    start: tuple[float, float, float],
    name: str,
    comments: tuple[str, ...],
) -> GridWorld:
    """The world of the free cells (at least one) of a (rows, columns) grid, top row first,
    with the robot at `start` (map-frame x, y in metres and a heading in degrees)."""
    floor, world_place = floor_of(free, place)
    rows, columns = floor.shape
    grid = np.where(floor, FLOOR, WALL)  # (rows, columns) characters, top row first
    x, y, heading = start
    text = "\n".join(
        [
            *(f"; {line}" for line in comments),
            f"version: {FORMAT_VERSION}",
            f"name: {name}",
            f"cell: {place.cell_m!r}",  # repr: the shortest text that reads back exactly
            f"origin: {world_place.left_x_m!r} {world_place.bottom_y_m!r}",
            f"start: {x!r} {y!r} {heading!r}",
            "",
            *("".join(characters) for characters in grid),
            "",
        ]
    )
    return GridWorld(text, columns, rows, world_place, start, floor)


def floor_of(free: np.ndarray, place: GridPlace) -> tuple[np.ndarray, GridPlace]:
    """The free cells' bounding box and one cell round it (walls where that ring lies past
    the grid's edge), and where it lies: the world's grid. There must be a free cell; the
    floor of a world's grid is that grid."""
    padded = np.pad(free, 1, constant_values=False)  # past the edge: wall
    rows, columns = np.flatnonzero(padded.any(axis=1)), np.flatnonzero(padded.any(axis=0))
    top, bottom, left, right = rows[0] - 1, rows[-1] + 1, columns[0] - 1, columns[-1] + 1
    floor = padded[top : bottom + 1, left : right + 1]
    # The grid's row and column of the floor's top-left corner: one less, for the padding.
    first_row, first_column = int(top) - 1, int(left) - 1
    return floor, GridPlace(
        place.cell_m,
        metres(place.left_x_m + first_column * place.cell_m),
        metres(place.bottom_y_m + (free.shape[0] - first_row - floor.shape[0]) * place.cell_m),
    )


def body_touches(
    free: np.ndarray, place: GridPlace, x_m: float, y_m: float, radius_m: float
) -> tuple[float, float] | None:
    """The centre (map-frame metres) of the cell not free nearest a body of this radius at
    (x, y) that the body touches (one past the grid's edge counts as a wall), or None."""
    rows, columns = free.shape
    row, column = place.cell(rows, x_m, y_m)
    reach = math.ceil(radius_m / place.cell_m) + 1
    r0, c0 = row - reach, column - reach
    window = np.zeros((2 * reach + 1, 2 * reach + 1), dtype=bool)  # True: free
    inner_r = slice(max(r0, 0), min(row + reach + 1, rows))
    inner_c = slice(max(c0, 0), min(column + reach + 1, columns))
    window[inner_r.start - r0 : inner_r.stop - r0, inner_c.start - c0 : inner_c.stop - c0] = free[
        inner_r, inner_c
    ]
    walls_r, walls_c = np.nonzero(~window)
    centres = [place.centre(rows, r + r0, c + c0) for r, c in zip(walls_r, walls_c, strict=True)]
    if not centres:
        return None
    half = place.cell_m / 2.0
    gaps = [
        math.hypot(max(abs(x_m - cx) - half, 0.0), max(abs(y_m - cy) - half, 0.0))
        for cx, cy in centres
    ]
    nearest = int(np.argmin(gaps))
    return centres[nearest] if gaps[nearest] < radius_m else None
