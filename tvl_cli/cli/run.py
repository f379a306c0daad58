"""`tvl run`: a behaviour performed with a learnt FAM, watched, traced and scored.

The command imports the modules that do its work when it runs, so that `--help` reads only
the options (and loads neither HDF5 nor the physics).
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING

import click

from tvl_cli.cli import views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.memory_options import memory_options
from tvl_cli.cli.options import (
    GOAL,
    HDF5,
    PICTURE,
    live_options,
    method_options,
    print_csv,
    print_json,
    reflex_options,
    refuse_both_formats,
    refuse_existing,
    refuse_shared_paths,
    robot_option,
    seed_option,
    world_file,
    world_given,
)
from tvl_cli.cli.params import complete_world
from tvl_cli.core.behaviours import BEHAVIOUR_NAMES, DEFAULT_THRESHOLD
from tvl_cli.core.errors import DEFAULT_RUN_MINUTES
from tvl_cli.core.method import DEFAULT, REFLEX_NAMES, MethodChoice
from tvl_cli.core.robot_config import SONAR_MODEL_NAMES, RobotConfig

if TYPE_CHECKING:
    from tvl_cli.agent.drive import StepSink
    from tvl_cli.commands.run import RunRequest, RunResult
    from tvl_cli.sim.worldmap import WorldMap


# Where `tvl run --view` shows the run as it goes.
TERMINAL, WINDOW = "terminal", "window"
VIEWS = (TERMINAL, WINDOW)


@click.command(epilog=examples("run"))
@click.argument("fam", type=click.Path(path_type=Path))
@click.argument("world_entry", metavar="WORLD", shell_complete=complete_world)
@click.option("--behaviour", type=click.Choice(BEHAVIOUR_NAMES), required=True)
@click.option(
    "--threshold",
    type=float,
    default=DEFAULT_THRESHOLD,
    show_default=True,
    help="A trajectory is fast at this fraction of its maximum, in (0, 1].",
)
@GOAL
@click.option(
    "--minutes",
    type=float,
    default=DEFAULT_RUN_MINUTES,
    show_default=True,
    help="Simulated minutes.",
)
@seed_option("the sonar and odometry noise")
@click.option("--png", type=PICTURE, default=None, help="Draw the path.")
@click.option("--log", "trace", type=HDF5, default=None, help="Write a run trace (.h5).")
@method_options
@reflex_options(
    default="ours, all but " + ", ".join(n for n in REFLEX_NAMES if n not in DEFAULT.reflexes)
)
@click.option(
    "--sonar",
    type=click.Choice(SONAR_MODEL_NAMES),
    default=None,
    help="The sonar model to drive with (default: the one the FAM was learnt with).",
)
@robot_option("The robot to drive, refused unless the FAM was learnt on it (default: the FAM's).")
@click.option(
    "--learn",
    is_flag=True,
    help="Learn while behaving: train the FAM on what the run meets, in memory.",
)
@click.option(
    "--learn-log",
    type=HDF5,
    default=None,
    metavar="LOG",
    help="Learn while behaving (as --learn) and append what is learnt to LOG as a behaving "
    "session, for `tvl train`.",
)
@memory_options(base="the one the FAM was trained through")
@click.option("--force", is_flag=True, help="Overwrite the --png and --log files.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as JSON.")
@click.option("--csv", "as_csv", is_flag=True, help="Print the metrics as a CSV row.")
@live_options("run")
@click.option(
    "--view",
    type=click.Choice(VIEWS),
    default=None,
    help="Watch the run as it goes: in the terminal (as --live), or in a window (as "
    "replay --gif draws it).",
)
def run(
    fam: Path,
    world_entry: str,
    behaviour: str,
    threshold: float,
    goal: tuple[float, float] | None,
    minutes: float,
    seed: int,
    png: Path | None,
    trace: Path | None,
    method: MethodChoice,
    learn: bool,
    learn_log: Path | None,
    robot: RobotConfig | None,
    force: bool,
    as_json: bool,
    as_csv: bool,
    live: bool,
    pace: float | None,
    view: str | None,
) -> None:
    """Perform a behaviour in WORLD with a learnt FAM.

    WORLD is a world file, a generated world (KIND:SEED) or a bundled world's name, as for
    `tvl learn`. Every rule beyond the paper's method is a reflex: --reflex none runs the
    paper's choice rule alone, and --paper the paper's whole method (no reflex, no echo
    memory) on the FAM."""
    from tvl_cli.commands.run import OnlineLearning, RunRequest, run_behaviour
    from tvl_cli.io.interrupts import STOPPED_EXIT, catching_signals

    refuse_both_formats(as_json, as_csv)
    if live and view is not None:
        raise click.UsageError("give --live or --view, not both")
    learning = OnlineLearning(learn_log) if learn or learn_log is not None else None
    world = world_given(world_entry)
    _check_outputs(fam, world, world_entry, png, trace, learn_log, force)
    request = RunRequest(
        fam,
        world,
        behaviour,
        threshold,
        minutes,
        seed,
        goal,
        png,
        trace,
        method,
        learning,
        robot,
    )
    with (
        catching_signals() as interrupted,
        _watching(request, TERMINAL if live else view, pace) as watch,
    ):
        result = run_behaviour(request, watch, interrupted.reason)
    _show_run(request, result, "json" if as_json else "csv" if as_csv else None)
    if result.stopped_by is not None:
        views.stopped(result.stopped_by, result.metrics.sim_s, trace)
        sys.exit(STOPPED_EXIT[result.stopped_by])


def _check_outputs(
    fam: Path,
    world: Path | WorldMap,
    given: str,
    png: Path | None,
    trace: Path | None,
    learn_log: Path | None,
    force: bool,
) -> None:
    """Before the run: refuse an output that is an input or another output, or one that exists
    without --force; warn of a learn log that holds other worlds."""
    refuse_shared_paths(
        {"--png": png, "--log": trace, "--learn-log": learn_log},
        {"FAM": fam, "WORLD": world_file(world)},
    )
    for output in (png, trace):
        if output is not None:
            refuse_existing(output, force)
    if learn_log is not None:
        views.warn_of_other_worlds(learn_log, world, given)


def _show_run(request: RunRequest, result: RunResult, form: str | None) -> None:
    """The run's results as JSON, as a CSV row or (`form` None) in words."""
    if form == "json":
        print_json(result.document())
    elif form == "csv":
        print_csv([asdict(result.metrics)])
    else:
        views.run_metrics(result.metrics, result.method)
        views.run_learning(result, request.learn.log if request.learn else None)


@contextmanager
def _watching(request: RunRequest, view: str | None, pace: float | None) -> Iterator[StepSink]:
    """What shows the run as it goes: a window, or the live view on a terminal that asked
    for either; else a progress bar (itself shown only on a terminal)."""
    if view is None or (view == TERMINAL and not views.out.is_terminal):
        with views.run_progress(request.minutes) as bar:
            yield bar
        return
    from tvl_cli.cli.live import LiveView, Sight, WindowView, live_view, window_view
    from tvl_cli.commands.run import request_robot
    from tvl_cli.sim.worldmap import resolve_goal, world_of

    world = world_of(request.world)
    robot = request_robot(request)
    goal = resolve_goal(request.world, world, request.behaviour, request.goal)
    sight = Sight(world, robot, request.threshold, goal, pace)
    if view == WINDOW:
        with window_view(WindowView(sight)) as shown:
            yield shown
        return
    with live_view(LiveView(sight), views.out) as watch:
        yield watch
