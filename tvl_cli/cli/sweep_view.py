"""How a sweep's results look in a terminal: what ran, what every run shares, and a table of
each setting's mean ± 95 % interval over its seeds that fits the terminal's width."""

from __future__ import annotations

from rich.cells import cell_len
from rich.table import Table

from tvl_cli.analysis.intervals import Interval
from tvl_cli.analysis.measures import MEASURES, Measure
from tvl_cli.cli.views import out
from tvl_cli.sweep.runner import TABLE_CSV, SweepResult
from tvl_cli.sweep.summary import KEY_LABELS, SweepSummary

TITLE = "mean ± 95 % interval over seeds (Student's t)"
# A table's left edge; and each column's padding either side and its rule on the right.
_TABLE_EDGE = 1
_COLUMN_EDGES = 3

Column = tuple[str, list[str]]  # a header and its cells


def show(result: SweepResult) -> None:
    again = (
        f" ({result.redone} of them again: their method or configuration changed)"
        if result.redone
        else ""
    )
    out.print(
        f"{result.cells} cells: {result.done} run now{again}, {result.skipped} done before; "
        f"the table is {result.out / TABLE_CSV}"
    )
    shared = result.summary.fixed.items()
    # Keys no run set (null) or set off (false) say nothing every run shares.
    fixed = ", ".join(
        f"{KEY_LABELS[k]} {_grid_value(v)}" for k, v in shared if v is not None and v is not False
    )
    if fixed:
        out.print(f"every run: {fixed}")
    for table in sweep_tables(result.summary, out.width):
        out.print(table)
    if result.plot is not None:
        out.print(f"plot: {result.plot}")


def sweep_tables(summary: SweepSummary, width: int) -> list[Table]:
    """A row for each setting: the grid values it does not share with the others, its seeds,
    and each measure's mean ± 95 % interval, rounded as the measure is. As many tables as
    `width` columns need: measures with no room beside the others go to another table, which
    repeats the setting's columns, so that no number is cut or folded."""
    groups = summary.groups
    setting: list[Column] = [
        (KEY_LABELS[key], [_grid_value(group.key[i]) for group in groups])
        for i, key in enumerate(summary.varying)
    ]
    seeds: Column = ("seeds", [str(group.rows) for group in groups])
    measured: list[Column] = [
        (MEASURES[m].label, [_interval_text(group.intervals[m], MEASURES[m]) for group in groups])
        for m in summary.measures
    ]
    base = _TABLE_EDGE + sum(_room(column, False) for column in [*setting, seeds])
    parts: list[list[Column]] = [[]]
    used = base
    for column in measured:
        if parts[-1] and used + _room(column, False) > width:
            parts.append([])
            used = base
        parts[-1].append(column)
        used += _room(column, False)
    tables = []
    for number, part in enumerate(parts):
        table = Table(title=TITLE if number == 0 else None)
        columns = [*setting, seeds, *part]
        # Headers unbroken where the table has the room, else wrapped at their spaces; each
        # column as wide as that, so that rich does not wrap a number to widen a header.
        # Only a setting wider than the terminal on its own is folded.
        whole = _TABLE_EDGE + sum(_room(column, True) for column in columns) <= width
        for column in columns:
            table.add_column(
                column[0],
                justify="left" if column in setting else "right",
                overflow="fold",
                width=_room(column, whole) - _COLUMN_EDGES if base <= width else None,
            )
        for row in zip(*(cells for _, cells in columns), strict=True):
            table.add_row(*row)
        tables.append(table)
    return tables


def _room(column: Column, whole_header: bool) -> int:
    """The width a column takes with its edges: its widest cell, or its header whole or its
    header's longest word."""
    header, cells = column
    words = [header] if whole_header else header.split()
    return max(map(cell_len, [*words, *cells])) + _COLUMN_EDGES


def _grid_value(value: object) -> str:
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    return f"{value:g}" if isinstance(value, float) else str(value)


def _interval_text(shown: Interval | None, measure: Measure) -> str:
    """mean ± half width, or the mean (low to high) where a bound cuts the interval; the
    mean alone from one seed; a dash where no run took it."""
    if shown is None:
        return "–"
    places = measure.decimals
    shown = shown.scaled(measure.scale)
    mean = f"{shown.mean:.{places}f}"
    if shown.half_width is None:
        return mean
    if shown.clipped:
        return f"{mean} ({shown.low:.{places}f}–{shown.high:.{places}f})"
    return f"{mean} ± {shown.half_width:.{places}f}"
