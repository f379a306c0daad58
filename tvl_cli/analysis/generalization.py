"""The generalization benchmark's figures from its rows (`tvl bench generalization`): for each
entry (ours, a reference, a controller) and configuration, the runs competent, goals
reached, contacts a minute and avoid speed, each share and mean with its 95 % interval over
the trials, beside the targets; the contact autopsy of the FAM-driven runs; and, world by
world, the runs competent and their mean speed (`--by-world`): where the runs fail.

A trial's figure is over every run of that trial (every world and behaviour); the interval
is Student's t over the trials' figures, as a sweep's intervals are over its seeds.
"""

from __future__ import annotations

import statistics
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from tvl_cli.analysis.autopsy import tally
from tvl_cli.analysis.intervals import Interval, interval

Row = dict[str, Any]

# The targets (SPEC §10): competent runs and goals reached, each configuration; contacts a
# minute; the multi FAM no less safe than the single; avoid speed against the map's DWA.
MIN_COMPETENT_SHARE = 0.9
MIN_GOAL_SHARE = 0.9
MAX_CONTACTS_PER_MIN = 0.1
MIN_SPEED_OF_DWA = 0.8
# The reference whose avoid speed is the speed reference.
SPEED_REFERENCE = "dwa-map"
# The method's ceiling: the decision rule fed the true velocities; each configuration within
# this many points of its competent share.
CEILING_REFERENCE = "oracle-velocities"
MAX_BELOW_CEILING = 0.03


@dataclass(frozen=True, slots=True)
class Figures:
    """One entry's runs with one configuration (None: a controller without one)."""

    entry: str
    role: str
    reads_map: bool
    method: str | None
    config: str | None
    runs: int
    competent: int
    by_behaviour: dict[str, tuple[int, int]]  # behaviour -> (competent, runs)
    goal_runs: int
    goals_reached: int
    competent_share: Interval | None  # over trials
    goal_share: Interval | None
    contacts_per_min: Interval | None
    avoid_speed_mps: Interval | None
    avoid_speed_of_reference: float | None  # avoid speed / the map DWA's in the same worlds
    autopsy: dict[str, Any] | None  # causes, time, goal failures summed (FAM-driven runs)
    # Its competent share below the oracle velocities' (None: no oracle among the rows).
    below_ceiling: float | None = None

    def to_dict(self) -> dict[str, Any]:
        def shown(found: Interval | None) -> dict[str, Any] | None:
            if found is None:
                return None
            return {"mean": found.mean, "half_width": found.half_width, "n": found.n}

        return {
            "entry": self.entry,
            "role": self.role,
            "reads_map": self.reads_map,
            "method": self.method,
            "config": self.config,
            "runs": self.runs,
            "competent": self.competent,
            "by_behaviour": [
                {"behaviour": b, "competent": c, "runs": n}
                for b, (c, n) in self.by_behaviour.items()
            ],
            "goal_runs": self.goal_runs,
            "goals_reached": self.goals_reached,
            "competent_share": shown(self.competent_share),
            "goal_share": shown(self.goal_share),
            "contacts_per_min": shown(self.contacts_per_min),
            "avoid_speed_mps": shown(self.avoid_speed_mps),
            "avoid_speed_of_reference": self.avoid_speed_of_reference,
            "autopsy": self.autopsy,
            "below_ceiling": self.below_ceiling,
        }


def summarise(rows: Sequence[Row], behaviours: Sequence[str]) -> list[Figures]:
    """Each entry's figures with each configuration, in the order the rows first give them."""
    groups: dict[tuple[str, str | None], list[Row]] = {}
    for row in rows:
        groups.setdefault((row["entry"], row.get("config")), []).append(row)
    reference = _avoid_speeds(r for r in rows if r["entry"] == SPEED_REFERENCE)
    figures = [_figures(runs, behaviours, reference) for runs in groups.values()]
    ceiling = next((f for f in figures if f.entry == CEILING_REFERENCE), None)
    if ceiling is None:
        return figures
    top = ceiling.competent / ceiling.runs if ceiling.runs else 0.0
    return [
        replace(f, below_ceiling=top - f.competent / f.runs if f.runs else None) for f in figures
    ]


@dataclass(frozen=True, slots=True)
class WorldFigures:
    """One entry's runs with one configuration in one world, every behaviour and trial."""

    competent: int
    runs: int
    mean_speed_mps: float  # over the runs, each run's mean speed


def by_world(rows: Sequence[Row]) -> dict[tuple[str, str | None], dict[str, WorldFigures]]:
    """(entry, configuration) -> world -> its figures there, in the order the rows first
    give each."""
    groups: dict[tuple[str, str | None], dict[str, list[Row]]] = {}
    for row in rows:
        key = (row["entry"], row.get("config"))
        groups.setdefault(key, {}).setdefault(row["world"], []).append(row)
    return {
        key: {
            world: WorldFigures(
                competent=sum(bool(r["competent"]) for r in runs),
                runs=len(runs),
                mean_speed_mps=statistics.fmean(r["mean_speed_mps"] for r in runs),
            )
            for world, runs in worlds.items()
        }
        for key, worlds in groups.items()
    }


def _figures(runs: list[Row], behaviours: Sequence[str], reference: dict[str, float]) -> Figures:
    first = runs[0]
    goals = [r for r in runs if r["behaviour"] == "goal"]
    avoid = _avoid_speeds(runs)
    shared = [w for w in avoid if w in reference]
    autopsies = [r["autopsy"] for r in runs if r.get("autopsy") is not None]
    return Figures(
        entry=first["entry"],
        role=first["role"],
        reads_map=bool(first["reads_map"]),
        method=first.get("method"),
        config=first.get("config"),
        runs=len(runs),
        competent=sum(bool(r["competent"]) for r in runs),
        by_behaviour={
            b: (
                sum(bool(r["competent"]) for r in runs if r["behaviour"] == b),
                sum(r["behaviour"] == b for r in runs),
            )
            for b in behaviours
            if any(r["behaviour"] == b for r in runs)
        },
        goal_runs=len(goals),
        goals_reached=sum(bool(r["goal_reached"]) for r in goals),
        competent_share=_over_trials(runs, lambda rs: _share(r["competent"] for r in rs)),
        goal_share=_over_trials(goals, lambda rs: _share(r["goal_reached"] for r in rs)),
        contacts_per_min=_over_trials(
            runs, lambda rs: statistics.fmean(r["contacts_per_min"] for r in rs)
        ),
        avoid_speed_mps=_over_trials(
            [r for r in runs if r["behaviour"] == "avoid"],
            lambda rs: statistics.fmean(r["mean_speed_mps"] for r in rs),
        ),
        avoid_speed_of_reference=_ratio(avoid, reference, shared),
        autopsy=tally(autopsies) if autopsies else None,
    )


def _ratio(
    speeds: dict[str, float], reference: dict[str, float], worlds: list[str]
) -> float | None:
    """The mean speed over the worlds both ran in, as a share of the reference's there."""
    if not worlds or not any(reference[w] for w in worlds):
        return None
    return statistics.fmean(speeds[w] for w in worlds) / statistics.fmean(
        reference[w] for w in worlds
    )


def _share(flags: Iterable[Any]) -> float:
    values = [bool(f) for f in flags]
    return sum(values) / len(values)


def _over_trials(runs: list[Row], figure: Any) -> Interval | None:
    """The figure of each trial's runs, and its mean and 95 % interval over the trials."""
    trials: dict[int, list[Row]] = {}
    for row in runs:
        trials.setdefault(row["seed"], []).append(row)
    return interval([figure(members) for members in trials.values()])


def _avoid_speeds(rows: Iterable[Row]) -> dict[str, float]:
    """Each world's mean avoid speed over its trials."""
    worlds: dict[str, list[float]] = {}
    for row in rows:
        if row["behaviour"] == "avoid":
            worlds.setdefault(row["world"], []).append(row["mean_speed_mps"])
    return {world: statistics.fmean(speeds) for world, speeds in worlds.items()}
