"""`tvl diff`: where two FAM files of one configuration disagree, rule by rule."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.analysis.famdiff import DEFAULT_TOLERANCE_MPS
from tvl_cli.cli import fam_views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import print_json
from tvl_cli.commands.diff import diff_files


@click.command(epilog=examples("diff"))
@click.argument("first", type=click.Path(path_type=Path))
@click.argument("second", type=click.Path(path_type=Path))
@click.option(
    "--tolerance",
    type=click.FloatRange(min=0.0),
    default=DEFAULT_TOLERANCE_MPS,
    show_default=True,
    help="m/s: velocities closer than this agree.",
)
@click.option(
    "--top",
    type=click.IntRange(min=0),
    default=20,
    show_default=True,
    help="How many of the rules that differ most to name (0: all).",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def diff(first: Path, second: Path, tolerance: float, top: int, as_json: bool) -> None:
    """Show where two FAM files of one configuration disagree, rule by rule."""
    differed = diff_files(first, second, tolerance, top)
    if as_json:
        print_json(differed.document())
    else:
        fam_views.fam_difference(differed.difference, first, second)
