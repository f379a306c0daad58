"""Options and checks shared by several commands."""

from __future__ import annotations

import functools
import json
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click
from click.core import ParameterSource

from tvl_cli.cli.params import (
    Parsed,
    complete_config,
    complete_method,
    complete_reflexes,
    goal_point,
)
from tvl_cli.core.errors import MAX_SEED, BadInput
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, DEFAULT_INIT_VELOCITY_MPS
from tvl_cli.core.labels import EVERY_TRAJECTORY, LABEL_RULES, MAX_LABEL_CEILING, ceiling_radius
from tvl_cli.core.memory import (
    NOT_CHOSEN,
    MemoryChoice,
)
from tvl_cli.core.method import (
    DEFAULT,
    FLAGS,
    MEMORY_SETTINGS,
    PAPER,
    PAPER_NAME,
    REFLEX_NAMES,
    MethodChoice,
    parse_reflexes,
)
from tvl_cli.core.robot_config import SLOWEST_TOP_MPS
from tvl_cli.core.robot_profiles import ROBOT_PROFILES
from tvl_cli.io.atomic import refuse_missing_directory, refuse_non_file
from tvl_cli.io.methodfile import resolve_method
from tvl_cli.io.robotfile import resolve_robot
from tvl_cli.io.table import csv_text
from tvl_cli.render.formats import picture_format, refuse_other_extension

if TYPE_CHECKING:
    from tvl_cli.sim.worldmap import WorldMap


class Seed(click.ParamType):
    """A seed: a whole number a 64-bit file field holds and numpy takes (0 to 2^63 - 1),
    said so in words rather than as click's range of nineteen digits."""

    name = "seed"

    def get_metavar(self, *args: Any, **kwargs: Any) -> str:
        return "N"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if isinstance(value, int) and not isinstance(value, bool):
            number = value
        else:
            try:
                number = int(str(value).strip())
            except ValueError:
                self.fail(f"{value!r} is not a whole number", param, ctx)
        if not 0 <= number <= MAX_SEED:
            self.fail(f"{value} is not a seed: a whole number from 0 to 2^63 - 1", param, ctx)
        return number


SEED = Seed()


def seed_option(what: str) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """--seed N, default 1, its help saying `what` it draws: the same seed and inputs give the
    same outputs."""
    return click.option(
        "--seed",
        type=SEED,
        default=1,
        show_default=True,
        help=f"Seed of {what}; the same seed gives the same result.",
    )


# `--robot NAME|FILE.toml`: a shipped robot by name, or a robot file (io.robotfile).
ROBOT = Parsed("NAME|FILE.toml", functools.partial(resolve_robot, label=""))


def robot_option(help_text: str, default: str | None = None) -> Callable[..., Any]:
    """--robot NAME|FILE.toml: the robots named (or any robot file), with `help_text`."""
    return click.option(
        "--robot",
        type=ROBOT,
        metavar=ROBOT.name,
        default=default,
        show_default=default is not None,
        help=f"{help_text} Robots: {', '.join(ROBOT_PROFILES)}, or a robot file (TOML).",
    )


class FormattedPath(click.Path):
    """An output whose name's extension says its format: `check` (render.formats) refuses
    a name that does not, on parsing, before any work."""

    def __init__(self, check: Callable[[str], object]) -> None:
        super().__init__(path_type=Path)
        self.check = check

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        path = super().convert(value, param, ctx)
        try:
            self.check(os.fsdecode(path))
        except BadInput as error:
            self.fail(str(error), param, ctx)
        return path


# A picture in the format its extension names; any other output named for its one format.
PICTURE = FormattedPath(picture_format)
PICTURE_HELP = "Picture file: .png, .svg, .pdf or .jpg."


def named_for(*extensions: str, kind: str = "") -> FormattedPath:
    """An output of one format, its name ending in one of `extensions`."""
    return FormattedPath(lambda path: refuse_other_extension(path, *extensions, kind=kind))


GIF = named_for(".gif", kind="a GIF")
MP4 = named_for(".mp4", kind="an MP4 video")
HDF5 = named_for(".h5", ".hdf5", kind="HDF5")
MCAP = named_for(".mcap", kind="MCAP")
JSON_FILE = named_for(".json", kind="JSON")
MARKDOWN = named_for(".md", kind="Markdown")
# --goal X,Y, for the commands that seek a goal; checked against the world where it is read.
GOAL = click.option(
    "--goal",
    type=Parsed("point", goal_point),
    default=None,
    metavar="X,Y",
    help="Goal in metres (default: the world's).",
)


def world_given(entry: str) -> Path | WorldMap:
    """The one world a command drives in, named as `tvl learn` names worlds (a file, a
    generated world KIND:SEED, a bundled world's name): its file, or the world made here."""
    from tvl_cli.sim.world_entries import named_world  # generating loads numpy: not for --help

    return named_world(entry)


def world_file(world: Path | WorldMap) -> Path | None:
    """The file a world was read from, as an input no output may overwrite (None: made here)."""
    return world if isinstance(world, Path) else None


def refuse_existing(path: Path, force: bool) -> None:
    """Output files are never overwritten unless the user says --force, and a missing
    directory is found before any work is done, not after."""
    refuse_non_file(path)
    if path.exists() and not force:
        raise BadInput(f"{path}: already exists (use --force to overwrite)")
    refuse_missing_directory(path)


def refuse_shared_paths(
    outputs: dict[str, Path | None], inputs: dict[str, Path | None] | None = None
) -> None:
    """Each output a file of its own: not another output (one would silently replace the
    other), nor an input (which --force would destroy). Keys name the options, as
    "--log"."""
    named = [(o, p) for o, p in outputs.items() if p is not None]
    given = [*named, *((i, p) for i, p in (inputs or {}).items() if p is not None)]
    for index, (option, path) in enumerate(named):
        for other, other_path in given[index + 1 :]:
            if path.resolve() == other_path.resolve():
                raise BadInput(
                    f"{path}: given as both {option} and {other}; each needs its own file"
                )


def refuse_outputs(
    outputs: dict[str, Path | None], inputs: dict[str, Path | None], force: bool
) -> None:
    """Before any work: each output given is a file of its own (`refuse_shared_paths`) that
    may be written (`refuse_existing`)."""
    refuse_shared_paths(outputs, inputs)
    for path in outputs.values():
        if path is not None:
            refuse_existing(path, force)


def label_options(command: Callable[..., None]) -> Callable[..., None]:
    """--decel, --margin, --labels, --label-ceiling and --label-ceiling-radius: how a recorded
    point becomes labels, settings of the method (method_options)."""
    options = (
        click.option(
            "--decel",
            type=float,
            default=None,
            help=f"Deceleration of the labels, m/s² (default: the method's; ours "
            f"{DEFAULT.decel_mps2:g}).",
        ),
        click.option(
            "--margin",
            type=float,
            default=None,
            help=f"Stop this far short of a collision point, m (default: the method's; ours "
            f"{DEFAULT.margin_m:g}).",
        ),
        click.option(
            "--labels",
            type=click.Choice(LABEL_RULES),
            default=None,
            help="What each recorded point labels: the trajectory driven, from where it "
            "bumped (bump, the paper's), or every trajectory, each from the echoes heard "
            f"around the point (heard) (default: the method's; ours {DEFAULT.labels}).",
        ),
        click.option(
            "--label-ceiling",
            type=float,
            default=None,
            help="Labels no faster than this many times the trajectory's top speed, 1 to "
            f"{MAX_LABEL_CEILING:g}: above 1 a label still tells how much farther a way is "
            "clear (the robot never drives faster than the top) (default: the method's; ours "
            f"{DEFAULT.label_ceiling:g}; the paper's {PAPER.label_ceiling:g}).",
        ),
        click.option(
            "--label-ceiling-radius",
            type=float,
            default=None,
            help="Lift only the labels of the arcs turning no wider than this radius, m, to the "
            f"ceiling; the wider arcs and the straight way stay at their top speed; "
            f"{EVERY_TRAJECTORY}: every trajectory's (default: the method's; ours "
            f"{DEFAULT.label_ceiling_radius_m:g}).",
        ),
    )
    for option in reversed(options):
        command = option(command)
    return command


def training_options(command: Callable[..., None]) -> Callable[..., None]:
    """--config, the labels' options (label_options), --no-symmetric and --init-velocity:
    learn and train label and train alike. The labels are the method's (method_options); the
    command is given `symmetric` and `init_velocity_mps`."""

    @functools.wraps(command)
    def with_settings(*args: Any, no_symmetric: bool, init_velocity: float, **kwargs: Any) -> None:
        command(*args, symmetric=not no_symmetric, init_velocity_mps=init_velocity, **kwargs)

    decorated: Callable[..., None] = click.option(
        "--init-velocity",
        type=click.FloatRange(0.0, SLOWEST_TOP_MPS, max_open=True),
        default=DEFAULT_INIT_VELOCITY_MPS,
        show_default=True,
        help="Every entry's velocity before training, m/s.",
    )(with_settings)
    decorated = click.option(
        "--no-symmetric", is_flag=True, help="Train each trajectory only on itself."
    )(decorated)
    decorated = label_options(decorated)
    return click.option(
        "--config",
        default="single",
        show_default=True,
        shell_complete=complete_config,
        help=f"{', '.join(BUILTIN_FAM_CONFIGS)} or FILE.json.",
    )(decorated)


def given_on_command_line(*options: str) -> list[str]:
    """Those of `options` (as "--from") that the user typed, rather than left at a default."""
    ctx = click.get_current_context()
    names = {flag: param.name for param in ctx.command.params for flag in param.opts}
    return [
        option
        for option in options
        if ctx.get_parameter_source(names[option]) is ParameterSource.COMMANDLINE
    ]


# The options that set one field of the method each, by their keyword: the value as given ->
# the field's value. Each command declares those of its choices (method_options takes them).
_SETTINGS: dict[str, tuple[str, Callable[[Any], Any]]] = {
    "decel": ("decel_mps2", float),
    "margin": ("margin_m", float),
    "labels": ("labels", str),
    "label_ceiling": ("label_ceiling", float),
    "label_ceiling_radius": ("label_ceiling_radius_m", ceiling_radius),  # inf: every trajectory
    "near": ("near_m", float),
    "explore": ("exploration", str),
    "sonar": ("sonar", str),
    "reflex": ("reflexes", parse_reflexes),
}
_MEMORY_SETTINGS = ("memory", "memory_window", "memory_range", "memory_patch", "memory_clearing")
# The flag of each setting of the memory, as a method choice names it.
_MEMORY_FLAGS = {
    f"memory.{key}": f"--{keyword.replace('_', '-')}"
    for key, keyword in zip(MEMORY_SETTINGS, _MEMORY_SETTINGS, strict=True)
}


def method_options(command: Callable[..., None]) -> Callable[..., None]:
    """--method and --paper, and the finer options the command declares (--decel, --reflex,
    --memory ...), given to the command as one `method` MethodChoice. A finer option beside
    the paper's method chosen by name that sets an addition otherwise than the paper is a
    contradiction, and refused."""

    @functools.wraps(command)
    def with_method(*args: Any, method: str | None, paper: bool, **kwargs: Any) -> None:
        if paper and method is not None:
            raise click.UsageError("give --method or --paper, not both")
        name = PAPER_NAME if paper else method
        settings = tuple(
            (field, convert(kwargs.pop(keyword)))
            for keyword, (field, convert) in _SETTINGS.items()
            if kwargs.get(keyword) is not None
        )
        for keyword in _SETTINGS:
            kwargs.pop(keyword, None)
        memory = (
            MemoryChoice(*(kwargs.pop(keyword) for keyword in _MEMORY_SETTINGS))
            if "memory" in kwargs
            else NOT_CHOSEN
        )
        chosen = None if name is None else resolve_method(name, label="--method")
        choice = MethodChoice(chosen, name, settings, memory)
        how = "--paper" if paper else f"--method {name}"
        for setting in choice.contradictions():
            flag = FLAGS.get(setting) or _MEMORY_FLAGS[setting]
            raise BadInput(f"{flag} cannot be given with {how}, which fixes it")
        command(*args, method=choice, **kwargs)

    with_method = click.option(
        "--paper",
        is_flag=True,
        help=f"Short for --method paper: the paper's method (labels at {PAPER.decel_mps2:g} "
        f"m/s² with a {PAPER.margin_m:g} m margin, collision points at bumps alone, no reflex, "
        "no echo memory).",
    )(with_method)
    return click.option(
        "--method",
        default=None,
        metavar="paper|default|FILE.toml",
        shell_complete=complete_method,
        help="Every choice of the method at once: the paper's, ours, or a method file; the "
        "options below change one choice of it (default: ours, with what the inputs were "
        "made with).",
    )(with_method)


def reflex_options(default: str) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """--reflex NAMES, a setting of the method (method_options); `default` says which
    reflexes a command runs with when neither is given."""

    def decorate(command: Callable[..., None]) -> Callable[..., None]:
        return click.option(
            "--reflex",
            default=None,
            shell_complete=complete_reflexes,
            metavar="NAMES",
            help=f"Reflexes beyond the paper, comma-separated: {', '.join(REFLEX_NAMES)}; "
            f"or all, or none (default: the method's; without one, {default}).",
        )(command)

    return decorate


def print_json(value: object, compact: bool = False) -> None:
    """A JSON document on stdout, indented, or on one line (`compact`: one of several)."""
    click.echo(json.dumps(value, indent=None if compact else 1, allow_nan=False))


def print_csv(rows: list[dict[str, object]]) -> None:
    """Rows as CSV on stdout, as `csv_text` writes them."""
    click.echo(csv_text(rows), nl=False)


def live_options(what: str) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """--live (draw `what` in the terminal as it goes) and its --pace, checked on parsing."""

    def checked_pace(ctx: click.Context, param: click.Parameter, pace: float | None) -> Any:
        if pace is not None and not (math.isfinite(pace) and pace > 0):
            raise BadInput(f"--pace {pace:g} must be a positive number of simulated seconds")
        return pace

    def decorate(command: Callable[..., None]) -> Callable[..., None]:
        command = click.option(
            "--pace",
            type=float,
            default=None,
            callback=checked_pace,
            help="--live: simulated seconds a wall second (default: flat out).",
        )(command)
        return click.option(
            "--live", is_flag=True, help=f"Draw the {what} in the terminal as it goes."
        )(command)

    return decorate


def refuse_both_formats(as_json: bool, as_csv: bool) -> None:
    if as_json and as_csv:
        raise click.UsageError("give --json or --csv, not both")
