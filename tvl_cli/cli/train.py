"""`tvl train`: a FAM file from learning logs, by log replay."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.cli import fam_views, views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.memory_options import memory_options
from tvl_cli.cli.options import HDF5, method_options, print_json, refuse_outputs, training_options
from tvl_cli.commands.train import TrainRequest
from tvl_cli.commands.train import train as train_fam
from tvl_cli.core.method import MethodChoice


@click.command(epilog=examples("train"))
@click.argument("logs", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("-o", "--output", type=HDF5, required=True, help="FAM file (.h5).")
@method_options
@training_options
@click.option(
    "--until-minute",
    type=float,
    default=None,
    help="Use only the episodes each session finished by this simulated minute.",
)
@memory_options(base="the one the logs were learnt through")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON summary.")
def train(
    logs: tuple[Path, ...],
    output: Path,
    method: MethodChoice,
    config: str,
    symmetric: bool,
    init_velocity_mps: float,
    until_minute: float | None,
    force: bool,
    as_json: bool,
) -> None:
    """Train a FAM file from learning logs (log replay)."""
    refuse_outputs({"-o": output}, {f"LOG {i + 1}": log for i, log in enumerate(logs)}, force)
    request = TrainRequest(
        logs, output, config, method, until_minute, symmetric, init_velocity_mps, force
    )
    with views.progress("training") as bar:
        trained = train_fam(request, bar)
    if as_json:
        print_json(trained.document())
    else:
        fam_views.train_summary(trained.summary, output, method)
