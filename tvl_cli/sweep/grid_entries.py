"""What a sweep's grid names: its methods, worlds, FAM configurations and goals, each found
(beside the grid file, generated, or shipped) and checked, every fault one line naming the
grid file."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from tvl_cli.commands.run import parse_goal
from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, FamConfig
from tvl_cli.core.memory import MemoryChoice
from tvl_cli.core.method import Method, MethodChoice, parse_reflexes
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.methodfile import resolve_method
from tvl_cli.sim.world_entries import named_worlds
from tvl_cli.sim.worldmap import WorldMap, check_goal
from tvl_cli.sweep.cell import METHOD_KEYS
from tvl_cli.sweep.grid_keys import ALL_GOALS

# World and configuration names become parts of file names in the sweep's directory.
_FILE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")


def method_entry(path: Path, entry: str) -> Method:
    """A preset by name, else a method file beside the grid."""
    return resolve_method(entry, path.parent, f"{path}: method")


def check_paper_runs(path: Path, entry: str, method: Method, values: dict[str, Any]) -> None:
    """The paper's method chosen by name: a key that sets one of our additions otherwise
    than the paper (a field of the method, the run's reflexes or memory) contradicts it, as
    such a flag beside `--paper` does."""
    for key in (*METHOD_KEYS, "reflexes", "run_memory"):
        for value in values[key]:
            if value is not None and _setting(method, entry, key, value).contradictions():
                raise BadInput(
                    f'{path}: {key} {value!r} contradicts method "{entry}", which fixes it '
                    f"(leave {key} out of its cells)"
                )


def _setting(method: Method, entry: str, key: str, value: Any) -> MethodChoice:
    """One grid key's value chosen over the grid's method, as a command's flag chooses it."""
    if key in ("memory", "run_memory"):
        return MethodChoice(method, entry, memory=MemoryChoice(kind=value))
    field = parse_reflexes(value) if key == "reflexes" else value
    return MethodChoice(method, entry, ((key, field),))


def _goal(path: Path, text: str) -> tuple[float, float]:
    try:
        return parse_goal(text)
    except BadInput:
        raise BadInput(
            f'{path}: goal {text!r} is not X,Y in metres, e.g. 3.5,2.0, nor "{ALL_GOALS}"'
        ) from None


def world_entry(path: Path, entry: str) -> WorldMap:
    """A world file beside the grid, else a generated world (KIND:SEED), else the bundled
    world of that name."""
    try:
        found = named_worlds(entry, path.parent)
    except BadInput as problem:
        raise BadInput(f"{path}: {problem}") from None
    if len(found) > 1:
        raise BadInput(
            f"{path}: world {entry!r} names {len(found)} worlds; a grid names each world alone"
        )
    return found[0].world


def config_entry(path: Path, entry: str) -> FamConfig:
    """A shipped configuration by name, else a JSON file beside the grid (whose faults name
    that file)."""
    file = path.parent / entry
    if entry not in BUILTIN_FAM_CONFIGS and not file.is_file():
        known = list(BUILTIN_FAM_CONFIGS)
        raise BadInput(
            f"{path}: config {entry!r}: neither a configuration ({', '.join(known)}) nor a "
            f"JSON file {file} ({did_you_mean(entry, known)})"
        )
    return resolve_fam_config(entry if entry in BUILTIN_FAM_CONFIGS else str(file), RobotConfig())


def named(path: Path, key: str, by_entry: dict[str, Any]) -> dict[str, Any]:
    """Worlds or configurations by the grid's entry, each distinctly named: a sweep knows
    them by their own names, which must be fit to name files."""
    entries: dict[str, str] = {}
    for entry, value in by_entry.items():
        name = value.name
        if not _FILE_NAME.fullmatch(name):
            raise BadInput(
                f"{path}: {key} {entry!r} is named {name!r}; a sweep needs a name of letters, "
                "digits, '.', '_' and '-'"
            )
        if name in entries:
            raise BadInput(
                f"{path}: {key}s {entries[name]!r} and {entry!r} are both named {name!r}; "
                "a sweep knows each by its name, so give one of them another name"
            )
        entries[name] = entry
    return by_entry


def goals_in(path: Path, world: WorldMap, given: tuple[str, ...]) -> list[str | None]:
    """The goals goal runs seek in a world, as their cells record them: each of the grid's
    (checked against the world), every goal of the world, else the world's first."""
    if ALL_GOALS in given or not given:
        if not world.goals:
            raise BadInput(f"{path}: world {world.name!r} has no goal; give one with goal")
        goals = list(world.goals) if given else [world.goals[0]]
    else:
        goals = [_goal(path, text) for text in given]
        if len(set(goals)) < len(goals):
            raise BadInput(f"{path}: 'goal' gives one goal twice")
    for x, y in goals:
        check_goal(world, x, y, where=f"{path}: goal {x:g},{y:g} in world {world.name!r}")
    # repr: the run reads back exactly the goal its row records.
    return [f"{float(x)!r},{float(y)!r}" for x, y in goals]
