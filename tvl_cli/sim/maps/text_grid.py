"""A world file's grid of characters: its cells, their centres in the world's frame, and the
checks and the outline that need the cells (sim.worldmap reads the file)."""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldheader import Circle, Header, Segment, Wall, WorldMapError

WALL, PILLAR, GOAL = "#", "o", "G"
START_HEADINGS = {">": 0.0, "<": math.pi, "^": math.pi / 2, "v": -math.pi / 2}
GRID_CHARS = "#.><^vGo"
_DIRECTIONS = (
    (0, 1),
    (1, 0),
    (0, -1),
    (-1, 0),
)  # (row, column) steps; fixed order keeps BFS stable


@dataclass(frozen=True, slots=True)
class MapGrid:
    """The map characters, top line first; cells past a short line's end are outside. The
    grid's bottom-left corner lies at `origin_m` in the world's frame."""

    rows: tuple[str, ...]
    lines: tuple[int, ...]  # source line number of each row
    cell_m: float
    origin_m: tuple[float, float] = (0.0, 0.0)

    @property
    def width_m(self) -> float:
        return round(max(len(row) for row in self.rows) * self.cell_m, 9)

    @property
    def height_m(self) -> float:
        return round(len(self.rows) * self.cell_m, 9)

    def inside(self, r: int, c: int) -> bool:
        return 0 <= r < len(self.rows) and 0 <= c < len(self.rows[r])

    def is_wall(self, r: int, c: int) -> bool:
        return self.inside(r, c) and self.rows[r][c] == WALL

    def is_open(self, r: int, c: int) -> bool:
        return self.inside(r, c) and self.rows[r][c] != WALL

    def centre(self, r: int, c: int) -> tuple[float, float]:
        """A cell's centre in the world's frame, to the nanometre (no 0.35000000000000003)."""
        x0, y0 = self.origin_m
        return (
            round(x0 + (c + 0.5) * self.cell_m, 9),
            round(y0 + (len(self.rows) - r - 0.5) * self.cell_m, 9),
        )

    def cell_at(self, x: float, y: float) -> tuple[int, int]:
        """The (row, column) of the cell holding a point of the world's frame (perhaps off
        the map)."""
        x0, y0 = self.origin_m
        column = math.floor((x - x0) / self.cell_m)
        return len(self.rows) - 1 - math.floor((y - y0) / self.cell_m), column

    def extent(self) -> str:
        """The map's extent in words, for the errors that name something outside it."""
        x0, y0 = self.origin_m
        return f"(the map is {x0:g}..{x0 + self.width_m:g} x {y0:g}..{y0 + self.height_m:g} m)"

    def holds(self, x: float, y: float) -> bool:
        """Whether a point lies within the map's extent (its edges too)."""
        x0, y0 = self.origin_m
        return x0 <= x <= x0 + self.width_m and y0 <= y <= y0 + self.height_m

    def where(self, r: int, c: int) -> str:
        return f"{self.lines[r]}:{c + 1}"


def _distance_to_cell(grid: MapGrid, x: float, y: float, r: int, c: int) -> float:
    cx, cy = grid.centre(r, c)
    half = grid.cell_m / 2
    return math.hypot(max(abs(x - cx) - half, 0.0), max(abs(y - cy) - half, 0.0))


def check_inside(grid: MapGrid, header: Header) -> None:
    """Header walls and pillars must stand within the map's extent: the grid encloses the
    robot's world, and nothing outside it could ever be met. A thick wall's corners count,
    not only its ends."""
    inside, extent = grid.holds, grid.extent()
    for wall in header.walls:
        ends = [end for segment in wall.outline() for end in (segment[:2], segment[2:])]
        if not all(inside(x, y) for x, y in ends):
            raise WorldMapError(f"{wall.where}: wall reaches outside the world {extent}")
    for x, y, r, where in header.discs:
        if not inside(x, y):
            raise WorldMapError(
                f"{where}: disc at x {x:g} y {y:g} r {r:g} is outside the world {extent}"
            )
    for x, y, r, where in header.rings:
        if not (inside(x - r, y - r) and inside(x + r, y + r)):
            raise WorldMapError(
                f"{where}: ring at x {x:g} y {y:g} r {r:g} reaches outside the world {extent}"
            )
    for region in header.rough:
        if not (inside(region.x_min, region.y_min) and inside(region.x_max, region.y_max)):
            raise WorldMapError(f"{region.where}: rough rectangle reaches outside {extent}")


def check_start_clear(
    grid: MapGrid, x: float, y: float, discs: tuple[Circle, ...], header: Header, start_at: str
) -> None:
    """The robot's body disc at the start must not overlap a wall, a disc or a ring."""
    radius = RobotConfig().radius_m
    body = f"(the robot is a disc of radius {radius:g} m)"
    reach = math.ceil(radius / grid.cell_m) + 1
    sr, sc = grid.cell_at(x, y)
    near = [
        (_distance_to_cell(grid, x, y, r, c), r, c)
        for r in range(sr - reach, sr + reach + 1)
        for c in range(sc - reach, sc + reach + 1)
        if grid.is_wall(r, c)
    ]
    if near and min(near)[0] < radius:
        _, r, c = min(near)
        raise WorldMapError(f"{start_at}: the start touches the wall at {grid.where(r, c)} {body}")
    for dx, dy, dr in discs:
        if math.hypot(x - dx, y - dy) < dr + radius:
            raise WorldMapError(
                f"{start_at}: the start overlaps the disc at x {dx:g} y {dy:g} r {dr:g} {body}"
            )
    for wall in header.walls:
        if wall.distance_m(x, y) < radius:
            line_col = ":".join(wall.where.rsplit(":", 2)[-2:])
            raise WorldMapError(f"{start_at}: the start touches the wall at {line_col} {body}")
    for rx, ry, rr, _ in header.rings:
        if abs(math.hypot(x - rx, y - ry) - rr) < radius:
            raise WorldMapError(
                f"{start_at}: the start touches the ring at x {rx:g} y {ry:g} r {rr:g} {body}"
            )


def ring_sides(grid: MapGrid, codes: np.ndarray, rings: tuple[Circle, ...]) -> np.ndarray:
    """(rows + 2, columns + 2) for each cell of the map and the ring of cells round it, which
    side of each ring wall its centre lies on, as one number (equal: the same sides)."""
    rows, columns = codes.shape
    x0, y0 = grid.origin_m
    xs = x0 + (np.arange(-1, columns + 1) + 0.5) * grid.cell_m  # (columns + 2,) metres
    ys = y0 + (rows - np.arange(-1, rows + 1) - 0.5) * grid.cell_m  # (rows + 2,) metres
    sides = np.zeros((rows + 2, columns + 2), dtype=np.int64)
    for bit, (x, y, r) in enumerate(rings):
        inside = np.hypot(xs[None, :] - x, ys[:, None] - y) < r
        sides |= inside.astype(np.int64) << (bit % 62)
    return sides


def first_escape(
    grid: MapGrid, sr: int, sc: int, rings: tuple[Circle, ...]
) -> tuple[int, int] | None:
    """Flood the open cells from the start; the first cell that leads off the map, or None.
    (Asked only of a map known to have one, to name it.)

    Ring walls block a step whose two cell centres lie on opposite sides of the circle.
    """

    def crosses_ring(a: tuple[float, float], b: tuple[float, float]) -> bool:
        return any(
            (math.hypot(a[0] - x, a[1] - y) < r) != (math.hypot(b[0] - x, b[1] - y) < r)
            for x, y, r in rings
        )

    seen = {(sr, sc)}
    queue = deque([(sr, sc)])
    while queue:
        r, c = queue.popleft()
        for dr, dc in _DIRECTIONS:
            nr, nc = r + dr, c + dc
            if (nr, nc) in seen or grid.is_wall(nr, nc):
                continue
            if crosses_ring(grid.centre(r, c), grid.centre(nr, nc)):
                continue
            if not grid.inside(nr, nc):
                return r, c
            seen.add((nr, nc))
            queue.append((nr, nc))
    return None


def check_goal_in(
    grid: MapGrid,
    x: float,
    y: float,
    discs: tuple[Circle, ...],
    walls: list[Wall],
    where: str,
) -> None:
    """A goal must lie inside the world, outside walls and pillars."""
    if not grid.holds(x, y):
        raise WorldMapError(f"{where}: goal x {x:g} y {y:g} is outside the world {grid.extent()}")
    x0, y0 = grid.origin_m
    r = min(int((grid.height_m - (y - y0)) / grid.cell_m), len(grid.rows) - 1)
    c = int((x - x0) / grid.cell_m)
    inside_disc = any(math.hypot(x - dx, y - dy) < dr for dx, dy, dr in discs)
    on_wall = any(wall.distance_m(x, y) == 0.0 for wall in walls)
    if not grid.is_open(r, c) or inside_disc or on_wall:
        raise WorldMapError(f"{where}: goal x {x:g} y {y:g} is inside a wall or pillar")


def wall_segments(grid: MapGrid, runs: np.ndarray) -> tuple[Segment, ...]:
    """The outline's runs (sim.maps.cells.outline_runs) as segments in the world's frame, each
    keeping the wall on its left."""
    x0, y0 = grid.origin_m
    rows, columns = len(grid.rows), max(len(row) for row in grid.rows)
    # Each grid line's coordinate, to the nanometre (3 * 0.1 reads 0.3).
    xs = np.array([round(x0 + k * grid.cell_m, 9) for k in range(columns + 1)])
    ys = np.array([round(y0 + k * grid.cell_m, 9) for k in range(rows + 1)])
    axis, line, direction, first, end = runs.T
    start = np.where(direction > 0, first, end)  # (n,) in cells, where each segment begins
    finish = np.where(direction > 0, end, first)
    segments = np.empty((len(runs), 4))  # (n, 4) x1, y1, x2, y2 metres
    h, v = axis == 0, axis == 1
    segments[h] = np.stack([xs[start[h]], ys[line[h]], xs[finish[h]], ys[line[h]]], axis=1)
    segments[v] = np.stack([xs[line[v]], ys[start[v]], xs[line[v]], ys[finish[v]]], axis=1)
    return tuple((x1, y1, x2, y2) for x1, y1, x2, y2 in segments.tolist())
