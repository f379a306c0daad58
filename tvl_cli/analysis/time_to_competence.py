"""Time to competence: whether an avoid run passes the competence test, the first learning
minute whose snapshot FAM's run does in each trial, and how the tables state it."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import fields

from tvl_cli.analysis.aggregation import by_trial
from tvl_cli.analysis.result_rows import Row
from tvl_cli.core import competence
from tvl_cli.core.metrics import RunMetrics


def is_competent(run: Row) -> bool:
    """Whether an avoid run (its `tvl run --json` keys) passes the competence test."""
    return competence.is_competent(RunMetrics(**{f.name: run[f.name] for f in fields(RunMetrics)}))


def time_to_competence(snapshots: Iterable[Row]) -> float | None:
    """Time to competence: the first learning minute whose snapshot FAM's avoid run is
    competent; None if none is."""
    competent = [row["minute"] for row in snapshots if is_competent(row)]
    return min(competent) if competent else None


def competence_times(snapshots: Iterable[Row]) -> list[float | None]:
    """Time to competence of each trial (seed) of a set of snapshot avoid runs."""
    return [time_to_competence(rows) for _, rows in sorted(by_trial(snapshots).items())]


def describe_competence(times: Sequence[float | None], horizon_min: float | None) -> str:
    """'7.3 (3/3)': the mean over the trials that became competent, and how many did."""
    reached = [t for t in times if t is not None]
    if not times:
        return "–"
    if not reached:
        within = f" {horizon_min:g}" if horizon_min is not None else ""
        return f"not within{within} min (0/{len(times)})"
    return f"{sum(reached) / len(reached):.1f} ({len(reached)}/{len(times)})"


COMPETENCE_NOTE = (
    f"Time to competence: the first learning minute after which an avoid run of "
    f"{competence.COMPETENCE_RUN_MINUTES:g} simulated minutes has at most "
    f"{competence.MAX_CONTACTS_PER_MIN:g} contacts (collisions and near misses) a minute "
    f"and a mean speed of at least "
    f"{competence.MIN_MEAN_SPEED_MPS:g} m/s.\n"
)


def competence_note(rows: Iterable[Row]) -> str:
    """The definition, and a warning when the avoid runs were not of the definition's length."""
    lengths = {r["run_minutes"] for r in rows if r.get("behaviour") == "avoid"}
    other = sorted(m for m in lengths if m != competence.COMPETENCE_RUN_MINUTES)
    if not other:
        return COMPETENCE_NOTE
    minutes = ", ".join(f"{m:g}" for m in other)
    return COMPETENCE_NOTE + f"These avoid runs lasted {minutes} min: not a competence result.\n"


def qlearn_checks(qlearn: Iterable[Row]) -> list[Row]:
    """Q-learning's competence checks (greedy avoid runs during learning), with their seed and
    `minute` the learning minutes before the check."""
    return [
        {**check, "minute": check["learn_minutes"], "seed": row["seed"]}
        for row in qlearn
        for check in row.get("competence_checks", [])
    ]
