"""`tvl export`: a run trace for other tools."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import MCAP, print_json, refuse_outputs
from tvl_cli.commands.export import export_mcap


@click.command(epilog=examples("export"))
@click.argument("run", metavar="RUN.h5", type=click.Path(path_type=Path))
@click.option(
    "--mcap",
    "output",
    type=MCAP,
    required=True,
    metavar="OUT.mcap",
    help="MCAP file for Foxglove.",
)
@click.option("--force", is_flag=True, help="Overwrite OUT.mcap.")
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
def export(run: Path, output: Path, force: bool, as_json: bool) -> None:
    """Write a run trace as MCAP, in Foxglove's schemas, to play back in Foxglove.

    Topics: /world (the scene), /tf, /pose and /odometry, /sonar (the echo points),
    /perceived (the seven perceived velocities) and /events, on the run's simulated clock.
    """
    refuse_outputs({"--mcap": output}, {"RUN.h5": run}, force)
    exported = export_mcap(run, output)
    if as_json:
        print_json(exported.document())
    else:
        counts = ", ".join(f"{topic} {n}" for topic, n in exported.messages.items())
        click.echo(f"{output}: {exported.steps} steps ({counts})")
