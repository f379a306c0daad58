"""The true collision points (sim.true_arcs), a reference that reads the map: in a box of
known size, each trajectory meets the wall where geometry says."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tvl_cli.core.labels import label_reach_m, velocity_labels
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.true_arcs import OUTLINE_TOLERANCE_M, TrueArcs, outline_points
from tvl_cli.sim.worldmap import parse_world

ROBOT = RobotConfig()
# A 6 m by 4 m room of quarter-metre cells: its inside runs from 0.25 to 5.75 m and 3.75 m.
BOX = parse_world(
    "version: 1\nname: box\ncell: 0.25\n\n"
    + "#" * 24
    + "\n"
    + "".join("#" + "." * 22 + "#\n" for _ in range(7))
    + "#..>" + "." * 19 + "#\n"
    + "".join("#" + "." * 22 + "#\n" for _ in range(7))
    + "#" * 24
    + "\n",
    "box",
)  # fmt: skip


def test_the_outline_lies_on_the_walls_close_enough_for_the_body() -> None:
    points = outline_points(BOX, ROBOT.radius_m)
    gaps = np.hypot(*np.diff(points[:50], axis=0).T)  # along the first wall
    # A body circle through two neighbours reaches no deeper than the tolerance between them.
    half = gaps.max() / 2
    assert ROBOT.radius_m - math.sqrt(ROBOT.radius_m**2 - half**2) <= OUTLINE_TOLERANCE_M + 1e-12
    assert gaps.max() > 0.02  # no closer than that asks
    assert points[:, 0].min() == pytest.approx(0.25) and points[:, 0].max() == pytest.approx(5.75)


@pytest.mark.parametrize("offset_m", np.linspace(0.0, 0.05, 11))
def test_the_body_meets_a_wall_or_a_pillar_within_the_tolerance_wherever_it_strikes(
    offset_m: float,
) -> None:
    # Straight at the far wall, and at a pillar of 0.1 m radius, from heights that strike the
    # outline between its points as well as on them.
    pillar = parse_world(BOX.text.replace("\n\n", "\ndisc: 4.0 1.0 0.1\n\n", 1), "pillar")
    straight = 3
    wall = TrueArcs(BOX, ROBOT).distances_m(np.array([[1.0, 1.0 + offset_m, 0.0]]), 10.0)
    # Between two points the body reaches past the outline by no more than the tolerance.
    assert 0.0 <= wall[0, straight] - (5.75 - 1.0 - ROBOT.radius_m) <= OUTLINE_TOLERANCE_M + 1e-12
    met = TrueArcs(pillar, ROBOT).distances_m(np.array([[1.0, 1.0 + offset_m, 0.0]]), 10.0)
    # The centre's line passes offset_m from the pillar's: it meets it where it comes within
    # the two radii of it.
    exact = 3.0 - math.sqrt((ROBOT.radius_m + 0.1) ** 2 - offset_m**2)
    assert 0.0 <= met[0, straight] - exact <= OUTLINE_TOLERANCE_M + 1e-12


def test_straight_ahead_meets_the_far_wall_a_body_radius_short() -> None:
    arcs = TrueArcs(BOX, ROBOT)
    pose = np.array([[1.0, 1.0, 0.0]])  # facing +x, 4.75 m from the inside of the far wall
    found = arcs.distances_m(pose, reach_m=10.0)
    assert found[0, 3] == pytest.approx(5.75 - 1.0 - ROBOT.radius_m, abs=OUTLINE_TOLERANCE_M)
    # Beyond the reach asked, nothing is met.
    assert np.isinf(arcs.distances_m(pose, reach_m=2.0)[0, 3])


def test_a_left_turn_meets_the_wall_where_its_circle_crosses_it() -> None:
    arcs = TrueArcs(BOX, ROBOT)
    # Facing -y from (3, 1.2): T1L (radius 2, centre (5, 1.2)) turns toward the bottom wall
    # at y = 0.25; the body meets it when its centre reaches y = 0.45.
    pose = np.array([[3.0, 1.2, -math.pi / 2]])
    found = arcs.distances_m(pose, reach_m=10.0)[0, 2]
    turned = math.asin((1.2 - 0.45) / 2.0)  # the angle round the centre to y = 0.45
    assert found == pytest.approx(2.0 * turned, abs=2e-3)


def test_true_velocities_are_the_labels_of_the_true_collision_points() -> None:
    arcs = TrueArcs(BOX, ROBOT)
    poses = np.array([[1.0, 1.0, 0.0], [5.2, 2.0, 0.0], [3.0, 2.0, math.pi / 2]])
    decel, margin = 0.1, 0.15
    v_max = np.array(ROBOT.v_max_mps)
    found = arcs.distances_m(poses, label_reach_m(max(ROBOT.v_max_mps), decel, margin))
    expected = velocity_labels(found, v_max, decel, margin)
    np.testing.assert_allclose(arcs.velocities_mps(found, decel, margin), expected)
    assert expected[1, 3] == pytest.approx(0.2, abs=1e-3)  # 0.35 m from the wall


def test_a_clearance_moves_every_collision_point_nearer() -> None:
    pose = np.array([[1.0, 1.0, 0.0]])
    touching = TrueArcs(BOX, ROBOT).distances_m(pose, 10.0)[0, 3]
    clear = TrueArcs(BOX, ROBOT, clearance_m=0.15).distances_m(pose, 10.0)[0, 3]
    assert clear == pytest.approx(touching - 0.15, abs=OUTLINE_TOLERANCE_M)


@pytest.mark.parametrize("seed", [2, 9])
def test_gathering_the_outline_by_cells_finds_what_every_point_would(seed: int) -> None:
    # A furnished rooms world, from anywhere in it: the points of the cells round a place
    # give the very distances that seeking among the whole outline gives.
    from tvl_cli.sim.worldgen import generate_world

    world = parse_world(generate_world("rooms", None, None, seed), "rooms")
    arcs = TrueArcs(world, ROBOT, clearance_m=0.15)
    everything = TrueArcs(world, ROBOT, clearance_m=0.15)
    everything._near = lambda x, y, within_m: everything._points  # type: ignore[method-assign]
    outline = outline_points(world, ROBOT.radius_m + 0.15)
    rng = np.random.default_rng(seed)
    low, high = outline.min(axis=0), outline.max(axis=0)
    poses = rng.uniform((*(low - 1.0), -math.pi), (*(high + 1.0), math.pi), (300, 3))
    reach = label_reach_m(max(ROBOT.v_max_mps), 0.1, 0.15)
    gathered, sought = arcs.distances_m(poses, reach), everything.distances_m(poses, reach)
    assert gathered.tobytes() == sought.tobytes()
    assert np.isfinite(gathered).any() and np.isinf(gathered).any()
    assert len(arcs._near(*poses[0, :2], reach)) < len(outline)  # fewer points asked
