"""`tvl learn`: exploratory learning into a log."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from tvl_cli.agent.explore import MinuteStats
from tvl_cli.cli import views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.memory_options import memory_options
from tvl_cli.cli.options import (
    HDF5,
    live_options,
    method_options,
    print_json,
    refuse_outputs,
    robot_option,
    seed_option,
    training_options,
)
from tvl_cli.cli.params import complete_world
from tvl_cli.commands.learn import LearnRequest, LearnResult, learn_to_log
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.errors import BadInput
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.method import DEFAULT, EXPLORATION_RULES, FIELDS, MethodChoice
from tvl_cli.core.robot_config import (
    EDGE_ECHO_RANGE_M,
    FASTEST_MPS,
    SONAR_MODEL_NAMES,
    RobotConfig,
)
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT_NAME
from tvl_cli.core.words import counted
from tvl_cli.io.interrupts import STOPPED_EXIT
from tvl_cli.sim.world_entries import named_worlds

DEFAULT_LEARN = LearnParams()


@click.command(epilog=examples("learn"))
@click.argument(
    "world_entries", metavar="WORLD...", nargs=-1, required=True, shell_complete=complete_world
)
@click.option(
    "--log",
    type=HDF5,
    required=True,
    help="Learning log (.h5) to create or add a session to.",
)
@click.option(
    "--minutes",
    type=float,
    default=DEFAULT_LEARN.minutes,
    show_default=True,
    help="Simulated minutes (in each world).",
)
@seed_option("every random choice (exploration's ties, sonar and odometry noise)")
@method_options
@training_options
@click.option(
    "--fam",
    "fam_out",
    type=HDF5,
    default=None,
    help="Also write the online FAM here (.h5).",
)
@click.option(
    "--learn-speed",
    type=click.FloatRange(0.0, FASTEST_MPS, min_open=True),
    default=DEFAULT_LEARN.learn_speed_mps,
    show_default=True,
    help="m/s, up to the fastest trajectory's.",
)
@click.option(
    "--near",
    type=float,
    default=None,
    help="m: a sonar ahead closing in this near marks a collision point (0: bumps only; "
    f"default: the method's, ours {DEFAULT.near_m:g}).",
)
@click.option(
    "--explore",
    type=click.Choice(EXPLORATION_RULES),
    default=None,
    help="Which pair to follow next: the least experienced (the paper's rule), the least "
    "experienced of those leading to places the odometry has not been, or a random one "
    f"(default: the method's, ours {DEFAULT.exploration}).",
)
@click.option(
    "--sonar",
    type=click.Choice(SONAR_MODEL_NAMES),
    default=None,
    help=f"edges: convex edges echo within a quarter of the ring's range ({EDGE_ECHO_RANGE_M:g} m "
    f"on the yamabico); ideal: nearest hit at any angle, no noise (default: the method's, ours "
    f"{DEFAULT.sonar}).",
)
@click.option(
    "--from-fam",
    type=click.Path(path_type=Path),
    default=None,
    help="Start a new log from this trained FAM (of the same --config).",
)
@robot_option("The robot that learns: its body, trajectories and sonar ring.", DEFAULT_ROBOT_NAME)
@memory_options(base=DEFAULT.memory.kind)
@click.option("--force", is_flag=True, help="Overwrite the --fam file.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON summary.")
@live_options("learning")
def learn(
    world_entries: tuple[str, ...],
    log: Path,
    minutes: float,
    seed: int,
    method: MethodChoice,
    config: str,
    symmetric: bool,
    init_velocity_mps: float,
    fam_out: Path | None,
    learn_speed: float,
    from_fam: Path | None,
    robot: RobotConfig,
    force: bool,
    as_json: bool,
    live: bool,
    pace: float | None,
) -> None:
    """Explore WORLD and learn trajectory velocities, recording every episode in a log.

    Several worlds (files, generated worlds as KIND:SEED or KIND:FIRST-LAST, bundled names)
    are learnt one after another, a session each in the same log, each going on from what
    the sessions before it learnt: experience from many worlds in one log and one FAM."""
    worlds = [found for entry in world_entries for found in named_worlds(entry)]
    files = {f"WORLD {w.entry}": w.path for w in worlds}
    refuse_outputs({"--fam": fam_out}, {"--log": log, **files, "--from-fam": from_fam}, force)
    if from_fam is not None and len(worlds) > 1:
        raise BadInput("--from-fam starts a new log: give it one world, then add the others")
    for index, named in enumerate(worlds):
        last = index == len(worlds) - 1
        request = LearnRequest(
            named.world if named.path is None else named.path,
            log,
            seed,
            config,
            LearnParams(minutes=minutes, learn_speed_mps=learn_speed),
            method.over(DEFAULT, FIELDS),
            fam_out if last else None,  # the online FAM after every world
            from_fam=from_fam,
            symmetric=symmetric,
            init_velocity_mps=init_velocity_mps,
            body=robot,
        )
        if index == 0:
            views.warn_of_other_worlds(log, named.path or named.world, named.entry)
        result = _learn_one(request, live, pace, quiet=as_json)
        if as_json:
            # One document a world, a line each (JSON Lines) when there are several.
            print_json(result.document(), compact=len(worlds) > 1)
        else:
            views.learn_summary(result, log)
        if result.summary.stopped_by:
            sys.exit(STOPPED_EXIT[result.summary.stopped_by])


def _learn_one(request: LearnRequest, live: bool, pace: float | None, quiet: bool) -> LearnResult:
    if live and views.out.is_terminal:
        return _learn_live(request, pace)
    with views.learning_progress(request.learn.minutes, quiet=quiet) as (on_minute, progress):
        return learn_to_log(request, on_minute, progress)


def _learn_live(request: LearnRequest, pace: float | None) -> LearnResult:
    """Learn with the live view: the robot exploring, and the last whole minute's counts."""
    from tvl_cli.cli.live import LiveView, Sight, live_view

    robot = request.robot
    view = LiveView(Sight(request.world_map(), robot, DEFAULT_THRESHOLD, pace=pace))

    def on_minute(stats: MinuteStats) -> None:
        view.caption = (
            f"minute {stats.minute + 1}: {counted(stats.episodes, 'episode')}, "
            f"{counted(stats.collisions, 'collision')}"
        )

    with live_view(view, views.out) as watch:
        return learn_to_log(request, on_minute, watch=watch)
