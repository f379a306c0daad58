"""WorldMap -> pymunk space for the physics, and numpy arrays of the same geometry for sensing.

The physics walls are thick so a body pushed into them can never tunnel through, yet contact
happens exactly where the map's geometry says: every obstacle is inflated by a skin and the
robot's collision disc is shrunk by the same skin (their Minkowski sum is unchanged), so a
wall segment of radius `skin` stops the body when its true edge reaches the wall's line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import pymunk

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.wall_grid import WallGrid, wall_grid
from tvl_cli.sim.worldmap import WorldMap

# A quarter of the body radius: walls become solid strips (10 cm wide for the default robot)
# while the robot keeps most of its radius as its collision disc.
SKIN_FRACTION = 0.25
# Penetration the solver leaves alone; the default (0.1) assumes pixels, not metres.
COLLISION_SLOP_M = 0.0005
# Fraction of an overlap left uncorrected after one second: about a third of the overlap is
# removed each 25 ms sub-step, so a contact settles within a few sub-steps.
COLLISION_BIAS = 1e-8
# Rings are built from chords; a chord may sag this much inside the true circle.
RING_MAX_SAG_M = 0.001
# Segment endpoints closer than this are the same wall corner.
CORNER_TOLERANCE_M = 1e-6
# Two walls meeting at a smaller angle than this (as its sine) are one straight wall.
_COLLINEAR_SINE = 1e-9
_ROBOT_MASS_KG = 10.0
# Every robot's disc is in this shape group (pymunk never collides shapes of one group);
# obstacles are in none (group 0).
ROBOT_GROUP = 1


@dataclass(frozen=True, slots=True, eq=False)
class StaticGeometry:
    """A world's obstacles as flat numpy arrays, built once for ray casting and clearances."""

    segments: np.ndarray  # (n, 4) x1, y1, x2, y2 metres
    discs: np.ndarray  # (m, 3) x, y, r metres; solid
    rings: np.ndarray  # (k, 3) x, y, r metres; free inside
    # Derived once for the vectorised queries (row 0 x, row 1 y):
    seg_start: np.ndarray  # (2, n) metres
    seg_delta: np.ndarray  # (2, n) end - start, metres
    seg_len: np.ndarray  # (n,) metres
    seg_normal: np.ndarray  # (2, n) (dy, -dx): a row vector D @ seg_normal is cross(D, delta)
    seg_moment: np.ndarray  # (n,) cross(start, delta), square metres
    seg_ends: np.ndarray  # (n, 2, 2) [start, end] x, y metres: where corners can be
    max_disc_radius_m: float  # 0 without discs
    roughness: float  # the world's, 0 to 1: how much sound its walls scatter diffusely
    seg_roughness: np.ndarray  # (n,) each wall's own (a `rough:` rectangle's, or the world's)
    grid: WallGrid  # the segments by cell, for the rays and points that ask only the near ones
    ring_roughness: np.ndarray = field(init=False)  # (k,) each ring wall's: the world's
    _corners: np.ndarray | None = field(default=None, init=False, repr=False)  # corner_sides

    def __post_init__(self) -> None:
        object.__setattr__(self, "ring_roughness", np.full(len(self.rings), self.roughness))

    @property
    def corner_sides(self) -> np.ndarray:
        """(n, 2) for the wall meeting each segment at its [start, end]: the side of this
        segment's line it lies on, as the sign of cross(end - start, other wall's direction);
        0 when no wall meets it there or the two are collinear. Seen from that side the
        corner is concave.

        Found when first asked: the sonar's echo rules read it, the clearance queries never,
        and a geometry made afresh every step of remembered patches (the ring DWA's) is
        only asked for clearances."""
        corners = self._corners
        if corners is None:
            corners = _corner_sides(self.segments)
            object.__setattr__(self, "_corners", corners)
        return corners

    def with_roughness(self, roughness: float) -> StaticGeometry:
        """The same obstacles with every wall, ring walls too, this rough."""
        return replace(
            self, roughness=roughness, seg_roughness=np.full(len(self.seg_len), roughness)
        )

    def element_of(self, kind: str, index: np.ndarray | int) -> np.ndarray:
        """Every obstacle of the world numbered once: its segments first, in the world's
        order, then its discs, then its ring walls. `kind` is "segment", "disc" or "ring"."""
        offset = {"segment": 0, "disc": len(self.seg_len)}.get(kind)
        if offset is None:
            offset = len(self.seg_len) + len(self.discs)
        return np.asarray(index) + offset

    def element_kind(self, element: int) -> str:
        """ "segment", "disc" or "ring": what element_of numbered `element`."""
        if element < len(self.seg_len):
            return "segment"
        return "disc" if element < len(self.seg_len) + len(self.discs) else "ring"


def static_geometry(world: WorldMap) -> StaticGeometry:
    """The arrays the sonar and clearance queries read; computed once per world."""
    return geometry_of(
        world.segments, world.discs, world.rings, world.roughness, world.segment_roughness
    )


def geometry_of(
    segments: object,
    discs: object = (),
    rings: object = (),
    roughness: float = 0.0,
    segment_roughness: object = (),
) -> StaticGeometry:
    """Obstacles as the queries read them: segments (n, 4) x1, y1, x2, y2, discs (m, 3) and
    ring walls (k, 3) x, y, r, metres (anything numpy reads as such), with the world's
    roughness and each segment's own (none given: the world's for all)."""
    segments = np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    discs = np.asarray(discs, dtype=np.float64).reshape(-1, 3)
    start = np.ascontiguousarray(segments[:, :2].T)  # (2, n) metres
    delta = np.ascontiguousarray((segments[:, 2:] - segments[:, :2]).T)  # (2, n) metres
    own = np.asarray(segment_roughness, dtype=np.float64)
    normal = np.stack([delta[1], -delta[0]])
    return StaticGeometry(
        segments=segments,
        discs=discs,
        rings=np.asarray(rings, dtype=np.float64).reshape(-1, 3),
        seg_start=start,
        seg_delta=delta,
        seg_len=np.hypot(delta[0], delta[1]),
        seg_normal=normal,
        seg_moment=start[0] * delta[1] - start[1] * delta[0],
        seg_ends=segments.reshape(-1, 2, 2),
        max_disc_radius_m=float(discs[:, 2].max(initial=0.0)),
        roughness=roughness,
        seg_roughness=own if len(own) else np.full(len(segments), roughness),
        grid=wall_grid(segments, normal, start),
    )


def _corner_sides(segments: np.ndarray) -> np.ndarray:
    """For each segment's start and end, the side of its line where another wall leaves it.

    A map's outline only meets itself at endpoints; where more than two walls meet (two wall
    cells touching diagonally) the first non-collinear one (lowest numbered endpoint) is
    taken.
    """
    n = len(segments)
    ends = np.concatenate([segments[:, :2], segments[:, 2:]])  # (2n, 2) starts, then ends
    far = np.concatenate([segments[:, 2:], segments[:, :2]])  # (2n, 2) the other end of each
    owner = np.tile(np.arange(n), 2)  # (2n,) segment of each endpoint
    delta = segments[:, 2:] - segments[:, :2]  # (n, 2) start -> end
    sides = np.zeros(2 * n)  # (2n,) -1, 0 or +1 for each endpoint
    here, there = _meeting_ends(ends)
    arm = far[there] - ends[there]  # the other wall, leaving the corner
    own = delta[owner[here]]
    cross = own[:, 0] * arm[:, 1] - own[:, 1] * arm[:, 0]
    turning = np.abs(cross) > _COLLINEAR_SINE * np.hypot(own[:, 0], own[:, 1]) * np.hypot(
        arm[:, 0], arm[:, 1]
    )
    keep = turning & (owner[here] != owner[there])
    here, there, cross = here[keep], there[keep], cross[keep]
    order = np.lexsort((there, here))  # by endpoint, then by the other's number
    here, cross = here[order], cross[order]
    first = np.unique(here, return_index=True)[1]  # each endpoint's lowest numbered other
    sides[here[first]] = np.sign(cross[first])
    return np.ascontiguousarray(sides.reshape(2, n).T)  # (n, 2) [start, end]


def _meeting_ends(ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every ordered pair (here, there) of distinct points (k, 2) within CORNER_TOLERANCE_M
    of each other on both axes, in time that grows with the points, not their square.

    Each point falls in a square bucket of the tolerance's side, numbered as a complex
    number (column + row i, exact below 2**53), so that sorting them sorts buckets by
    column, then row; a point's partners lie in its own bucket or the eight round it, each
    found by a binary search among the sorted buckets."""
    bucket = np.floor(ends / CORNER_TOLERANCE_M)  # (k, 2)
    keys = bucket[:, 0] + 1j * bucket[:, 1]  # (k,)
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]
    here_parts, there_parts = [], []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            target = keys + (dx + 1j * dy)
            low = np.searchsorted(sorted_keys, target, side="left")
            high = np.searchsorted(sorted_keys, target, side="right")
            counts = high - low
            here = np.repeat(np.arange(len(ends)), counts)
            offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
            here_parts.append(here)
            there_parts.append(order[np.repeat(low, counts) + offsets])
    here, there = np.concatenate(here_parts), np.concatenate(there_parts)
    near = np.all(np.abs(ends[here] - ends[there]) <= CORNER_TOLERANCE_M, axis=1)
    near &= here != there
    return here[near], there[near]


def clearances_m(
    geometry: StaticGeometry, points: np.ndarray, body_radius_m: float, limit_m: float = math.inf
) -> np.ndarray:
    """(p,) metres from the edge of a body centred at each of points (p, 2) to the nearest
    obstacle; 0 where the body touches or overlaps one, inf where none lies within limit_m
    of the centre (a world with no obstacles)."""
    return _clearances(geometry, points, body_radius_m, limit_m)[0]


def nearest_element(geometry: StaticGeometry, x: float, y: float) -> tuple[int, float]:
    """The obstacle nearest (x, y), as StaticGeometry.element_of numbers it, and its distance
    in metres; (-1, inf) in a world with none."""
    gap, element = _clearances(geometry, np.array([[x, y]]), 0.0, math.inf)
    return int(element[0]), float(gap[0])


def _clearances(
    geometry: StaticGeometry, points: np.ndarray, body_radius_m: float, limit_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """clearances_m, and the nearest obstacle to each point (p,) as element_of numbers it."""
    from tvl_cli.sim.clearance_kernel import clearances  # compiled: loaded on first use

    g = geometry
    points = np.ascontiguousarray(points, dtype=np.float64)
    found = np.empty(len(points))  # (p,) metres
    nearest = np.empty(len(points), dtype=np.int64)  # (p,) obstacles
    clearances(
        points, g.seg_start, g.seg_delta, g.seg_len, g.grid.kernel_input, g.discs, g.rings,
        body_radius_m, limit_m, found, nearest,
    )  # fmt: skip
    return found, nearest


def clearance_m(geometry: StaticGeometry, x: float, y: float, body_radius_m: float) -> float:
    """Metres from the edge of a body centred at (x, y) to the nearest obstacle (0 if touching)."""
    return float(clearances_m(geometry, np.array([[x, y]]), body_radius_m)[0])


def skin_m(robot: RobotConfig) -> float:
    """How much obstacles are inflated, and the robot's collision disc shrunk, in the physics."""
    return SKIN_FRACTION * robot.radius_m


def build_space(world: WorldMap, robot: RobotConfig) -> tuple[pymunk.Space, pymunk.Body]:
    """A space holding the world's static obstacles and the robot's disc at the start pose."""
    space = static_space(world, robot)
    return space, add_robot_body(space, robot, world.start)


def static_space(world: WorldMap, robot: RobotConfig) -> pymunk.Space:
    """A space holding the world's static obstacles, inflated by the robot's skin.

    Shapes have no friction: the robot's velocity is set by its wheels every sub-step and a
    contact only removes the part of it that goes into an obstacle.
    """
    skin = skin_m(robot)
    space = pymunk.Space()
    space.collision_slop = COLLISION_SLOP_M
    space.collision_bias = COLLISION_BIAS
    static: list[pymunk.Shape] = [
        pymunk.Segment(space.static_body, (x1, y1), (x2, y2), skin)
        for x1, y1, x2, y2 in world.segments
    ]
    static += [pymunk.Circle(space.static_body, r + skin, (x, y)) for x, y, r in world.discs]
    for x, y, r in world.rings:
        points = _ring_points(x, y, r)
        static += [
            pymunk.Segment(space.static_body, a, b, skin)
            for a, b in zip(points, points[1:] + points[:1], strict=True)
        ]
    # pymunk's shapes have no friction unless given one, which these never are.
    space.add(*static)
    return space


def add_robot_body(
    space: pymunk.Space, robot: RobotConfig, pose: tuple[float, float, float]
) -> pymunk.Body:
    """A robot's disc added to the space at rest at a pose. Robot discs share a group, so
    that robots in one space never touch one another."""
    body_radius = robot.radius_m - skin_m(robot)
    body = pymunk.Body(_ROBOT_MASS_KG, pymunk.moment_for_circle(_ROBOT_MASS_KG, 0, body_radius))
    disc = pymunk.Circle(body, body_radius)
    disc.friction = 0.0
    disc.filter = pymunk.ShapeFilter(group=ROBOT_GROUP)
    x, y, theta = pose
    body.position = (x, y)
    body.angle = theta
    space.add(body, disc)
    return body


def _ring_points(x: float, y: float, r: float) -> list[tuple[float, float]]:
    """Points on a circle close enough that no chord sags more than RING_MAX_SAG_M inside it."""
    half_angle = math.acos(max(1.0 - RING_MAX_SAG_M / r, -1.0))
    count = max(16, math.ceil(math.pi / half_angle))
    angles = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)  # (count,) radians
    return [(x + r * math.cos(a), y + r * math.sin(a)) for a in angles]
