"""Static geometry, clearances and the pymunk space built from a WorldMap."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import (
    CORNER_TOLERANCE_M,
    RING_MAX_SAG_M,
    StaticGeometry,
    build_space,
    clearance_m,
    clearances_m,
    skin_m,
    static_geometry,
)
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import Circle, Segment, WorldMap, parse_world


def room(
    width_m: float,
    height_m: float,
    *,
    start: tuple[float, float, float] | None = None,
    walls: tuple[Segment, ...] = (),
    discs: tuple[Circle, ...] = (),
    rings: tuple[Circle, ...] = (),
    outline: bool = True,
) -> WorldMap:
    """A world: a rectangular room (its 4 wall segments, unless outline is False) and extras."""
    w, h = width_m, height_m
    box: tuple[Segment, ...] = ((0, 0, w, 0), (w, 0, w, h), (w, h, 0, h), (0, h, 0, 0))
    return WorldMap(
        name="room",
        cell_m=0.25,
        width_m=w,
        height_m=h,
        segments=(box if outline else ()) + walls,
        discs=discs,
        rings=rings,
        start=start if start is not None else (w / 2, h / 2, 0.0),
        goals=(),
        text="",
    )


def square_block(x0: float, y0: float, size: float) -> tuple[Segment, ...]:
    """The 4 outline segments of a solid square obstacle."""
    x1, y1 = x0 + size, y0 + size
    return ((x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0))


def test_geometry_arrays_have_documented_shapes() -> None:
    world = room(4, 3, discs=((1, 1, 0.2),), rings=((2, 1.5, 1.0),))
    geometry = static_geometry(world)
    assert geometry.segments.shape == (4, 4)
    assert geometry.discs.shape == (1, 3)
    assert geometry.rings.shape == (1, 3)
    assert geometry.seg_start.shape == (2, 4)
    np.testing.assert_allclose(geometry.seg_len, [4, 3, 4, 3])


def free_side(geometry: StaticGeometry, i: int, centre: tuple[float, float], inside: bool) -> float:
    """The side (sign of the cross product) of segment i facing away from, or towards, centre."""
    x1, y1, x2, y2 = geometry.segments[i]
    middle = np.array([(x1 + x2) / 2, (y1 + y2) / 2])
    point = middle + (1 if inside else -1) * 0.1 * (np.array(centre) - middle)
    return float(np.sign((x2 - x1) * (point[1] - y1) - (y2 - y1) * (point[0] - x1)))


def test_room_corners_open_towards_the_free_inside() -> None:
    geometry = static_geometry(room(4, 3))
    for i in range(4):
        side = free_side(geometry, i, (2.0, 1.5), inside=True)
        assert geometry.corner_sides[i, 0] == side
        assert geometry.corner_sides[i, 1] == side


def test_block_corners_open_away_from_the_free_outside() -> None:
    geometry = static_geometry(room(4, 4, walls=square_block(1, 1, 1), outline=False))
    for i in range(4):
        side = free_side(geometry, i, (1.5, 1.5), inside=False)
        assert geometry.corner_sides[i, 0] == -side
        assert geometry.corner_sides[i, 1] == -side


def test_free_segment_ends_have_no_corner() -> None:
    geometry = static_geometry(room(4, 3, walls=((1, 1, 3, 1),), outline=False))
    assert np.all(geometry.corner_sides == 0)


def test_clearance_is_distance_from_body_edge_to_nearest_wall() -> None:
    geometry = static_geometry(room(4, 3))
    assert clearance_m(geometry, 1.0, 2.0, 0.2) == pytest.approx(0.8)
    assert clearance_m(geometry, 3.7, 0.5, 0.2) == pytest.approx(0.1)


def test_clearance_measures_to_the_nearest_point_of_a_segment() -> None:
    geometry = static_geometry(room(4, 4, walls=((1, 1, 2, 1),), outline=False))
    # Beyond the segment's end the nearest point is the end itself.
    assert clearance_m(geometry, 3.0, 2.0, 0.2) == pytest.approx(math.hypot(1, 1) - 0.2)


def test_clearance_sees_discs_and_ring_walls() -> None:
    geometry = static_geometry(
        room(10, 10, discs=((3, 5, 0.5),), rings=((5, 5, 4.0),), outline=False)
    )
    assert clearance_m(geometry, 4.0, 5.0, 0.2) == pytest.approx(0.3)  # disc edge at x = 3.5
    assert clearance_m(geometry, 8.5, 5.0, 0.2) == pytest.approx(0.3)  # ring wall at x = 9


def test_clearance_is_zero_when_touching_or_overlapping() -> None:
    geometry = static_geometry(room(4, 3))
    assert clearance_m(geometry, 0.2, 1.5, 0.2) == pytest.approx(0.0)
    assert clearance_m(geometry, 0.1, 1.5, 0.2) == 0.0


def test_clearances_are_vectorised_over_points() -> None:
    geometry = static_geometry(room(4, 3))
    points = np.array([[1.0, 2.0], [3.7, 0.5], [2.0, 1.5]])
    np.testing.assert_allclose(clearances_m(geometry, points, 0.2), [0.8, 0.1, 1.3])


def test_space_holds_every_wall_disc_and_the_robot() -> None:
    robot = RobotConfig()
    space, body = build_space(room(4, 3, discs=((1, 1, 0.2),)), robot)
    segments = [s for s in space.shapes if isinstance(s, pymunk.Segment)]
    circles = [s for s in space.shapes if isinstance(s, pymunk.Circle) and s.body is not body]
    assert len(segments) == 4
    assert all(s.radius == pytest.approx(skin_m(robot)) for s in segments)
    assert [c.radius for c in circles] == [pytest.approx(0.2 + skin_m(robot))]
    (disc,) = body.shapes
    assert isinstance(disc, pymunk.Circle)
    # Inflated obstacles and a shrunk body: contact where the map's geometry says.
    assert disc.radius + skin_m(robot) == pytest.approx(robot.radius_m)
    assert tuple(body.position) == (2.0, 1.5)


def test_ring_chords_stay_within_the_allowed_sag() -> None:
    space, _ = build_space(room(8, 8, rings=((4, 4, 3.5),), outline=False), RobotConfig())
    chords = [s for s in space.shapes if isinstance(s, pymunk.Segment)]
    assert len(chords) > 16
    for chord in chords:
        for end in (chord.a, chord.b):
            assert math.dist(end, (4, 4)) == pytest.approx(3.5)
        middle = (chord.a + chord.b) / 2
        assert 3.5 - math.dist(middle, (4, 4)) <= RING_MAX_SAG_M


def _corner_sides_by_all_pairs(segments: np.ndarray) -> np.ndarray:
    """The corner rule compared over every pair of endpoints: the obvious quadratic way."""
    n = len(segments)
    ends = np.concatenate([segments[:, :2], segments[:, 2:]])
    far = np.concatenate([segments[:, 2:], segments[:, :2]])
    owner = np.tile(np.arange(n), 2)
    delta = segments[:, 2:] - segments[:, :2]
    sides = np.zeros(2 * n)
    for here in range(2 * n):
        for there in range(2 * n):
            same = np.all(np.abs(ends[here] - ends[there]) <= CORNER_TOLERANCE_M)
            if sides[here] or not same or owner[here] == owner[there]:
                continue
            arm, own = far[there] - ends[there], delta[owner[here]]
            cross = own[0] * arm[1] - own[1] * arm[0]
            if abs(cross) > 1e-9 * np.hypot(*own) * np.hypot(*arm):
                sides[here] = np.sign(cross)
    return sides.reshape(2, n).T


@pytest.mark.parametrize("kind", ["lab", "rooms", "corridor"])
def test_corner_sides_match_the_all_pairs_rule(kind: str) -> None:
    world = parse_world(generate_world(kind, None, None, 3), kind)
    geometry = static_geometry(world)
    expected = _corner_sides_by_all_pairs(geometry.segments)
    assert np.array_equal(geometry.corner_sides, expected)
    assert np.count_nonzero(expected) > 0
