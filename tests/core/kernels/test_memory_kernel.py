"""The echo memory's compiled cast agrees with its numpy reference on random memories."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tvl_cli.core.kernels.memory import remembered_ranges
from tvl_cli.core.kernels.memory_reference import remembered_ranges_reference
from tvl_cli.core.memory import PATCHES, POINTS
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.sonar import SonarRing

ROBOT = RobotConfig()
RING = SonarRing(ROBOT.sonar, ROBOT.radius_m)
HALF_CONE = math.radians(ROBOT.sonar.cone_deg) / 2.0


@pytest.mark.parametrize("within_m", [None, 2.0, "live"])
@pytest.mark.parametrize("kind", [POINTS, PATCHES])
def test_the_kernel_casts_as_the_reference_does(kind: str, within_m: object) -> None:
    rng = np.random.default_rng(5)
    met = unmet = 0
    for _ in range(150):
        origins, directions = RING.rays(tuple(rng.uniform((-1, -1, -4), (1, 1, 4))))
        echoes = int(rng.integers(0, 400))
        centres = rng.uniform(-3.0, 3.0, (echoes, 2))  # metres
        axes = rng.normal(size=(echoes, 2))
        axes /= np.linalg.norm(axes, axis=1)[:, None]
        half_widths = rng.uniform(0.05, 0.5, echoes)  # metres
        heard = rng.integers(0, 100, echoes)  # steps
        args = (kind, origins, directions, ROBOT.sonar.rays_per_beam, HALF_CONE)
        # How far to look: anywhere, 2 m in every beam, or a ring's random readings.
        within = (
            None
            if within_m is None
            else np.full(16, 2.0)
            if within_m == 2.0
            else rng.uniform(0.15, 4.0, 16)
        )
        memory = (centres, axes, half_widths, heard, 50, within)
        compiled = remembered_ranges(*args, *memory)
        reference = remembered_ranges_reference(*args, *memory)
        np.testing.assert_allclose(compiled, reference, rtol=0, atol=1e-12)
        met += int(np.isfinite(reference).sum())
        unmet += int(np.isinf(reference).sum())
    assert met > 500  # most casts met something: the comparison was not of empty memories
    # Looking no farther than given left some beams with nothing, as the reference.
    assert within_m is None or unmet > 100
