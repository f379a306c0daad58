"""The `rooms` generator: indoor worlds of rooms joined by doorways and corridors, furnished
with pillars, blocks, L-shaped walls and walls at an angle, with a goal the robot can reach.

The floor is cut in two again and again by one-cell walls (0.25 m), each with a doorway;
some cuts are corridors (two parallel walls with a doorway in each). Each room then gets a
few pieces of furniture, always leaving at least 0.75 m of floor between them and the walls,
and the goal is put on the floor the robot can reach from its start keeping its clearance.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.canvas import CELL_M, Canvas
from tvl_cli.sim.geometry import clearances_m, static_geometry
from tvl_cli.sim.worldheader import WorldMapError
from tvl_cli.sim.worldmap import parse_world

ROOMS_DEFAULT_SIZE_M = (9.0, 7.0)
ROOMS_MIN_SIZE_M = (5.0, 4.0)
ROOM_MIN_CELLS = 8  # 2 m: the shortest side of a room
DOOR_CELLS = (4, 5, 6)  # doorways of 1.0, 1.25 or 1.5 m
CORRIDOR_CELLS = (4, 10)  # corridors from 1.0 to 2.5 m wide
CORRIDOR_CHANCE = 0.35
MAX_CUTS_DEEP = 3  # up to 8 rooms
KEEP_CLEAR = 3  # cells (0.75 m) of floor kept round every piece of furniture
PILLAR_RADII_M = (0.1, 0.15, 0.2, 0.3)
TRIES = 30  # positions tried for one cut or piece before leaving it out
# The goal must be reachable by a body keeping this much floor to every side, and stand
# where a robot keeping its usual clearance (0.3-0.4 m) comes within 0.3 m of it.
PATH_CLEARANCE_M = 0.1
GOAL_CLEARANCE_M = 0.3
# Goal seeking steers by the goal's bearing, with no map: the goal is at least 2 m off and,
# where the layout allows, its way round the furniture at most 1.3 times as long as the
# straight one (in grid steps); else it is anywhere in the farthest third of the floor.
GOAL_MIN_DISTANCE_M = 2.0
GOAL_MAX_DETOUR = 1.3
# Cell centres whose clearance is computed at once: the query holds a few (points, walls)
# arrays, which for every cell of a 100 m hall at once would take gigabytes.
CLEARANCE_BATCH = 4096
PIECES = ("pillar", "block", "L wall", "angled wall")


@dataclass(frozen=True, slots=True)
class Doorway:
    """A gap the generator left in a wall it drew, in cells of the map."""

    down_column: bool  # the wall runs down a column (else along a row)
    line: int  # the wall's column, or its row
    first: int  # the first free cell along the wall: a row, or a column
    cells: int

    @property
    def width_m(self) -> float:
        return self.cells * CELL_M


@dataclass(frozen=True, slots=True)
class RoomsPlan:
    """What the generator drew, so that a world can be checked against what was meant."""

    rooms: int
    corridor_widths_m: tuple[float, ...]
    doorways: tuple[Doorway, ...]
    furniture: tuple[str, ...]  # one of PIECES for each piece placed
    # Each room with the walls round it, x0 y0 x1 y1 metres: where a material may be laid.
    room_extents_m: tuple[tuple[float, float, float, float], ...] = ()


@dataclass(frozen=True, slots=True)
class _Region:
    """A rectangle of floor cells, inclusive: rows top to bottom, columns left to right."""

    r0: int
    c0: int
    r1: int
    c1: int

    @property
    def rows(self) -> int:
        return self.r1 - self.r0 + 1

    @property
    def cols(self) -> int:
        return self.c1 - self.c0 + 1


def layout_rooms(canvas: Canvas, rng: np.random.Generator) -> RoomsPlan:
    """Draw rooms, furniture, the start and a goal on the canvas; the record of what was drawn."""
    solid = canvas.grid == "#"  # (rows, cols) cells no piece may be put on or next to
    doorways: list[Doorway] = []
    corridors: list[int] = []  # widths in cells
    floor = _Region(1, 1, canvas.rows - 2, canvas.cols - 2)
    regions = _cut(canvas, rng, floor, solid, 0, doorways, corridors)
    furniture = [piece for region in regions for piece in _furnish(canvas, rng, region, solid)]
    _place_start(canvas, rng, solid)
    _place_goal(canvas, rng)
    return RoomsPlan(
        rooms=len(regions),
        corridor_widths_m=tuple(cells * CELL_M for cells in corridors),
        doorways=tuple(doorways),
        furniture=tuple(furniture),
        room_extents_m=tuple(
            (
                (room.c0 - 1) * CELL_M,
                (canvas.rows - room.r1 - 2) * CELL_M,
                (room.c1 + 2) * CELL_M,
                (canvas.rows - room.r0 + 1) * CELL_M,
            )
            for room in regions
        ),
    )


def _cut(
    canvas: Canvas,
    rng: np.random.Generator,
    region: _Region,
    solid: np.ndarray,
    depth: int,
    doorways: list[Doorway],
    corridors: list[int],
) -> list[_Region]:
    """Cut a region into rooms; the rooms, the corridors left out (but added to `corridors`,
    as every doorway drawn is to `doorways`)."""
    if depth == MAX_CUTS_DEEP or (depth > 0 and rng.random() < 0.25):
        return [region]
    across = region.cols >= region.rows  # a wall down a column when the room is wide
    corridor = int(rng.integers(CORRIDOR_CELLS[0], CORRIDOR_CELLS[1] + 1))
    corridor = corridor if rng.random() < CORRIDOR_CHANCE else 0
    span, start = (region.cols, region.c0) if across else (region.rows, region.r0)
    taken = 1 + (corridor + 1 if corridor else 0)  # cells the cut itself uses
    room_space = span - taken - 2 * ROOM_MIN_CELLS
    if room_space < 0:
        return [region]
    for _ in range(TRIES):
        first = start + ROOM_MIN_CELLS + int(rng.integers(room_space + 1))
        lines = [first, first + corridor + 1] if corridor else [first]
        if all(_wall_fits(region, line, across, solid) for line in lines):
            break
    else:
        return [region]
    doorways += [_draw_wall(canvas, rng, region, line, across, solid) for line in lines]
    if corridor:
        corridors.append(corridor)
    last = lines[-1]
    if across:
        before = _Region(region.r0, region.c0, region.r1, first - 1)
        after = _Region(region.r0, last + 1, region.r1, region.c1)
    else:
        before = _Region(region.r0, region.c0, first - 1, region.c1)
        after = _Region(last + 1, region.c0, region.r1, region.c1)
    return _cut(canvas, rng, before, solid, depth + 1, doorways, corridors) + _cut(
        canvas, rng, after, solid, depth + 1, doorways, corridors
    )


def _wall_fits(region: _Region, line: int, across: bool, solid: np.ndarray) -> bool:
    """A new wall must not end in an earlier doorway: both its ends must meet solid wall."""
    if across:
        return bool(solid[region.r0 - 1, line] and solid[region.r1 + 1, line])
    return bool(solid[line, region.c0 - 1] and solid[line, region.c1 + 1])


def _draw_wall(
    canvas: Canvas,
    rng: np.random.Generator,
    region: _Region,
    line: int,
    across: bool,
    solid: np.ndarray,
) -> Doorway:
    """A one-cell wall across the region with a doorway, not at either end."""
    length = region.rows if across else region.cols
    door = int(rng.choice(DOOR_CELLS))
    at = 1 + int(rng.integers(max(length - door - 1, 1)))
    cells = np.full(length, True)
    cells[at : at + door] = False
    if across:
        rows = np.arange(region.r0, region.r1 + 1)
        canvas.grid[rows[cells], line] = "#"
        solid[rows[cells], line] = True
    else:
        cols = np.arange(region.c0, region.c1 + 1)
        canvas.grid[line, cols[cells]] = "#"
        solid[line, cols[cells]] = True
    return Doorway(across, line, (region.r0 if across else region.c0) + at, door)


def _furnish(
    canvas: Canvas, rng: np.random.Generator, room: _Region, solid: np.ndarray
) -> list[str]:
    """Up to three pieces, each kept KEEP_CLEAR cells from the walls and from each other; the
    names of those that found room."""
    placed = []
    for _ in range(int(rng.integers(0, 4))):
        piece = int(rng.integers(4))
        if piece == 0:
            fits = _pillar(canvas, rng, room, solid)
        elif piece == 1:
            fits = _footprint(canvas, rng, room, solid, _block(rng))
        elif piece == 2:
            fits = _footprint(canvas, rng, room, solid, _l_wall(rng))
        else:
            fits = _angled_wall(canvas, rng, room, solid)
        if fits:
            placed.append(PIECES[piece])
    return placed


def _spot(
    rng: np.random.Generator, room: _Region, solid: np.ndarray, height: int, width: int
) -> tuple[int, int] | None:
    """Top-left cell of a free height x width footprint with KEEP_CLEAR free cells round it."""
    k = KEEP_CLEAR
    free_rows, free_cols = room.rows - height - 2 * k, room.cols - width - 2 * k
    if free_rows < 0 or free_cols < 0:
        return None
    for _ in range(TRIES):
        r = room.r0 + k + int(rng.integers(free_rows + 1))
        c = room.c0 + k + int(rng.integers(free_cols + 1))
        if not solid[r - k : r + height + k, c - k : c + width + k].any():
            return r, c
    return None


def _footprint(
    canvas: Canvas, rng: np.random.Generator, room: _Region, solid: np.ndarray, shape: np.ndarray
) -> bool:
    spot = _spot(rng, room, solid, *shape.shape)
    if spot is None:
        return False
    r, c = spot
    h, w = shape.shape
    canvas.grid[r : r + h, c : c + w][shape] = "#"
    solid[r : r + h, c : c + w] = True
    return True


def _block(rng: np.random.Generator) -> np.ndarray:
    """A convex block from 0.5 x 0.5 m to 1 x 0.75 m."""
    return np.ones((int(rng.integers(2, 4)), int(rng.integers(2, 5))), dtype=bool)


def _l_wall(rng: np.random.Generator) -> np.ndarray:
    """An L of one-cell walls, arms 1 to 2 m, turned any of four ways."""
    h, w = int(rng.integers(4, 9)), int(rng.integers(4, 9))
    shape = np.zeros((h, w), dtype=bool)
    shape[-1, :] = True
    shape[:, 0] = True
    return np.rot90(shape, int(rng.integers(4)))


def _pillar(canvas: Canvas, rng: np.random.Generator, room: _Region, solid: np.ndarray) -> bool:
    radius_m = float(rng.choice(PILLAR_RADII_M))
    cells = 1 + 2 * math.ceil(radius_m / CELL_M - 0.5)  # an odd square covering the disc
    spot = _spot(rng, room, solid, cells, cells)
    if spot is None:
        return False
    r, c = spot
    canvas.disc(*canvas.centre_m(r + cells // 2, c + cells // 2), radius_m)
    solid[r : r + cells, c : c + cells] = True
    return True


def _angled_wall(
    canvas: Canvas, rng: np.random.Generator, room: _Region, solid: np.ndarray
) -> bool:
    """A straight wall 0.75 to 1.5 m long at 15 to 75 degrees off the grid, thin like a table
    edge or 0.1 m thick, inside a square of free floor."""
    length_m = float(rng.uniform(0.75, 1.5))
    angle = math.radians(float(rng.uniform(15.0, 75.0))) * (1 if rng.random() < 0.5 else -1)
    cells = math.ceil(length_m / CELL_M)
    spot = _spot(rng, room, solid, cells, cells)
    if spot is None:
        return False
    r, c = spot
    x0, y0 = canvas.centre_m(r + cells - 1, c)  # bottom-left cell of the square
    cx, cy = x0 + (cells - 1) * CELL_M / 2, y0 + (cells - 1) * CELL_M / 2
    dx, dy = length_m / 2 * math.cos(angle), length_m / 2 * math.sin(angle)
    thickness = 0.0 if rng.random() < 0.5 else 0.1
    canvas.header.append(
        f"wall: {cx - dx:.3f} {cy - dy:.3f} {cx + dx:.3f} {cy + dy:.3f} {thickness:g}"
    )
    solid[r : r + cells, c : c + cells] = True
    return True


def _place_start(canvas: Canvas, rng: np.random.Generator, solid: np.ndarray) -> None:
    """On a cell with two free cells (0.5 m) all round, facing any of the four ways."""
    blocked = np.pad(solid, 2, constant_values=True)
    windows = np.lib.stride_tricks.sliding_window_view(blocked, (5, 5))  # (rows, cols, 5, 5)
    clear = np.argwhere(~windows.any(axis=(2, 3)))
    if not len(clear):
        raise WorldMapError("no floor for the start")
    r, c = clear[rng.integers(len(clear))]
    canvas.grid[r, c] = ">^<v"[int(rng.integers(4))]


def _place_goal(canvas: Canvas, rng: np.random.Generator) -> None:
    """On open floor that a body keeping PATH_CLEARANCE_M reaches from the start, walking
    cell to cell."""
    world = parse_world(canvas.text("rooms", "", ""), "<rooms>")
    rows, cols = canvas.grid.shape
    centres = np.array([canvas.centre_m(r, c) for r in range(rows) for c in range(cols)])
    geometry, radius_m = static_geometry(world), RobotConfig().radius_m
    clearance = np.concatenate(
        [
            clearances_m(geometry, centres[i : i + CLEARANCE_BATCH], radius_m)
            for i in range(0, len(centres), CLEARANCE_BATCH)
        ]
    )  # (rows * cols,) metres
    passable = (clearance >= PATH_CLEARANCE_M).reshape(rows, cols)
    start = tuple(int(i) for i in np.argwhere(np.isin(canvas.grid, list(">^<v")))[0])
    steps = np.full((rows, cols), -1)
    steps[start] = 0
    queue = deque([start])
    while queue:
        r, c = queue.popleft()
        for nr, nc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if passable[nr, nc] and steps[nr, nc] < 0:
                steps[nr, nc] = steps[r, c] + 1
                queue.append((nr, nc))
    open_floor = (clearance >= GOAL_CLEARANCE_M).reshape(rows, cols)
    reached = np.argwhere((steps > 0) & open_floor)
    if not len(reached):
        raise WorldMapError("no open floor the robot can reach from the start")
    walked = steps[tuple(reached.T)]
    straight = np.abs(reached - np.array(start)).sum(axis=1)  # grid steps with no obstacle
    direct = reached[
        (straight * CELL_M >= GOAL_MIN_DISTANCE_M) & (walked <= GOAL_MAX_DETOUR * straight)
    ]
    candidates = direct if len(direct) else reached[walked >= np.quantile(walked, 2 / 3)]
    r, c = candidates[rng.integers(len(candidates))]
    canvas.header.append("goal: {:g} {:g}".format(*canvas.centre_m(int(r), int(c))))
