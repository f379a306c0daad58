"""`tvl sweep`: a grid of settings learnt, trained and run, locally or on a Dask cluster."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from tvl_cli.cli import documents, views
from tvl_cli.cli.options import print_csv, print_json, refuse_both_formats
from tvl_cli.commands.sweep import SweepRequest, default_out, run_sweep


@click.command()
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
    metavar="tcp://HOST:PORT",
    default=None,
    help="Run the cells on the workers of this Dask scheduler (needs tvl[sweep]).",
)
@click.option("--json", "as_json", is_flag=True, help="Print a JSON summary.")
@click.option("--csv", "as_csv", is_flag=True, help="Print the results table as CSV.")
def sweep(
    grid: Path,
    out: Path | None,
    workers: int | None,
    scheduler: str | None,
    as_json: bool,
    as_csv: bool,
) -> None:
    """Learn, train and run every combination of a grid's settings into one results table.

    GRID is a TOML file whose keys each give one value or a list: world, seed and
    behaviour, and config, learn_minutes, threshold, goal, run_minutes and reflexes (README,
    "Sweeps"). Each combination is a cell: one run, after the learning and training it needs,
    each done once for every cell that shares it. Rows go to results.jsonl as runs end, and
    the grid's table to results.csv (and results.parquet with pyarrow) in the directory."""
    refuse_both_formats(as_json, as_csv)
    if workers is not None and scheduler is not None:
        raise click.UsageError("give --workers or --scheduler, not both (a cluster has its own)")
    request = SweepRequest(
        grid, out or default_out(grid), workers or os.cpu_count() or 1, scheduler
    )
    try:
        with views.progress("cells", quiet=as_json) as bar:
            result = run_sweep(request, bar)
    except KeyboardInterrupt:
        views.say(f"interrupted: the runs that ended are in {request.out}; run again to go on")
        sys.exit(130)
    if as_json:
        print_json(documents.sweep_json(result, request))
    elif as_csv:
        print_csv(result.rows)
    else:
        views.sweep(result)
