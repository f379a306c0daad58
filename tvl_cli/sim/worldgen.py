"""World generators: the text of a world file for each kind (`tvl world new KIND`)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.sim.canvas import CELL_M, Canvas
from tvl_cli.sim.rooms import ROOMS_DEFAULT_SIZE_M, ROOMS_MIN_SIZE_M, RoomsPlan, layout_rooms
from tvl_cli.sim.worldheader import WorldMapError
from tvl_cli.sim.worldmap import parse_world

MAX_SIZE_M = 100.0  # 400 x 400 cells: a big hall, still a small file
ATTEMPTS = 20  # random layouts drawn before giving up on a size
# Rough enough to be heard at a slant close in (47° off the normal within 1.8 m:
# docs/guide/robot.md, *What real sonars hear beyond the specular rule*), as brick or a
# curtain is; smooth painted plaster is 0.
DEFAULT_ROUGHNESS = 0.3
BUNDLED_DIR = Path(__file__).resolve().parent.parent / "data"


def _square(canvas: Canvas, rng: np.random.Generator) -> None:
    canvas.grid[canvas.cell(0.5, 0.5)] = ">"


def _circle(canvas: Canvas, rng: np.random.Generator) -> None:
    width_m, height_m = canvas.cols * CELL_M, canvas.rows * CELL_M
    radius_m = min(width_m, height_m) / 2 - 2 * CELL_M  # a cell of floor between ring and border
    canvas.header.append(f"ring: {width_m / 2:g} {height_m / 2:g} {radius_m:g}")
    canvas.grid[canvas.cell(0.5, 0.5)] = ">"


CORRIDOR_CELLS = round(1.2 / CELL_M)  # a corridor about 1.2 m wide


def _corridor(canvas: Canvas, rng: np.random.Generator) -> None:
    k = 1 + CORRIDOR_CELLS
    canvas.grid[k:-k, k:-k] = "#"  # the block the corridor loops around
    canvas.grid[canvas.rows - 2 - CORRIDOR_CELLS // 2, canvas.cols // 2] = ">"


# Pillars (radius 0.2 m) and goals as fractions of the width and height, after Figure 22:
# staggered pillars between the start (left) and four goals (right), one goal behind a pair
# of pillars with a gap barely wider than the robot.
OBSTACLE_RADIUS_M = 0.2
OBSTACLE_PILLARS = (
    (0.35, 0.30),
    (0.35, 0.70),
    (0.55, 0.15),
    (0.55, 0.50),
    (0.55, 0.85),
    (0.78, 0.37),
    (0.78, 0.63),
)
# Goals stand in the open, at least 0.6 m from any wall (the robot stops within 0.3 m of
# a goal and keeps its clearance from walls); the last one waits behind a narrow gap.
OBSTACLE_GOALS = ((0.85, 0.22), (0.85, 0.78), (0.88, 0.50), (0.70, 0.30))


def _obstacles(canvas: Canvas, rng: np.random.Generator) -> None:
    width_m, height_m = canvas.cols * CELL_M, canvas.rows * CELL_M
    for fx, fy in OBSTACLE_PILLARS:
        canvas.disc(round(fx * width_m, 2), round(fy * height_m, 2), OBSTACLE_RADIUS_M)
    for fx, fy in OBSTACLE_GOALS:
        canvas.grid[canvas.cell(fx, fy)] = "G"
    canvas.grid[canvas.cell(0.15, 0.5)] = ">"


PASSAGE_CELLS = 3  # 0.75 m: the 0.4 m robot fits with under 0.2 m each side, as in Figure 26b


def _narrow(canvas: Canvas, rng: np.random.Generator) -> None:
    """Two rooms joined by a narrow passage through a thick wall, with a goal inside it."""
    left, right = round(0.45 * canvas.cols), round(0.7 * canvas.cols)
    top = canvas.rows // 2 - PASSAGE_CELLS // 2
    canvas.grid[:, left:right] = "#"
    canvas.grid[top : top + PASSAGE_CELLS, left:right] = "."
    canvas.grid[canvas.rows // 2, (left + right) // 2] = "G"
    canvas.grid[canvas.rows // 2, round(0.15 * canvas.cols)] = ">"


LAB_GAP = 3  # cells (0.75 m) kept free between pieces of furniture: the robot can always pass
LAB_TRIES = 50  # positions tried for one piece before leaving it out
LAB_AREA_M2 = 48.0  # furniture counts below are for 8 m x 6 m and scale with the floor area
STAND_RADIUS_M = 0.05  # lamp and tripod stands: thin poles


def _lab(canvas: Canvas, rng: np.random.Generator) -> None:
    """A cluttered lab: benches along the walls, desks with thin overhanging table tops,
    pillars and thin stands, with room for the robot to pass between any two of them."""
    floor = _LabFloor(canvas, rng, np.zeros(canvas.grid.shape, dtype=bool))
    scale = canvas.rows * canvas.cols * CELL_M**2 / LAB_AREA_M2

    def count(n: int) -> int:
        return max(1, round(n * scale))

    for _ in range(count(3)):  # benches, 0.5-0.75 m deep, 1.5-2.25 m long, along a wall
        side = int(rng.integers(4))
        bench = np.ones((int(rng.integers(2, 4)), int(rng.integers(6, 10))), dtype=bool)
        floor.build(bench if side < 2 else bench.T, side)
    for _ in range(count(2)):  # desks 0.75 m deep with a one-cell table top sticking out
        length, overhang = int(rng.integers(5, 8)), int(rng.integers(2, 5))
        desk = np.zeros((3, length + overhang), dtype=bool)
        desk[:, :length] = True
        desk[0, length:] = True
        desk = np.rot90(desk, int(rng.integers(4)))
        floor.build(np.fliplr(desk) if rng.integers(2) else desk, None)
    # Pillars (a disc of radius <= 1 cell on the middle cell of its footprint, so 2 cells of
    # gap still leave over 0.6 m of floor), then thin stands that sonar barely sees.
    for radius_m in rng.uniform(0.15, 0.25, count(3)).round(2):
        spot = floor.place(np.ones((3, 3), dtype=bool), None, gap=2)
        if spot is not None:
            canvas.disc(*canvas.centre_m(spot[0] + 1, spot[1] + 1), float(radius_m))
    for _ in range(count(2)):
        spot = floor.place(np.ones((1, 1), dtype=bool), None)
        if spot is not None:
            canvas.disc(*canvas.centre_m(*spot), STAND_RADIUS_M)
    floor.place_start()


@dataclass(frozen=True, slots=True)
class _LabFloor:
    """The lab's floor as its furniture is placed, each piece `gap` cells from every other."""

    canvas: Canvas
    rng: np.random.Generator
    taken: np.ndarray  # (rows, cols) cells claimed by furniture

    def place(
        self, footprint: np.ndarray, wall_side: int | None, gap: int = LAB_GAP
    ) -> tuple[int, int] | None:
        """Top-left cell for a footprint, against a wall (0 top, 1 bottom, 2 left, 3 right)
        or free-standing, `gap` cells from everything else; None if no spot was found."""
        h, w = footprint.shape
        rows, cols = self.canvas.rows, self.canvas.cols
        margin = 1 if wall_side is not None else 1 + gap
        if rows - margin - h < margin or cols - margin - w < margin:
            return None
        for _ in range(LAB_TRIES):
            r = int(self.rng.integers(margin, rows - margin - h + 1))
            c = int(self.rng.integers(margin, cols - margin - w + 1))
            if wall_side == 0:
                r = 1
            elif wall_side == 1:
                r = rows - 1 - h
            elif wall_side == 2:
                c = 1
            elif wall_side == 3:
                c = cols - 1 - w
            near = self.taken[max(r - gap, 0) : r + h + gap, max(c - gap, 0) : c + w + gap]
            if not near.any():
                self.taken[r : r + h, c : c + w] = True
                return r, c
        return None

    def build(self, footprint: np.ndarray, wall_side: int | None) -> None:
        """Wall in a footprint where place() finds it room, if it does."""
        spot = self.place(footprint, wall_side)
        if spot is not None:
            r, c = spot
            h, w = footprint.shape
            self.canvas.grid[r : r + h, c : c + w][footprint] = "#"

    def place_start(self) -> None:
        """The robot's start, facing a random way, on a cell with 0.5 m of floor all round (none
        if no cell has)."""
        blocked = np.pad(self.taken | (self.canvas.grid == "#"), 2, constant_values=True)
        windows = np.lib.stride_tricks.sliding_window_view(blocked, (5, 5))  # (rows, cols, 5, 5)
        clear = np.argwhere(~windows.any(axis=(2, 3)))  # cells with 0.5 m of floor all round
        if len(clear):
            r, c = clear[self.rng.integers(len(clear))]
            self.canvas.grid[r, c] = ">^<v"[int(self.rng.integers(4))]


@dataclass(frozen=True, slots=True)
class Kind:
    """A generator of worlds: what it makes, its sizes, and the function that lays it out."""

    about: str
    default_size_m: tuple[float, float]
    min_size_m: tuple[float, float]
    layout: Callable[[Canvas, np.random.Generator], object]  # returns its record, if it keeps one
    seeded: bool = False  # only seeded kinds draw from the generator


KINDS: dict[str, Kind] = {
    "square": Kind("an empty square arena", (4.0, 4.0), (1.25, 1.25), _square),
    "circle": Kind("a circular wall in a square room", (5.0, 5.0), (2.0, 2.0), _circle),
    "corridor": Kind("a closed-loop corridor 1.25 m wide", (6.0, 4.5), (3.5, 3.5), _corridor),
    "obstacles": Kind("pillars between the start and 4 goals", (7.0, 5.0), (3.5, 3.0), _obstacles),
    "narrow": Kind("a goal inside a 0.75 m passage", (6.0, 4.0), (4.0, 3.0), _narrow),
    "lab": Kind(
        "benches, desks with thin table tops, pillars, stands", (8.0, 6.0), (5.0, 4.0), _lab, True
    ),
    "rooms": Kind(
        "rooms, doorways and corridors, furnished, with a reachable goal",
        ROOMS_DEFAULT_SIZE_M,
        ROOMS_MIN_SIZE_M,
        layout_rooms,
        True,
    ),
}


@dataclass(frozen=True, slots=True)
class Materials:
    """Rooms whose walls are rough: each room of a rooms world is, with chance `share`, with
    `roughness`; the others keep smooth walls."""

    share: float = 0.0
    roughness: float = DEFAULT_ROUGHNESS

    def __post_init__(self) -> None:
        if not (math.isfinite(self.share) and 0.0 <= self.share <= 1.0):
            raise BadInput(f"--rough {self.share:g} must be a share of the rooms from 0 to 1")
        if not (math.isfinite(self.roughness) and 0.0 < self.roughness <= 1.0):
            raise BadInput(f"--roughness {self.roughness:g} must be more than 0 and at most 1")


SMOOTH = Materials()


def generate_world(
    kind: str,
    width_m: float | None,
    height_m: float | None,
    seed: int,
    materials: Materials = SMOOTH,
) -> str:
    """The text of a world file of KIND (sizes in metres, rounded to whole cells), its walls
    of the materials given (rooms worlds only)."""
    return draw_world(kind, width_m, height_m, seed, materials)[0]


def draw_world(
    kind: str,
    width_m: float | None,
    height_m: float | None,
    seed: int,
    materials: Materials = SMOOTH,
) -> tuple[str, object]:
    """The text of a world file of KIND, and the layout's own record of what it drew (None
    for kinds that keep none): a rooms world's RoomsPlan."""
    if kind not in KINDS:
        raise BadInput(f"unknown world kind {kind!r} (choose from {', '.join(KINDS)})")
    if materials != SMOOTH and kind != "rooms":
        raise BadInput(
            f"--rough is for rooms worlds; give a {kind} world's walls a `roughness:` line"
        )
    spec = KINDS[kind]
    width_m = spec.default_size_m[0] if width_m is None else width_m
    height_m = spec.default_size_m[1] if height_m is None else height_m
    min_w, min_h = spec.min_size_m
    if not (min_w <= width_m <= MAX_SIZE_M and min_h <= height_m <= MAX_SIZE_M):
        raise BadInput(
            f"size {width_m:g} x {height_m:g} m: a {kind} world is from "
            f"{min_w:g} x {min_h:g} m to {MAX_SIZE_M:g} x {MAX_SIZE_M:g} m"
        )
    cols, rows = round(width_m / CELL_M), round(height_m / CELL_M)
    command = f"tvl world new {kind} --size {cols * CELL_M:g} {rows * CELL_M:g}"
    command += f" --seed {seed}" if spec.seeded else ""
    name = generated_name(kind, cols, rows, seed, materials)
    rng = np.random.default_rng(seed)
    error = ""
    for _ in range(ATTEMPTS if spec.seeded else 1):
        canvas = Canvas(cols, rows)
        try:
            record = spec.layout(canvas, rng)
            if isinstance(record, RoomsPlan) and materials != SMOOTH:
                _lay_materials(canvas, record, materials, seed)
            text = canvas.text(kind, spec.about, command + _materials_options(materials), name)
            parse_world(text, f"<{kind}>")
        except WorldMapError as problem:  # a layout may box its start or goal in: draw again
            error = str(problem)
            continue
        return text, record
    raise BadInput(f"cannot make a {kind} world of {width_m:g} x {height_m:g} m ({error})")


def generated_name(kind: str, cols: int, rows: int, seed: int, materials: Materials) -> str:
    """A generated world's name: its kind, then what sets it apart from others of that kind,
    a size other than the kind's default (metres), the seed of a seeded kind, rough rooms
    (`rooms-s7`, `square-6x6`, `rooms-s7-rough0.5`). A sweep knows a world by its name, so
    worlds generated apart stay apart in one grid. Worlds of an older tvl, named for their
    kind alone, still load under that name."""
    spec = KINDS[kind]
    default_cells = tuple(round(size_m / CELL_M) for size_m in spec.default_size_m)
    name = kind
    if (cols, rows) != default_cells:
        name += f"-{cols * CELL_M:g}x{rows * CELL_M:g}"
    if spec.seeded:
        name += f"-s{seed}"
    if materials != SMOOTH:
        name += f"-rough{materials.share:g}"
        if materials.roughness != DEFAULT_ROUGHNESS:
            name += f"-roughness{materials.roughness:g}"
    return name


def _lay_materials(canvas: Canvas, plan: RoomsPlan, materials: Materials, seed: int) -> None:
    """A `rough:` line for each room drawn rough. The draws come from a generator of their
    own, so that a seed lays out the same rooms whatever their walls are made of."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(1,)))
    for x0, y0, x1, y1 in plan.room_extents_m:
        if rng.random() < materials.share:
            canvas.header.append(f"rough: {materials.roughness:g} {x0:g} {y0:g} {x1:g} {y1:g}")


def _materials_options(materials: Materials) -> str:
    if materials == SMOOTH:
        return ""
    return f" --rough {materials.share:g} --roughness {materials.roughness:g}"


def bundled_world_path(name: str) -> Path:
    """The world file `name` shipped inside the package (works after a non-editable install)."""
    path = BUNDLED_DIR / f"{name}.txt"
    if not path.is_file():
        raise BadInput(f"no bundled world {name!r} (bundled: {', '.join(KINDS)})")
    return path
