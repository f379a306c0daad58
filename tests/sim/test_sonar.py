"""The sonar ring against real geometry: head-on walls, grazing walls, corners, noise, modes."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pymunk
import pytest
from cluttered_hall import cluttered_hall
from test_geometry import room, square_block

from tvl_cli.core.robot_config import SonarConfig
from tvl_cli.sim.geometry import StaticGeometry, clearance_m, static_geometry
from tvl_cli.sim.sonar import SonarRing
from tvl_cli.sim.worldmap import load_world

RADIUS = 0.2
QUIET = SonarConfig(noise_sigma_m=0.0, noise_fraction=0.0)
IDEAL = SonarConfig(ideal=True)
# One long wall along y = 5 (seen from below), far from anything else.
LONG_WALL = static_geometry(room(40, 10, walls=((-20, 5, 60, 5),), outline=False))


def read(
    config: SonarConfig, geometry: StaticGeometry, pose: tuple[float, float, float], seed: int = 0
) -> np.ndarray:
    return SonarRing(config, RADIUS).read(geometry, pose, np.random.default_rng(seed))


def facing_wall(distance_m: float, off_normal_deg: float) -> tuple[float, float, float]:
    """A pose whose S0 transducer is distance_m from LONG_WALL, beam turned off its normal."""
    heading = math.pi / 2 - math.radians(off_normal_deg)
    x = 20.0 - RADIUS * math.cos(heading)
    y = 5.0 - distance_m - RADIUS * math.sin(heading)
    return (x, y, heading)


@pytest.mark.parametrize("distance", [0.3, 1.0, 2.5, 3.8])
def test_wall_head_on_reads_its_distance_within_noise(distance: float) -> None:
    config = SonarConfig()
    readings = np.array(
        [read(config, LONG_WALL, facing_wall(distance, 0.0), seed)[0] for seed in range(200)]
    )
    sigma = config.noise_sigma_m + config.noise_fraction * distance
    assert np.all(np.abs(readings - distance) < 5 * sigma)
    assert readings.mean() == pytest.approx(distance, abs=sigma / 2)
    assert readings.std() == pytest.approx(sigma, rel=0.2)


def test_wall_head_on_without_noise_reads_exactly_its_distance() -> None:
    assert read(QUIET, LONG_WALL, facing_wall(1.7, 0.0))[0] == pytest.approx(1.7)


def test_wall_within_the_specular_angle_still_echoes() -> None:
    # At 15 degrees off the normal, rays from 2.5 to 27.5 degrees: the nearest echo comes
    # from the ray nearest the normal.
    reading = read(QUIET, LONG_WALL, facing_wall(1.0, 15.0))[0]
    assert reading == pytest.approx(1.0 / math.cos(math.radians(2.5)))


def test_wall_60_degrees_off_its_normal_gives_no_echo() -> None:
    assert read(SonarConfig(), LONG_WALL, facing_wall(1.0, 60.0))[0] == 4.0


def test_ideal_mode_sees_the_grazing_wall() -> None:
    # The beam's nearest ray is 60 - 12.5 = 47.5 degrees off the normal.
    reading = read(IDEAL, LONG_WALL, facing_wall(1.0, 60.0))[0]
    assert reading == pytest.approx(1.0 / math.cos(math.radians(47.5)))


def test_ideal_mode_has_no_noise() -> None:
    pose = facing_wall(1.3, 0.0)
    assert read(IDEAL, LONG_WALL, pose, seed=1)[0] == read(IDEAL, LONG_WALL, pose, seed=2)[0]


def test_concave_corner_echoes_at_its_range() -> None:
    # Looking into a room's corner along its diagonal: both walls 45 degrees off the normal.
    geometry = static_geometry(room(6, 6))
    pose = (1.5, 1.5, math.radians(225))
    expected = math.hypot(1.5, 1.5) - RADIUS
    assert read(QUIET, geometry, pose)[0] == pytest.approx(expected)


def test_convex_corner_seen_the_same_way_gives_no_echo() -> None:
    # The corner of a solid block, pointing at the robot along the same diagonal.
    geometry = static_geometry(room(8, 8, walls=square_block(3, 3, 1), outline=False))
    pose = (1.5, 1.5, math.radians(45))
    assert read(QUIET, geometry, pose)[0] == 4.0
    assert read(IDEAL, geometry, pose)[0] == pytest.approx(math.hypot(1.5, 1.5) - RADIUS)


def test_convex_corner_echoes_within_the_edge_echo_range() -> None:
    geometry = static_geometry(room(8, 8, walls=square_block(3, 3, 1), outline=False))
    corner_m = math.hypot(1.5, 1.5) - RADIUS
    pose = (1.5, 1.5, math.radians(45))
    near = dataclasses.replace(QUIET, edge_echo_range_m=corner_m + 0.01)
    far = dataclasses.replace(QUIET, edge_echo_range_m=corner_m - 0.01)
    assert read(near, geometry, pose)[0] == pytest.approx(corner_m)
    assert read(far, geometry, pose)[0] == 4.0


def test_a_thin_walls_end_is_an_edge() -> None:
    # A thin wall along y = 2 from x = 2 rightwards, its free end met at 60 degrees off its
    # normal: an edge, heard only with edge echoes.
    geometry = static_geometry(room(8, 8, walls=((2.0, 2.0, 6.0, 2.0),), outline=False))
    heading = math.radians(30.0)
    end = np.array([2.0, 2.0])
    transducer = end - 0.8 * np.array([math.cos(heading), math.sin(heading)])
    pose = (*(transducer - RADIUS * np.array([math.cos(heading), math.sin(heading)])), heading)
    assert read(QUIET, geometry, pose)[0] == 4.0
    edges = dataclasses.replace(QUIET, edge_echo_range_m=1.0)
    assert read(edges, geometry, pose)[0] == pytest.approx(0.8, abs=1e-9)


def test_smooth_wall_at_a_grazing_angle_stays_silent_with_edge_echoes() -> None:
    # Figure 12 of the paper: only the ends of a wall are edges, not its flat middle.
    edges = dataclasses.replace(QUIET, edge_echo_range_m=4.0)
    assert read(edges, LONG_WALL, facing_wall(1.0, 60.0))[0] == 4.0


def rough_wall(roughness: float) -> StaticGeometry:
    return LONG_WALL.with_roughness(roughness)


def test_rough_wall_echoes_at_a_grazing_angle_within_its_diffuse_range() -> None:
    # 60 degrees off the normal the nearest ray meets the wall 47.5 degrees off it, at
    # 1 / cos(47.5) = 1.48 m; roughness 0.2 hears it to 4 sqrt(0.2 cos 47.5) = 1.47 m.
    hit_m = 1.0 / math.cos(math.radians(47.5))
    diffuse_m = 4.0 * math.sqrt(0.2 * math.cos(math.radians(47.5)))
    assert diffuse_m < hit_m < 4.0 * math.sqrt(0.3 * math.cos(math.radians(47.5)))
    assert read(QUIET, rough_wall(0.2), facing_wall(1.0, 60.0))[0] == 4.0
    assert read(QUIET, rough_wall(0.3), facing_wall(1.0, 60.0))[0] == pytest.approx(hit_m)


def test_a_rough_wall_reads_as_a_smooth_one_square_on() -> None:
    pose = facing_wall(2.0, 0.0)
    assert read(QUIET, rough_wall(1.0), pose)[0] == read(QUIET, LONG_WALL, pose)[0]


def test_a_rough_ring_wall_echoes_at_a_grazing_angle() -> None:
    # Inside a ring of radius 2 near its edge, looking along it: the ray meets the ring
    # far off its normal, silent when smooth.
    world = room(10, 10, rings=((5.0, 5.0, 2.0),), outline=False)
    pose = (5.0, 3.4, 0.0)
    smooth = read(QUIET, static_geometry(world), pose)[0]
    rough = read(QUIET, static_geometry(world).with_roughness(1.0), pose)[0]
    assert rough < smooth


def test_corner_off_the_beam_axis_still_echoes() -> None:
    # The corner lies between two rays of the beam, 10 degrees off its axis.
    geometry = static_geometry(room(6, 6))
    pose = (1.5, 1.5, math.radians(235))
    transducer = (1.5 + RADIUS * math.cos(pose[2]), 1.5 + RADIUS * math.sin(pose[2]))
    assert read(QUIET, geometry, pose)[0] == pytest.approx(math.hypot(*transducer))


def test_disc_echoes_from_its_near_side() -> None:
    geometry = static_geometry(room(8, 8, discs=((5, 4, 0.3),), outline=False))
    assert read(QUIET, geometry, (2.0, 4.0, 0.0))[0] == pytest.approx(5 - 0.3 - 2 - RADIUS)


def test_disc_met_off_its_normal_echoes_from_its_nearest_point() -> None:
    # The disc sits 2.8 m away midway between two rays (6.25 degrees apart): both meet it 30
    # degrees off its normal, yet the point of it facing the transducer lies inside the cone.
    half_gap = math.radians(3.125)
    centre = (2.2 + 2.8 * math.cos(half_gap), 4.0 + 2.8 * math.sin(half_gap))
    geometry = static_geometry(room(8, 8, discs=((*centre, 0.3),), outline=False))
    pose = (2.0, 4.0, 0.0)
    assert read(QUIET, geometry, pose)[0] == pytest.approx(2.8 - 0.3)
    assert read(IDEAL, geometry, pose)[0] > 2.8 - 0.3  # the nearest ray hit, off the near point


def test_disc_outside_every_ray_of_the_cone_is_not_heard() -> None:
    geometry = static_geometry(room(8, 8, discs=((4.0, 5.5, 0.1),), outline=False))
    assert read(QUIET, geometry, (2.0, 4.0, 0.0))[0] == 4.0


def test_ring_wall_echoes_all_round_from_its_centre() -> None:
    geometry = static_geometry(room(8, 8, rings=((4, 4, 3.0),), outline=False))
    np.testing.assert_allclose(read(QUIET, geometry, (4.0, 4.0, 0.7)), 3.0 - RADIUS)


def test_transducers_are_numbered_counter_clockwise_from_the_front() -> None:
    # Heading +x in a 6 x 4 room: left (+y) wall 1 m away, right 3 m, front 4 m, rear 1 m.
    readings = read(QUIET, static_geometry(room(6, 4)), (1.2, 3.0, 0.0))
    assert readings[0] == 4.0  # the front wall is 4.6 m away, beyond the range
    assert readings[4] == pytest.approx(1.0 - RADIUS)
    assert readings[8] == pytest.approx(1.2 - RADIUS)
    assert readings[12] == pytest.approx(3.0 - RADIUS)


def test_readings_are_clamped_to_the_minimum_range() -> None:
    # The body's edge 5 cm from the wall: nearer than the transducer can measure.
    readings = read(SonarConfig(), LONG_WALL, facing_wall(0.05, 0.0))
    assert readings[0] == SonarConfig().min_range_m


def test_no_echo_within_range_reads_the_maximum_exactly() -> None:
    readings = read(SonarConfig(), LONG_WALL, facing_wall(5.0, 0.0))
    assert readings[0] == 4.0
    assert np.all(readings == 4.0)


def test_a_near_obstacle_hides_the_wall_behind_it() -> None:
    # A grazing wall in front of a head-on wall: the ray is lost, not passed through.
    screen = ((19.0, 3.0, 21.0, 4.5),)
    geometry = static_geometry(room(40, 10, walls=((-20, 5, 60, 5), *screen), outline=False))
    assert read(QUIET, geometry, facing_wall(2.0, 0.0))[0] == 4.0


def test_same_seed_gives_the_same_readings_bit_for_bit() -> None:
    geometry = static_geometry(room(6, 4))
    first = read(SonarConfig(), geometry, (2.0, 1.5, 0.4), seed=7)
    again = read(SonarConfig(), geometry, (2.0, 1.5, 0.4), seed=7)
    assert first.tobytes() == again.tobytes()
    other = read(SonarConfig(), geometry, (2.0, 1.5, 0.4), seed=8)
    assert not np.array_equal(first, other)


def test_wider_cone_sees_a_wall_further_off_its_axis() -> None:
    wide = dataclasses.replace(QUIET, cone_deg=60.0)
    pose = facing_wall(1.0, 35.0)
    assert read(QUIET, LONG_WALL, pose)[0] == 4.0
    assert read(wide, LONG_WALL, pose)[0] < 4.0


def test_ideal_readings_match_pymunk_ray_queries_in_the_lab() -> None:
    world = load_world("worlds/lab.txt")
    geometry = static_geometry(world)
    ring = SonarRing(IDEAL, RADIUS)
    space = pymunk.Space()
    space.add(*[pymunk.Segment(space.static_body, s[:2], s[2:], 0.0) for s in world.segments])
    space.add(*[pymunk.Circle(space.static_body, r, (x, y)) for x, y, r in world.discs])
    rng = np.random.default_rng(3)
    poses = [
        (x, y, rng.uniform(-math.pi, math.pi))
        for x, y in rng.uniform((0, 0), (world.width_m, world.height_m), size=(200, 2))
        if clearance_m(geometry, x, y, RADIUS) > 0.0
    ]
    for pose in poses[:20]:
        origins, directions = ring.rays(pose)
        nearest = np.full(len(origins), np.inf)  # (16 * rays,) metres
        for i, (origin, direction) in enumerate(zip(origins, directions, strict=True)):
            end = origin + IDEAL.max_range_m * direction
            info = space.segment_query_first(tuple(origin), tuple(end), 0.0, pymunk.ShapeFilter())
            if info is not None:
                nearest[i] = info.alpha * IDEAL.max_range_m
        expected = np.clip(nearest.reshape(16, -1).min(axis=1), 0.15, 4.0)
        np.testing.assert_allclose(ring.read(geometry, pose, rng), expected, atol=1e-9)


def test_a_large_world_reads_exactly_as_if_every_wall_were_tested(monkeypatch) -> None:
    """Each ray tests only the walls of the cells it crosses in a large world, with the same
    readings as one cell holding every wall."""
    from tvl_cli.sim import wall_grid
    from tvl_cli.sim.worldmap import parse_world

    world = parse_world(cluttered_hall(600, seed=3), "hall")
    geometry = static_geometry(world)
    assert geometry.grid.columns * geometry.grid.rows > 100
    sonar = SonarRing(SonarConfig(), 0.2)
    poses = np.random.default_rng(4).uniform((1, 1, -math.pi), (29, 29, math.pi), (300, 3))
    bucketed = [sonar.read(geometry, tuple(p), np.random.default_rng(5)) for p in poses]
    monkeypatch.setattr(wall_grid, "MIN_WALLS_TO_BUCKET", math.inf)
    one_cell = static_geometry(world)
    assert one_cell.grid.columns * one_cell.grid.rows == 1
    every = [sonar.read(one_cell, tuple(p), np.random.default_rng(5)) for p in poses]
    np.testing.assert_array_equal(bucketed, every)
    assert (np.array(every) < SonarConfig().max_range_m).mean() > 0.5  # walls were heard


def _rays_meet_nothing(ring: SonarRing, geometry: StaticGeometry, pose) -> np.ndarray:
    """(16,) bool: transducers none of whose rays crosses any wall, disc or ring ahead."""
    origins, directions = ring.rays(pose)
    far = origins + 10.0 * ring.config.max_range_m * directions

    def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    meets = np.zeros(len(origins), dtype=bool)
    for x1, y1, x2, y2 in geometry.segments:
        a, b = np.array([x1, y1]), np.array([x2, y2])
        # The segment's ends lie on either side of the ray, and the ray's ends on either
        # side of the segment.
        ends_apart = cross(far - origins, a - origins) * cross(far - origins, b - origins) <= 0
        ray_apart = cross(b - a, origins - a) * cross(b - a, far - a) <= 0
        meets |= ends_apart & ray_apart
    return ~meets.reshape(16, -1).any(axis=1)


def test_a_ray_that_meets_nothing_hears_nothing_outside_the_square() -> None:
    # Backed into the square's left wall and facing out of the world: the front beams cross
    # no wall at all, so no wall's corner may echo to them.
    geometry = static_geometry(load_world("worlds/square.txt"))
    ring = SonarRing(QUIET, RADIUS)
    pose = (0.1, 2.0, math.pi)
    silent = _rays_meet_nothing(ring, geometry, pose)
    assert silent[[0, 1, 15]].all()
    readings = ring.read(geometry, pose, np.random.default_rng(0))
    assert np.all(readings[silent] == QUIET.max_range_m)


@pytest.mark.slow  # over a second
def test_a_ray_that_meets_nothing_hears_nothing_among_many_blocks() -> None:
    # A hall of 300 square blocks, read at random poses clear of them: a beam none of whose
    # rays crosses any wall reads the maximum range, however many walls lie elsewhere.
    rng = np.random.default_rng(11)
    blocks = tuple(
        wall
        for x, y in rng.uniform(1.0, 39.0, (300, 2))
        for wall in square_block(float(x), float(y), 0.4)
    )
    geometry = static_geometry(room(40, 40, walls=blocks, outline=False))
    ring = SonarRing(QUIET, RADIUS)
    silent_beams = 0
    for x, y, theta in rng.uniform((0, 0, -math.pi), (40, 40, math.pi), (300, 3)):
        pose = (float(x), float(y), float(theta))
        if clearance_m(geometry, x, y, RADIUS) <= 0.0:
            continue
        silent = _rays_meet_nothing(ring, geometry, pose)
        readings = ring.read(geometry, pose, rng)
        silent_beams += int(silent.sum())
        assert np.all(readings[silent] == QUIET.max_range_m), pose
    assert silent_beams > 100  # the test looked at many beams that meet nothing
