"""The echo memory's compiled kernels agree with their numpy references: keeping echoes, on
random readings into a buffer that wraps round, and the cast, on random memories."""

from __future__ import annotations

import math

import numpy as np
import pytest
from kernel_references.memory_reference import (
    remember_echoes_reference,
    remembered_ranges_reference,
)

from tvl_cli.agent.memory_kernel import remember_echoes, remembered_ranges
from tvl_cli.core.memory import PATCHES, POINTS
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.sonar import SonarRing

ROBOT = RobotConfig()
RING = SonarRing(ROBOT.sonar, ROBOT.radius_m)
HALF_CONE = math.radians(ROBOT.sonar.cone_deg) / 2.0


@pytest.mark.parametrize("clearing", [False, True])
@pytest.mark.parametrize("within_m", [None, 2.0, "live"])
@pytest.mark.parametrize("kind", [POINTS, PATCHES])
def test_the_kernel_casts_as_the_reference_does(
    kind: str, within_m: object, clearing: bool
) -> None:
    rng = np.random.default_rng(5)
    met = unmet = differs = 0
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
        # Each beam cleared of the echoes wider than 0.2 m either side, or of all of them, or
        # of none; or every beam meets every echo.
        limits = rng.choice([0.2, 0.0, np.inf], 16) if clearing else None
        memory = (centres, axes, half_widths, heard, 50, within, limits)
        compiled = remembered_ranges(*args, *memory)
        reference = remembered_ranges_reference(*args, *memory)
        np.testing.assert_allclose(compiled, reference, rtol=0, atol=1e-12)
        met += int(np.isfinite(reference).sum())
        unmet += int(np.isinf(reference).sum())
        whole = remembered_ranges_reference(*args, *memory[:-1])
        differs += int((reference != whole).sum())
    assert met > 500  # most casts met something: the comparison was not of empty memories
    # Looking no farther than given left some beams with nothing, as the reference.
    assert within_m is None or unmet > 100
    # Clearing changed what some beams met; without it, nothing changed.
    assert (differs > 50) if clearing else differs == 0


def test_the_kernel_keeps_echoes_as_the_reference_does() -> None:
    rng = np.random.default_rng(6)
    slots = 40  # fewer than a few readings' echoes: the buffer wraps round
    buffers = [
        (np.zeros((slots, 2)), np.zeros((slots, 2)), np.zeros(slots), np.full(slots, -1))
        for _ in range(2)
    ]
    next_slots = [0, 0]
    kept = at_range = 0
    for step in range(60):
        origins, directions = RING.rays(tuple(rng.uniform((-1, -1, -4), (1, 1, 4))))
        ring = rng.uniform(ROBOT.sonar.min_range_m, 5.0, 16)
        ring[rng.random(16) < 0.3] = ROBOT.sonar.max_range_m  # heard nothing
        ring[rng.random(16) < 0.1] = 3.0  # at the memory's range: kept
        reading = (origins, directions, ROBOT.sonar.rays_per_beam, ring, ROBOT.sonar.max_range_m)
        settings = (3.0, math.tan(HALF_CONE), 0.15, step)
        for i, keep in enumerate((remember_echoes, remember_echoes_reference)):
            next_slots[i] = keep(*reading, *settings, *buffers[i], next_slots[i])
        assert next_slots[0] == next_slots[1]
        for compiled, reference in zip(*buffers, strict=True):
            assert compiled.tobytes() == reference.tobytes()
        kept += int(((ring < ROBOT.sonar.max_range_m) & (ring <= 3.0)).sum())
        at_range += int((ring == 3.0).sum())
    assert kept > 3 * slots  # it wrapped round several times
    assert at_range > 0
    assert (buffers[0][2] > 0.15).any() and (buffers[0][2] == 0.15).any()  # both widths
