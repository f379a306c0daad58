"""Text map -> WorldMap: pure parsing with errors that name file, line and column."""

from __future__ import annotations

import math
from collections import defaultdict, deque
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.core.errors import BadInput
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.text import decoded
from tvl_cli.core.words import counted
from tvl_cli.sim.worldheader import (
    HEADER_LINE,
    Circle,
    Header,
    Segment,
    Wall,
    WorldMapError,
    read_header,
)


@dataclass(frozen=True, slots=True)
class WorldMap:
    """A world: static geometry in metres, origin bottom-left, x right, y up."""

    name: str
    cell_m: float
    width_m: float
    height_m: float
    segments: tuple[Segment, ...]  # maximal straight wall outlines, then the header walls
    discs: tuple[Circle, ...]  # round pillars (solid)
    rings: tuple[Circle, ...]  # circular walls; the robot lives inside
    start: tuple[float, float, float]  # x, y, heading (radians, CCW from +x)
    goals: tuple[tuple[float, float], ...]
    text: str  # the source, stored in every log so a world travels with its data
    # The share of sound its walls scatter diffusely (`roughness:` header); 0 is smooth.
    roughness: float = 0.0
    # Each segment's own share, as `rough:` rectangles give it (empty: the world's for all).
    segment_roughness: tuple[float, ...] = ()


MAX_FILE_BYTES = 1 << 20  # 1 MB: far beyond any hand-made map, small enough to read at once
WALL, PILLAR, GOAL = "#", "o", "G"
START_HEADINGS = {">": 0.0, "<": math.pi, "^": math.pi / 2, "v": -math.pi / 2}
GRID_CHARS = "#.><^vGo"
_DIRECTIONS = (
    (0, 1),
    (1, 0),
    (0, -1),
    (-1, 0),
)  # (row, column) steps; fixed order keeps BFS stable


def load_world(path: str | Path) -> WorldMap:
    """Read and parse a world file; WorldMapError if it is too big, not UTF-8, empty or invalid."""
    path = Path(path)
    try:
        with path.open("rb") as file:
            data = file.read(MAX_FILE_BYTES + 1)
    except OSError as error:
        raise WorldMapError(f"{path}: cannot read ({error.strerror})") from None
    if len(data) > MAX_FILE_BYTES:
        raise WorldMapError(f"{path}: file is over 1 MB (a world map is a small text file)")
    return parse_world(decoded(data, str(path), WorldMapError), str(path))


@dataclass(frozen=True, slots=True)
class _Grid:
    """The map characters, top line first; cells past a short line's end are outside."""

    rows: tuple[str, ...]
    lines: tuple[int, ...]  # source line number of each row
    cell_m: float

    @property
    def width_m(self) -> float:
        return max(len(row) for row in self.rows) * self.cell_m

    @property
    def height_m(self) -> float:
        return len(self.rows) * self.cell_m

    def inside(self, r: int, c: int) -> bool:
        return 0 <= r < len(self.rows) and 0 <= c < len(self.rows[r])

    def is_wall(self, r: int, c: int) -> bool:
        return self.inside(r, c) and self.rows[r][c] == WALL

    def is_open(self, r: int, c: int) -> bool:
        return self.inside(r, c) and self.rows[r][c] != WALL

    def centre(self, r: int, c: int) -> tuple[float, float]:
        return (c + 0.5) * self.cell_m, (len(self.rows) - r - 0.5) * self.cell_m

    def where(self, r: int, c: int) -> str:
        return f"{self.lines[r]}:{c + 1}"


def parse_world(text: str, source: str) -> WorldMap:
    """Parse the text of a world file (SPEC §3); `source` names the file in error messages."""
    grid, header = _split(text, source)
    return _build(grid, header, text, source)


def check_goal(world: WorldMap, x: float, y: float, where: str) -> None:
    """WorldMapError unless a goal at (x, y) lies in the robot's part of the world."""
    grid, header = _split(world.text, world.name)
    _check_goal(grid, x, y, world.discs, header.walls, where)
    sx, sy, _ = world.start
    for cx, cy, r in world.rings:
        if (math.hypot(sx - cx, sy - cy) < r) != (math.hypot(x - cx, y - cy) < r):
            raise WorldMapError(
                f"{where}: goal x {x:g} y {y:g} is on the other side of a ring wall"
            )


def resolve_goal(
    world_path: Path, world: WorldMap, behaviour: str, goal: tuple[float, float] | None
) -> tuple[float, float] | None:
    """The goal a run seeks: --goal checked against the world, else the world's first goal;
    None for other behaviours, which take no goal."""
    if behaviour != "goal":
        if goal is not None:
            raise BadInput("--goal is for --behaviour goal only")
        return None
    if goal is not None:
        check_goal(world, *goal, where=f"--goal {goal[0]:g},{goal[1]:g}")
        return goal
    if not world.goals:
        raise BadInput(f"{world_path}: world has no goal; give one with --goal X,Y")
    return world.goals[0]


def layout(world: WorldMap) -> tuple[tuple[str, ...], Header]:
    """The world's map rows (top first) and its header, as written: what its geometry was
    built from, for a reader that needs the cells rather than the outlines."""
    grid, header = _split(world.text, world.name)
    return grid.rows, header


def _split(text: str, source: str) -> tuple[_Grid, Header]:
    """The header and the grid of a world text, checked for form only."""
    lines = [line.rstrip("\r") for line in text.split("\n")]
    if not any(line.strip() and not line.startswith(";") for line in lines):
        raise WorldMapError(f"{source}: file is empty (a world needs a map of # walls and a start)")
    header = Header()
    rows: list[str] = []
    row_lines: list[int] = []
    for number, line in enumerate(lines, start=1):
        if line.startswith(";"):
            continue
        match = HEADER_LINE.fullmatch(line)
        if match:
            if rows:
                raise WorldMapError(
                    f"{source}:{number}:1: header line after the map (put it first)"
                )
            read_header(header, match, f"{source}:{number}", number)
        elif rows or line.strip():
            rows.append(line.rstrip())
            row_lines.append(number)
    while rows and not rows[-1]:
        rows.pop()
        row_lines.pop()
    if not rows:
        raise WorldMapError(f"{source}: no map (header lines only)")
    if "" in rows:
        blank = row_lines[rows.index("")]
        raise WorldMapError(f"{source}:{blank}:1: blank line inside the map")
    return _Grid(tuple(rows), tuple(row_lines), header.cell_m), header


def _build(grid: _Grid, header: Header, text: str, source: str) -> WorldMap:
    starts: list[tuple[int, int]] = []
    pillars: list[Circle] = []
    goals = list(header.goals)
    half = grid.cell_m / 2
    for r, row in enumerate(grid.rows):
        for c, char in enumerate(row):
            if char not in GRID_CHARS:
                raise WorldMapError(
                    f"{source}:{grid.where(r, c)}: unknown character {char!r} "
                    f"(expected one of {' '.join(GRID_CHARS)})"
                )
            x, y = grid.centre(r, c)
            if char in START_HEADINGS:
                if starts:
                    first = grid.where(*starts[0])
                    raise WorldMapError(
                        f"{source}:{grid.where(r, c)}: two starts, at {first} and "
                        f"{grid.where(r, c)} (a world has exactly one)"
                    )
                starts.append((r, c))
            elif char == PILLAR:
                pillars.append((x, y, half))
            elif char == GOAL:
                goals.append((x, y, f"{source}:{grid.where(r, c)}"))
    if not starts:
        raise WorldMapError(f"{source}: no start (put one of > < ^ v in the map)")
    sr, sc = starts[0]
    discs = (*((x, y, r) for x, y, r, _ in header.discs), *pillars)
    width_m, height_m = grid.width_m, grid.height_m
    _check_inside(header, width_m, height_m)
    sx, sy = grid.centre(sr, sc)
    start_at = f"{source}:{grid.where(sr, sc)}"
    _check_start_clear(grid, sr, sc, discs, header, start_at)
    rings = tuple((x, y, r) for x, y, r, _ in header.rings)
    escape = _escape(grid, sr, sc, rings)
    if escape is not None:
        raise WorldMapError(
            f"{source}:{grid.where(*escape)}: open boundary: the robot can leave the world here "
            "(walls must enclose the start)"
        )
    for x, y, where in goals:
        _check_goal(grid, x, y, discs, header.walls, where)
    segments = (*_wall_segments(grid), *(s for w in header.walls for s in w.outline()))
    return WorldMap(
        name=header.name or Path(source).stem,
        cell_m=grid.cell_m,
        width_m=width_m,
        height_m=height_m,
        segments=segments,
        discs=discs,
        rings=rings,
        start=(sx, sy, START_HEADINGS[grid.rows[sr][sc]]),
        goals=tuple((x, y) for x, y, _ in goals),
        text=text,
        roughness=header.roughness,
        segment_roughness=tuple(
            header.roughness_at((x1 + x2) / 2.0, (y1 + y2) / 2.0) for x1, y1, x2, y2 in segments
        ),
    )


def _distance_to_cell(grid: _Grid, x: float, y: float, r: int, c: int) -> float:
    cx, cy = grid.centre(r, c)
    half = grid.cell_m / 2
    return math.hypot(max(abs(x - cx) - half, 0.0), max(abs(y - cy) - half, 0.0))


def _check_inside(header: Header, width_m: float, height_m: float) -> None:
    """Header walls and pillars must stand within the map's extent: the grid encloses the
    robot's world, and nothing outside it could ever be met. A thick wall's corners count,
    not only its ends."""

    def inside(x: float, y: float) -> bool:
        return 0.0 <= x <= width_m and 0.0 <= y <= height_m

    extent = f"(the map is 0..{width_m:g} x 0..{height_m:g} m)"
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


def _check_start_clear(
    grid: _Grid, sr: int, sc: int, discs: tuple[Circle, ...], header: Header, start_at: str
) -> None:
    """The robot's body disc at the start must not overlap a wall, a disc or a ring."""
    radius = RobotConfig().radius_m
    x, y = grid.centre(sr, sc)
    body = f"(the robot is a disc of radius {radius:g} m)"
    reach = math.ceil(radius / grid.cell_m)
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


def _escape(grid: _Grid, sr: int, sc: int, rings: tuple[Circle, ...]) -> tuple[int, int] | None:
    """Flood the open cells from the start; the first cell that leads off the map, or None.

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


def _check_goal(
    grid: _Grid,
    x: float,
    y: float,
    discs: tuple[Circle, ...],
    walls: list[Wall],
    where: str,
) -> None:
    """A goal must lie inside the world, outside walls and pillars."""
    width_m, height_m = grid.width_m, grid.height_m
    if not (0 <= x <= width_m and 0 <= y <= height_m):
        raise WorldMapError(
            f"{where}: goal x {x:g} y {y:g} is outside the world "
            f"(0..{width_m:g} x 0..{height_m:g} m)"
        )
    r = min(int((height_m - y) / grid.cell_m), len(grid.rows) - 1)
    c = int(x / grid.cell_m)
    inside_disc = any(math.hypot(x - dx, y - dy) < dr for dx, dy, dr in discs)
    on_wall = any(wall.distance_m(x, y) == 0.0 for wall in walls)
    if not grid.is_open(r, c) or inside_disc or on_wall:
        raise WorldMapError(f"{where}: goal x {x:g} y {y:g} is inside a wall or pillar")


def _wall_segments(grid: _Grid) -> tuple[Segment, ...]:
    """The outline between wall cells and open cells, as maximal straight segments.

    Each segment keeps the wall on its left. Unit edges are keyed by the line they lie on
    and their direction, so collinear neighbours with the wall on the same side merge.
    Edges between two wall cells, or facing off the map, are never seen by the robot.
    """
    edges: dict[tuple[str, int, int], list[int]] = defaultdict(list)  # (axis, line, dir) -> starts
    n = len(grid.rows)
    for r, row in enumerate(grid.rows):
        j = n - 1 - r  # row counted from the bottom, in cells
        for c, char in enumerate(row):
            if char != WALL:
                continue
            if grid.is_open(r + 1, c):  # open below: runs +x along y = j
                edges["h", j, 1].append(c)
            if grid.is_open(r - 1, c):  # open above: runs -x along y = j + 1
                edges["h", j + 1, -1].append(c)
            if grid.is_open(r, c + 1):  # open right: runs +y along x = c + 1
                edges["v", c + 1, 1].append(j)
            if grid.is_open(r, c - 1):  # open left: runs -y along x = c
                edges["v", c, -1].append(j)

    def metres(k: int) -> float:
        return round(k * grid.cell_m, 9)  # so that 3 * 0.1 reads 0.3

    segments: list[Segment] = []
    for (axis, line, direction), starts in sorted(edges.items()):
        starts.sort()
        first = previous = starts[0]
        for s in [*starts[1:], None]:
            if s == previous + 1:
                previous = s
                continue
            a, b = (first, previous + 1) if direction > 0 else (previous + 1, first)
            if axis == "h":
                segments.append((metres(a), metres(line), metres(b), metres(line)))
            else:
                segments.append((metres(line), metres(a), metres(line), metres(b)))
            if s is not None:
                first = previous = s
    return tuple(segments)


def world_to_dict(world: WorldMap) -> dict[str, Any]:
    """The world's geometry as plain JSON values (`tvl world show --json`); the start's
    heading in degrees, as every --json document gives a pose."""
    x, y, heading = world.start
    return {
        "name": world.name,
        "cell_m": world.cell_m,
        "segments": [list(s) for s in world.segments],
        "discs": [list(d) for d in world.discs],
        "start": [x, y, math.degrees(heading)],
        "goals": [list(g) for g in world.goals],
        "rings": [list(r) for r in world.rings],
    }


def describe(world: WorldMap) -> str:
    """A short readable summary of a world (`tvl world show`)."""
    x, y, heading = world.start
    goals = ", ".join(f"({gx:g}, {gy:g})" for gx, gy in world.goals) or "none"
    return "\n".join(
        [
            f"name      {world.name}",
            f"size      {world.width_m:g} x {world.height_m:g} m (cell {world.cell_m:g} m)",
            f"walls     {counted(len(world.segments), 'segment')}, "
            f"{counted(len(world.rings), 'ring')}",
            f"discs     {len(world.discs)}",
            f"start     x {x:g} y {y:g}, heading {math.degrees(heading):g}°",
            f"goals     {goals}",
        ]
    )
