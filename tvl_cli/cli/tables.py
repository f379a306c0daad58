"""How values look in the terminal's tables: the one home of the rules every table follows.

- A table fits the terminal (80 columns is the narrowest kept in mind): a cell too long for
  its column folds onto the next lines, whole, rather than being cut short with an ellipsis
  (a path cut to `tvl-dem…` names no file).
- Units go in the header, `clearance (m)`, not in every cell.
- Numbers are rounded for reading; `--json` keeps them whole.
- `yes`/`no` for a flag, `—` for nothing, words for a key: `mean_wall_clearance_m` reads
  "mean wall clearance (m)".
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

from rich.table import Table

NOTHING = "—"
# A key's last word that names its unit, and how a header writes the unit.
UNITS = {
    "m": "m",
    "mps": "m/s",
    "mps2": "m/s²",
    "s": "s",
    "min": "min",
    "deg": "°",
    "radps": "rad/s",
}
# Keys the words of which say less than a label would.
LABELS = {
    "sim_s": "simulated time (s)",
    "sim_minutes": "simulated minutes",
    "delta_v": "ΔV (m/s per step)",
    "backoffs": "back-offs",
    "wall_s": "wall-clock time (s)",
}
# The metrics of reaching a goal, which a run that sought none does not show.
GOAL_METRICS = ("goal_reached", "time_to_goal_s")
# Decimals a rounded number keeps; beyond FIXED_RANGE a number reads better in powers of ten.
DIGITS = 2
FIXED_RANGE = (1e-3, 1e6)


def label(key: str) -> str:
    """A key in words, its unit in brackets: `mean_speed_mps` -> "mean speed (m/s)"."""
    if key in LABELS:
        return LABELS[key]
    *words, last = key.split("_")
    if words and last in UNITS:
        if words[-1] == "per":  # contacts_per_min: contacts (/min)
            return f"{' '.join(words[:-1])} (/{UNITS[last]})"
        return f"{' '.join(words)} ({UNITS[last]})"
    return key.replace("_", " ")


def cell(value: Any, digits: int = DIGITS) -> str:
    """A value as a table shows it: rounded, yes/no, — for None, a list joined by commas and
    a mapping as its labelled values."""
    if value is None:
        return NOTHING
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return number(value, digits)
    if isinstance(value, Mapping):
        return ", ".join(f"{label(str(k))} {cell(v, digits)}" for k, v in value.items())
    if isinstance(value, list | tuple):
        return ", ".join(cell(v, digits) for v in value) or NOTHING
    return str(value)


def number(value: float, digits: int = DIGITS) -> str:
    if not math.isfinite(value) or value == 0 or FIXED_RANGE[0] <= abs(value) < FIXED_RANGE[1]:
        return f"{value:.{digits}f}"
    return f"{value:.{digits}e}"


def percent(fraction: float) -> str:
    return f"{fraction:.0%}"


def table(
    *columns: str, title: str | None = None, right: Iterable[str] = (), header: bool = True
) -> Table:
    """A table whose cells fold rather than cut; the columns named in `right` (numbers)
    aligned right."""
    aligned = set(right)
    made = Table(title=title, show_header=header, title_justify="left")
    for name in columns:
        made.add_column(name, justify="right" if name in aligned else "left", overflow="fold")
    return made


def facts(rows: Iterable[tuple[str, Any]], title: str | None = None) -> Table:
    """A two-column table of labelled values, a fact a row."""
    made = table("", "", title=title, header=False)
    for key, value in rows:
        made.add_row(key, cell(value))
    return made


def labelled(values: Mapping[str, Any], title: str | None = None) -> Table:
    """A record's values as facts under their keys' labels."""
    return facts(((label(key), value) for key, value in values.items()), title)
