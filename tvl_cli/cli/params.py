"""Option types that parse text into typed values (X,Y into two floats), and the shell
completions of options whose values are names (configurations, figures, reflexes).

Completions run in the shell's completion request, never in a command: each loads only
what it lists.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click
from click.shell_completion import CompletionItem

from tvl_cli.core.errors import BadInput


class Parsed(click.ParamType):
    """A value written as text (X,Y; INPUT=METRES) parsed into the value the command takes
    by `parse`, whose BadInput, naming the text and the form it should have, is the error
    of the option."""

    def __init__(self, name: str, parse: Callable[[str], Any]) -> None:
        self.name = name
        self.parse = parse

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if not isinstance(value, str):
            return value  # a default, already typed
        try:
            return self.parse(value)
        except BadInput as error:
            self.fail(str(error), param, ctx)


def goal_point(text: str) -> tuple[float, float]:
    """'X,Y' in metres, as a grid's goals are read."""
    from tvl_cli.commands.run import parse_goal  # loaded when a goal is given, not for --help

    return parse_goal(text)


def pair_of_names(text: str) -> tuple[str, str]:
    """'A,B': two names, e.g. two FAM inputs."""
    names = tuple(part.strip() for part in text.split(","))
    if len(names) != 2 or not all(names):
        raise BadInput(f"{text!r} is not two input names A,B, e.g. front,front-left")
    return names[0], names[1]


def name_and_metres(text: str) -> tuple[str, float]:
    """'INPUT=METRES': a name and a range in metres."""
    name, _, metres = text.partition("=")
    try:
        value = float(metres)
    except ValueError:
        value = float("nan")
    if not name.strip() or value != value:  # NaN: not a number
        raise BadInput(f"{text!r} is not INPUT=METRES, e.g. front-right=0.5")
    return name.strip(), value


def _starting(incomplete: str, names: list[str] | tuple[str, ...]) -> list[CompletionItem]:
    return [CompletionItem(name) for name in names if name.startswith(incomplete)]


def _named_or_file(incomplete: str, names: list[str]) -> list[CompletionItem]:
    """What an option naming a shipped thing or a file of the user's own completes to."""
    return [*_starting(incomplete, names), CompletionItem(incomplete, "file")]


def complete_config(
    ctx: click.Context, param: click.Parameter, incomplete: str
) -> list[CompletionItem]:
    """--config: a shipped configuration by name, or a JSON file."""
    from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS

    return _named_or_file(incomplete, list(BUILTIN_FAM_CONFIGS))


def complete_world(
    ctx: click.Context, param: click.Parameter, incomplete: str
) -> list[CompletionItem]:
    """WORLD: a bundled world by name, a generated one begun as KIND:, or a world file."""
    from tvl_cli.sim.worldgen import KINDS  # the generators load numpy: a completion only

    return _named_or_file(incomplete, [*KINDS, *(f"{kind}:" for kind in KINDS)])


def complete_reflexes(
    ctx: click.Context, param: click.Parameter, incomplete: str
) -> list[CompletionItem]:
    """--reflex: all, none, or reflex names, comma-separated (the last one completed)."""
    from tvl_cli.core.method import ALL, NONE, REFLEX_NAMES

    done, _, last = incomplete.rpartition(",")
    if not done:
        return _starting(last, [ALL, NONE, *REFLEX_NAMES])
    given = done.split(",")
    return [
        CompletionItem(f"{done},{name}")
        for name in REFLEX_NAMES
        if name.startswith(last) and name not in given
    ]


def complete_method(
    ctx: click.Context, param: click.Parameter, incomplete: str
) -> list[CompletionItem]:
    """--method: a preset by name, or a method file."""
    from tvl_cli.core.method import PRESETS

    return _named_or_file(incomplete, list(PRESETS))


def complete_schema_command(
    ctx: click.Context, param: click.Parameter, incomplete: str
) -> list[CompletionItem]:
    """schema COMMAND: the commands that print JSON, a word at a time (`world` then `new`)."""
    from tvl_cli.io.json_documents import SCHEMA_COMMANDS

    typed = list(ctx.params.get("command") or ())
    following = [
        words[len(typed)]
        for words in (command.split() for command in SCHEMA_COMMANDS)
        if len(words) > len(typed) and words[: len(typed)] == typed
    ]
    return _starting(incomplete, list(dict.fromkeys(following)))


def complete_trajectory(
    ctx: click.Context, param: click.Parameter, incomplete: str
) -> list[CompletionItem]:
    """--trajectory: the robot's trajectory names."""
    from tvl_cli.core.robot_config import ALL_TRAJECTORY_NAMES

    return _starting(incomplete, ALL_TRAJECTORY_NAMES)


def complete_figure(
    ctx: click.Context, param: click.Parameter, incomplete: str
) -> list[CompletionItem]:
    """figure NAME: the figures `tvl figure` draws."""
    # matplotlib: in a completion request only
    from tvl_cli.render.experiment_figures import FIGURES

    return _starting(incomplete, list(FIGURES))
