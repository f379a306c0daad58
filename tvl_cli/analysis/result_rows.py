"""A sweep's results file read and type-checked: one JSON line per run, each a row of the
experiments' numbers.

Each line of a results file (a sweep's results.jsonl) is one cell: its grid values (`kind`:
learn, tvl, dwa or qlearn; `world`, `seed`, `config`, `minute`, `behaviour`, `threshold`,
`method`, `reflexes`, ...) and what its work found, as `tvl ... --json` prints it.
"""

from __future__ import annotations

import json
import math
from dataclasses import fields
from pathlib import Path
from typing import Any

from tvl_cli.core import jsontext
from tvl_cli.core.behaviours import is_threshold
from tvl_cli.core.errors import BadInput
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.text import decoded

Row = dict[str, Any]


def read_results(path: Path) -> dict[int, Row]:
    """The runs of a JSON-lines results file by line number; BadInput naming the line that is
    not one."""
    try:
        text = decoded(path.read_bytes(), str(path))
    except FileNotFoundError:
        raise BadInput(f"{path}: no such results file") from None
    except OSError as error:
        raise BadInput(f"{path}: cannot read ({error.strerror})") from None
    rows: dict[int, Row] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        try:
            row = jsontext.loads(line, where)
        except json.JSONDecodeError as error:
            raise BadInput(f"{where}:{error.colno}: not JSON ({error.msg})") from None
        if not isinstance(row, dict) or not isinstance(row.get("kind"), str):
            raise BadInput(f'{where}: not a run (an object with a "kind")')
        _check_types(row, where)
        rows[number] = row
    return rows


# The keys the figures read, by what they must hold. Parameters and measures are numbers
# (finite: json reads NaN and Infinity, which would show as "–"); only the measures a run may
# not have taken, and the grid values a kind of cell does not read, can be null. `minutes` (a
# learn cell's or a run's) and `competence_checks` (Q-learning's) are lists of objects whose
# keys are checked as a run's are.
_WORDS = (
    "world",
    "config",
    "learn_config",
    "behaviour",
    "method",
    "reflexes",
    "goal",
    "exploration",
    "memory",
    "run_memory",
    "trace_file",
)
_NUMBERS = (
    "seed",
    "minute",
    "coverage",
    "threshold",
    "learn_minutes",
    "run_minutes",
    "competence_every",
    "near_m",
    "delta_v",
    "learn_collisions",
    *(f.name for f in fields(RunMetrics) if f.name != "goal_reached"),
)
_MAYBE_TAKEN = (
    "mean_wall_clearance_m",
    "time_to_goal_s",
    "time_to_competence_min",
    # grid values some kinds of cell do not read
    "minute",
    "threshold",
    "learn_minutes",
    "run_minutes",
    "competence_every",
    "near_m",
)
_MAYBE_NAMED = (
    "goal", "config", "learn_config", "behaviour", "method", "reflexes", "exploration",
    "memory", "run_memory",
)  # fmt: skip
_FLAGS = ("goal_reached", "online", "trace")
_MAYBE_FLAGGED = ("goal_reached",)  # null: the run sought no goal
_LISTS = ("minutes", "competence_checks")


def _check_types(row: Row, where: str) -> None:
    """BadInput naming the first key a figure reads that does not hold what it names."""
    for key in _WORDS:
        if key in row and not isinstance(row[key], str):
            if row[key] is None and key in _MAYBE_NAMED:
                continue
            raise BadInput(f"{where}: {key!r} is {row[key]!r}, expected text")
    for key in dict.fromkeys((*_NUMBERS, *_MAYBE_TAKEN)):
        value = row.get(key)
        if key not in row or (value is None and key in _MAYBE_TAKEN):
            continue
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise BadInput(f"{where}: {key!r} is {value!r}, expected a number")
    for key in _FLAGS:
        if key in row and not isinstance(row[key], bool):
            if row[key] is None and key in _MAYBE_FLAGGED:
                continue
            raise BadInput(f"{where}: {key!r} is {row[key]!r}, expected true or false")
    if row.get("threshold") is not None and not is_threshold(row["threshold"]):
        raise BadInput(f"{where}: 'threshold' is {row['threshold']!r}, outside (0, 1]")
    for key in _LISTS:
        items = row.get(key, [])
        if not isinstance(items, list):
            raise BadInput(f"{where}: {key!r} is {items!r}, expected a list of objects")
        for index, item in enumerate(items, start=1):
            at = f"{where}: {key!r} item {index}"
            if not isinstance(item, dict):
                raise BadInput(f"{at} is {item!r}, expected an object")
            _check_types(item, at)
