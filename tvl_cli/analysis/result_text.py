"""How the figures' tables and legends write the results: numbers, a mean ± its 95 %
interval, the methods by name, worlds and methods in their order, markdown tables."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

from tvl_cli.analysis.aggregation import distinct, select
from tvl_cli.analysis.intervals import Interval, interval
from tvl_cli.analysis.result_rows import Row
from tvl_cli.core.method import DEFAULT_NAME, PAPER_NAME

# The order in which figures and tables list the worlds.
WORLD_ORDER = ("square", "circle", "corridor", "obstacles", "narrow", "lab")


def number(value: float | None, digits: int = 2) -> str:
    return "–" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"


def spread(values: Iterable[float | None], digits: int = 2) -> str:
    """'0.31 ± 0.04': the mean of the values and the half width of its 95 % interval (the
    mean alone from one value; a dash from none)."""
    return interval_text(interval([v for v in values if v is not None]), digits)


def interval_text(shown: Interval | None, digits: int = 2) -> str:
    if shown is None:
        return "–"
    if shown.half_width is None:
        return number(shown.mean, digits)
    return f"{number(shown.mean, digits)} ± {number(shown.half_width, digits)}"


# How figures and tables name a sweep's methods: ours (the default) and the paper's.
METHOD_LABELS = {DEFAULT_NAME: "ours", PAPER_NAME: "paper's method"}


def method_label(method: str | None) -> str:
    return METHOD_LABELS.get(method or DEFAULT_NAME, str(method))


def methods_of(rows: Iterable[Row]) -> list[str]:
    """The methods TVL learnt and ran by among the rows: ours first, then the paper's, then
    any method file."""
    return distinct(select(rows, kind=("tvl", "learn")), "method", tuple(METHOD_LABELS))


def markdown(title: str, header: Sequence[str], body: Iterable[Sequence[str]]) -> str:
    lines = [f"### {title}", "", "| " + " | ".join(header) + " |"]
    lines.append("|" + "|".join(" --- " for _ in header) + "|")
    lines += ["| " + " | ".join(cells) + " |" for cells in body]
    return "\n".join(lines) + "\n"
