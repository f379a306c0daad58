"""Options and checks shared by several commands."""

from __future__ import annotations

import functools
import json
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click
from click.core import ParameterSource

from tvl_cli.agent.reflexes import STACK_ORDER, parse_reflexes
from tvl_cli.cli.params import complete_config, complete_reflexes
from tvl_cli.core.config import BUILTIN_FAM_CONFIGS, SLOWEST_TOP_MPS
from tvl_cli.core.errors import MAX_SEED, BadInput
from tvl_cli.core.fam import DEFAULT_INIT_VELOCITY_MPS
from tvl_cli.core.labels import (
    DEFAULT_DECEL_MPS2,
    DEFAULT_MARGIN_M,
    PAPER_DECEL_MPS2,
    PAPER_MARGIN_M,
)
from tvl_cli.core.memory import (
    DEFAULT_PATCH_M,
    DEFAULT_RANGE_M,
    DEFAULT_WINDOW_S,
    MEMORY_KINDS,
    NONE,
    MemoryChoice,
)
from tvl_cli.core.training import TrainParams
from tvl_cli.io.atomic import refuse_non_file
from tvl_cli.io.table import csv_text
from tvl_cli.render.formats import picture_format, refuse_other_extension

SEED = click.IntRange(0, MAX_SEED)


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


# A picture in the format its extension names; an animation named for its one format.
PICTURE = FormattedPath(picture_format)
PICTURE_HELP = "Picture file: .png, .svg, .pdf or .jpg."
GIF = FormattedPath(functools.partial(refuse_other_extension, extension=".gif"))
MP4 = FormattedPath(functools.partial(refuse_other_extension, extension=".mp4"))


def refuse_existing(path: Path, force: bool) -> None:
    """Output files are never overwritten unless the user says --force, and a missing
    directory is found before any work is done, not after."""
    refuse_non_file(path)
    if path.exists() and not force:
        raise BadInput(f"{path}: already exists (use --force to overwrite)")
    if not path.parent.is_dir():
        raise BadInput(f"{path}: cannot write, directory {path.parent} does not exist")


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
            refuse_beside_paper("--decel", "--margin")
            decel, margin = PAPER_DECEL_MPS2, PAPER_MARGIN_M
        params = TrainParams(decel, margin, not no_symmetric, init_velocity)
        command(*args, train_params=params, **kwargs)

    options = (
        click.option(
            "--config",
            default="single",
            show_default=True,
            shell_complete=complete_config,
            help=f"{', '.join(BUILTIN_FAM_CONFIGS)} or FILE.json.",
        ),
        click.option(
            "--paper",
            is_flag=True,
            help=f"The paper's method: labels at {PAPER_DECEL_MPS2:g} m/s² with a "
            f"{PAPER_MARGIN_M:g} m margin (and, learning, collision points by bumps only and "
            "the least experienced choice).",
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
            type=click.FloatRange(0.0, SLOWEST_TOP_MPS, max_open=True),
            default=DEFAULT_INIT_VELOCITY_MPS,
            show_default=True,
            help="Every entry's velocity before training, m/s.",
        ),
    )
    for option in reversed(options):
        with_params = option(with_params)
    return with_params


def given_on_command_line(*options: str) -> list[str]:
    """Those of `options` (as "--from") that the user typed, rather than left at a default."""
    ctx = click.get_current_context()
    names = {flag: param.name for param in ctx.command.params for flag in param.opts}
    return [
        option
        for option in options
        if ctx.get_parameter_source(names[option]) is ParameterSource.COMMANDLINE
    ]


def refuse_beside_paper(*options: str) -> None:
    """--paper fixes these options: giving one as well is a contradiction, not a choice."""
    for option in given_on_command_line(*options):
        raise BadInput(f"{option} cannot be given with --paper, which fixes it")


def reflex_options(default: str) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """--reflex NAMES and --paper, given to the command as one `reflexes` tuple."""

    def decorate(command: Callable[..., None]) -> Callable[..., None]:
        @functools.wraps(command)
        def with_reflexes(*args: Any, reflex: str, paper: bool, **kwargs: Any) -> None:
            if paper:
                refuse_beside_paper("--reflex")
            reflexes = () if paper else parse_reflexes(reflex)
            command(*args, reflexes=reflexes, **kwargs)

        with_reflexes = click.option(
            "--paper", is_flag=True, help="The paper's method alone: no reflexes."
        )(with_reflexes)
        return click.option(
            "--reflex",
            default=default,
            show_default=True,
            shell_complete=complete_reflexes,
            metavar="NAMES",
            help=f"Reflexes beyond the paper, comma-separated: {', '.join(STACK_ORDER)}; "
            "or all, or none.",
        )(with_reflexes)

    return decorate


MEMORY_OPTIONS = ("--memory", "--memory-window", "--memory-range", "--memory-patch")


def memory_options(base: str) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """--memory, --memory-window, --memory-range and --memory-patch, given to the command as
    one `memory` MemoryChoice to apply over `base` (said in the help). The paper's method
    keeps no memory: with --paper they are refused, and the choice is none."""

    def decorate(command: Callable[..., None]) -> Callable[..., None]:
        @functools.wraps(command)
        def with_memory(
            *args: Any,
            memory: str | None,
            memory_window: float | None,
            memory_range: float | None,
            memory_patch: float | None,
            **kwargs: Any,
        ) -> None:
            choice = MemoryChoice(memory, memory_window, memory_range, memory_patch)
            if click.get_current_context().params.get("paper"):
                refuse_beside_paper(
                    "--memory", "--memory-window", "--memory-range", "--memory-patch"
                )
                choice = MemoryChoice(kind=NONE)
            command(*args, memory=choice, **kwargs)

        options = (
            click.option(
                "--memory",
                type=click.Choice(MEMORY_KINDS),
                default=None,
                help=f"What the FAM reads: the live ring (none), or with echoes remembered as "
                f"points or patches (default: {base}).",
            ),
            click.option(
                "--memory-window",
                type=float,
                default=None,
                help=f"Seconds of echoes remembered (default {DEFAULT_WINDOW_S:g} with a memory).",
            ),
            click.option(
                "--memory-range",
                type=float,
                default=None,
                help=f"Echoes farther than this are not remembered, m (default "
                f"{DEFAULT_RANGE_M:g}).",
            ),
            click.option(
                "--memory-patch",
                type=float,
                default=None,
                help=f"Patches are at least this wide, m (default {DEFAULT_PATCH_M:g}).",
            ),
        )
        for option in reversed(options):
            with_memory = option(with_memory)
        return with_memory

    return decorate


def print_json(value: object) -> None:
    click.echo(json.dumps(value, indent=1, allow_nan=False))


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
