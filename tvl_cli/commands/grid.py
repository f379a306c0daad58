"""A sweep's grid: a TOML file whose keys each give one value or a list, into a cell for every
combination of them. A cell is one `tvl run` and the learning and training before it.

    world = ["square", "circle"]        # required: bundled world names or world files
    seed = [1, 2, 3]                    # required: of the learning and of the run
    behaviour = ["wall-left", "wall-right"]   # required
    config = ["single", "multi"]        # single, multi, designed or a FAM configuration file
    learn_minutes = 15
    threshold = [0.65, 0.8, 0.95]
    run_minutes = 5
    goal = ["3.5,2.0"]                  # goal runs only; default the world's first goal
    method = ["default", "paper"]       # as `--method`: a preset or a method file; default ours
    reflexes = ["all", "none"]          # as `tvl run --reflex`; default each method's own

Files are named relative to the grid file's folder.
"""

from __future__ import annotations

import math
import re
from dataclasses import astuple, dataclass, fields
from itertools import product
from pathlib import Path
from typing import Any

from tvl_cli.agent.explore import LearnParams
from tvl_cli.commands.run import parse_goal
from tvl_cli.core.errors import (
    DEFAULT_RUN_MINUTES,
    MAX_SEED,
    BadInput,
    check_minutes,
    check_run_minutes,
    did_you_mean,
)
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, SINGLE, FamConfig
from tvl_cli.core.method import (
    DEFAULT_NAME,
    PAPER_NAME,
    PRESETS,
    REFLEX_NAMES,
    Method,
    MethodChoice,
    parse_reflexes,
    reflexes_text,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.trajectory_choice import BEHAVIOUR_NAMES, DEFAULT_THRESHOLD, is_threshold
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.methodfile import read_method
from tvl_cli.io.tomlfile import read_toml
from tvl_cli.sim.worldgen import bundled_world_path
from tvl_cli.sim.worldmap import WorldMap, check_goal, load_world


@dataclass(frozen=True, slots=True)
class Cell:
    """One run of a sweep by its grid values, which are the columns its row adds to the run's
    metrics and, together, the key that finds the row again."""

    world: str  # the world's name
    seed: int  # of the learning and of the run
    config: str  # the FAM configuration's name
    learn_minutes: float
    behaviour: str
    threshold: float
    goal: str | None  # "X,Y" in metres for a goal run; None for the other behaviours
    run_minutes: float
    method: str  # as `--method` takes it: a preset's name, or a method file beside the grid
    reflexes: str  # as `tvl run --reflex` takes them

    def key(self) -> tuple[Any, ...]:
        return astuple(self)

    def learn_params(self) -> LearnParams:
        return LearnParams(minutes=self.learn_minutes)

    def run_method(self, method: Method) -> MethodChoice:
        """The run's method: the cell's, with the cell's reflexes."""
        return MethodChoice(method, self.method, (("reflexes", parse_reflexes(self.reflexes)),))

    def goal_xy(self) -> tuple[float, float] | None:
        return None if self.goal is None else parse_goal(self.goal)


COLUMNS = tuple(f.name for f in fields(Cell))


@dataclass(frozen=True, slots=True)
class Grid:
    worlds: dict[str, str]  # name -> the world file's text, which the sweep runs a copy of
    configs: dict[str, FamConfig]  # by name
    methods: dict[str, Method]  # by the grid's entry
    cells: tuple[Cell, ...]  # in the grid's order: the last key varies fastest


# Each key (a column of Cell) with the type of its values and the values it has when the grid
# does not give it; None: the grid must. `goal` defaults to none given: the world's first.
_KEYS: dict[str, tuple[type, tuple[Any, ...] | None]] = {
    "world": (str, None),
    "seed": (int, None),
    "config": (str, (SINGLE.name,)),
    "learn_minutes": (float, (LearnParams().minutes,)),
    "behaviour": (str, None),
    "threshold": (float, (DEFAULT_THRESHOLD,)),
    "goal": (str, ()),
    "run_minutes": (float, (DEFAULT_RUN_MINUTES,)),
    "method": (str, (DEFAULT_NAME,)),
    "reflexes": (str, ()),
}
_TYPE_NAMES = {str: "text", int: "a whole number", float: "a number"}
# World and configuration names become parts of file names in the sweep's directory.
_FILE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")


def read_grid(path: Path, max_cells: int | None = None) -> Grid:
    """The grid of a TOML file, every value checked; BadInput naming the file and the key (or
    the line of a syntax error) at the first fault, or the number of cells when it is over
    `max_cells` (None: no cap), counted before any cell is made."""
    table = read_toml(path, "grid")
    unknown = [key for key in table if key not in _KEYS]
    if unknown:
        raise BadInput(
            f"{path}: unknown key {unknown[0]!r} ({did_you_mean(unknown[0], list(_KEYS))})"
        )
    values = {key: _values(path, table, key) for key in _KEYS}
    for seed in values["seed"]:
        if not 0 <= seed <= MAX_SEED:
            raise BadInput(f"{path}: seed {seed} is outside 0 to {MAX_SEED}")
    for minutes in values["learn_minutes"]:
        check_minutes(minutes, f"{path}: learn_minutes")
    for minutes in values["run_minutes"]:
        check_run_minutes(minutes, RobotConfig().control_period_s, f"{path}: run_minutes")
    for threshold in values["threshold"]:
        if not is_threshold(threshold):
            raise BadInput(f"{path}: threshold {threshold:g} is outside (0, 1]")
    for behaviour in values["behaviour"]:
        if behaviour not in BEHAVIOUR_NAMES:
            raise BadInput(
                f"{path}: behaviour {behaviour!r} is not one of {', '.join(BEHAVIOUR_NAMES)}"
            )
    for reflexes in values["reflexes"]:
        _check_reflexes(path, reflexes)
    methods = {entry: _method(path, entry) for entry in values["method"]}
    for entry, method in methods.items():
        _check_paper_reflexes(path, entry, method, values["reflexes"])
    if values["goal"] and "goal" not in values["behaviour"]:
        raise BadInput(f"{path}: goal is for the goal behaviour, which the grid does not run")
    worlds = _named(path, "world", {e: load_world(_world_file(path, e)) for e in values["world"]})
    configs = _named(path, "config", {e: _config(path, e) for e in values["config"]})
    goals = [_goal(path, text) for text in values["goal"]]
    if len(set(goals)) < len(goals):
        raise BadInput(f"{path}: 'goal' gives one goal twice")
    goals_in = {
        name: _goals_in(path, world, goals) if "goal" in values["behaviour"] else []
        for name, world in worlds.items()
    }
    _check_cap(path, _count_cells(values, configs, goals_in), max_cells)
    cells = [
        Cell(world, seed, config, learn, behaviour, threshold, goal, run, method, reflexes)
        for world, seed, config, learn, behaviour, threshold in product(
            worlds,
            values["seed"],
            configs,
            values["learn_minutes"],
            values["behaviour"],
            values["threshold"],
        )
        # Only goal runs seek a goal: the goals multiply them alone.
        for goal in (goals_in[world] if behaviour == "goal" else [None])
        for run, method in product(values["run_minutes"], methods)
        # Without reflexes in the grid, each method runs with its own.
        for reflexes in values["reflexes"] or (reflexes_text(methods[method].reflexes),)
    ]
    return Grid(
        worlds={name: world.text for name, world in worlds.items()},
        configs=configs,
        methods=methods,
        cells=tuple(cells),
    )


def _count_cells(
    values: dict[str, tuple[Any, ...]],
    configs: dict[str, FamConfig],
    goals_in: dict[str, list[str | None]],
) -> int:
    """The cells read_grid makes, from the lengths of its lists, as its product nests them
    (without reflexes in the grid, each method runs once, with its own)."""
    runs = sum(
        len(goals_in[world]) if behaviour == "goal" else 1
        for world in goals_in
        for behaviour in values["behaviour"]
    )
    per_run = math.prod(
        len(values[key]) for key in ("seed", "learn_minutes", "threshold", "run_minutes", "method")
    )
    return runs * per_run * len(configs) * (len(values["reflexes"]) or 1)


def _check_cap(path: Path, cells: int, max_cells: int | None) -> None:
    if max_cells is not None and cells > max_cells:
        raise BadInput(
            f"{path}: {cells:,} cells, over the cap of {max_cells:,}; give --max-cells "
            f"{cells} or --yes to run them all"
        )


def _values(path: Path, table: dict[str, Any], key: str) -> tuple[Any, ...]:
    """A key's values: the one given, or the list; checked for type and repeats."""
    kind, default = _KEYS[key]
    if key not in table:
        if default is None:
            raise BadInput(f"{path}: no {key!r}; a grid must give it")
        return default
    given = table[key]
    items = given if isinstance(given, list) else [given]
    if not items:
        raise BadInput(f"{path}: {key!r} is an empty list")
    for number, item in enumerate(items, start=1):
        if not _is_a(kind, item):
            which = f"{key!r} item {number}" if isinstance(given, list) else repr(key)
            raise BadInput(f"{path}: {which} is {item!r}, expected {_TYPE_NAMES[kind]}")
    values = tuple(float(item) if kind is float else item for item in items)
    seen: set[Any] = set()  # a set: a grid's lists may be long
    for value in values:
        if value in seen:
            raise BadInput(f"{path}: {key!r} gives {value!r} twice")
        seen.add(value)
    return values


def _is_a(kind: type, item: Any) -> bool:
    if isinstance(item, bool):  # TOML's true and false are Python ints too
        return False
    if kind is float:
        return isinstance(item, int | float) and math.isfinite(item)
    return isinstance(item, kind)


def _check_reflexes(path: Path, text: str) -> None:
    try:
        parse_reflexes(text)
    except BadInput:
        raise BadInput(
            f"{path}: reflexes {text!r} is not all, none or names from "
            f"{', '.join(REFLEX_NAMES)}, comma-separated (the paper's whole method is "
            'method = "paper")'
        ) from None


def _method(path: Path, entry: str) -> Method:
    """A preset by name, else a method file beside the grid."""
    return PRESETS[entry] if entry in PRESETS else read_method(path.parent / entry)


def _check_paper_reflexes(
    path: Path, entry: str, method: Method, reflexes: tuple[str, ...]
) -> None:
    """The paper's method has no reflex: cells that add some contradict it, as `--reflex`
    beside `--paper` does."""
    if entry != PAPER_NAME:
        return
    for text in reflexes:
        if parse_reflexes(text) != method.reflexes:
            raise BadInput(
                f'{path}: reflexes {text!r} contradicts method "paper", which has none '
                "(leave reflexes out to run each method with its own)"
            )


def _goal(path: Path, text: str) -> tuple[float, float]:
    try:
        return parse_goal(text)
    except BadInput:
        raise BadInput(f"{path}: goal {text!r} is not X,Y in metres, e.g. 3.5,2.0") from None


def _world_file(path: Path, entry: str) -> Path:
    """A world file beside the grid, else the bundled world of that name."""
    file = path.parent / entry
    if file.is_file():
        return file
    try:
        return bundled_world_path(entry)
    except BadInput:
        raise BadInput(
            f"{path}: world {entry!r}: no such world file {file}, nor a bundled world"
        ) from None


def _config(path: Path, entry: str) -> FamConfig:
    spec = entry if entry in BUILTIN_FAM_CONFIGS else str(path.parent / entry)
    return resolve_fam_config(spec, RobotConfig())


def _named(path: Path, key: str, by_entry: dict[str, Any]) -> dict[str, Any]:
    """Worlds or configurations by their own names, which a sweep knows them by: distinct,
    and fit to name files."""
    named: dict[str, Any] = {}
    entries: dict[str, str] = {}
    for entry, value in by_entry.items():
        name = value.name
        if not _FILE_NAME.fullmatch(name):
            raise BadInput(
                f"{path}: {key} {entry!r} is named {name!r}; a sweep needs a name of letters, "
                "digits, '.', '_' and '-'"
            )
        if name in named:
            raise BadInput(
                f"{path}: {key}s {entries[name]!r} and {entry!r} are both named {name!r}; "
                "a sweep knows each by its name, so give one of them another"
            )
        named[name], entries[name] = value, entry
    return named


def _goals_in(path: Path, world: WorldMap, goals: list[tuple[float, float]]) -> list[str | None]:
    """The goals goal runs seek in a world, as their cells record them: each of the grid's
    (checked against the world), else the world's first."""
    if not goals:
        if not world.goals:
            raise BadInput(f"{path}: world {world.name!r} has no goal; give one with goal")
        goals = [world.goals[0]]
    for x, y in goals:
        check_goal(world, x, y, where=f"{path}: goal {x:g},{y:g} in world {world.name!r}")
    # repr: the run reads back exactly the goal its row records.
    return [f"{float(x)!r},{float(y)!r}" for x, y in goals]
