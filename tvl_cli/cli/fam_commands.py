"""`tvl train`, `tvl inspect` and `tvl diff`: FAM files from logs, their rules in words, and
where two disagree."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.analysis.famdiff import DEFAULT_TOLERANCE_MPS
from tvl_cli.analysis.rules import SORT_KEYS
from tvl_cli.cli import documents, fam_views, views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.memory_options import memory_options
from tvl_cli.cli.options import (
    HDF5,
    PICTURE,
    given_on_command_line,
    method_options,
    print_csv,
    print_json,
    refuse_both_formats,
    refuse_existing,
    refuse_shared_paths,
    training_options,
)
from tvl_cli.cli.params import Parsed, complete_trajectory, name_and_metres, pair_of_names
from tvl_cli.commands.diff import diff_files
from tvl_cli.commands.inspect import InspectRequest, inspect_fam
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
    refuse_shared_paths({"-o": output}, {f"LOG {i + 1}": log for i, log in enumerate(logs)})
    refuse_existing(output, force)
    request = TrainRequest(
        logs, output, config, method, until_minute, symmetric, init_velocity_mps, force
    )
    with views.progress("training") as bar:
        summary = train_fam(request, bar)
    if as_json:
        print_json(documents.train_json(summary, logs, config, until_minute, output))
    else:
        fam_views.train_summary(summary, output, method)


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
        refuse_shared_paths({"--png": png}, {"FAM": fam})
        refuse_existing(png, force)
    found = inspect_fam(
        InspectRequest(fam, trajectory, top, sort, untrained, explain, png, over, fix)
    )
    if as_json:
        drawn_over = found.over or over
        options = {
            "trajectory": trajectory,
            "top": top,
            "sort": sort,
            "untrained": untrained,
            "over": None if drawn_over is None else list(drawn_over),
            "fix": dict(fix),
        }
        print_json(
            documents.inspect_json(
                fam, found.loaded, options, found.ring, found.rules, found.explanation, png
            )
        )
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
    difference = diff_files(first, second, tolerance, top)
    if as_json:
        print_json(documents.diff_json(difference, first, second, top))
    else:
        fam_views.fam_difference(difference, first, second)
