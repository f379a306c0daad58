"""What a sweep shows of its rows: each setting's mean and 95 % interval over its seeds, as a
table, and one measure against a grid key as a plot (`tvl sweep --plot x=…,y=…,hue=…`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.analysis.intervals import Group, Interval, group_intervals
from tvl_cli.analysis.measures import MEASURES, headline
from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.io.table import Row
from tvl_cli.sweep.grid import COLUMNS

# What the intervals are over: a setting is every grid key but this one.
TRIALS = "seed"
SETTING_KEYS = tuple(column for column in COLUMNS if column != TRIALS)
# The grid keys as a table's header or a plot's axis names them, with their units.
KEY_LABELS = {
    "kind": "kind",
    "world": "world",
    "learn_config": "learnt with",
    "learn_minutes": "learn (min)",
    "exploration": "exploration",
    "near_m": "near (m)",
    "memory": "memory",
    "config": "config",
    "minute": "FAM at (min)",
    "behaviour": "behaviour",
    "threshold": "threshold",
    "goal": "goal (m)",
    "run_minutes": "run (min)",
    "online": "learns as it runs",
    "competence_every": "checks every (min)",
    "trace": "traced",
    "method": "method",
    "reflexes": "reflexes",
    "run_memory": "run memory",
}
_PLOT_PARTS = ("x", "y", "hue")
PLOT_FORM = "x=KEY,y=MEASURE[,hue=KEY]"


@dataclass(frozen=True, slots=True)
class PlotAxes:
    x: str  # a grid key
    y: str  # a measure
    hue: str | None = None  # a grid key: a line of points for each of its values


@dataclass(frozen=True, slots=True)
class SweepSummary:
    """The table: a row for each setting, its intervals over seeds in the measures' order."""

    varying: tuple[str, ...]  # the setting keys whose values differ: the table's first columns
    fixed: dict[str, Any]  # the others, each with its one value
    measures: tuple[str, ...]
    groups: list[Group]  # keyed by the values of `varying`


def parse_plot(text: str) -> PlotAxes:
    """`x=KEY,y=MEASURE[,hue=KEY]`; BadInput naming the part that is wrong, with the nearest
    right one."""
    parts: dict[str, str] = {}
    for item in text.split(","):
        name, equals, value = (piece.strip() for piece in item.partition("="))
        if not equals or not value:
            raise BadInput(f"--plot {text!r}: {item.strip()!r} is not NAME=VALUE ({PLOT_FORM})")
        if name not in _PLOT_PARTS:
            raise BadInput(f"--plot {text!r}: no part {name!r} ({did_you_mean(name, _PLOT_PARTS)})")
        if name in parts:
            raise BadInput(f"--plot {text!r}: {name} is given twice")
        parts[name] = value
    for needed in ("x", "y"):
        if needed not in parts:
            raise BadInput(f"--plot {text!r}: no {needed}= ({PLOT_FORM})")
    axes = PlotAxes(parts["x"], parts["y"], parts.get("hue"))
    for part, key in (("x", axes.x), ("hue", axes.hue)):
        if key is not None:
            _check_setting_key(f"--plot {part}={key}", key)
    _check_measure(f"--plot y={axes.y}", axes.y)
    if axes.hue == axes.x:
        raise BadInput(f"--plot {text!r}: x and hue are both {axes.x!r}; give hue another key")
    return axes


def parse_measures(text: str) -> tuple[str, ...]:
    """A comma-separated list of measures; BadInput naming one it does not know."""
    measures = tuple(name.strip() for name in text.split(","))
    for measure in measures:
        _check_measure(f"--measures {measure}", measure)
    return measures


def _check_setting_key(where: str, key: str) -> None:
    if key == TRIALS:
        raise BadInput(f"{where}: the intervals are over the seeds; give another grid key")
    if key not in SETTING_KEYS:
        raise BadInput(f"{where}: no grid key {key!r} ({did_you_mean(key, SETTING_KEYS)})")


def _check_measure(where: str, measure: str) -> None:
    if measure not in MEASURES:
        raise BadInput(f"{where}: no measure {measure!r} ({did_you_mean(measure, list(MEASURES))})")


def summarise(rows: list[Row], measures: tuple[str, ...] | None = None) -> SweepSummary:
    """The table of the rows (a sweep's, in the grid's order), with these measures or, by
    default, the headline ones of the rows' behaviours."""
    values = {key: list(dict.fromkeys(row.get(key) for row in rows)) for key in SETTING_KEYS}
    varying = tuple(key for key in SETTING_KEYS if len(values[key]) > 1)
    fixed = {key: found[0] for key, found in values.items() if len(found) == 1}
    # Learn cells have no behaviour: their rows add no measure of their own.
    shown = measures or headline(b for b in values["behaviour"] if b is not None)
    return SweepSummary(varying, fixed, shown, group_intervals(rows, varying, shown))


def default_plot_path(out: Path, axes: PlotAxes) -> Path:
    """Beside the sweep's table, named for what it plots."""
    hue = f"-{axes.hue}" if axes.hue else ""
    return out / f"{axes.y}-by-{axes.x}{hue}.png"


@dataclass(frozen=True, slots=True)
class PlotData:
    # hue (None without one) -> its points: (x, the measure's interval there, as shown)
    series: dict[Any, list[tuple[Any, Interval]]]
    pooled: tuple[str, ...]  # grid keys that vary besides x and hue: pooled with the seeds


def plot_data(rows: list[Row], axes: PlotAxes) -> PlotData:
    """The measure's mean and 95 % interval at each x, for each hue, scaled as shown (a
    share as a percentage). Keys that vary besides x and hue are pooled with the seeds."""
    measure = MEASURES[axes.y]
    by = (axes.x, axes.hue) if axes.hue else (axes.x,)
    series: dict[Any, list[tuple[Any, Interval]]] = {}
    for group in group_intervals(rows, by, (axes.y,)):
        shown = group.intervals[axes.y]
        if shown is None:  # no run of this setting took the measure
            continue
        hue = group.key[1] if axes.hue else None
        series.setdefault(hue, []).append((group.key[0], _scaled(shown, measure.scale)))
    if not series:
        raise BadInput(f"--plot y={axes.y}: no run of this sweep took it")
    pooled = tuple(key for key in summarise(rows, (axes.y,)).varying if key not in by)
    return PlotData(series, pooled)


def plot(rows: list[Row], axes: PlotAxes, path: Path) -> None:
    """Draw the plot_data of the rows to `path`, in the format its extension names; the
    title says what the intervals are over."""
    from tvl_cli.render.sweep_plot import draw_intervals  # matplotlib only when plotting

    data = plot_data(rows, axes)
    label = MEASURES[axes.y].label
    over = ", ".join([f"{TRIALS}s", *data.pooled])
    draw_intervals(
        data.series,
        x_label=KEY_LABELS[axes.x],
        y_label=label,
        hue_label=KEY_LABELS[axes.hue] if axes.hue else None,
        title=f"{label}: mean and 95 % interval over {over}",
        path=path,
    )


def _scaled(shown: Interval, scale: float) -> Interval:
    half = None if shown.half_width is None else shown.half_width * scale
    return Interval(shown.mean * scale, half, shown.n)
