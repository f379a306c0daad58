"""An occupancy grid -> the text of a world: free cells are floor, every other cell a wall.

A cell that is not known to be free is a wall, so that the robot never drives into the
unknown. The world keeps only the free cells' bounding box and one cell round it, which is
all a robot inside can reach or hear (a wall hides what lies behind it); where that ring
would lie past the grid's edge it is padded with walls, so the world is always enclosed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.angles import wrap_rad
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldheader import FORMAT_VERSION
from tvl_cli.sim.worldmap import START_HEADINGS, WALL

FLOOR = "."


@dataclass(frozen=True, slots=True)
class GridPlace:
    """Where a grid lies in its map's frame (metres)."""

    cell_m: float
    left_x_m: float  # x of the grid's left edge
    bottom_y_m: float  # y of its bottom edge


@dataclass(frozen=True, slots=True)
class GridWorld:
    """A world made from a grid, and where it lies in the map's frame."""

    text: str
    columns: int
    rows: int
    place: GridPlace  # the world's own origin is its bottom-left corner, at place's edges
    start: tuple[float, float, float]  # world x, y (m) of the start cell's centre, heading rad


def grid_world(
    free: np.ndarray,
    place: GridPlace,
    start: tuple[float, float, float],
    name: str,
    comments: tuple[str, ...],
) -> GridWorld:
    """The world of the free cells (at least one) of a (rows, columns) grid, top row first,
    with the robot at `start` (map-frame x, y in metres and a heading in degrees, a multiple
    of 90), moved to its cell's centre. ValueError saying why the start cannot be there."""
    floor, top, left = _crop_to_floor(free)
    rows, columns = floor.shape
    world_place = GridPlace(
        place.cell_m,
        place.left_x_m + left * place.cell_m,
        place.bottom_y_m + (free.shape[0] - top - rows) * place.cell_m,
    )
    heading = _start_char(start[2])
    row, column = _start_cell(floor, world_place, start[0], start[1])
    _check_clear(floor, world_place, row, column)
    grid = np.where(floor, FLOOR, WALL)  # (rows, columns) characters, top row first
    grid[row, column] = heading
    text = "\n".join(
        [
            *(f"; {line}" for line in comments),
            # The map's frame, for a reader who places goals or compares paths with the map.
            f"; map frame: x = world x + {world_place.left_x_m!r}, "
            f"y = world y + {world_place.bottom_y_m!r}",
            f"version: {FORMAT_VERSION}",
            f"name: {name}",
            f"cell: {place.cell_m!r}",  # repr: the shortest text that reads back exactly
            "",
            *("".join(characters) for characters in grid),
            "",
        ]
    )
    x, y = _centre(rows, row, column, place.cell_m)
    return GridWorld(text, columns, rows, world_place, (x, y, START_HEADINGS[heading]))


def _crop_to_floor(free: np.ndarray) -> tuple[np.ndarray, int, int]:
    """The free cells' bounding box and one cell round it, and the grid's (row, column) of
    its top-left corner (-1 where the ring lies past the grid's edge). There must be a free
    cell."""
    padded = np.pad(free, 1, constant_values=False)  # past the edge: wall
    rows, columns = np.flatnonzero(padded.any(axis=1)), np.flatnonzero(padded.any(axis=0))
    top, bottom, left, right = rows[0] - 1, rows[-1] + 1, columns[0] - 1, columns[-1] + 1
    return padded[top : bottom + 1, left : right + 1], int(top) - 1, int(left) - 1


def _start_char(heading_deg: float) -> str:
    """The map character of a start facing `heading_deg` (CCW from +x)."""
    for char, heading_rad in START_HEADINGS.items():
        if abs(wrap_rad(math.radians(heading_deg) - heading_rad)) < 1e-9:
            return char
    raise ValueError(f"heading {heading_deg:g}° is not 0, 90, 180 or 270 (a world starts so)")


def _start_cell(floor: np.ndarray, place: GridPlace, x_m: float, y_m: float) -> tuple[int, int]:
    """The (row, column) of the free cell holding map-frame (x, y)."""
    rows, columns = floor.shape
    column = math.floor((x_m - place.left_x_m) / place.cell_m)
    row = rows - 1 - math.floor((y_m - place.bottom_y_m) / place.cell_m)
    if not (0 <= row < rows and 0 <= column < columns) or not floor[row, column]:
        raise ValueError(f"x {x_m:g} y {y_m:g} is not on the map's free floor")
    return row, column


def _check_clear(floor: np.ndarray, place: GridPlace, row: int, column: int) -> None:
    """The robot's body at the start cell's centre must not touch a wall cell."""
    radius_m = RobotConfig().radius_m
    cell_m = place.cell_m
    reach = math.ceil(radius_m / cell_m)
    rows, columns = floor.shape
    r0, r1 = max(row - reach, 0), min(row + reach + 1, rows)
    c0, c1 = max(column - reach, 0), min(column + reach + 1, columns)
    walls_r, walls_c = np.nonzero(~floor[r0:r1, c0:c1])  # cells near the start, in the window
    if not len(walls_r):
        return
    # Each wall cell's nearest point to the start's centre, as cell counts from it.
    gap_r = np.maximum(np.abs(walls_r + r0 - row) - 0.5, 0.0)
    gap_c = np.maximum(np.abs(walls_c + c0 - column) - 0.5, 0.0)
    distance_m = np.hypot(gap_r, gap_c) * cell_m
    nearest = int(np.argmin(distance_m))
    if distance_m[nearest] < radius_m:
        x, y = _centre(rows, int(walls_r[nearest]) + r0, int(walls_c[nearest]) + c0, cell_m)
        raise ValueError(
            f"the robot (a disc of radius {radius_m:g} m) would touch the wall cell at "
            f"x {x + place.left_x_m:g} y {y + place.bottom_y_m:g}"
        )


def _centre(rows: int, row: int, column: int, cell_m: float) -> tuple[float, float]:
    """World x, y (m) of a cell's centre, its rows counted from the top."""
    return (column + 0.5) * cell_m, (rows - row - 0.5) * cell_m
