"""The compiled true clearance is, bit for bit, what the numpy reference computes, on real
worlds at random points."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_references.clearance_reference import clearances_reference
from kernel_worlds import every_world, random_poses

from tvl_cli.sim.clearance_kernel import clearances
from tvl_cli.sim.geometry import clearance_m, clearances_m, geometry_of

WORLDS = every_world()


@pytest.mark.parametrize("name", sorted(WORLDS))
def test_the_kernel_measures_as_the_reference_at_random_points(name: str) -> None:
    g = WORLDS[name]
    points = np.ascontiguousarray(random_poses(g, 500, seed=len(name))[:, :2])
    inputs = (points, g.seg_start, g.seg_delta, g.seg_len, g.grid.kernel_input, g.discs, g.rings,
              0.2, np.inf)  # fmt: skip
    compiled, reference = np.empty(len(points)), np.empty(len(points))
    compiled_which = np.empty(len(points), dtype=np.int64)
    reference_which = np.empty(len(points), dtype=np.int64)
    clearances(*inputs, compiled, compiled_which)
    clearances_reference(*inputs, reference, reference_which)
    assert compiled.tobytes() == reference.tobytes()
    np.testing.assert_array_equal(compiled_which, reference_which)
    assert (compiled_which >= 0).all()
    assert 0.0 < (compiled > 0.0).mean() < 1.0  # points clear of obstacles and touching them
    one_by_one = [clearance_m(g, x, y, 0.2) for x, y in points]
    assert np.array(one_by_one).tobytes() == compiled.tobytes()


def test_no_obstacles_leave_an_infinite_clearance() -> None:
    nothing = geometry_of(np.empty((0, 4)))
    g = nothing
    walls = (g.seg_start, g.seg_delta, g.seg_len, g.grid.kernel_input)
    found, which = np.empty(1), np.empty(1, dtype=np.int64)
    clearances(np.array([[1.0, 2.0]]), *walls, g.discs, g.rings, 0.2, np.inf, found, which)
    assert found[0] == np.inf and which[0] == -1


@pytest.mark.parametrize("name", ["hall", "lab", "circle"])
def test_within_a_limit_the_kernel_measures_as_the_reference(name: str) -> None:
    """Asked only within 0.3 m of each point, the nearer obstacles are measured, and the
    rest read inf: the floor of a world asks no further than the robot's radius."""
    g = WORLDS[name]
    points = np.ascontiguousarray(random_poses(g, 2000, seed=7)[:, :2])
    inputs = (points, g.seg_start, g.seg_delta, g.seg_len, g.grid.kernel_input, g.discs, g.rings,
              0.2, 0.3)  # fmt: skip
    compiled, reference = np.empty(len(points)), np.empty(len(points))
    compiled_which = np.empty(len(points), dtype=np.int64)
    reference_which = np.empty(len(points), dtype=np.int64)
    clearances(*inputs, compiled, compiled_which)
    clearances_reference(*inputs, reference, reference_which)
    assert compiled.tobytes() == reference.tobytes()
    np.testing.assert_array_equal(compiled_which, reference_which)
    unlimited = clearances_m(g, points, 0.2)
    near = unlimited <= 0.1
    assert near.any() and (~near).any()
    np.testing.assert_array_equal(compiled[near], unlimited[near])
    assert (compiled[~near] == np.inf).all() and (compiled_which[~near] == -1).all()
