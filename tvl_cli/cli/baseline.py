"""`tvl baseline`: the DWA and Q-learning, to measure TVL against."""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.baselines.dwa import BEHAVIOURS as DWA_BEHAVIOURS
from tvl_cli.baselines.dwa import SENSORS as DWA_SENSORS
from tvl_cli.cli import views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.groups import Subcommands
from tvl_cli.cli.memory_options import memory_options
from tvl_cli.cli.options import (
    GOAL,
    PICTURE,
    method_options,
    print_json,
    reflex_options,
    refuse_outputs,
    seed_option,
    world_file,
    world_given,
)
from tvl_cli.cli.params import complete_world
from tvl_cli.commands.baseline import dwa_session, qlearn_session
from tvl_cli.core.method import NONE, MethodChoice


@click.group(cls=Subcommands, epilog=examples("baseline"))
def baseline() -> None:
    """Controllers to measure TVL against: DWA and tabular Q-learning."""


@baseline.command("dwa", epilog=examples("baseline dwa"))
@click.argument("world_entry", metavar="WORLD", shell_complete=complete_world)
@click.option("--behaviour", type=click.Choice(DWA_BEHAVIOURS), default="avoid", show_default=True)
@GOAL
@click.option("--minutes", type=float, default=5.0, show_default=True, help="Simulated minutes.")
@seed_option("the sonar and odometry noise")
@click.option("--png", type=PICTURE, default=None, help="Draw the path.")
@method_options
@reflex_options(default=NONE)
@click.option(
    "--sensor",
    type=click.Choice(DWA_SENSORS),
    default=DWA_SENSORS[0],
    show_default=True,
    help="How it knows the obstacles: the world's true map and pose, or the sonar ring's "
    "echoes placed by odometry.",
)
@memory_options(base="none: the last reading's echoes alone")
@click.option("--force", is_flag=True, help="Overwrite the --png file.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as JSON.")
def baseline_dwa(
    world_entry: str,
    behaviour: str,
    goal: tuple[float, float] | None,
    minutes: float,
    seed: int,
    png: Path | None,
    method: MethodChoice,
    sensor: str,
    force: bool,
    as_json: bool,
) -> None:
    """Drive WORLD with the Dynamic Window Approach, by the true map or by the sonar ring."""
    world = world_given(world_entry)
    refuse_outputs({"--png": png}, {"WORLD": world_file(world)}, force)
    report = dwa_session(
        world,
        behaviour,
        goal,
        minutes,
        seed,
        png,
        method,
        sensor,
    )
    if as_json:
        print_json(report.document())
    else:
        views.run_metrics(report.metrics, report.method)


@baseline.command("qlearn", epilog=examples("baseline qlearn"))
@click.argument("world_entry", metavar="WORLD", shell_complete=complete_world)
@click.option(
    "--learn-minutes", type=float, default=15.0, show_default=True, help="Simulated minutes."
)
@click.option(
    "--minutes", type=float, default=5.0, show_default=True, help="Greedy run, simulated minutes."
)
@seed_option("exploration and the sonar and odometry noise")
@click.option(
    "--competence-every",
    type=float,
    default=None,
    metavar="K",
    help="Judge competence with a 5-minute greedy run every K learning minutes.",
)
@click.option("--png", type=PICTURE, default=None, help="Draw the greedy run.")
@method_options
@reflex_options(default=NONE)
@click.option("--force", is_flag=True, help="Overwrite the --png file.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as JSON.")
def baseline_qlearn(
    world_entry: str,
    learn_minutes: float,
    minutes: float,
    seed: int,
    competence_every: float | None,
    png: Path | None,
    method: MethodChoice,
    force: bool,
    as_json: bool,
) -> None:
    """Learn a Q-table over the single FAM's rules in WORLD, then avoid greedily with it."""
    world = world_given(world_entry)
    refuse_outputs({"--png": png}, {"WORLD": world_file(world)}, force)
    report = qlearn_session(world, learn_minutes, minutes, seed, competence_every, png, method)
    if as_json:
        print_json(report.document())
    else:
        views.run_metrics(report.result.evaluation, report.method)
        click.echo(report.summary())
