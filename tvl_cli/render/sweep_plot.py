"""A sweep's plot: a measure's mean with its 95 % interval as error bars, against a grid key,
one line of points for each value of another."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from tvl_cli.analysis.intervals import Interval
from tvl_cli.render.formats import save_picture

FIGURE_SIZE_IN = (6.4, 4.2)
# Side by side at one x, the lines' points spread over this share of the gap between x
# values, so that their error bars do not hide each other.
DODGE = 0.2
MAX_TICKS = 12  # numbers on x up to this many are each a tick; more, matplotlib's own


def draw_intervals(
    series: dict[Any, list[tuple[Any, Interval]]],
    x_label: str,
    y_label: str,
    hue_label: str | None,
    title: str,
    path: Path,
) -> None:
    """Each series (hue -> its (x, interval) points) as points with error bars, joined by a
    line where x is a number; written to `path` in the format its extension names. Words
    on x (worlds, configurations) stand evenly spaced in the order they come."""
    xs = [x for points in series.values() for x, _ in points]
    numeric = all(isinstance(x, int | float) and not isinstance(x, bool) for x in xs)
    categories = list(dict.fromkeys(xs))
    gaps = np.diff(sorted(categories)) if numeric else np.ones(1)
    gap = float(gaps.min()) if len(gaps) else 1.0
    figure = Figure(figsize=FIGURE_SIZE_IN, layout="constrained")
    ax = figure.subplots()
    for index, (hue, points) in enumerate(series.items()):
        shift = DODGE * gap * (index / (len(series) - 1) - 0.5) if len(series) > 1 else 0.0
        if numeric:
            points = sorted(points, key=lambda point: point[0])
            where = np.array([x for x, _ in points], dtype=float) + shift
        else:
            where = np.array([categories.index(x) + shift for x, _ in points])
        means = [shown.mean for _, shown in points]
        # Below and above each mean, to the interval's ends (cut at what the measure can be).
        # A point of one seed has no interval: no bar, rather than a bar of nought.
        below = [np.nan if s.low is None else s.mean - s.low for _, s in points]
        above = [np.nan if s.high is None else s.high - s.mean for _, s in points]
        ax.errorbar(
            where,
            means,
            yerr=[below, above],
            fmt="o-" if numeric else "o",
            capsize=3,
            markersize=4,
            label=None if hue_label is None else _text(hue),
        )
    if not numeric:
        ax.set_xticks(range(len(categories)), [_text(x) for x in categories])
    elif len(categories) <= MAX_TICKS:  # a grid's few values, each marked where it is
        ax.set_xticks(sorted(categories), [_text(x) for x in sorted(categories)])
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    if hue_label is not None:
        ax.legend(title=hue_label, fontsize=8)
    save_picture(figure, path)


def _text(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)
