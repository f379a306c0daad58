"""The exploration experiment's tables from hand-made result rows."""

from __future__ import annotations

import numpy as np
from test_results import run_row

from tvl_cli.analysis.exploration import (
    competence_rows,
    coverage_rows,
    mean_curve,
    minute_reaching,
)


def learn(rule: str, seed: int, coverage: list[float], near_m: float = 0.16) -> dict:
    minutes = [{"minute": float(m), "coverage": c} for m, c in enumerate(coverage)]
    return {
        "kind": "learn",
        "world": "lab",
        "exploration": rule,
        "near_m": near_m,
        "seed": seed,
        "minutes": minutes,
    }


def avoid(rule: str, world: str, seed: int, learnt: float, competent: bool) -> dict:
    return run_row(
        kind="tvl",
        world=world,
        exploration=rule,
        seed=seed,
        minute=learnt,
        mean_speed_mps=0.4 if competent else 0.1,
    )


def test_the_goal_is_reached_at_the_end_of_the_first_minute_at_or_above_it() -> None:
    assert minute_reaching(np.array([0.5, 0.89, 0.9, 0.95]), 0.9) == 3.0
    assert minute_reaching(np.array([0.5, 0.89]), 0.9) is None


def test_the_mean_curve_stops_at_the_shortest_run() -> None:
    runs = [learn("random", 1, [0.2, 0.4, 0.6]), learn("random", 2, [0.4, 0.6])]
    np.testing.assert_allclose(mean_curve(runs), [0.3, 0.5])


def test_coverage_rows_read_each_rule_at_5_15_and_45_minutes() -> None:
    slow = [0.01 * m for m in range(1, 46)]  # 45 % after 45 minutes
    fast = [min(1.0, 0.1 * m) for m in range(1, 46)]  # 90 % after 9 minutes
    rows = [learn("least-experience", 1, slow), learn("novelty", 1, fast)]
    never = "not within 45 min (0/1)"
    assert coverage_rows(rows, ("lab",)) == [
        ["sonar", "least-experience", "5 % (5–5)", "15 % (15–15)", "45 % (45–45)", never],
        ["sonar", "novelty", "50 % (50–50)", "100 % (100–100)", "100 % (100–100)", "9.0 (1/1)"],
    ]


def test_time_to_competence_is_the_shortest_learning_that_made_avoid_competent() -> None:
    rows = [
        avoid("novelty", "lab", 1, 5, False),
        avoid("novelty", "lab", 1, 15, True),
        avoid("novelty", "lab", 1, 45, True),
        avoid("novelty", "rooms-1001", 1, 5, True),
        avoid("random", "lab", 1, 5, False),
        avoid("random", "lab", 1, 45, False),
        avoid("random", "rooms-1001", 1, 45, True),
    ]
    header, body = competence_rows(rows)
    assert header == ["rule", "lab", "rooms-1001", "all worlds"]
    assert body == [
        ["novelty", "15.0 (1/1)", "5.0 (1/1)", "10.0 (2/2)"],
        ["random", "not within 45 min (0/1)", "45.0 (1/1)", "45.0 (1/2)"],
    ]
