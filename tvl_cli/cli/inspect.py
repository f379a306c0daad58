"""`tvl inspect`: a FAM file's rules in words, as CSV or JSON, or drawn."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.analysis.rules import SORT_KEYS
from tvl_cli.cli import fam_views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import (
    PICTURE,
    given_on_command_line,
    print_csv,
    print_json,
    refuse_both_formats,
    refuse_outputs,
)
from tvl_cli.cli.params import Parsed, complete_trajectory, name_and_metres, pair_of_names
from tvl_cli.commands.inspect import InspectRequest, inspect_fam


@click.command(epilog=examples("inspect"))
@click.argument("fam", type=click.Path(path_type=Path))
@click.option(
    "--trajectory",
    default=None,
    shell_complete=complete_trajectory,
    help="Only this trajectory's rules, e.g. T1L.",
)
@click.option(
    "--top",
    type=click.IntRange(min=0),
    default=20,
    show_default=True,
    help="How many rules (0: all).",
)
@click.option("--sort", type=click.Choice(SORT_KEYS), default="experience", show_default=True)
@click.option("--untrained", is_flag=True, help="List the rules no exemplar has reached.")
@click.option(
    "--explain",
    metavar="R0,...,R15",
    default=None,
    help="Explain how one ring of 16 ranges (m) is perceived.",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.option("--csv", "as_csv", is_flag=True, help="Print the rules as CSV, a row each.")
@click.option(
    "--png",
    type=PICTURE,
    default=None,
    help="Draw the learnt velocity over the two inputs of --over, a panel per trajectory.",
)
@click.option(
    "--over",
    type=Parsed("inputs", pair_of_names),
    default=None,
    metavar="A,B",
    help="The two inputs of --png (default: the pair most of the FAM's tables read, "
    "front,front-left for single).",
)
@click.option(
    "--fix",
    type=Parsed("input", name_and_metres),
    multiple=True,
    metavar="INPUT=METRES",
    help="Hold another input at a range for --png (default: open space); repeatable.",
)
@click.option("--force", is_flag=True, help="Overwrite the --png file.")
def inspect(
    fam: Path,
    trajectory: str | None,
    top: int,
    sort: str,
    untrained: bool,
    explain: str | None,
    as_json: bool,
    as_csv: bool,
    png: Path | None,
    over: tuple[str, str] | None,
    fix: tuple[tuple[str, float], ...],
    force: bool,
) -> None:
    """Print a FAM file's rules as a person reads them.

    The method the FAM was made by comes first (unrecorded for FAMs written before files
    recorded it)."""
    refuse_both_formats(as_json, as_csv)
    if explain is not None and as_csv:
        raise click.UsageError("--csv lists rules; --explain prints in words or --json")
    if png is not None:
        refuse_outputs({"--png": png}, {"FAM": fam}, force)
    found = inspect_fam(
        InspectRequest(fam, trajectory, top, sort, untrained, explain, png, over, fix)
    )
    if as_json:
        print_json(found.document())
    elif found.explanation is not None:
        fam_views.explanation(found.explanation)
    elif as_csv:
        print_csv([rule.to_row() for rule in found.rules or []])
    else:
        fam_views.say_method(found.loaded.made_by.record())
        fam_views.say_robot(found.loaded.robot_config)
        if png is not None and found.over is not None:
            click.echo(f"{png}: the learnt velocity over {' and '.join(found.over)}")
        # A picture asked for alone is the answer; rules asked for as well come after it.
        if png is None or given_on_command_line(*RULE_OPTIONS):
            fam_views.rules(found.rules or [])


# inspect's options that choose rules to print: with --png, the rules print only if one is given.
RULE_OPTIONS = ("--trajectory", "--top", "--sort", "--untrained")
