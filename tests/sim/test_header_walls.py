"""Walls drawn by `wall:` header lines, parsed from text and met by the real sonar and physics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig, SonarConfig
from tvl_cli.sim.geometry import static_geometry
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.sonar import SonarRing
from tvl_cli.sim.worldmap import WorldMap, parse_world

ROBOT = RobotConfig()
QUIET = SonarConfig(noise_sigma_m=0.0, noise_fraction=0.0)
T0 = ROBOT.trajectories[ROBOT.trajectory_index("T0")]


def room_with(*walls: str, cols: int = 32, rows: int = 16) -> WorldMap:
    """An 8 x 4 m walled room (0.25 m cells) with the start at its left, facing +x."""
    grid = ["#" * cols] + ["#" + "." * (cols - 2) + "#" for _ in range(rows - 2)] + ["#" * cols]
    middle = rows // 2
    grid[middle] = "#." + ">" + grid[middle][3:]
    header = [f"wall: {wall}" for wall in walls]
    return parse_world("\n".join([*header, *grid, ""]), "walls.txt")


# A thin edge across the room at x = 4 m, from y = 1 to y = 3.
THIN = room_with("4 1 4 3")
# A 0.4 m thick wall on the same line.
THICK = room_with("4 1 4 3 0.4")


def s0_reading(world: WorldMap, pose: tuple[float, float, float]) -> float:
    ring = SonarRing(QUIET, ROBOT.radius_m)
    return float(ring.read(static_geometry(world), pose, np.random.default_rng(0))[0])


def test_a_thin_wall_is_one_segment_and_a_thick_one_four() -> None:
    plain = room_with()
    assert len(THIN.segments) == len(plain.segments) + 1
    assert THIN.segments[-1] == (4.0, 1.0, 4.0, 3.0)
    sides = THICK.segments[-4:]
    xs = sorted({round(x, 9) for s in sides for x in (s[0], s[2])})
    assert xs == [3.8, 4.2]


@pytest.mark.parametrize(("x", "heading"), [(2.0, 0.0), (6.0, math.pi)])
def test_the_sonar_hears_a_thin_wall_head_on_from_either_face(x: float, heading: float) -> None:
    pose = (x, 2.0, heading)
    assert s0_reading(THIN, pose) == pytest.approx(2.0 - ROBOT.radius_m)


def test_the_sonar_hears_the_near_face_of_a_thick_wall() -> None:
    assert s0_reading(THICK, (2.0, 2.0, 0.0)) == pytest.approx(1.8 - ROBOT.radius_m)


def test_a_thin_wall_at_grazing_incidence_returns_no_echo() -> None:
    # Beam axis 60 degrees off the wall's normal: its nearest ray is 47.5 degrees off, beyond
    # the specular angle, and nothing else lies within range along it.
    heading = math.radians(60.0)
    pose = (4.0 - 1.0 * math.cos(heading), 2.0 - 1.0 * math.sin(heading), heading)
    reading = s0_reading(THIN, pose)
    assert reading == QUIET.max_range_m
    ideal = SonarRing(SonarConfig(ideal=True), ROBOT.radius_m)
    seen = ideal.read(static_geometry(THIN), pose, np.random.default_rng(0))[0]
    assert seen < QUIET.max_range_m  # the wall is there: only its angle hides it


@pytest.mark.parametrize(("world", "face_x"), [(THIN, 4.0), (THICK, 3.8)])
def test_driving_into_a_header_wall_bumps_and_never_passes_it(
    world: WorldMap, face_x: float
) -> None:
    sim = Simulator(world, ROBOT, np.random.default_rng(0))
    sim.place(2.0, 2.0, 0.0)
    bumped = False
    for _ in range(100):  # 10 s at 0.6 m/s: far more than the 2 m to the wall
        sim.step(Command.follow(T0, T0.v_max_mps))
        bumped = bumped or sim.bumped
    x, _, _ = sim.pose
    assert bumped
    assert x == pytest.approx(face_x - ROBOT.radius_m, abs=0.01)


def test_a_thick_slanted_wall_is_a_closed_rectangle_turning_left() -> None:
    sides = room_with("2 1 5 3 0.3").segments[-4:]
    lengths = [math.hypot(x2 - x1, y2 - y1) for x1, y1, x2, y2 in sides]
    assert lengths == pytest.approx([math.sqrt(13), 0.3, math.sqrt(13), 0.3])
    for (ax, ay, bx, by), (cx, cy, dx, dy) in zip(sides, sides[1:] + sides[:1], strict=True):
        assert (bx, by) == pytest.approx((cx, cy))
        assert (bx - ax) * (dy - cy) - (by - ay) * (dx - cx) > 0  # the solid is on the left


def test_a_thick_wall_seen_corner_on_returns_no_echo() -> None:
    # Its faces at 32.5-57.5 degrees to every ray: no specular echo, and a convex corner
    # sends nothing back either.
    pose = (3.3, 3.5, -math.pi / 4)
    assert s0_reading(THICK, pose) == QUIET.max_range_m
    ideal = SonarRing(SonarConfig(ideal=True), ROBOT.radius_m)
    seen = ideal.read(static_geometry(THICK), pose, np.random.default_rng(0))[0]
    assert seen == pytest.approx(math.hypot(0.5, 0.5) - ROBOT.radius_m, abs=0.06)


# Two thin edges meeting at (5, 1): the quarter x > 5, y > 1 is inside the corner.
THIN_L = room_with("5 1 6 1", "5 1 5 2")


def test_two_thin_walls_meeting_echo_as_a_corner_from_inside_only() -> None:
    inside = s0_reading(THIN_L, (5.5, 1.5, -3 * math.pi / 4))
    assert inside == pytest.approx(math.hypot(0.5, 0.5) - ROBOT.radius_m, abs=0.01)
    assert s0_reading(THIN_L, (4.5, 0.5, math.pi / 4)) == QUIET.max_range_m


@pytest.mark.parametrize("thickness", [0.0, 0.2])
def test_driving_into_a_slanted_header_wall_bumps_and_stays_on_its_side(thickness: float) -> None:
    # The wall y = x - 2 runs from the floor's bottom edge to its top edge: no way round it.
    world = room_with(f"2.25 0.25 5.75 3.75 {thickness:g}")
    sim = Simulator(world, ROBOT, np.random.default_rng(0))
    sim.place(2.0, 2.0, 0.0)
    bumped, nearest = False, math.inf
    for _ in range(150):
        sim.step(Command.follow(T0, T0.v_max_mps))
        bumped = bumped or sim.bumped
        x, y, _ = sim.pose
        nearest = min(nearest, (y - x + 2.0) / math.sqrt(2.0))  # metres from the wall's line
    assert bumped
    assert nearest == pytest.approx(thickness / 2 + ROBOT.radius_m, abs=0.01)
