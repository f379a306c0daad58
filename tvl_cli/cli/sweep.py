"""`tvl sweep`: a grid of settings learnt, trained and run, locally or on a Dask cluster."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from tvl_cli.cli import sweep_view, views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import (
    PICTURE,
    print_csv,
    print_json,
    refuse_both_formats,
    refuse_existing,
)
from tvl_cli.sweep.executors import DEFAULT_SCHEDULER_TIMEOUT_S
from tvl_cli.sweep.grid import FULL, SIZES
from tvl_cli.sweep.runner import (
    DEFAULT_MAX_CELLS,
    SweepRequest,
    SweepResult,
    default_out,
    run_sweep,
)
from tvl_cli.sweep.summary import PLOT_FORM, parse_measures, parse_plot


@click.command(epilog=examples("sweep"))
@click.argument("grid", type=click.Path(path_type=Path))
@click.option(
    "--out",
    type=click.Path(path_type=Path),
    default=None,
    help="The sweep's directory: logs, FAMs and results (default: results/GRID's name). "
    "Running again goes on where it stopped.",
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    default=None,
    help="Local processes (default: one a core).",
)
@click.option(
    "--scheduler",
    metavar="local[:N]|tcp://HOST:PORT",
    default=None,
    help="Run the cells on a Dask cluster: local[:N] starts one of N workers here (default: "
    "one a core), an address uses that scheduler's workers (needs tvl[sweep]).",
)
@click.option(
    "--scheduler-timeout",
    "scheduler_timeout_s",
    type=click.FloatRange(min=0.0, min_open=True),
    default=DEFAULT_SCHEDULER_TIMEOUT_S,
    show_default=True,
    help="Seconds a scheduler has to answer.",
)
@click.option(
    "--max-cells",
    type=click.IntRange(min=1),
    default=DEFAULT_MAX_CELLS,
    show_default=True,
    help="Refuse a grid of more cells, counted before any is made.",
)
@click.option("--yes", is_flag=True, help="Run a grid of any number of cells.")
@click.option(
    "--size",
    type=click.Choice(SIZES),
    default=FULL,
    show_default=True,
    help="The grid file as written (full: the paper's trial counts), or its [quick] or "
    "[tiny] table's smaller study. Give each size its own --out.",
)
@click.option(
    "--measures",
    default=None,
    metavar="NAME,...",
    help="The table's measures, as `tvl run --json` names them (default: contacts/min and "
    "speed, with wall clearance and goals reached where the grid has those runs).",
)
@click.option(
    "--plot",
    "plot_text",
    default=None,
    metavar=PLOT_FORM,
    help="Plot a measure's mean and 95 % interval over seeds against a grid key, a line "
    "for each value of another (e.g. x=threshold,y=mean_speed_mps,hue=config).",
)
@click.option(
    "-o",
    "--plot-out",
    type=PICTURE,
    default=None,
    help="The plot's picture: .png, .svg, .pdf or .jpg (default: beside the table, "
    "redrawn by each sweep).",
)
@click.option("--force", is_flag=True, help="Overwrite the plot's picture given by -o.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON summary.")
@click.option("--csv", "as_csv", is_flag=True, help="Print the results table as CSV.")
def sweep(
    grid: Path,
    out: Path | None,
    workers: int | None,
    scheduler: str | None,
    scheduler_timeout_s: float,
    max_cells: int,
    yes: bool,
    size: str,
    measures: str | None,
    plot_text: str | None,
    plot_out: Path | None,
    force: bool,
    as_json: bool,
    as_csv: bool,
) -> None:
    """Learn, train and run every combination of a grid's settings into one results table.

    GRID is a TOML file whose keys each give one value or a list: world and seed, and kind,
    behaviour, config, learn_config, learn_minutes, minute, the method's fields exploration,
    near_m and memory, threshold, goal, run_minutes, online, competence_every, trace,
    method, reflexes and run_memory, in [[part]]s if need be (docs/guide/experiments.md,
    "Sweeps"; the paper's figures are experiments/grids/). Each combination is a cell: one
    run (a TVL run or a baseline's) or a learning log's record, after the learning and
    training it needs, each done once for every cell that shares it. Rows go to
    results.jsonl as runs end, and the grid's table to results.csv (and results.parquet with
    pyarrow) in the directory. The terminal shows each setting's mean and 95 % interval over
    its seeds. One sweep at a time runs in a directory."""
    refuse_both_formats(as_json, as_csv)
    if workers is not None and scheduler is not None:
        raise click.UsageError("give --workers or --scheduler, not both (a cluster has its own)")
    if plot_out is not None and plot_text is None:
        raise click.UsageError("-o/--plot-out is the plot's file; give --plot too")
    if plot_out is not None:
        refuse_existing(plot_out, force)
    request = SweepRequest(
        grid,
        out or default_out(grid),
        workers or os.cpu_count() or 1,
        scheduler,
        scheduler_timeout_s,
        None if yes else max_cells,
        parse_measures(measures) if measures is not None else None,
        parse_plot(plot_text) if plot_text is not None else None,
        plot_out,
        size,
    )
    result = _run(request, quiet=as_json)
    if as_json:
        print_json(result.document())
    elif as_csv:
        print_csv(result.rows)
    else:
        sweep_view.show(result)


def _run(request: SweepRequest, quiet: bool) -> SweepResult:
    """Run the sweep under a progress bar, `quiet` (for --json) without the bar or the
    dashboard's link; Ctrl-C exits 130, saying where the runs that ended are."""

    def on_dashboard(link: str) -> None:
        if not quiet:  # a script reading the JSON keeps a clean stderr, as with the bar
            views.say(f"dashboard: {link}")

    try:
        with views.progress("cells", quiet=quiet) as bar:
            return run_sweep(request, bar, on_dashboard)
    except KeyboardInterrupt:
        views.say(f"interrupted: the runs that ended are in {request.out}; run again to go on")
        sys.exit(130)
