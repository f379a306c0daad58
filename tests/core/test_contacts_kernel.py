"""The compiled heard contacts are what core.arcs computes in numpy, pose by pose, on real
worlds' outlines and at random poses, each pose with its own window of points."""

from __future__ import annotations

import math

import numpy as np
import pytest
from kernel_worlds import WORLDS as WORLD_FILES
from kernel_worlds import random_poses

from tvl_cli.core.arcs import first_contacts_m
from tvl_cli.core.contacts_kernel import first_contacts_in_windows
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import static_geometry
from tvl_cli.sim.true_arcs import outline_points
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import load_world, parse_world

ROBOT = RobotConfig()
CURVATURES = np.array([t.curvature_per_m for t in ROBOT.trajectories])
WORLDS = {
    "lab": load_world(WORLD_FILES / "lab.txt"),
    "rooms": parse_world(generate_world("rooms", None, None, 5), "rooms"),
}


def nearest_first(
    poses: np.ndarray, points: np.ndarray, first: np.ndarray, stop: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each pose's window of points copied out in order of distance from the pose, one after
    another: (points, first, stop) as the kernel reads them with nearest_first."""
    windows = []
    for pose, a, b in zip(poses, first, stop, strict=True):
        window = points[a:b]
        windows.append(window[np.argsort(((window - pose[:2]) ** 2).sum(axis=1))])
    sizes = np.array([len(w) for w in windows])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    return np.ascontiguousarray(np.concatenate(windows)), starts, starts + sizes


@pytest.mark.parametrize("ordered", [False, True], ids=["as-read", "nearest-first"])
@pytest.mark.parametrize("name", sorted(WORLDS))
def test_the_kernel_finds_each_poses_contacts_as_numpy_does_in_its_window(
    name: str, ordered: bool
) -> None:
    world = WORLDS[name]
    # Sparse, as echoes are.
    points = np.ascontiguousarray(outline_points(world, ROBOT.radius_m)[::3])
    poses = np.ascontiguousarray(random_poses(static_geometry(world), 200, seed=11))
    rng = np.random.default_rng(5)
    first = rng.integers(0, len(points), len(poses))
    stop = np.minimum(first + rng.integers(0, 3000, len(poses)), len(points))
    expected = np.array(
        [
            first_contacts_m(tuple(pose), CURVATURES, points[a:b], ROBOT.radius_m)
            for pose, a, b in zip(poses, first, stop, strict=True)
        ]
    )
    if ordered:
        points, first, stop = nearest_first(poses, points, first, stop)
    found = np.empty((len(poses), len(CURVATURES)))
    first_contacts_in_windows(
        poses, CURVATURES, points, first, stop, ROBOT.radius_m, math.inf, ordered, found
    )
    np.testing.assert_array_equal(np.isinf(found), np.isinf(expected))
    finite = np.isfinite(found)
    np.testing.assert_allclose(found[finite], expected[finite], rtol=0, atol=1e-9)
    assert 0.2 < finite.mean() < 1.0  # contacts and free arcs both


@pytest.mark.parametrize("reach_m", [0.5, 1.5])
def test_points_taken_nearest_first_find_what_points_as_read_find_within_a_reach(
    reach_m: float,
) -> None:
    """Stopping at the first point too far to better any trajectory loses no contact: the
    same distances, bit for bit, as asking every point of the window."""
    world = WORLDS["rooms"]
    points = np.ascontiguousarray(outline_points(world, ROBOT.radius_m))
    poses = np.ascontiguousarray(random_poses(static_geometry(world), 100, seed=3))
    first, stop = np.zeros(len(poses), np.int64), np.full(len(poses), len(points), np.int64)
    as_read = np.empty((len(poses), len(CURVATURES)))
    first_contacts_in_windows(
        poses, CURVATURES, points, first, stop, ROBOT.radius_m, reach_m, False, as_read
    )
    ordered, first, stop = nearest_first(poses, points, first, stop)
    sorted_found = np.empty_like(as_read)
    first_contacts_in_windows(
        poses, CURVATURES, ordered, first, stop, ROBOT.radius_m, reach_m, True, sorted_found
    )
    np.testing.assert_array_equal(sorted_found, as_read)
    assert np.isfinite(as_read).any() and np.isinf(as_read).any()


def contacts_of_one_point(x_m: float, reach_m: float) -> np.ndarray:
    """(T,) metres: first_contacts_in_windows from the origin facing +x, sought within
    reach_m, with a single point x_m ahead."""
    found = np.empty((1, len(CURVATURES)))
    first_contacts_in_windows(
        np.zeros((1, 3)), CURVATURES, np.array([[x_m, 0.0]]), np.zeros(1, np.int64),
        np.ones(1, np.int64), ROBOT.radius_m, reach_m, False, found,
    )  # fmt: skip
    return found[0]


def test_a_point_beyond_the_reach_is_left_out_and_one_within_it_kept() -> None:
    reach_m = 1.0
    straight = int(np.flatnonzero(CURVATURES == 0.0)[0])
    # The body's edge meets a point x ahead once its centre has come x - radius straight on.
    within = reach_m + ROBOT.radius_m - 0.01
    np.testing.assert_array_equal(
        contacts_of_one_point(within, reach_m), contacts_of_one_point(within, math.inf)
    )
    assert contacts_of_one_point(within, reach_m)[straight] == pytest.approx(reach_m - 0.01)
    beyond = reach_m + ROBOT.radius_m + 0.01
    assert contacts_of_one_point(beyond, math.inf)[straight] == pytest.approx(reach_m + 0.01)
    assert np.isinf(contacts_of_one_point(beyond, reach_m)).all()
