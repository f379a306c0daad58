"""Learning while behaving (`tvl run --learn`): the online experiment's settings and
conditions, each run's contacts a minute in each of its minutes, and its table."""

from __future__ import annotations

from collections.abc import Iterable

from tvl_cli.analysis.aggregation import distinct, mean, seed_interval, select
from tvl_cli.analysis.result_rows import Row
from tvl_cli.analysis.result_text import interval_text, number

# The online experiment's runs (their `online`): the FAM fixed, or learning while behaving
# (`tvl run --learn`), by their labels.
ONLINE_SETTINGS = {False: "fixed", True: "learns"}


def minute_rates(run: Row) -> list[float]:
    """A run's contacts a minute in each of its simulated minutes (`tvl run --json`'s
    `minutes`; a last, partial minute counted at its own length)."""
    return [m["contacts"] * 60.0 / m["sim_s"] for m in run["minutes"] if m["sim_s"]]


def online_conditions(rows: Iterable[Row]) -> list[tuple[float, float]]:
    """(exploration minutes before behaving, threshold) of the online experiment's runs."""
    runs = select(rows, kind="tvl", online=tuple(ONLINE_SETTINGS))
    return [
        (start, threshold)
        for start in distinct(runs, "minute")
        for threshold in distinct(select(runs, minute=start), "threshold")
    ]


def online_rows(rows: list[Row]) -> list[list[str]]:
    """Per start, threshold and setting: contacts a minute in the runs' first and last
    minutes and over the whole run, speed, and the episodes learnt while behaving."""
    table = []
    for start, threshold in online_conditions(rows):
        for setting, label in ONLINE_SETTINGS.items():
            runs = select(rows, kind="tvl", online=setting, minute=start, threshold=threshold)
            if not runs:
                continue
            rates = [minute_rates(r) for r in runs]
            learnt = [r["learnt"]["episodes"] for r in runs if "learnt" in r]
            table.append(
                [
                    f"{start:g}",
                    f"{threshold:g}",
                    label,
                    number(mean(r[0] for r in rates if r)),
                    number(mean(r[-1] for r in rates if r)),
                    interval_text(seed_interval(runs, "contacts_per_min")),
                    interval_text(seed_interval(runs, "mean_speed_mps")),
                    f"{mean(learnt):.0f}" if learnt else "–",
                    str(len(runs)),
                ]
            )
    return table


ONLINE_HEADER = (
    "explored, min",
    "threshold",
    "FAM",
    "first minute contacts/min",
    "last minute contacts/min",
    "whole run contacts/min",
    "speed m/s",
    "episodes learnt",
    "runs",
)
