"""Coverage: the fraction of the floor the robot can reach whose cells its centre has passed,
from true poses. The floor comes from clearances measured in the world's geometry (sim); the
rest is plain numpy.

The cells are the world map's own. A cell is reachable when a body of the robot's radius fits
with its centre on the cell's centre and can get there from the start's cell through
neighbouring cells (up, down, left, right), fitting at the midpoint of each step too, so that
no gap narrower than the body joins two rooms. A reachable cell is visited once a logged pose
lies in it: its centre passed, rather than its floor swept by the body, because a learner
that stops short of walls (`tvl learn --near`) never sweeps the strip beside them, and a
swept-floor fraction would stay below 1 however well it explored.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.world import clearances_m, static_geometry
from tvl_cli.sim.worldmap import WorldMap


@dataclass(frozen=True, slots=True)
class CoverageGrid:
    """Square cells over a world's extent, row 0 along y = 0 and column 0 along x = 0."""

    cell_m: float
    rows: int
    columns: int

    def lattice_xy(self) -> np.ndarray:
        """(2 * rows - 1, 2 * columns - 1, 2) metres: the cells' centres at even indices, the
        midpoints between neighbours at an odd index; where the caller measures clearances."""
        half = self.cell_m / 2
        xs = half * (np.arange(2 * self.columns - 1) + 1)  # (2C - 1,) metres
        ys = half * (np.arange(2 * self.rows - 1) + 1)  # (2R - 1,) metres
        return np.stack(np.meshgrid(xs, ys), axis=-1)

    def cell_index(self, xy: np.ndarray) -> np.ndarray:
        """(n,) flat index (row * columns + column) of the cell holding each of (n, 2+)
        points; -1 outside the grid."""
        points = np.asarray(xy, dtype=np.float64).reshape(-1, np.shape(xy)[-1])
        column = np.floor(points[:, 0] / self.cell_m).astype(np.int64)
        row = np.floor(points[:, 1] / self.cell_m).astype(np.int64)
        inside = (column >= 0) & (column < self.columns) & (row >= 0) & (row < self.rows)
        return np.where(inside, row * self.columns + column, -1)


def grid_over(width_m: float, height_m: float, cell_m: float) -> CoverageGrid:
    """The cells covering a world of this size (a partial cell at the far edges counts)."""
    return CoverageGrid(
        cell_m, max(1, math.ceil(height_m / cell_m)), max(1, math.ceil(width_m / cell_m))
    )


@dataclass(frozen=True, slots=True, eq=False)
class Floor:
    """The reachable cells of a grid."""

    grid: CoverageGrid
    reachable: np.ndarray  # (rows * columns,) bool, flat as CoverageGrid.cell_index

    @property
    def cells(self) -> int:
        return int(self.reachable.sum())


def reachable_floor(
    grid: CoverageGrid, clearance_m: np.ndarray, start_xy: tuple[float, float]
) -> Floor:
    """The cells reachable from the start's cell, given the clearance (metres from the body's
    edge to the nearest obstacle, 0 where it touches) at each point of `grid.lattice_xy()`.
    The start's cell counts even if the start is off its centre: the robot stands in it."""
    fits = np.asarray(clearance_m) > 0.0  # (2R - 1, 2C - 1)
    centre = fits[::2, ::2].copy()  # (R, C)
    start = int(grid.cell_index(np.array([start_xy]))[0])
    if start < 0:
        raise ValueError(f"start {start_xy} lies outside the grid")
    centre.flat[start] = True
    # A step between two neighbours: both centres fit, and so does the midpoint between them.
    across = fits[::2, 1::2] & centre[:, :-1] & centre[:, 1:]  # (R, C - 1) column j <-> j + 1
    along = fits[1::2, ::2] & centre[:-1, :] & centre[1:, :]  # (R - 1, C) row i <-> i + 1
    reached = np.zeros(grid.rows * grid.columns, dtype=bool)
    reached[start] = True
    queue = deque([divmod(start, grid.columns)])
    while queue:
        row, column = queue.popleft()
        steps = (
            (row, column + 1, column + 1 < grid.columns and across[row, column]),
            (row, column - 1, column > 0 and across[row, column - 1]),
            (row + 1, column, row + 1 < grid.rows and along[row, column]),
            (row - 1, column, row > 0 and along[row - 1, column]),
        )
        for r, c, open_step in steps:
            flat = r * grid.columns + c
            if open_step and not reached[flat]:
                reached[flat] = True
                queue.append((r, c))
    return Floor(grid, reached)


def world_floor(world: WorldMap, robot: RobotConfig) -> Floor:
    """The cells of the world a body of the robot's radius can reach from the start."""
    grid = grid_over(world.width_m, world.height_m, world.cell_m)
    lattice = grid.lattice_xy()  # (2R - 1, 2C - 1, 2) metres
    clearance = clearances_m(static_geometry(world), lattice.reshape(-1, 2), robot.radius_m)
    return reachable_floor(grid, clearance.reshape(lattice.shape[:2]), world.start[:2])


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
