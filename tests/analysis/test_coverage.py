"""Coverage: reachable cells of a world, and the fraction of them a list of poses passed."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from cluttered_hall import cluttered_hall
from kernel_references.clearance_reference import clearances_reference

from tvl_cli.analysis import coverage
from tvl_cli.analysis.coverage import (
    CoverageGrid,
    CoverageTracker,
    coverage_by_minute,
    coverage_of,
    reachable_floor,
    world_floor,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import static_geometry
from tvl_cli.sim.worldmap import parse_world

ROBOT = RobotConfig()
# Half-metre cells: a room 2 m by 1 m inside the walls, its 8 cells' centres 0.25 m from the
# nearest wall, so a body of radius 0.2 m fits on every one.
ROOM = "version: 1\nname: room\ncell: 0.5\n\n######\n#>...#\n#....#\n######\n"
# Two rooms joined by a doorway one cell (0.5 m) wide: 9 cells on the left, 1 in the doorway,
# 15 on the right.
TWO_ROOMS = (
    "version: 1\nname: two\ncell: 0.5\n{disc}\n"
    "###########\n#>..#.....#\n#.........#\n#...#.....#\n###########\n"
)


def test_every_cell_of_a_plain_room_is_reachable() -> None:
    floor = world_floor(parse_world(ROOM, "room"), ROBOT)
    assert floor.cells == 8


def test_coverage_of_hand_made_poses_is_the_fraction_of_cells_passed() -> None:
    floor = world_floor(parse_world(ROOM, "room"), ROBOT)
    poses = np.array(
        [
            [0.75, 1.25, 0.0],  # the start's cell (top row, first column)
            [1.10, 1.20, 0.0],  # top row, second column
            [1.40, 1.30, 0.0],  # the same cell again
            [1.90, 1.25, 0.0],  # top row, third column
            [0.60, 0.70, 3.1],  # bottom row, first column
            [0.20, 0.20, 0.0],  # inside the wall: not a reachable cell
        ]
    )
    assert coverage_of(floor, poses) == pytest.approx(4 / 8)


def test_coverage_by_minute_counts_each_minutes_poses_on_top_of_the_earlier() -> None:
    floor = world_floor(parse_world(ROOM, "room"), ROBOT)
    poses = np.array([[0.75, 1.25], [1.25, 1.25], [1.25, 0.75], [2.25, 0.75], [0.75, 0.75]])
    assert coverage_by_minute(floor, poses, [2, 0, 3]) == pytest.approx([2 / 8, 2 / 8, 5 / 8])


def test_a_doorway_the_body_fits_through_joins_the_rooms() -> None:
    floor = world_floor(parse_world(TWO_ROOMS.format(disc=""), "two"), ROBOT)
    assert floor.cells == 9 + 1 + 15


def test_a_doorway_narrower_than_the_body_keeps_the_far_room_out_of_reach() -> None:
    # A pillar of radius 0.1 m in the middle of the doorway leaves gaps of 0.15 m either side.
    narrowed = TWO_ROOMS.format(disc="disc: 2.25 1.25 0.1\n")
    floor = world_floor(parse_world(narrowed, "two"), ROBOT)
    assert floor.cells == 9


def test_the_tracker_ignores_poses_off_the_grid() -> None:
    floor = world_floor(parse_world(ROOM, "room"), ROBOT)
    tracker = CoverageTracker(floor)
    tracker.add(np.array([[-1.0, 0.5], [9.0, 9.0]]))
    assert tracker.fraction == 0.0


def test_a_step_between_cells_needs_the_body_to_fit_halfway_too() -> None:
    """Two cells whose centres fit, with an obstacle only between them, are not joined."""
    grid = CoverageGrid(0.5, rows=1, columns=2)  # two cells side by side
    fits = np.array([[True, False, True]])  # (1, 3): centre, midpoint, centre
    floor = reachable_floor(grid, fits, (0.25, 0.25))
    assert floor.reachable.tolist() == [True, False]


def test_the_floor_of_a_world_of_many_walls_takes_memory_for_its_cells_not_their_product() -> None:
    # A 30 m hall of 3,000 walls at half-metre cells: 14,161 lattice points. Every point
    # against every wall at once, in numpy, would take 324 MiB an array (a 100 m hall of
    # 10,000 walls, 47.5 GiB); one point at a time, the floor's own arrays.
    world = parse_world(cluttered_hall(3000, seed=1), "hall")
    world_floor(parse_world(ROOM, "room"), ROBOT)  # the kernel compiled and loaded first
    tracemalloc.start()
    try:
        floor = world_floor(world, ROBOT)
        peak_mib = tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()
    assert peak_mib < 32, peak_mib
    assert floor.cells > 0


@pytest.mark.slow  # over a second
@pytest.mark.parametrize("walls", [0, 40, 600])
def test_the_floor_is_the_one_all_points_against_all_obstacles_at_once_give(walls: int) -> None:
    world = parse_world(cluttered_hall(walls, seed=2), "hall")
    floor = world_floor(world, ROBOT)
    geometry = static_geometry(world)
    lattice = floor.grid.lattice_xy()
    points = lattice.reshape(-1, 2)
    clearance, nearest = np.empty(len(points)), np.empty(len(points), dtype=np.int64)
    clearances_reference(
        points, geometry.seg_start, geometry.seg_delta, geometry.seg_len,
        geometry.grid.kernel_input, geometry.discs, geometry.rings, ROBOT.radius_m, np.inf,
        clearance, nearest,
    )  # fmt: skip
    fits = clearance.reshape(lattice.shape[:2]) > 0.0
    expected = reachable_floor(floor.grid, fits, world.start[:2])
    np.testing.assert_array_equal(floor.reachable, expected.reachable)


def test_a_world_of_more_cells_than_the_floor_takes_is_measured_in_squares_of_them(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With room for 100 cells, the 8 x 6 m lab at 0.25 m (768 cells) is measured in squares
    of 3 x 3 of its cells: 11 x 8 of them."""
    monkeypatch.setattr(coverage, "MAX_FLOOR_CELLS", 100)
    world = parse_world(Path("worlds/lab.txt").read_text(), "lab")
    floor = world_floor(world, ROBOT)
    assert (floor.grid.cell_m, floor.grid.rows, floor.grid.columns) == (0.75, 8, 11)
    assert 0 < floor.cells < 88
