"""The exploration experiment's numbers (experiments/grids/exploration.toml): coverage while
learning and time to competence, by the rule that chose where to learn (`tvl learn --explore`).

Its learn cells carry `exploration`, `near_m` (where the sonar places collision points; 0:
bumps alone) and the per-minute rows `tvl replay --json` prints, with their `coverage`; its
avoid runs carry `exploration` and `minute`, the length of learning their FAM had.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from tvl_cli.analysis.aggregation import distinct, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.time_to_competence import competence_times, describe_competence

# The coverage asked of 45 minutes' learning in the lab.
COVERAGE_GOAL = 0.9
# Learning minutes at which the coverage table reads the curves.
COVERAGE_READINGS_MIN = (5, 15, 45)


def coverage_curve(run: Row) -> np.ndarray:
    """(M,) a learn run's coverage at the end of each of its minutes, first to last."""
    return np.array([m["coverage"] for m in run["minutes"]], dtype=float)


def mean_curve(runs: Iterable[Row]) -> np.ndarray:
    """(M,) the mean coverage of the runs at the end of each minute all of them reached."""
    curves = [coverage_curve(r) for r in runs]
    shortest = min((len(c) for c in curves), default=0)
    if not shortest:
        return np.zeros(0)
    return np.mean([c[:shortest] for c in curves], axis=0)


def minute_reaching(curve: np.ndarray, goal: float) -> float | None:
    """The first learning minute at whose end the coverage reached the goal; None if none."""
    reached = np.flatnonzero(curve >= goal)
    return float(reached[0] + 1) if len(reached) else None


def collision_points(near_m: float | None) -> str:
    """How a row's learner placed its collision points, in words."""
    return "bumps" if near_m == 0 else "sonar"


def coverage_rows(rows: list[Row], worlds: tuple[str, ...]) -> list[list[str]]:
    """Per collision-point setting and rule, over the learn runs in these worlds: the mean
    coverage (lowest–highest of the runs) at each reading, and when the goal was reached."""
    learnt = select(rows, kind="learn", world=worlds)
    table = []
    for near_m in distinct(learnt, "near_m"):
        for rule in distinct(learnt, "exploration"):
            curves = [coverage_curve(r) for r in select(learnt, near_m=near_m, exploration=rule)]
            cells = []
            for minute in COVERAGE_READINGS_MIN:
                at = [c[minute - 1] for c in curves if len(c) >= minute]
                cells.append(
                    f"{100 * np.mean(at):.0f} % ({100 * min(at):.0f}–{100 * max(at):.0f})"
                    if at
                    else "–"
                )
            horizon = max((len(c) for c in curves), default=None)
            times = [minute_reaching(c, COVERAGE_GOAL) for c in curves]
            table.append(
                [collision_points(near_m), rule, *cells, describe_competence(times, horizon)]
            )
    return table


COVERAGE_HEADER = (
    "collision points",
    "rule",
    *(f"coverage at {m} min" for m in COVERAGE_READINGS_MIN),
    f"{100 * COVERAGE_GOAL:.0f} % covered at, min (trials)",
)


def competence_rows(rows: list[Row]) -> tuple[list[str], list[list[str]]]:
    """Header and body: per rule, the time to competence in each world and in all of them
    (the mean over the trials that became competent, and how many did)."""
    snapshots = select(rows, kind="tvl", behaviour="avoid")
    worlds = distinct(snapshots, "world", ("lab",))
    horizon = max((r["minute"] for r in snapshots), default=None)
    header = ["rule", *worlds, "all worlds"]
    body = []
    for rule in distinct(snapshots, "exploration"):
        # A snapshot's learning length is the minute time to competence reads.
        runs = select(snapshots, exploration=rule)
        cells = [
            describe_competence(competence_times(select(runs, world=world)), horizon)
            for world in worlds
        ]
        every = [t for world in worlds for t in competence_times(select(runs, world=world))]
        body.append([rule, *cells, describe_competence(every, horizon)])
    return header, body
