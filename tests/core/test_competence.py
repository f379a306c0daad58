"""Competence: at most 0.2 contacts per minute at a mean speed of at least 0.3 m/s."""

from __future__ import annotations

import pytest

from tvl_cli.core.competence import is_competent
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_profiles import TURTLEBOT3


def avoid_run(collisions: int, near_misses: int, mean_speed_mps: float) -> RunMetrics:
    contacts = collisions + near_misses
    return RunMetrics(
        sim_s=300.0,
        distance_m=300.0 * mean_speed_mps,
        mean_speed_mps=mean_speed_mps,
        mean_drive_speed_mps=mean_speed_mps,
        collisions=collisions,
        near_misses=near_misses,
        contacts=contacts,
        contacts_per_min=contacts / 5.0,
        collisions_per_min=collisions / 5.0,
        backoffs=near_misses,
        spins=0,
        trapped=0,
        mean_clearance_m=0.5,
        mean_wall_clearance_m=None,
        goal_reached=False,
        time_to_goal_s=None,
    )


@pytest.mark.parametrize(
    ("collisions", "near_misses", "mean_speed_mps", "competent"),
    [
        (1, 0, 0.3, True),
        (0, 1, 0.3, True),
        (0, 0, 0.6, True),
        (2, 0, 0.5, False),
        (0, 2, 0.5, False),  # near misses count: backing off is not competence
        (1, 1, 0.5, False),
        (0, 0, 0.29, False),
    ],
)
def test_competence_needs_few_contacts_and_enough_speed(
    collisions: int, near_misses: int, mean_speed_mps: float, competent: bool
) -> None:
    assert is_competent(avoid_run(collisions, near_misses, mean_speed_mps)) is competent


def test_the_speed_asked_is_half_the_robots_top_speed() -> None:
    fastest = max(TURTLEBOT3.v_max_mps)  # 0.22 m/s
    assert is_competent(avoid_run(0, 0, 0.11), fastest)
    assert not is_competent(avoid_run(0, 0, 0.109), fastest)
    assert not is_competent(avoid_run(0, 0, 0.29))  # the paper's robot's, by default
