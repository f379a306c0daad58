"""The compiled sonar ring reads as the numpy reference does, on real worlds at random poses,
for one robot a call or many."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
import pytest
from kernel_references.ring_reference import ring_ranges_reference
from kernel_worlds import every_world, random_poses

from tvl_cli.core.robot_config import SONAR_MODELS, SonarConfig
from tvl_cli.sim.geometry import StaticGeometry
from tvl_cli.sim.ring_kernel import ring_ranges
from tvl_cli.sim.sonar import SonarRing

WORLDS = every_world()
POSES = 300
# Readings agree this closely: numpy's matrix products may fuse a multiply and an add.
AGREE_M = 1e-12


def cast_with_sources(
    ranges: Callable[..., None],
    ring: SonarRing,
    geometry: StaticGeometry,
    poses: np.ndarray,
    noise: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """(N, 16) metres read at poses (N, 3) by a ring kernel, compiled or not, and (N, 16)
    the obstacles the beams heard."""
    readings = np.empty((len(poses), 16))
    sources = np.empty((len(poses), 16), dtype=np.int64)
    ranges(*ring.cast_inputs(geometry, poses, noise), readings, sources)
    return readings, sources


def cast(
    ranges: Callable[..., None],
    ring: SonarRing,
    geometry: StaticGeometry,
    poses: np.ndarray,
    noise: np.ndarray,
) -> np.ndarray:
    """(N, 16) metres read at poses (N, 3) by a ring kernel, compiled or not."""
    return cast_with_sources(ranges, ring, geometry, poses, noise)[0]


@pytest.mark.slow
@pytest.mark.parametrize("model", sorted(SONAR_MODELS))
@pytest.mark.parametrize("name", sorted(WORLDS))
def test_the_kernel_reads_as_the_reference_at_random_poses(name: str, model: str) -> None:
    geometry = WORLDS[name]
    ring = SonarRing(SONAR_MODELS[model], 0.2)
    poses = random_poses(geometry, POSES, seed=len(name))
    noise = np.random.default_rng(1).standard_normal((POSES, 16))
    (compiled, heard), (reference, expected) = (
        cast_with_sources(ring_ranges, ring, geometry, poses, noise),
        cast_with_sources(ring_ranges_reference, ring, geometry, poses, noise),
    )
    np.testing.assert_allclose(compiled, reference, rtol=0.0, atol=AGREE_M)
    assert (reference < SONAR_MODELS[model].max_range_m).mean() > 0.05  # echoes were heard
    np.testing.assert_array_equal(heard, expected)
    # A beam that heard nothing reads the maximum range, and every shorter reading names its
    # obstacle (noise may still push a far echo out to the maximum).
    silent = heard < 0
    assert (reference[silent] == SONAR_MODELS[model].max_range_m).all()
    assert (heard[reference < SONAR_MODELS[model].max_range_m] >= 0).all()


def test_many_robots_in_one_call_read_as_each_alone() -> None:
    geometry = WORLDS["hall"]
    ring = SonarRing(SonarConfig(edge_echo_range_m=1.0), 0.2)
    poses = random_poses(geometry, 64, seed=8)
    noise = np.random.default_rng(2).standard_normal((64, 16))
    together = ring.ranges(geometry, poses, noise)
    alone = [ring.ranges(geometry, poses[i : i + 1], noise[i : i + 1])[0] for i in range(64)]
    assert together.tobytes() == np.array(alone).tobytes()
    # The rays walked cells, each holding a few of the walls.
    assert geometry.grid.columns * geometry.grid.rows > 1
    assert np.diff(geometry.grid.first).max() < len(geometry.seg_len) / 10


def test_a_read_draws_its_noise_from_the_generator_as_before() -> None:
    geometry = WORLDS["lab"]
    ring = SonarRing(SonarConfig(), 0.2)
    pose = (2.0, 1.5, 0.4)
    read = ring.read(geometry, pose, np.random.default_rng(7))
    noise = np.random.default_rng(7).standard_normal(16)[None, :]
    expected = cast(ring_ranges_reference, ring, geometry, np.array([pose]), noise)[0]
    np.testing.assert_allclose(read, expected, rtol=0.0, atol=AGREE_M)


def test_per_wall_roughness_is_each_walls_own() -> None:
    # The lab rough on one wall only: a grazing view of it is heard, of the others not.
    geometry = WORLDS["lab"]
    ring = SonarRing(dataclasses.replace(SonarConfig(), noise_sigma_m=0.0, noise_fraction=0.0), 0.2)
    poses = random_poses(geometry, 400, seed=3)
    noise = np.zeros((400, 16))
    smooth = ring.ranges(geometry, poses, noise)
    one_rough = dataclasses.replace(geometry, seg_roughness=geometry.seg_roughness.copy())
    one_rough.seg_roughness[7] = 1.0
    rough = ring.ranges(one_rough, poses, noise)
    expected = cast(ring_ranges_reference, ring, one_rough, poses, noise)
    np.testing.assert_allclose(rough, expected, rtol=0.0, atol=AGREE_M)
    assert (rough < smooth).any() and not (rough > smooth).any()
