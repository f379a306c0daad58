"""Competence: at most 0.2 collisions per minute at a mean speed of at least 0.3 m/s."""

from __future__ import annotations

import pytest

from tvl_cli.core.competence import is_competent
from tvl_cli.core.metrics import RunMetrics


def avoid_run(collisions_per_min: float, mean_speed_mps: float) -> RunMetrics:
    return RunMetrics(
        300.0,
        300.0 * mean_speed_mps,
        mean_speed_mps,
        0,
        collisions_per_min,
        0.5,
        None,
        False,
        None,
        0,
    )


@pytest.mark.parametrize(
    ("collisions_per_min", "mean_speed_mps", "competent"),
    [(0.2, 0.3, True), (0.0, 0.6, True), (0.4, 0.5, False), (0.0, 0.29, False)],
)
def test_competence_needs_few_collisions_and_enough_speed(
    collisions_per_min: float, mean_speed_mps: float, competent: bool
) -> None:
    assert is_competent(avoid_run(collisions_per_min, mean_speed_mps)) is competent
