"""The `tvl` command line: click commands that parse, call one function and render the result."""

from __future__ import annotations

import functools
import json
import sys
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import Any

import click
from click.core import ParameterSource

from tvl_cli import __version__
from tvl_cli.agent.explore import PAPER_NEAR_M, LearnParams
from tvl_cli.agent.reflexes import ALL as ALL_REFLEXES
from tvl_cli.agent.reflexes import NONE as NO_REFLEXES
from tvl_cli.agent.reflexes import STACK_ORDER, parse_reflexes
from tvl_cli.analysis.rules import SORT_KEYS, parse_ring, select_rules
from tvl_cli.baselines.dwa import BEHAVIOURS as DWA_BEHAVIOURS
from tvl_cli.cli import views
from tvl_cli.commands.baseline import dwa_session, qlearn_session
from tvl_cli.commands.demo import run_demo
from tvl_cli.commands.learn import LearnRequest, learn_to_log, resolve_fam_config
from tvl_cli.commands.replay import replay as replay_file
from tvl_cli.commands.run import RunRequest, parse_goal, run_fam
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.behaviours import BEHAVIOUR_NAMES, DEFAULT_THRESHOLD
from tvl_cli.core.config import RobotConfig
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import DEFAULT_INIT_VELOCITY_MPS
from tvl_cli.core.labels import (
    DEFAULT_DECEL_MPS2,
    DEFAULT_MARGIN_M,
    PAPER_DECEL_MPS2,
    PAPER_MARGIN_M,
)
from tvl_cli.core.training import TrainParams
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.famfile import read_fam, write_fam
from tvl_cli.sim.worldgen import KINDS, generate_world
from tvl_cli.sim.worldmap import describe, load_world, world_to_dict


class TvlGroup(click.Group):
    """Turns BadInput into one line on stderr and exit 2; --debug shows the traceback."""

    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except BadInput as error:
            if ctx.obj and ctx.obj.get("debug"):
                raise
            click.echo(f"tvl: error: {error}", err=True)
            sys.exit(2)
        except click.UsageError as error:
            # One line like every other bad input; `tvl COMMAND --help` shows the usage.
            command = f" {error.ctx.command_path}" if error.ctx else ""
            click.echo(f"tvl: error:{command}: {error.format_message()}", err=True)
            sys.exit(2)


@click.group(cls=TvlGroup)
@click.version_option(__version__, prog_name="tvl")
@click.option("--debug", is_flag=True, help="Show the traceback of an error.")
@click.pass_context
def main(ctx: click.Context, debug: bool) -> None:
    """Trajectory Velocity Learning for a simulated sonar-ring mobile robot."""
    ctx.obj = {"debug": debug}


def refuse_existing(path: Path, force: bool) -> None:
    """Output files are never overwritten unless the user says --force, and a missing
    directory is found before any work is done, not after."""
    if path.exists() and not force:
        raise BadInput(f"{path}: already exists (use --force to overwrite)")
    if not path.parent.is_dir():
        raise BadInput(f"{path}: cannot write, directory {path.parent} does not exist")


# --- world commands ---------------------------------------------------------------


@main.group()
def world() -> None:
    """Make, check, show and draw text-map worlds."""


@world.command("new")
@click.argument("kind", type=click.Choice(list(KINDS)))
@click.option("-o", "--output", type=click.Path(path_type=Path), required=True, help="World file.")
@click.option("--size", type=(float, float), default=None, metavar="W H", help="Metres.")
@click.option("--seed", type=int, default=1, show_default=True, help="Layout seed (lab).")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
def world_new(
    kind: str, output: Path, size: tuple[float, float] | None, seed: int, force: bool
) -> None:
    """Write a generated world of KIND."""
    width_m, height_m = size if size else (None, None)
    text = generate_world(kind, width_m, height_m, seed)
    refuse_existing(output, force)
    with atomic_output(output) as temporary:
        temporary.write_text(text, encoding="utf-8")


@world.command("show")
@click.argument("file", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print the geometry as JSON.")
def world_show(file: Path, as_json: bool) -> None:
    """Print a summary of a world file (or its geometry as JSON)."""
    loaded = load_world(file)
    click.echo(json.dumps(world_to_dict(loaded)) if as_json else describe(loaded))


@world.command("check")
@click.argument("file", type=click.Path(path_type=Path))
def world_check(file: Path) -> None:
    """Validate a world file (exit 2 naming the problem)."""
    w = load_world(file)
    click.echo(
        f"{file}: ok ({len(w.segments)} segments, {len(w.discs)} discs, "
        f"{len(w.rings)} rings, {len(w.goals)} goals)"
    )


@world.command("render")
@click.argument("file", type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(path_type=Path), required=True, help="PNG file.")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
def world_render(file: Path, output: Path, force: bool) -> None:
    """Draw a world file as a PNG picture."""
    from tvl_cli.render.plot import render_world  # matplotlib is slow to import; only this needs it

    loaded = load_world(file)
    refuse_existing(output, force)
    render_world(loaded, output)


# --- FAM commands: train, inspect -------------------------------------------------


DEFAULT_LEARN = LearnParams()


def training_options(command: Callable[..., None]) -> Callable[..., None]:
    """--config, --decel, --margin, --no-symmetric and --init-velocity, given to the command
    as `config` and one `train_params`: learn and train label and train alike."""

    @functools.wraps(command)
    def with_params(
        *args: Any,
        decel: float,
        margin: float,
        no_symmetric: bool,
        init_velocity: float,
        paper: bool,
        **kwargs: Any,
    ) -> None:
        if paper:
            _refuse_beside_paper("--decel", "--margin")
            decel, margin = PAPER_DECEL_MPS2, PAPER_MARGIN_M
        params = TrainParams(decel, margin, not no_symmetric, init_velocity)
        command(*args, train_params=params, **kwargs)

    options = (
        click.option(
            "--config", default="single", show_default=True, help="single, multi or FILE.json."
        ),
        click.option(
            "--paper",
            is_flag=True,
            help=f"The paper's method: labels at {PAPER_DECEL_MPS2:g} m/s² with a "
            f"{PAPER_MARGIN_M:g} m margin (and, learning, collision points by bumps only).",
        ),
        click.option(
            "--decel",
            type=float,
            default=DEFAULT_DECEL_MPS2,
            show_default=True,
            help="Deceleration of the labels, m/s².",
        ),
        click.option(
            "--margin",
            type=float,
            default=DEFAULT_MARGIN_M,
            show_default=True,
            help="Stop this far short of a collision point, m.",
        ),
        click.option("--no-symmetric", is_flag=True, help="Train each trajectory only on itself."),
        click.option(
            "--init-velocity",
            type=float,
            default=DEFAULT_INIT_VELOCITY_MPS,
            show_default=True,
            help="Every entry's velocity before training, m/s.",
        ),
    )
    for option in reversed(options):
        with_params = option(with_params)
    return with_params


def _refuse_beside_paper(*options: str) -> None:
    """--paper fixes these options: giving one as well is a contradiction, not a choice."""
    ctx = click.get_current_context()
    for option in options:
        name = option.lstrip("-").replace("-", "_")
        if ctx.get_parameter_source(name) is ParameterSource.COMMANDLINE:
            raise BadInput(f"{option} cannot be given with --paper, which fixes it")


def reflex_options(default: str) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """--reflex NAMES and --paper, given to the command as one `reflexes` tuple."""

    def decorate(command: Callable[..., None]) -> Callable[..., None]:
        @functools.wraps(command)
        def with_reflexes(*args: Any, reflex: str, paper: bool, **kwargs: Any) -> None:
            if paper:
                _refuse_beside_paper("--reflex")
            reflexes = () if paper else parse_reflexes(reflex)
            command(*args, reflexes=reflexes, **kwargs)

        with_reflexes = click.option(
            "--paper", is_flag=True, help="The paper's method alone: no reflexes."
        )(with_reflexes)
        return click.option(
            "--reflex",
            default=default,
            show_default=True,
            metavar="NAMES",
            help=f"Reflexes beyond the paper, comma-separated: {', '.join(STACK_ORDER)}; "
            "or all, or none.",
        )(with_reflexes)

    return decorate


def _print_json(value: object) -> None:
    click.echo(json.dumps(value, indent=1, allow_nan=False))


@main.command()
@click.argument("logs", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(path_type=Path), required=True, help="FAM file.")
@training_options
@click.option(
    "--until-minute",
    type=float,
    default=None,
    help="Use only the episodes each session finished by this simulated minute.",
)
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
def train(
    logs: tuple[Path, ...],
    output: Path,
    config: str,
    train_params: TrainParams,
    until_minute: float | None,
    force: bool,
) -> None:
    """Train a FAM file from learning logs (log replay)."""
    refuse_existing(output, force)
    fam_config = resolve_fam_config(config, RobotConfig())
    with views.progress("training") as bar:
        summary = train_from_logs(list(logs), fam_config, train_params, bar, until_minute)
    write_fam(output, summary.fam, robot_config=summary.robot, provenance=summary.provenance)
    views.train_summary(summary, output)


@main.command()
@click.argument("fam", type=click.Path(path_type=Path))
@click.option("--trajectory", default=None, help="Only this trajectory's rules, e.g. T1L.")
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
def inspect(
    fam: Path,
    trajectory: str | None,
    top: int,
    sort: str,
    untrained: bool,
    explain: str | None,
    as_json: bool,
) -> None:
    """Print a FAM file's rules as a person reads them."""
    loaded = read_fam(fam)
    if explain is not None:
        explanation = loaded.fam.explain(parse_ring(explain, loaded.robot_config.sonar.count))
        if as_json:
            _print_json(explanation.to_dict())
        else:
            views.explanation(explanation)
        return
    rules = select_rules(loaded.fam, trajectory, top, sort, untrained)
    if as_json:
        _print_json(
            {
                "config": loaded.fam.config.to_dict(),
                "provenance": loaded.provenance,
                "rules": [r.to_dict() for r in rules],
            }
        )
    else:
        for rule in rules:
            click.echo(rule.sentence())


# --- learn, run, replay, demo -----------------------------------------------------


@main.command()
@click.argument("world_file", metavar="WORLD", type=click.Path(path_type=Path))
@click.option(
    "--log",
    type=click.Path(path_type=Path),
    required=True,
    help="Learning log to create or add a session to.",
)
@click.option(
    "--minutes",
    type=float,
    default=DEFAULT_LEARN.minutes,
    show_default=True,
    help="Simulated minutes.",
)
@click.option("--seed", type=int, default=1, show_default=True)
@training_options
@click.option(
    "--fam",
    "fam_out",
    type=click.Path(path_type=Path),
    default=None,
    help="Also write the online FAM here.",
)
@click.option(
    "--learn-speed",
    type=float,
    default=DEFAULT_LEARN.learn_speed_mps,
    show_default=True,
    help="m/s.",
)
@click.option(
    "--near",
    type=float,
    default=DEFAULT_LEARN.near_m,
    show_default=True,
    help="m: a sonar ahead closing in this near marks a collision point (0: bumps only).",
)
@click.option(
    "--sonar",
    type=click.Choice(["real", "ideal"]),
    default="real",
    show_default=True,
    help="ideal: nearest hit at any angle, no noise.",
)
@click.option("--force", is_flag=True, help="Overwrite the --fam file.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON summary.")
def learn(
    world_file: Path,
    log: Path,
    minutes: float,
    seed: int,
    config: str,
    fam_out: Path | None,
    train_params: TrainParams,
    learn_speed: float,
    near: float,
    sonar: str,
    force: bool,
    as_json: bool,
) -> None:
    """Explore WORLD and learn trajectory velocities, recording every episode in a log."""
    if fam_out is not None:
        refuse_existing(fam_out, force)
    if click.get_current_context().params["paper"]:
        _refuse_beside_paper("--near")
        near = PAPER_NEAR_M
    request = LearnRequest(
        world_file,
        log,
        seed,
        config,
        LearnParams(minutes=minutes, learn_speed_mps=learn_speed, near_m=near),
        train_params,
        fam_out,
        ideal_sonar=sonar == "ideal",
    )
    with views.learning_progress(minutes, quiet=as_json) as (on_minute, on_progress):
        result = learn_to_log(request, on_minute, on_progress)
    if as_json:
        _print_json(views.learn_json(result))
    else:
        views.learn_summary(result, log)
    if result.summary.stopped_by:
        sys.exit(130 if result.summary.stopped_by == "SIGINT" else 143)


@main.command()
@click.argument("fam", type=click.Path(path_type=Path))
@click.argument("world_file", metavar="WORLD", type=click.Path(path_type=Path))
@click.option("--behaviour", type=click.Choice(BEHAVIOUR_NAMES), required=True)
@click.option(
    "--threshold",
    type=float,
    default=DEFAULT_THRESHOLD,
    show_default=True,
    help="A trajectory is fast at this fraction of its maximum, in (0, 1].",
)
@click.option("--goal", default=None, metavar="X,Y", help="Goal in metres (default: the world's).")
@click.option("--minutes", type=float, default=5.0, show_default=True, help="Simulated minutes.")
@click.option("--seed", type=int, default=1, show_default=True)
@click.option("--png", type=click.Path(path_type=Path), default=None, help="Draw the path.")
@click.option(
    "--log", "trace", type=click.Path(path_type=Path), default=None, help="Write a run trace."
)
@reflex_options(default=ALL_REFLEXES)
@click.option(
    "--sonar",
    type=click.Choice(["real", "ideal"]),
    default=None,
    help="The sonar model to drive with (default: the one the FAM was learnt with).",
)
@click.option("--force", is_flag=True, help="Overwrite the --png and --log files.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as JSON.")
def run(
    fam: Path,
    world_file: Path,
    behaviour: str,
    threshold: float,
    goal: str | None,
    minutes: float,
    seed: int,
    png: Path | None,
    trace: Path | None,
    reflexes: tuple[str, ...],
    sonar: str | None,
    force: bool,
    as_json: bool,
) -> None:
    """Perform a behaviour in WORLD with a learnt FAM.

    Every rule beyond the paper's method is a reflex: --paper (or --reflex none) runs the
    paper's method alone."""
    for output in (png, trace):
        if output is not None:
            refuse_existing(output, force)
    request = RunRequest(
        fam,
        world_file,
        behaviour,
        threshold,
        minutes,
        seed,
        parse_goal(goal) if goal else None,
        png,
        trace,
        reflexes,
        sonar,
    )
    metrics = run_fam(request)
    if as_json:
        _print_json(asdict(metrics))
    else:
        views.run_metrics(metrics, reflexes)


@main.command()
@click.argument("file", type=click.Path(path_type=Path))
@click.option("--png", type=click.Path(path_type=Path), default=None, help="Draw the paths.")
@click.option(
    "--curves",
    type=click.Path(path_type=Path),
    default=None,
    help="Draw the learning curves (learning logs).",
)
@click.option("--force", is_flag=True, help="Overwrite the PNG files.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def replay(file: Path, png: Path | None, curves: Path | None, force: bool, as_json: bool) -> None:
    """Summarise a learning log or a run trace, and draw it."""
    for output in (png, curves):
        if output is not None:
            refuse_existing(output, force)
    summary = replay_file(file, png, curves)
    if as_json:
        _print_json(summary.to_dict())
    else:
        views.replay(summary)


@main.command()
@click.argument("directory", default="tvl-demo", type=click.Path(path_type=Path))
@click.option("--force", is_flag=True, help="Write into a DIRECTORY that is not empty.")
def demo(directory: Path, force: bool) -> None:
    """Learn, train, run and draw on a bundled world, in seconds."""
    views.demo(run_demo(directory, force, views.say))


# --- baselines --------------------------------------------------------------------


@main.group()
def baseline() -> None:
    """Controllers to measure TVL against: DWA and tabular Q-learning."""


@baseline.command("dwa")
@click.argument("world_file", metavar="WORLD", type=click.Path(path_type=Path))
@click.option("--behaviour", type=click.Choice(DWA_BEHAVIOURS), default="avoid", show_default=True)
@click.option("--goal", default=None, metavar="X,Y", help="Goal in metres (default: the world's).")
@click.option("--minutes", type=float, default=5.0, show_default=True, help="Simulated minutes.")
@click.option("--seed", type=int, default=1, show_default=True)
@click.option("--png", type=click.Path(path_type=Path), default=None, help="Draw the path.")
@reflex_options(default=NO_REFLEXES)
@click.option("--force", is_flag=True, help="Overwrite the --png file.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as JSON.")
def baseline_dwa(
    world_file: Path,
    behaviour: str,
    goal: str | None,
    minutes: float,
    seed: int,
    png: Path | None,
    reflexes: tuple[str, ...],
    force: bool,
    as_json: bool,
) -> None:
    """Drive WORLD with the Dynamic Window Approach, which knows the true obstacles."""
    if png is not None:
        refuse_existing(png, force)
    metrics = dwa_session(
        world_file, behaviour, parse_goal(goal) if goal else None, minutes, seed, png, reflexes
    )
    if as_json:
        _print_json(asdict(metrics))
    else:
        views.run_metrics(metrics, reflexes)


@baseline.command("qlearn")
@click.argument("world_file", metavar="WORLD", type=click.Path(path_type=Path))
@click.option(
    "--learn-minutes", type=float, default=15.0, show_default=True, help="Simulated minutes."
)
@click.option(
    "--minutes", type=float, default=5.0, show_default=True, help="Greedy run, simulated minutes."
)
@click.option("--seed", type=int, default=1, show_default=True)
@click.option(
    "--competence-every",
    type=float,
    default=None,
    metavar="K",
    help="Judge competence with a 5-minute greedy run every K learning minutes.",
)
@click.option("--png", type=click.Path(path_type=Path), default=None, help="Draw the greedy run.")
@reflex_options(default=NO_REFLEXES)
@click.option("--force", is_flag=True, help="Overwrite the --png file.")
@click.option("--json", "as_json", is_flag=True, help="Print the metrics as JSON.")
def baseline_qlearn(
    world_file: Path,
    learn_minutes: float,
    minutes: float,
    seed: int,
    competence_every: float | None,
    png: Path | None,
    reflexes: tuple[str, ...],
    force: bool,
    as_json: bool,
) -> None:
    """Learn a Q-table over the single FAM's rules in WORLD, then avoid greedily with it."""
    if png is not None:
        refuse_existing(png, force)
    report = qlearn_session(
        world_file, learn_minutes, minutes, seed, competence_every, png, reflexes
    )
    if as_json:
        _print_json(report.to_dict())
    else:
        views.run_metrics(report.result.evaluation, reflexes)
        click.echo(report.summary())


# --- experiment figures -----------------------------------------------------------


@main.command()
@click.argument("name", metavar="NAME")
@click.argument("results", type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(path_type=Path), required=True, help="PNG file.")
@click.option("--table", type=click.Path(path_type=Path), default=None, help="Markdown file.")
@click.option("--force", is_flag=True, help="Overwrite the PNG and table files.")
def figure(name: str, results: Path, output: Path, table: Path | None, force: bool) -> None:
    """Draw figure NAME (fig19, fig21, fig22, fig24, fig27) from an experiment's RESULTS
    (JSON lines) and print its summary table."""
    from tvl_cli.render.figures import (
        draw_figure,  # matplotlib is slow to import; only this needs it
    )

    for path in (output, table):
        if path is not None:
            refuse_existing(path, force)
    click.echo(draw_figure(name, results, output, table), nl=False)
