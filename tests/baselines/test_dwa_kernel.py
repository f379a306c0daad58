"""The walked free distances are, bit for bit, what the numpy reference makes of every arc
point's clearance, on real worlds from random poses, and on remembered patches."""

from __future__ import annotations

import math

import numpy as np
import pytest
from kernel_references.dwa_reference import free_distances_reference
from kernel_worlds import every_world, random_poses

from tvl_cli.baselines.dwa import WALK_M
from tvl_cli.baselines.dwa_kernel import walked_free_distances
from tvl_cli.baselines.dwa_window import (
    DwaParams,
    arc_lengths,
    arc_points,
    clearance_read_m,
    dynamic_window,
    ray_points,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import StaticGeometry, clearance_m, clearances_m, geometry_of

P = DwaParams()
RADIUS_M = RobotConfig().radius_m
S_M = arc_lengths(P)
READ_M = clearance_read_m(S_M, P)
WORLDS = every_world()


def arcs_from(pose: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """(N, K, 2): the dynamic window's arcs from a random velocity, and every wander ray."""
    window = dynamic_window(rng.uniform(0.0, P.v_max_mps), rng.uniform(-1.0, 1.0), 0.1, P)
    rays = ray_points(tuple(pose), np.linspace(-math.pi, math.pi, 24, endpoint=False), S_M)
    return np.concatenate([arc_points(tuple(pose), window, S_M), rays])


def both(g: StaticGeometry, pose: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's free distances and the reference's, from every point's clearance."""
    here = clearance_m(g, pose[0], pose[1], RADIUS_M)
    allowed = min(P.margin_m, here)
    walked = np.empty(len(points))
    walked_free_distances(
        np.ascontiguousarray(points), S_M, allowed, here - allowed, g.seg_start, g.seg_delta,
        g.seg_len, g.grid.kernel_input, g.discs, g.rings, RADIUS_M, READ_M, WALK_M, walked,
    )  # fmt: skip
    clearance = clearances_m(g, points.reshape(-1, 2), RADIUS_M).reshape(points.shape[:2])
    return walked, free_distances_reference(clearance, here, S_M, P.margin_m)


@pytest.mark.parametrize("name", sorted(WORLDS))
def test_walking_the_arcs_finds_every_free_distance_the_reference_does(name: str) -> None:
    g = WORLDS[name]
    rng = np.random.default_rng(len(name))
    walked_all, expected_all = [], []
    for pose in random_poses(g, 40, seed=len(name)):
        walked, expected = both(g, pose, arcs_from(pose, rng))
        walked_all.append(walked)
        expected_all.append(expected)
    walked, expected = np.concatenate(walked_all), np.concatenate(expected_all)
    assert walked.tobytes() == expected.tobytes()
    # Arcs blocked at once, part way and free to their end are all among them.
    assert (expected < S_M[0]).any() and (expected == S_M[-1]).any()
    assert ((expected > S_M[0]) & (expected < S_M[-1])).any()


def test_walking_among_crowded_overlapping_patches_finds_the_same() -> None:
    # Patches as the echo memory keeps them: many nearly the same, heard again and again.
    rng = np.random.default_rng(3)
    centres = rng.uniform(0.0, 3.0, (60, 2))
    copies = np.repeat(centres, 12, axis=0) + rng.normal(0.0, 0.01, (720, 2))
    across = rng.normal(size=(720, 2))
    across *= rng.uniform(0.1, 0.4, (720, 1)) / np.linalg.norm(across, axis=1, keepdims=True)
    g = geometry_of(np.hstack([copies - across, copies + across]))
    assert g.grid.columns * g.grid.rows > 1  # bucketed, as a memory's patches are
    for pose in rng.uniform((0.0, 0.0, -math.pi), (3.0, 3.0, math.pi), (30, 3)):
        walked, expected = both(g, pose, arcs_from(pose, rng))
        assert walked.tobytes() == expected.tobytes()
