"""How a suite's figures look: plain columns in a terminal, or Markdown tables for a page."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import click

from tvl_cli.analysis.autopsy import CAUSES, GOAL_FAILURES, SLOW_CAUSES, TIME_CLASSES
from tvl_cli.analysis.generalization import (
    MAX_BELOW_CEILING,
    MAX_CONTACTS_PER_MIN,
    MIN_COMPETENT_SHARE,
    MIN_GOAL_SHARE,
    MIN_SPEED_OF_DWA,
    Figures,
    by_world,
)
from tvl_cli.analysis.intervals import Interval

Table = tuple[tuple[str, ...], list[tuple[str, ...]]]  # a header and its rows


def show_generalization(result: Any, where: Any, markdown: bool, each_world: bool) -> None:
    click.echo(generalization_header(result, where))
    tables = [figures_table(result.figures), autopsy_table(result.figures)]
    if each_world:
        tables.append(world_table(result.figures, list(result.plan.worlds), result.run.rows))
    for table in tables:
        if table[1]:
            click.echo()
            click.echo(render(table, markdown))


def generalization_header(result: Any, where: Any) -> str:
    plan, run, request = result.plan, result.run, result.request
    seeds, trials = plan.world_seeds, plan.trials
    return (
        f"rooms worlds {seeds[0]}-{seeds[-1]} ({request.world_set} set, {len(seeds)} worlds), "
        f"trials {trials[0]}-{trials[-1]}, learning {plan.size.learn_minutes:g} min, runs "
        f"{plan.size.run_minutes:g} min at threshold {request.threshold:g}; {run.cells} cells "
        f"({run.done} run now, {run.skipped} before) in {run.wall_s:.0f} s, "
        f"{run.cpu_s:.0f} s of CPU in all; rows in {where.out / 'results.csv'}"
    )


def row_name(figures: Figures) -> str:
    kind = {"method": "ours", "reference": "reference", "controller": "controller"}
    reads = ", reads the map" if figures.reads_map else ""
    config = f" · {figures.config}" if figures.config else ""
    return f"{figures.entry}{config} ({kind[figures.role]}{reads})"


def figures_table(all_figures: Sequence[Figures]) -> Table:
    behaviours = list(dict.fromkeys(b for f in all_figures for b in f.by_behaviour))
    header = (
        "row", "method", "competent", *behaviours, "goals reached", "contacts/min",
        "avoid m/s", "of DWA's", "below oracle",
    )  # fmt: skip
    rows = [
        (
            row_name(f),
            f.method or "–",
            _share(f.competent, f.runs, f.competent_share),
            *(_count(f.by_behaviour.get(b)) for b in behaviours),
            _share(f.goals_reached, f.goal_runs, f.goal_share),
            _interval(f.contacts_per_min),
            _interval(f.avoid_speed_mps),
            "–" if f.avoid_speed_of_reference is None else f"{f.avoid_speed_of_reference:.0%}",
            "–" if f.below_ceiling is None else f"{100 * f.below_ceiling:+.0f} pts",
        )
        for f in all_figures
    ]
    target = (
        "target", "", f">= {MIN_COMPETENT_SHARE:.0%}", *("" for _ in behaviours),
        f">= {MIN_GOAL_SHARE:.0%}", f"<= {MAX_CONTACTS_PER_MIN:g}, multi <= single", "",
        f">= {MIN_SPEED_OF_DWA:.0%}", f"<= {100 * MAX_BELOW_CEILING:.0f} pts",
    )  # fmt: skip
    return header, [*rows, target]


def autopsy_table(all_figures: Sequence[Figures]) -> Table:
    """Where the FAM-driven runs' contacts came from, where their time went, why they drove
    slowly, and why their goal runs failed: each line with a count somewhere."""
    shown = [f for f in all_figures if f.autopsy is not None]
    columns = [f.autopsy for f in shown if f.autopsy is not None]
    rows: list[tuple[str, ...]] = []
    for cause in CAUSES:
        if any(c["causes"][cause] for c in columns):
            rows.append((f"contacts: {cause}", *(str(c["causes"][cause]) for c in columns)))
    for name in TIME_CLASSES:
        if any(c["time_s"][name] for c in columns):
            shares = [c["time_s"][name] / (sum(c["time_s"].values()) or 1) for c in columns]
            rows.append((f"time: {name}", *(f"{s:.0%}" for s in shares)))
    for cause in SLOW_CAUSES:
        if any(c["slow_time_s"][cause] for c in columns):
            shares = [c["slow_time_s"][cause] / (sum(c["time_s"].values()) or 1) for c in columns]
            rows.append((f"slow: {cause}", *(f"{s:.0%}" for s in shares)))
    for reason in GOAL_FAILURES:
        if any(c["goal_failures"][reason] for c in columns):
            rows.append(
                (f"goal missed: {reason}", *(str(c["goal_failures"][reason]) for c in columns))
            )
    rated = [c["rated_fast"] for c in columns]
    if any(r["contacts"] for r in rated):
        rows.append(("rated-fast: true m/s (median)", *(_mps(r["median_true_mps"]) for r in rated)))
        rows.append(
            ("rated-fast: rated m/s (median)", *(_mps(r["median_rated_mps"]) for r in rated))
        )
        rows.append(
            (
                "rated-fast: under 1 exemplar of experience",
                *(
                    "–" if r["untrained_share"] is None else f"{r['untrained_share']:.0%}"
                    for r in rated
                ),
            )
        )
        rows.append(("rated-fast: most often on", *(_most_driven(r) for r in rated)))
    header = ("autopsy", *(_column_name(f) for f in shown))
    return header, rows


def world_table(all_figures: Sequence[Figures], worlds: Sequence[str], rows: Any) -> Table:
    """World by world, each row's competent runs and their mean speed there (every behaviour
    and trial): the worlds where the runs fail, and how fast each row drove in them."""
    found = by_world(rows)
    keys = [(f.entry, f.config) for f in all_figures]
    header = ("world", *(_column_name(f) for f in all_figures))
    lines = []
    for world in worlds:
        cells = []
        for key in keys:
            there = found.get(key, {}).get(world)
            cells.append(
                "–"
                if there is None
                else f"{there.competent}/{there.runs}, {there.mean_speed_mps:.2f} m/s"
            )
        lines.append((world, *cells))
    return header, lines


def _column_name(figures: Figures) -> str:
    return f"{figures.entry} · {figures.config}" if figures.config else figures.entry


def _mps(value: float | None) -> str:
    return "–" if value is None else f"{value:.2f}"


def _most_driven(rated_fast: dict[str, Any]) -> str:
    """The trajectory most rated-fast contacts were met on, with its share of those whose
    trajectory the rows kept."""
    driven = rated_fast.get("by_trajectory") or []  # rows made before they kept it: none
    if not driven:
        return "–"
    kept = sum(d["contacts"] for d in driven)
    return f"{driven[0]['trajectory']} ({driven[0]['contacts'] / kept:.0%})"


def _share(part: int, whole: int, over_trials: Interval | None) -> str:
    if not whole:
        return "–"
    spread = ""
    if over_trials is not None and over_trials.half_width is not None:
        spread = f" ± {100 * over_trials.half_width:.0f}"
    return f"{part}/{whole} ({100 * part / whole:.0f} %{spread})"


def _count(found: tuple[int, int] | None) -> str:
    return "–" if found is None else f"{found[0]}/{found[1]}"


def _interval(found: Interval | None, digits: int = 2) -> str:
    if found is None:
        return "–"
    if found.half_width is None:
        return f"{found.mean:.{digits}f}"
    return f"{found.mean:.{digits}f} ± {found.half_width:.{digits}f}"


def render(table: Table, markdown: bool) -> str:
    """A header and rows as Markdown, or in columns as wide as their widest cell."""
    header, rows = table
    if markdown:
        lines = [header, tuple("---" for _ in header), *rows]
        return "\n".join("| " + " | ".join(cells) + " |" for cells in lines)
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = [header, tuple("-" * w for w in widths), *rows]
    return "\n".join(
        "  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip() for r in lines
    )


def show_claims(result: Any, where: Any, markdown: bool) -> None:
    run, trials = result.run, result.trials
    click.echo(
        f"the paper's claims, trials {trials[0]}-{trials[-1]} ({result.request.size} size); "
        f"{run.cells} cells ({run.done} run now, {run.skipped} before) in {run.wall_s:.0f} s, "
        f"{run.cpu_s:.0f} s of CPU in all; rows in {where.out / 'results.csv'}"
    )
    click.echo()
    click.echo(render(claims_table(result.verdicts, result.request.methods), markdown))


def claims_table(verdicts: Sequence[Any], methods: Sequence[str]) -> Table:
    header = ("claim", "the paper reports", *(f"--method {m}" for m in methods))
    rows = [
        (
            row.claim,
            row.reported,
            *(
                f"{'met' if row.verdicts[m].met else 'missed'}: {row.verdicts[m].measured}"
                for m in methods
            ),
        )
        for row in verdicts
    ]
    return header, rows
