"""Text map -> WorldMap: pure parsing with errors that name file, line and column."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.text import decoded
from tvl_cli.core.words import counted
from tvl_cli.sim.maps.cells import OUTSIDE, char_codes, first_where, outline_runs, reaches_outside
from tvl_cli.sim.maps.text_grid import (
    GOAL,
    GRID_CHARS,
    PILLAR,
    START_HEADINGS,
    WALL,
    MapGrid,
    check_goal_in,
    check_inside,
    check_start_clear,
    first_escape,
    ring_sides,
    wall_segments,
)
from tvl_cli.sim.world_budget import BYTES_PER_CELL, max_file_bytes, over_budget
from tvl_cli.sim.worldheader import (
    HEADER_LINE,
    Circle,
    Header,
    Segment,
    WorldMapError,
    read_header,
)

# A map of up to this many cells is flooded cell by cell in Python (in a few milliseconds),
# sparing the shipped and hand-made worlds the compiled flood's loading; a larger one is
# flooded by the compiled kernel first.
FLOOD_IN_PYTHON_CELLS = 20_000


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
    # Where the grid's bottom-left corner lies (`origin:` header, metres): the frame of the
    # map the world was made from, which every coordinate of the world is given in.
    origin_m: tuple[float, float] = (0.0, 0.0)


def load_world(path: str | Path) -> WorldMap:
    """Read and parse a world file; WorldMapError if it is too big, not UTF-8, empty or invalid."""
    path = Path(path)
    limit = max_file_bytes()
    try:
        with path.open("rb") as file:
            data = file.read(limit + 1)
    except OSError as error:
        raise WorldMapError(f"{path}: cannot read ({error.strerror})") from None
    if len(data) > limit:
        raise WorldMapError(
            f"{path}: file is over {limit:,} bytes, more cells than this machine can simulate "
            f"(a world may take half its memory, {BYTES_PER_CELL} bytes a cell)"
        )
    return parse_world(decoded(data, str(path), WorldMapError), str(path))


def world_of(world: Path | WorldMap) -> WorldMap:
    """A world as a command was given it: read from its file, or made here (generated)."""
    return load_world(world) if isinstance(world, Path) else world


def parse_world(text: str, source: str) -> WorldMap:
    """Parse the text of a world file (SPEC §3); `source` names the file in error messages."""
    grid, header = _split(text, source)
    return _build(grid, header, text, source)


def check_goal(world: WorldMap, x: float, y: float, where: str) -> None:
    """WorldMapError unless a goal at (x, y) lies in the robot's part of the world."""
    grid, header = _split(world.text, world.name)
    check_goal_in(grid, x, y, world.discs, header.walls, where)
    sx, sy, _ = world.start
    for cx, cy, r in world.rings:
        if (math.hypot(sx - cx, sy - cy) < r) != (math.hypot(x - cx, y - cy) < r):
            raise WorldMapError(
                f"{where}: goal x {x:g} y {y:g} is on the other side of a ring wall"
            )


def resolve_goal(
    given: Path | WorldMap, world: WorldMap, behaviour: str, goal: tuple[float, float] | None
) -> tuple[float, float] | None:
    """The goal a run seeks in `world` (as `given`: its file, or itself made here): --goal
    checked against the world, else the world's first goal; None for other behaviours,
    which take no goal."""
    if behaviour != "goal":
        if goal is not None:
            raise BadInput("--goal is for --behaviour goal only")
        return None
    if goal is not None:
        check_goal(world, *goal, where=f"--goal {goal[0]:g},{goal[1]:g}")
        return goal
    if not world.goals:
        where = given if isinstance(given, Path) else world.name
        raise BadInput(f"{where}: world has no goal; give one with --goal X,Y")
    return world.goals[0]


def layout(world: WorldMap) -> tuple[tuple[str, ...], Header]:
    """The world's map rows (top first) and its header, as written: what its geometry was
    built from, for a reader that needs the cells rather than the outlines."""
    grid, header = _split(world.text, world.name)
    return grid.rows, header


def _split(text: str, source: str) -> tuple[MapGrid, Header]:
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
    return MapGrid(tuple(rows), tuple(row_lines), header.cell_m, header.origin_m), header


def _build(grid: MapGrid, header: Header, text: str, source: str) -> WorldMap:
    codes = char_codes(grid.rows)  # (rows, columns) code points, top row first
    outside = codes == OUTSIDE
    wall = codes == ord(WALL)
    _check_characters(grid, codes, outside, header, source)
    runs = outline_runs(wall, ~(wall | outside))
    too_large = over_budget(codes.size, len(runs) + 4 * len(header.walls))
    if too_large:
        raise WorldMapError(f"{source}: {too_large}; use a coarser or smaller map")
    start = _start(grid, codes, header, source)
    pillars = tuple((*grid.centre(r, c), grid.cell_m / 2) for r, c in _cells(codes, PILLAR))
    goals = [*header.goals, *((*grid.centre(r, c), f"{source}:{grid.where(r, c)}")
                              for r, c in _cells(codes, GOAL))]  # fmt: skip
    discs = (*((x, y, r) for x, y, r, _ in header.discs), *pillars)
    check_inside(grid, header)
    (sr, sc), (sx, sy, heading), start_at = start
    check_start_clear(grid, sx, sy, discs, header, start_at)
    rings = tuple((x, y, r) for x, y, r, _ in header.rings)
    escape = _escape(grid, codes, (sr, sc), rings)
    if escape is not None:
        raise WorldMapError(
            f"{source}:{grid.where(*escape)}: open boundary: the robot can leave the world here "
            "(walls must enclose the start)"
        )
    for x, y, where in goals:
        check_goal_in(grid, x, y, discs, header.walls, where)
    segments = (*wall_segments(grid, runs),
                *(s for w in header.walls for s in w.outline()))  # fmt: skip
    return WorldMap(
        name=header.name or Path(source).stem,
        cell_m=grid.cell_m,
        width_m=grid.width_m,
        height_m=grid.height_m,
        segments=segments,
        discs=discs,
        rings=rings,
        start=(sx, sy, heading),
        goals=tuple((x, y) for x, y, _ in goals),
        text=text,
        roughness=header.roughness,
        segment_roughness=_roughness_of(header, segments),
        origin_m=grid.origin_m,
    )


def _roughness_of(header: Header, segments: tuple[Segment, ...]) -> tuple[float, ...]:
    """Each segment's roughness: its `rough:` rectangle's, else the world's."""
    if not header.rough:
        return (header.roughness,) * len(segments)
    return tuple(
        header.roughness_at((x1 + x2) / 2.0, (y1 + y2) / 2.0) for x1, y1, x2, y2 in segments
    )


def _escape(
    grid: MapGrid, codes: np.ndarray, start: tuple[int, int], rings: tuple[Circle, ...]
) -> tuple[int, int] | None:
    """The first open cell, flooding from the start, that leads off the map, or None. A
    small map is flooded cell by cell at once; a large one is first asked of the compiled
    flood (the flood cell by cell then only names the cell of a map that has one)."""
    if codes.size <= FLOOD_IN_PYTHON_CELLS:
        return first_escape(grid, *start, rings)
    outside = codes == OUTSIDE
    open_cells = ~(outside | (codes == ord(WALL)))
    if not reaches_outside(open_cells, outside, start, ring_sides(grid, codes, rings)):
        return None
    return first_escape(grid, *start, rings)


def _cells(codes: np.ndarray, chars: str) -> list[tuple[int, int]]:
    """The (row, column) of every cell holding one of `chars`, in reading order."""
    rows, columns = np.nonzero(np.isin(codes, [ord(char) for char in chars]))
    return list(zip(rows.tolist(), columns.tolist(), strict=True))


def _check_characters(
    grid: MapGrid, codes: np.ndarray, outside: np.ndarray, header: Header, source: str
) -> None:
    """Every character must be a map character and the map must hold exactly one start
    (a start character, or the header's `start:`); the first fault in reading order is
    named."""
    unknown = ~np.isin(codes, [ord(char) for char in GRID_CHARS]) & ~outside
    starts = _cells(codes, "".join(START_HEADINGS))
    bad = first_where(unknown)
    second = starts[1] if len(starts) > 1 else None
    if bad is not None and (second is None or bad < second):
        char = chr(int(codes[bad]))
        raise WorldMapError(
            f"{source}:{grid.where(*bad)}: unknown character {char!r} "
            f"(expected one of {' '.join(GRID_CHARS)})"
        )
    if second is not None:
        first = grid.where(*starts[0])
        raise WorldMapError(
            f"{source}:{grid.where(*second)}: two starts, at {first} and "
            f"{grid.where(*second)} (a world has exactly one)"
        )
    if starts and header.start is not None:
        raise WorldMapError(
            f"{header.start[3]}: two starts, the header's and the map's at "
            f"{grid.where(*starts[0])} (a world has exactly one)"
        )
    if not starts and header.start is None:
        raise WorldMapError(f"{source}: no start (put one of > < ^ v in the map, or a start: line)")


def _start(
    grid: MapGrid, codes: np.ndarray, header: Header, source: str
) -> tuple[tuple[int, int], tuple[float, float, float], str]:
    """The start's cell, its pose (x, y metres, heading rad) and where it was given."""
    if header.start is None:
        ((r, c),) = _cells(codes, "".join(START_HEADINGS))
        return (
            (r, c),
            (*grid.centre(r, c), START_HEADINGS[grid.rows[r][c]]),
            (f"{source}:{grid.where(r, c)}"),
        )
    x, y, heading, where = header.start
    r, c = grid.cell_at(x, y)
    if not grid.is_open(r, c):
        raise WorldMapError(
            f"{where}: the start x {x:g} y {y:g} is not on the map's floor {grid.extent()}"
        )
    return (r, c), (x, y, heading), where


def world_to_dict(world: WorldMap) -> dict[str, Any]:
    """The world's geometry as plain JSON values (`tvl world show --json`); the start's
    heading in degrees, as every --json document gives a pose."""
    x, y, heading = world.start
    return {
        "name": world.name,
        "cell_m": world.cell_m,
        "origin_m": list(world.origin_m),
        "size_m": [world.width_m, world.height_m],
        "segments": [list(s) for s in world.segments],
        "discs": [list(d) for d in world.discs],
        "start": [x, y, math.degrees(heading)],
        "goals": [list(g) for g in world.goals],
        "rings": [list(r) for r in world.rings],
    }


def describe(world: WorldMap) -> str:
    """A short readable summary of a world (`tvl world show`)."""
    x, y, heading = world.start
    x0, y0 = world.origin_m
    goals = ", ".join(f"({gx:g}, {gy:g})" for gx, gy in world.goals) or "none"
    return "\n".join(
        [
            f"name      {world.name}",
            f"size      {world.width_m:g} x {world.height_m:g} m (cell {world.cell_m:g} m)",
            f"extent    x {x0:g} to {x0 + world.width_m:g}, y {y0:g} to {y0 + world.height_m:g} m",
            f"walls     {counted(len(world.segments), 'segment')}, "
            f"{counted(len(world.rings), 'ring')}",
            f"discs     {len(world.discs)}",
            f"start     x {x:g} y {y:g}, heading {math.degrees(heading):g}°",
            f"goals     {goals}",
        ]
    )
