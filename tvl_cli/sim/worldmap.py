"""Text map -> WorldMap: pure parsing with errors that name file, line and column."""

from __future__ import annotations

import math
import re
from collections import defaultdict, deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from tvl_cli.core.config import RobotConfig
from tvl_cli.core.errors import BadInput

Segment = tuple[float, float, float, float]  # x1, y1, x2, y2 in metres
Circle = tuple[float, float, float]  # x, y, radius in metres


@dataclass(frozen=True, slots=True)
class WorldMap:
    """A world: static geometry in metres, origin bottom-left, x right, y up."""

    name: str
    cell_m: float
    width_m: float
    height_m: float
    segments: tuple[Segment, ...]  # maximal straight wall outlines
    discs: tuple[Circle, ...]  # round pillars (solid)
    rings: tuple[Circle, ...]  # circular walls; the robot lives inside
    start: tuple[float, float, float]  # x, y, heading (radians, CCW from +x)
    goals: tuple[tuple[float, float], ...]
    text: str  # the source, stored in every log so a world travels with its data


class WorldMapError(BadInput):
    """A world file that cannot be read or does not describe a closed world with one start."""


FORMAT_VERSION = 1
MAX_FILE_BYTES = 1 << 20  # 1 MB: far beyond any hand-made map, small enough to read at once
DEFAULT_CELL_M = 0.25
WALL, PILLAR, GOAL = "#", "o", "G"
START_HEADINGS = {">": 0.0, "<": math.pi, "^": math.pi / 2, "v": -math.pi / 2}
GRID_CHARS = "#.><^vGo"
HEADER_KEYS = ("version", "name", "cell", "disc", "ring", "goal")
_NUMBERS = {  # key -> (how many numbers, what they are); the last must be positive but for goals
    "cell": (1, "a size in metres, > 0"),
    "disc": (3, "x y r in metres, r > 0"),
    "ring": (3, "x y r in metres, r > 0"),
    "goal": (2, "x y in metres"),
}
_HEADER_LINE = re.compile(r"\s*([A-Za-z_]\w*)\s*:\s*(.*?)\s*")
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
    try:
        text = data.decode("utf-8-sig")  # tolerate the byte-order mark some editors write
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        col = error.start - (data.rfind(b"\n", 0, error.start) + 1) + 1
        raise WorldMapError(
            f"{path}:{line}:{col}: not UTF-8 text (byte 0x{data[error.start]:02x})"
        ) from None
    return parse_world(text, str(path))


@dataclass(slots=True)
class _Header:
    """Header values as read, with the line of each one-off key to name a duplicate."""

    seen: dict[str, int] = field(default_factory=dict)
    name: str | None = None
    cell_m: float = DEFAULT_CELL_M
    discs: list[Circle] = field(default_factory=list)
    rings: list[Circle] = field(default_factory=list)
    goals: list[tuple[float, float, str]] = field(default_factory=list)  # x, y, "line:col"


@dataclass(frozen=True, slots=True)
class _Grid:
    """The map characters, top line first; cells past a short line's end are outside."""

    rows: tuple[str, ...]
    lines: tuple[int, ...]  # source line number of each row
    cell_m: float

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
    grid, _ = _split(world.text, world.name)
    _check_goal(grid, x, y, world.discs, world.width_m, world.height_m, where)
    sx, sy, _ = world.start
    for cx, cy, r in world.rings:
        if (math.hypot(sx - cx, sy - cy) < r) != (math.hypot(x - cx, y - cy) < r):
            raise WorldMapError(
                f"{where}: goal x {x:g} y {y:g} is on the other side of a ring wall"
            )


def _split(text: str, source: str) -> tuple[_Grid, _Header]:
    """The header and the grid of a world text, checked for form only."""
    lines = [line.rstrip("\r") for line in text.split("\n")]
    if not any(line.strip() and not line.startswith(";") for line in lines):
        raise WorldMapError(f"{source}: file is empty (a world needs a map of # walls and a start)")
    header = _Header()
    rows: list[str] = []
    row_lines: list[int] = []
    for number, line in enumerate(lines, start=1):
        if line.startswith(";"):
            continue
        match = _HEADER_LINE.fullmatch(line)
        if match:
            if rows:
                raise WorldMapError(
                    f"{source}:{number}:1: header line after the map (put it first)"
                )
            _read_header(header, match, f"{source}:{number}", number)
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


def _read_header(header: _Header, match: re.Match[str], where: str, number: int) -> None:
    key, value = match.group(1), match.group(2)
    value_at = f"{where}:{match.start(2) + 1}"
    if key not in HEADER_KEYS:
        raise WorldMapError(
            f"{where}:{match.start(1) + 1}: unknown header key {key!r} "
            f"(expected one of {' '.join(HEADER_KEYS)})"
        )
    if key in ("version", "name", "cell"):
        if key in header.seen:
            raise WorldMapError(
                f"{where}:1: {key!r} given twice (first on line {header.seen[key]})"
            )
        header.seen[key] = number
    if key == "version":
        if value != str(FORMAT_VERSION):
            raise WorldMapError(
                f"{value_at}: unsupported version {value!r} "
                f"(this tvl reads version {FORMAT_VERSION})"
            )
    elif key == "name":
        if not value:
            raise WorldMapError(f"{value_at}: bad value for 'name': it is empty")
        header.name = value
    else:
        numbers = _numbers(key, value, value_at)
        if key == "cell":
            header.cell_m = numbers[0]
        elif key == "goal":
            header.goals.append((numbers[0], numbers[1], value_at.split(":", 1)[1]))
        else:
            (header.discs if key == "disc" else header.rings).append(
                (numbers[0], numbers[1], numbers[2])
            )


def _numbers(key: str, value: str, value_at: str) -> tuple[float, ...]:
    """The numbers of a `cell`, `disc`, `ring` or `goal` header; sizes must be positive."""
    wanted, usage = _NUMBERS[key]
    try:
        numbers = tuple(float(part) for part in value.split())
    except ValueError:
        numbers = ()
    if (
        len(numbers) != wanted
        or not all(math.isfinite(n) for n in numbers)
        or (key != "goal" and numbers[-1] <= 0)
    ):
        raise WorldMapError(f"{value_at}: bad value for {key!r}: {value!r} (expected {usage})")
    return numbers


def _build(grid: _Grid, header: _Header, text: str, source: str) -> WorldMap:
    starts: list[tuple[int, int]] = []
    pillars: list[Circle] = []
    goals = [(x, y, f"{source}:{where}") for x, y, where in header.goals]
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
    discs = (*header.discs, *pillars)
    sx, sy = grid.centre(sr, sc)
    start_at = f"{source}:{grid.where(sr, sc)}"
    _check_start_clear(grid, sr, sc, discs, header.rings, start_at)
    escape = _escape(grid, sr, sc, header.rings)
    if escape is not None:
        raise WorldMapError(
            f"{source}:{grid.where(*escape)}: open boundary: the robot can leave the world here "
            "(walls must enclose the start)"
        )
    width_m = max(len(row) for row in grid.rows) * grid.cell_m
    height_m = len(grid.rows) * grid.cell_m
    for x, y, where in goals:
        _check_goal(grid, x, y, discs, width_m, height_m, where)
    return WorldMap(
        name=header.name or Path(source).stem,
        cell_m=grid.cell_m,
        width_m=width_m,
        height_m=height_m,
        segments=_wall_segments(grid),
        discs=discs,
        rings=tuple(header.rings),
        start=(sx, sy, START_HEADINGS[grid.rows[sr][sc]]),
        goals=tuple((x, y) for x, y, _ in goals),
        text=text,
    )


def _distance_to_cell(grid: _Grid, x: float, y: float, r: int, c: int) -> float:
    cx, cy = grid.centre(r, c)
    half = grid.cell_m / 2
    return math.hypot(max(abs(x - cx) - half, 0.0), max(abs(y - cy) - half, 0.0))


def _check_start_clear(
    grid: _Grid, sr: int, sc: int, discs: tuple[Circle, ...], rings: list[Circle], start_at: str
) -> None:
    """The robot's body disc at the start must not overlap a wall cell, a disc or a ring."""
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
    for rx, ry, rr in rings:
        if abs(math.hypot(x - rx, y - ry) - rr) < radius:
            raise WorldMapError(
                f"{start_at}: the start touches the ring at x {rx:g} y {ry:g} r {rr:g} {body}"
            )


def _escape(grid: _Grid, sr: int, sc: int, rings: list[Circle]) -> tuple[int, int] | None:
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
    width_m: float,
    height_m: float,
    where: str,
) -> None:
    """A goal must lie inside the world, outside walls and pillars."""
    if not (0 <= x <= width_m and 0 <= y <= height_m):
        raise WorldMapError(
            f"{where}: goal x {x:g} y {y:g} is outside the world "
            f"(0..{width_m:g} x 0..{height_m:g} m)"
        )
    r = min(int((height_m - y) / grid.cell_m), len(grid.rows) - 1)
    c = int(x / grid.cell_m)
    inside_disc = any(math.hypot(x - dx, y - dy) < dr for dx, dy, dr in discs)
    if not grid.is_open(r, c) or inside_disc:
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
    """The world's geometry as plain JSON values (`tvl world show --json`)."""
    return {
        "name": world.name,
        "cell_m": world.cell_m,
        "segments": [list(s) for s in world.segments],
        "discs": [list(d) for d in world.discs],
        "start": list(world.start),
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
            f"walls     {len(world.segments)} segments, {len(world.rings)} rings",
            f"discs     {len(world.discs)}",
            f"start     x {x:g} y {y:g}, heading {math.degrees(heading):g}°",
            f"goals     {goals}",
        ]
    )
