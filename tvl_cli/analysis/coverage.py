"""Coverage: the fraction of the floor the robot can reach whose cells its centre has passed,
from true poses. The floor comes from clearances measured in the world's geometry (sim); the
rest is plain numpy.

The cells are the world map's own (in a world of more than a million of them, squares of
several, so that its floor is measured in a second or so). A cell is reachable when a body
of the robot's radius fits with its centre on the cell's centre and can get there from the
start's cell through neighbouring cells (up, down, left, right), fitting at the midpoint of
each step too, so that no gap narrower than the body joins two rooms. A reachable cell is
visited once a logged pose lies in it: its centre passed, rather than its floor swept by the
body, because a learner that stops short of walls (`tvl learn --near`) never sweeps the
strip beside them, and a swept-floor fraction would stay below 1 however well it explored.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import clearances_m, static_geometry
from tvl_cli.sim.worldmap import WorldMap

# A floor of more cells than this is measured on squares of several of the world's cells: its
# lattice of 4 points a cell then takes about a second to measure, whatever the world's size.
MAX_FLOOR_CELLS = 1 << 20
# Lattice rows measured at once: the points' coordinates and clearances of a block stay a few
# megabytes whatever the world's size.
_LATTICE_ROWS_AT_ONCE = 256


@dataclass(frozen=True, slots=True)
class CoverageGrid:
    """Square cells over a world's extent, row 0 along its bottom edge (y = y0_m) and column
    0 along its left edge (x = x0_m)."""

    cell_m: float
    rows: int
    columns: int
    x0_m: float = 0.0
    y0_m: float = 0.0

    def lattice_axes(self) -> tuple[np.ndarray, np.ndarray]:
        """The x (2 * columns - 1,) and y (2 * rows - 1,) metres of the lattice: the cells'
        centres at even indices, the midpoints between neighbours at odd ones; where the
        caller measures clearances."""
        half = self.cell_m / 2
        xs = self.x0_m + half * (np.arange(2 * self.columns - 1) + 1)
        ys = self.y0_m + half * (np.arange(2 * self.rows - 1) + 1)
        return xs, ys

    def lattice_xy(self) -> np.ndarray:
        """(2 * rows - 1, 2 * columns - 1, 2) metres: the lattice's points (lattice_axes)."""
        return np.stack(np.meshgrid(*self.lattice_axes()), axis=-1)

    def cell_index(self, xy: np.ndarray) -> np.ndarray:
        """(n,) flat index (row * columns + column) of the cell holding each of (n, 2+)
        points; -1 outside the grid."""
        points = np.asarray(xy, dtype=np.float64).reshape(-1, np.shape(xy)[-1])
        column = np.floor((points[:, 0] - self.x0_m) / self.cell_m).astype(np.int64)
        row = np.floor((points[:, 1] - self.y0_m) / self.cell_m).astype(np.int64)
        inside = (column >= 0) & (column < self.columns) & (row >= 0) & (row < self.rows)
        return np.where(inside, row * self.columns + column, -1)


def grid_over(world: WorldMap) -> CoverageGrid:
    """The world's own cells over its extent (a partial cell at the far edges counts); in a
    world of more than MAX_FLOOR_CELLS cells, squares of as few of them as bring the count
    under it."""
    cells = math.ceil(world.height_m / world.cell_m) * math.ceil(world.width_m / world.cell_m)
    cell_m = world.cell_m * max(1, math.ceil(math.sqrt(cells / MAX_FLOOR_CELLS)))
    rows = max(1, math.ceil(world.height_m / cell_m))
    return CoverageGrid(cell_m, rows, max(1, math.ceil(world.width_m / cell_m)), *world.origin_m)


@dataclass(frozen=True, slots=True, eq=False)
class Floor:
    """The reachable cells of a grid."""

    grid: CoverageGrid
    reachable: np.ndarray  # (rows * columns,) bool, flat as CoverageGrid.cell_index

    @property
    def cells(self) -> int:
        return int(self.reachable.sum())


def reachable_floor(grid: CoverageGrid, fits: np.ndarray, start_xy: tuple[float, float]) -> Floor:
    """The cells reachable from the start's cell, given where a body fits (its edge clear of
    every obstacle) at each point of `grid.lattice_xy()` (2R - 1, 2C - 1). The start's cell
    counts even if the start is off its centre: the robot stands in it.

    A step between two neighbours is open when both centres fit, and so does the midpoint
    between them: on the lattice with each midpoint kept only where its step is open (and
    the points between four cells dropped), the cells reachable are the centres a flood from
    the start's reaches (sim.flood_kernel)."""
    from tvl_cli.sim.flood_kernel import flood  # compiled: loaded on first use

    start = int(grid.cell_index(np.array([start_xy]))[0])
    if start < 0:
        raise ValueError(f"start {start_xy} lies outside the grid")
    open_points = np.array(fits, dtype=bool)  # (2R - 1, 2C - 1)
    centre = open_points[::2, ::2]  # (R, C), a view
    row, column = divmod(start, grid.columns)
    centre[row, column] = True
    open_points[::2, 1::2] &= centre[:, :-1] & centre[:, 1:]  # column j <-> j + 1
    open_points[1::2, ::2] &= centre[:-1, :] & centre[1:, :]  # row i <-> i + 1
    open_points[1::2, 1::2] = False
    reached = np.zeros_like(open_points)
    flood(open_points, 2 * row, 2 * column, reached)
    return Floor(grid, np.ascontiguousarray(reached[::2, ::2]).reshape(-1))


def world_floor(world: WorldMap, robot: RobotConfig) -> Floor:
    """The cells of the world a body of the robot's radius can reach from the start.

    Each lattice point asks only the walls within the robot's radius of it (the clearance
    kernel's limit, through the geometry's grid of walls), so the cost grows with the
    world's area and the walls' length, not with their product."""
    grid = grid_over(world)
    geometry = static_geometry(world)
    xs, ys = grid.lattice_axes()
    fits = np.empty((len(ys), len(xs)), dtype=bool)  # (2R - 1, 2C - 1)
    radius_m = robot.radius_m
    for first in range(0, len(ys), _LATTICE_ROWS_AT_ONCE):
        rows = ys[first : first + _LATTICE_ROWS_AT_ONCE]
        points = np.stack(np.meshgrid(xs, rows), axis=-1).reshape(-1, 2)
        clearance = clearances_m(geometry, points, radius_m, limit_m=radius_m)
        fits[first : first + len(rows)] = (clearance > 0.0).reshape(len(rows), len(xs))
    return reachable_floor(grid, fits, world.start[:2])


class CoverageTracker:
    """The reachable cells passed so far, as poses arrive."""

    def __init__(self, floor: Floor) -> None:
        self.floor = floor
        self._visited = np.zeros_like(floor.reachable)  # (rows * columns,) bool

    def add(self, poses: np.ndarray) -> None:
        """Count the cells holding these (n, 2+) true positions (x, y first) as visited."""
        cells = self.floor.grid.cell_index(poses)
        self._visited[cells[cells >= 0]] = True

    @property
    def fraction(self) -> float:
        """Visited reachable cells over reachable cells."""
        return float((self._visited & self.floor.reachable).sum()) / self.floor.cells


def coverage_of(floor: Floor, poses: np.ndarray) -> float:
    """The coverage after all these (n, 2+) true positions."""
    tracker = CoverageTracker(floor)
    tracker.add(poses)
    return tracker.fraction


def coverage_by_minute(
    floor: Floor, poses: np.ndarray, exemplars_by_minute: Sequence[float] | np.ndarray
) -> list[float]:
    """The coverage at the end of each learning minute, from a session's poses in order and
    how many of them each minute recorded (its per-minute `exemplars`)."""
    tracker = CoverageTracker(floor)
    fractions = []
    end = 0
    for count in exemplars_by_minute:
        start, end = end, end + int(count)
        tracker.add(poses[start:end])
        fractions.append(tracker.fraction)
    return fractions
