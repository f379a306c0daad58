"""A world -> an occupancy grid at its own cell size: the cells its solids fill.

A cell is occupied where the map has a `#`, where a pillar, disc or thick wall covers part of
it, and where a thin wall or a ring wall passes through it; a line running along a cell edge
fills the cells on both sides, since a map must not let the robot through a wall. Cells past
the end of a short map line lie outside the world.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from tvl_cli.sim.worldmap import WALL, WorldMap, layout

# Coordinates computed two ways (a wall's corner, a cell's edge) differ in the last bits; a
# solid reaching within this share of a cell of a cell's edge only touches that edge.
_TOLERANCE_CELLS = 1e-9


@dataclass(frozen=True, slots=True, eq=False)
class Raster:
    """A world's cells, (rows, columns) top row first."""

    occupied: np.ndarray  # bool
    outside: np.ndarray  # bool: past the end of a short map line, not part of the world


def rasterise(world: WorldMap) -> Raster:
    """The cells a world's walls, pillars, discs and rings fill, at its cell size."""
    rows, header = layout(world)
    columns = max(len(row) for row in rows)
    chars = np.array([list(row.ljust(columns)) for row in rows])  # (rows, columns)
    cells = _Cells(world.cell_m, len(rows), columns, *world.origin_m)
    occupied = chars == WALL
    for x, y, r in world.discs:
        window, cx, cy = cells.window(x - r, y - r, x + r, y + r)
        occupied[window] |= _rectangle_distance(x, y, cx, cy, cells.half_m) < r - cells.eps_m
    for wall in header.walls:
        if wall.thickness_m == 0.0 and (wall.x1 == wall.x2 or wall.y1 == wall.y2):
            # Along the grid, a line may run on a cell edge and fill neither side: drawn a
            # hair thick, it fills both.
            wall = replace(wall, thickness_m=4.0 * cells.eps_m)
        if wall.thickness_m > 0.0:
            corners = np.array([segment[:2] for segment in wall.outline()])  # (4, 2)
        else:
            corners = np.array([[wall.x1, wall.y1], [wall.x2, wall.y2]])
        low, high = corners.min(axis=0), corners.max(axis=0)
        window, cx, cy = cells.window(low[0], low[1], high[0], high[1])
        occupied[window] |= cells.overlap(corners, cx, cy)
    for x, y, r in world.rings:
        window, cx, cy = cells.window(x - r, y - r, x + r, y + r)
        nearest = _rectangle_distance(x, y, cx, cy, cells.half_m)
        farthest = np.hypot(np.abs(cx - x) + cells.half_m, np.abs(cy - y) + cells.half_m)
        occupied[window] |= (nearest <= r + cells.eps_m) & (r - cells.eps_m <= farthest)
    return Raster(occupied, chars == " ")


@dataclass(frozen=True, slots=True)
class _Cells:
    """The grid's geometry: cell size, shape, where its bottom-left corner lies, and windows
    of cell centres."""

    cell_m: float
    rows: int
    columns: int
    x0_m: float
    y0_m: float

    @property
    def half_m(self) -> float:
        return self.cell_m / 2.0

    @property
    def eps_m(self) -> float:
        return _TOLERANCE_CELLS * self.cell_m

    def window(
        self, x_min: float, y_min: float, x_max: float, y_max: float
    ) -> tuple[tuple[slice, slice], np.ndarray, np.ndarray]:
        """The cells whose squares may meet a box (the world's frame), and their centres' x
        and y (m), each (rows, columns) of the window."""
        x_min, x_max, y_min, y_max = (
            x_min - self.x0_m, x_max - self.x0_m, y_min - self.y0_m, y_max - self.y0_m
        )  # fmt: skip
        c0 = max(math.floor(x_min / self.cell_m) - 1, 0)
        c1 = min(math.floor(x_max / self.cell_m) + 2, self.columns)
        # Rows count down from the top; y counts up from the bottom.
        r0 = max(self.rows - 1 - math.floor(y_max / self.cell_m) - 1, 0)
        r1 = min(self.rows - math.floor(y_min / self.cell_m) + 1, self.rows)
        cx = self.x0_m + (np.arange(c0, c1) + 0.5) * self.cell_m
        cy = self.y0_m + (self.rows - np.arange(r0, r1) - 0.5) * self.cell_m
        return (slice(r0, r1), slice(c0, c1)), *np.meshgrid(cx, cy)

    def overlap(self, corners: np.ndarray, cx: np.ndarray, cy: np.ndarray) -> np.ndarray:
        """Where a convex polygon (or a segment, as two corners) reaches into each cell's
        square: their projections overlap, by more than a touch, on every axis that could
        separate them (the squares' and the polygon's edge normals)."""
        edges = np.roll(corners, -1, axis=0) - corners  # (k, 2)
        normals = np.stack([-edges[:, 1], edges[:, 0]], axis=1)
        axes = np.concatenate([np.eye(2), normals[np.hypot(*normals.T) > 0]])
        meets = np.ones(cx.shape, dtype=bool)
        for ax, ay in axes:
            projected = corners @ np.array([ax, ay])
            centre = cx * ax + cy * ay
            reach = self.half_m * (abs(ax) + abs(ay))
            touch = self.eps_m * math.hypot(ax, ay)
            meets &= (projected.max() > centre - reach + touch) & (
                projected.min() < centre + reach - touch
            )
        return meets


def _rectangle_distance(
    x: float, y: float, cx: np.ndarray, cy: np.ndarray, half_m: float
) -> np.ndarray:
    """Metres from a point to each cell's square (0 inside it)."""
    return np.hypot(
        np.maximum(np.abs(cx - x) - half_m, 0.0), np.maximum(np.abs(cy - y) - half_m, 0.0)
    )
