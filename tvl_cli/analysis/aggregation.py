"""Result rows selected and averaged over the trials: the rows with given values, a key's
values in order, each trial's rows, and means with their 95 % intervals, alone or along a
curve.

Trials are the seeds; figures show their mean and 95 % interval, tables their mean ± that
interval.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from tvl_cli.analysis.intervals import Interval, interval
from tvl_cli.analysis.result_rows import Row


def select(rows: Iterable[Row], **where: Any) -> list[Row]:
    """The rows whose keys have the given values (a tuple: any of its values)."""
    return [row for row in rows if all(_is(row.get(key), value) for key, value in where.items())]


def _is(value: Any, wanted: Any) -> bool:
    return value in wanted if isinstance(wanted, tuple) else value == wanted


def distinct(rows: Iterable[Row], key: str, order: Sequence[Any] = ()) -> list[Any]:
    """The values of `key` in `order` first, then the others sorted."""
    present = {row[key] for row in rows if row.get(key) is not None}
    return [v for v in order if v in present] + sorted(present - set(order))


def mean(values: Iterable[float | None]) -> float | None:
    """The mean of the values that are not None; None if there are none."""
    known = [v for v in values if v is not None]
    return sum(known) / len(known) if known else None


def seed_interval(rows: Iterable[Row], key: str) -> Interval | None:
    """The mean of `key` over the seeds (each seed's rows averaged first: the wall sides of a
    threshold, say) and its 95 % interval; None if no row has it."""
    by_seed: dict[Any, list[float | None]] = {}
    for row in rows:
        by_seed.setdefault(row.get("seed"), []).append(row.get(key))
    means = [mean(values) for values in by_seed.values()]
    return interval([m for m in means if m is not None])


def curve(rows: Iterable[Row], x: str, y: str) -> tuple[np.ndarray, np.ndarray]:
    """Mean of `y` over the trials at each value of `x`: (K,), (K,) arrays."""
    xs, means, _ = curve_band(rows, x, y)
    return xs, means


def curve_band(rows: Iterable[Row], x: str, y: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean of `y` over the trials (seeds) at each value of `x`, and the half width of its
    95 % interval (NaN from one trial): (K,), (K,), (K,) arrays."""
    by_x: dict[float, list[Row]] = {}
    for row in rows:
        by_x.setdefault(row[x], []).append(row)
    points = [(v, seed_interval(by_x[v], y)) for v in sorted(by_x)]
    known = [(v, shown) for v, shown in points if shown is not None]
    return (
        np.array([v for v, _ in known], dtype=float),
        np.array([shown.mean for _, shown in known], dtype=float),
        np.array([np.nan if s.half_width is None else s.half_width for _, s in known], dtype=float),
    )


def by_trial(rows: Iterable[Row]) -> dict[int, list[Row]]:
    trials: dict[int, list[Row]] = {}
    for row in rows:
        trials.setdefault(row["seed"], []).append(row)
    return trials


def final_runs(snapshots: Iterable[Row]) -> list[Row]:
    """Each trial's run with its last snapshot FAM."""
    return [max(rows, key=lambda r: r["minute"]) for rows in by_trial(snapshots).values()]


def learning_minutes(rows: Iterable[Row]) -> list[Row]:
    """The per-minute rows (minute, delta_v, collisions, ...) of every learn record, with its
    seed and world; `minute` counted from 1, so it is also when that minute ended."""
    return [
        {**minute, "seed": row["seed"], "world": row["world"]}
        for row in rows
        if row["kind"] == "learn"
        for minute in row.get("minutes", [])
    ]
