"""The header lines of a world file (`key: value`), checked as they are read.

Besides the name, the cell size, pillars, ring walls and goals, a header may place the map in
the frame of the map it was made from (`origin: x y`, the grid's bottom-left corner; every
coordinate of the world is in that frame), start the robot anywhere facing any way (`start:
x y heading`, degrees, instead of a start in the grid) and draw straight walls at any angle:
`wall: x1 y1 x2 y2 [thickness]`. A wall with no thickness is a thin edge
(a table top seen from the side), solid and echoing from both faces; a thick one is a solid
rectangle centred on the line.

Walls are as rough as the `roughness:` line says (smooth without one), except those within a
`rough: R x1 y1 x2 y2` rectangle, whose walls have roughness R: rooms of painted plaster
beside rooms of brick or curtains. A wall belongs to the last rectangle holding its middle.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from tvl_cli.core.errors import BadInput

Segment = tuple[float, float, float, float]  # x1, y1, x2, y2 in metres
Circle = tuple[float, float, float]  # x, y, radius in metres


class WorldMapError(BadInput):
    """A world file that cannot be read or does not describe a closed world with one start."""


FORMAT_VERSION = 1
DEFAULT_CELL_M = 0.25
# Cells from a centimetre (finer than any sonar can tell) to 10 m (a hall per character).
MIN_CELL_M, MAX_CELL_M = 0.01, 10.0
# As fine as the finest map: a shorter wall is a slip of the pen, not a shape a sonar could
# tell from a point.
MIN_WALL_M = MIN_CELL_M
# A map's frame may lie this far from its corner (metres): a UTM northing fits.
MAX_ORIGIN_M = 1e7
# A start's heading, degrees: a turn either way.
MAX_HEADING_DEG = 360.0
HEADER_KEYS = (
    "version", "name", "cell", "origin", "start", "roughness", "rough", "disc", "ring", "goal",
    "wall",
)  # fmt: skip
# Keys a header gives at most once.
ONE_OFF_KEYS = ("version", "name", "cell", "origin", "start", "roughness")
HEADER_LINE = re.compile(r"\s*([A-Za-z_]\w*)\s*:\s*(.*?)\s*")
_NUMBERS = {  # key -> (how many numbers, what they are); the last must be positive but for goals
    "cell": (1, f"a size in metres from {MIN_CELL_M:g} to {MAX_CELL_M:g}"),
    "origin": (2, f"x y in metres, each from {-MAX_ORIGIN_M:g} to {MAX_ORIGIN_M:g}"),
    "start": (
        3,
        f"x y heading: metres, then degrees from {-MAX_HEADING_DEG:g} to {MAX_HEADING_DEG:g}",
    ),
    "roughness": (1, "a fraction from 0 (smooth) to 1"),
    "rough": (5, "R x1 y1 x2 y2: a roughness from 0 to 1, then a rectangle's corners in metres"),
    "disc": (3, "x y r in metres, r > 0"),
    "ring": (3, f"x y r in metres, r >= {MIN_WALL_M:g}"),
    "goal": (2, "x y in metres"),
}
_WALL_USAGE = (
    f"x1 y1 x2 y2 [thickness] in metres, ends at least {MIN_WALL_M:g} m apart, thickness >= 0"
)


@dataclass(frozen=True, slots=True)
class Wall:
    """A straight wall from a header line, and where it was written."""

    x1: float
    y1: float
    x2: float
    y2: float
    thickness_m: float
    where: str  # "file:line:column" of its numbers

    def outline(self) -> tuple[Segment, ...]:
        """The segments the robot meets: the line itself when thin, else the four sides of
        the rectangle, counter-clockwise: the solid on their left, as on the map's outline."""
        if self.thickness_m == 0.0:
            return ((self.x1, self.y1, self.x2, self.y2),)
        length = math.hypot(self.x2 - self.x1, self.y2 - self.y1)
        half = self.thickness_m / 2.0
        nx, ny = -(self.y2 - self.y1) / length * half, (self.x2 - self.x1) / length * half
        corners = [
            (self.x1 - nx, self.y1 - ny),
            (self.x2 - nx, self.y2 - ny),
            (self.x2 + nx, self.y2 + ny),
            (self.x1 + nx, self.y1 + ny),
        ]
        return tuple((*a, *b) for a, b in zip(corners, corners[1:] + corners[:1], strict=True))

    def distance_m(self, x: float, y: float) -> float:
        """Metres from a point to the wall's solid (0 inside it)."""
        dx, dy = self.x2 - self.x1, self.y2 - self.y1
        along = ((x - self.x1) * dx + (y - self.y1) * dy) / (dx * dx + dy * dy)
        along = min(max(along, 0.0), 1.0)
        to_line = math.hypot(x - self.x1 - along * dx, y - self.y1 - along * dy)
        return max(to_line - self.thickness_m / 2.0, 0.0)


@dataclass(frozen=True, slots=True)
class RoughRegion:
    """The walls within a rectangle, and their roughness; where it was written."""

    roughness: float
    x_min: float
    y_min: float
    x_max: float
    y_max: float
    where: str

    def holds(self, x: float, y: float) -> bool:
        return self.x_min <= x <= self.x_max and self.y_min <= y <= self.y_max


@dataclass(slots=True)
class Header:
    """Header values as read, with the line of each one-off key to name a duplicate; `where`
    is the "file:line:column" of a value, for the checks that need the whole map."""

    seen: dict[str, int] = field(default_factory=dict)
    name: str | None = None
    cell_m: float = DEFAULT_CELL_M
    origin_m: tuple[float, float] = (0.0, 0.0)  # the grid's bottom-left corner
    start: tuple[float, float, float, str] | None = None  # x, y, heading (rad), where
    roughness: float = 0.0  # smooth walls: only near-normal echoes (paper Fig. 12)
    discs: list[tuple[float, float, float, str]] = field(default_factory=list)  # x, y, r, where
    rings: list[tuple[float, float, float, str]] = field(default_factory=list)  # x, y, r, where
    goals: list[tuple[float, float, str]] = field(default_factory=list)  # x, y, where
    walls: list[Wall] = field(default_factory=list)
    rough: list[RoughRegion] = field(default_factory=list)

    def roughness_at(self, x: float, y: float) -> float:
        """The roughness of a wall whose middle is at (x, y)."""
        holding = [region for region in self.rough if region.holds(x, y)]
        return holding[-1].roughness if holding else self.roughness


def read_header(header: Header, match: re.Match[str], where: str, number: int) -> None:
    """Add one `key: value` line (matched by HEADER_LINE) at `where` ("file:line")."""
    key, value = match.group(1), match.group(2)
    value_at = f"{where}:{match.start(2) + 1}"
    if key not in HEADER_KEYS:
        raise WorldMapError(
            f"{where}:{match.start(1) + 1}: unknown header key {key!r} "
            f"(expected one of {' '.join(HEADER_KEYS)})"
        )
    if key in ONE_OFF_KEYS:
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
    elif key == "wall":
        header.walls.append(_wall(value, value_at))
    else:
        numbers = _numbers(key, value, value_at)
        if key == "cell":
            header.cell_m = numbers[0]
        elif key == "origin":
            header.origin_m = (numbers[0], numbers[1])
        elif key == "start":
            header.start = (numbers[0], numbers[1], math.radians(numbers[2]), value_at)
        elif key == "roughness":
            header.roughness = numbers[0]
        elif key == "goal":
            header.goals.append((numbers[0], numbers[1], value_at))
        elif key == "rough":
            r, x1, y1, x2, y2 = numbers
            xs, ys = sorted((x1, x2)), sorted((y1, y2))
            header.rough.append(RoughRegion(r, xs[0], ys[0], xs[1], ys[1], value_at))
        elif key == "disc":
            header.discs.append((numbers[0], numbers[1], numbers[2], value_at))
        else:
            header.rings.append((numbers[0], numbers[1], numbers[2], value_at))


def _floats(value: str) -> tuple[float, ...]:
    try:
        numbers = tuple(float(part) for part in value.split())
    except ValueError:
        return ()
    return numbers if all(math.isfinite(n) for n in numbers) else ()


def _numbers(key: str, value: str, value_at: str) -> tuple[float, ...]:
    """The numbers of a `cell`, `origin`, `start`, `roughness`, `rough`, `disc`, `ring` or
    `goal` header, each in its range; sizes must be positive."""
    wanted, usage = _NUMBERS[key]
    numbers = _floats(value)
    if (
        len(numbers) != wanted
        or (key in ("cell", "disc", "ring") and numbers[-1] <= 0)
        or (key in ("roughness", "rough") and not 0 <= numbers[0] <= 1)
        or (key == "rough" and (numbers[1] == numbers[3] or numbers[2] == numbers[4]))
        # A ring is a wall bent round: no shorter across than the shortest straight wall.
        or (key == "ring" and numbers[-1] < MIN_WALL_M)
        or (key == "cell" and not MIN_CELL_M <= numbers[0] <= MAX_CELL_M)
        or (key == "origin" and not all(abs(n) <= MAX_ORIGIN_M for n in numbers))
        or (key == "start" and not abs(numbers[2]) <= MAX_HEADING_DEG)
    ):
        raise WorldMapError(f"{value_at}: bad value for {key!r}: {value!r} (expected {usage})")
    return numbers


def _wall(value: str, value_at: str) -> Wall:
    numbers = _floats(value)
    if len(numbers) == 4:
        numbers += (0.0,)
    if (
        len(numbers) != 5
        or numbers[4] < 0
        or math.hypot(numbers[2] - numbers[0], numbers[3] - numbers[1]) < MIN_WALL_M
    ):
        raise WorldMapError(f"{value_at}: bad value for 'wall': {value!r} (expected {_WALL_USAGE})")
    x1, y1, x2, y2, thickness = numbers
    return Wall(x1, y1, x2, y2, thickness, value_at)
