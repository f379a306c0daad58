"""A sweep's grid: a TOML file whose keys each give one value or a list, into a cell for every
combination of them. A cell is one piece of work and what it needs before it: a `tvl run`
after the learning and training its FAM needs (kind "tvl"), the learning alone (kind "learn",
its row the log's minutes as `tvl replay` reads them), or a baseline as `tvl baseline` runs
it (kinds "dwa" and "qlearn").

    kind = ["learn", "tvl", "dwa", "qlearn"]   # default "tvl"
    world = ["square", "circle", "rooms:1001"] # required: bundled names, world files, KIND:SEED
    seed = [1, 2, 3]                     # required: of the learning and of the run
    behaviour = ["wall-left", "wall-right"]    # default avoid
    config = ["single", "multi"]         # the FAM trained: single, multi, designed or a file
    learn_config = "single"              # the FAM the learner explores with; "same": config
    learn_minutes = 15
    minute = { from = 0, to = 15, step = 1 }   # the FAM of the log's first minutes
    exploration = ["novelty", "random"]  # a field of the method (default: the method's),
    near_m = [0.16, 0]                   # for the learning, the training and the run
    memory = ["none", "patches"]         # alike: the exploration rule, the collision points
                                         # (0: bumps alone), the echo memory's kind
    threshold = [0.65, 0.8, 0.95]
    goal = ["3.5,2.0"]                   # goal runs only: X,Y, or "all" the world's goals;
                                         # default the world's first
    run_minutes = 5
    online = [false, true]               # learn while behaving, as `tvl run --learn`
    competence_every = 1                 # qlearn: judge competence every N learning minutes
    trace = true                         # keep each run's trace, for paths in a figure
    method = ["default", "paper"]        # as `--method`: a preset or a method file
    reflexes = ["all", "none"]           # as `--reflex`; default each method's own (TVL runs)
                                         # and none (baselines, as `tvl baseline`)
    run_memory = ["none"]                # the run alone reads through this echo memory, as
                                         # `tvl run --memory` does a FAM learnt through another;
                                         # default the method's

Keys named after a field of the method (core.method.Method) set that field of the cell's
method, whatever the `method` it starts from; `reflexes` (a run's alone) and `run_memory` are
the run's, as `tvl run --reflex` and `--memory` set them over a FAM. Beside the paper's method
chosen by name, a key that sets one of our additions otherwise than the paper is refused, as
`--paper` refuses such a flag.

A key takes a range of numbers as `{ from = A, to = B, step = S }` (B included). Each kind
reads only its own keys (`minute` means nothing to DWA), so one list of kinds makes each
baseline cell once, not once per snapshot minute.

`[[part]]` tables are grids of their own that take the keys above them and change some: the
cells of a grid are every part's (a cell two parts make is run once). The file as written is
the full size, the paper's trial counts; `[tiny]` and `[quick]` tables give keys that override
the file's everywhere, top and parts alike, for `tvl sweep --size tiny|quick`, and a part's
own `[part.tiny]` or `[part.quick]` has the last word on that part.

Files are named relative to the grid file's folder.
"""

from __future__ import annotations

import math
import re
from dataclasses import astuple, dataclass, fields, replace
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
from tvl_cli.core.memory import MEMORY_KINDS, MemoryChoice, MemoryConfig
from tvl_cli.core.method import (
    DEFAULT_NAME,
    EXPLORATION_RULES,
    REFLEX_NAMES,
    Method,
    MethodChoice,
    method_from_dict,
    parse_reflexes,
    reflexes_text,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.trajectory_choice import BEHAVIOUR_NAMES, DEFAULT_THRESHOLD, is_threshold
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.methodfile import resolve_method
from tvl_cli.io.tomlfile import read_toml
from tvl_cli.sim.worldgen import KINDS, bundled_world_path, generate_world
from tvl_cli.sim.worldmap import WorldMap, check_goal, load_world, parse_world

# The kinds of cell, as `tvl figure` knows them among a table's rows.
TVL, LEARN, DWA, QLEARN = "tvl", "learn", "dwa", "qlearn"
KINDS_OF_CELL = (TVL, LEARN, DWA, QLEARN)
# The sizes a grid file is run at: as written (the paper's trial counts), or a table of it.
FULL, QUICK, TINY = "full", "quick", "tiny"
SIZES = (TINY, QUICK, FULL)
# `learn_config = "same"`: the learner explores with the FAM the cell trains.
SAME = "same"
# `goal = "all"`: a goal run to each of the world's goals.
ALL_GOALS = "all"
# The keys that are fields of the method, each a cell's column of that name.
METHOD_KEYS = ("exploration", "near_m", "memory")
# A `[[part]]`: a grid of its own under the file's keys.
PART = "part"


@dataclass(frozen=True, slots=True)
class Cell:
    """One piece of work of a sweep by its grid values, which are the columns its row adds to
    what the work found and, together, the key that finds the row again. Keys a kind does
    not read are None (False for the flags)."""

    kind: str  # one of KINDS_OF_CELL
    world: str  # the world's name
    seed: int  # of the learning and of the run
    learn_config: str | None  # the FAM configuration the learner explores with
    learn_minutes: float | None
    # The cell's own fields of the method (None: the method's): the exploration rule, where
    # collision points fall (core.method.Method.near_m), and the echo memory's kind.
    exploration: str | None
    near_m: float | None
    memory: str | None
    config: str | None  # the trained FAM configuration's name
    minute: float | None  # the FAM of the log's first minutes; None: of the whole log
    behaviour: str | None
    threshold: float | None
    goal: str | None  # "X,Y" in metres for a goal run; None for the other behaviours
    run_minutes: float | None
    online: bool  # the run learns as it goes (`tvl run --learn`)
    competence_every: float | None  # Q-learning's competence checks, learning minutes apart
    trace: bool  # the run keeps its trace in the sweep's directory
    method: str | None  # as `--method` takes it: a preset's name, or a method file beside
    # the grid; None for a baseline
    reflexes: str | None  # as `--reflex` takes them
    run_memory: str | None  # the echo memory the run reads through (`tvl run --memory`);
    # None: the one its FAM was trained through

    def key(self) -> tuple[Any, ...]:
        return astuple(self)

    def learn_params(self) -> LearnParams:
        return LearnParams(minutes=self.learn_minutes or LearnParams().minutes)

    def learning_method(self, method: Method) -> Method:
        """The grid's method with the cell's own fields of it."""
        return replace(method, **self.method_fields())

    def method_fields(self) -> dict[str, Any]:
        """The fields of the method the cell gives, as Method holds them."""
        given = {name: getattr(self, name) for name in METHOD_KEYS}
        fields = {name: value for name, value in given.items() if value is not None}
        if "memory" in fields:
            fields["memory"] = MemoryConfig(fields["memory"])
        return fields

    def run_method(self, method: Method) -> MethodChoice:
        """The run's method: the cell's, with the cell's reflexes."""
        reflexes = parse_reflexes(self.reflexes or reflexes_text(method.reflexes))
        memory = MemoryChoice(kind=self.run_memory)
        return MethodChoice(method, self.method, (("reflexes", reflexes),), memory)

    def baseline_method(self) -> MethodChoice:
        """A baseline's method: alone, with the cell's reflexes, as `tvl baseline --reflex`."""
        return MethodChoice(settings=(("reflexes", parse_reflexes(self.reflexes or "none")),))

    def goal_xy(self) -> tuple[float, float] | None:
        return None if self.goal is None else parse_goal(self.goal)


COLUMNS = tuple(f.name for f in fields(Cell))


@dataclass(frozen=True, slots=True)
class Grid:
    worlds: dict[str, str]  # name -> the world file's text, which the sweep runs a copy of
    configs: dict[str, FamConfig]  # by name
    methods: dict[str, Method]  # by the grid's entry
    cells: tuple[Cell, ...]  # in the grid's order: the last key varies fastest
    size: str = FULL


@dataclass(frozen=True, slots=True)
class _Key:
    kind: type  # of its values
    default: tuple[Any, ...] | None  # its values when the grid does not give it; None: must
    kinds: tuple[str, ...]  # the kinds of cell that read it


_EVERY = KINDS_OF_CELL
_LEARNT = (TVL, LEARN)
_RUNS = (TVL, DWA, QLEARN)
_BEHAVING = (TVL, DWA)
# Each key (a column of Cell) with its type, its default, and the kinds that read it, in the
# order the grid's product nests them: the last varies fastest. `goal` defaults to none
# given: the world's first. `reflexes` to none given: each method's own, none for baselines.
_KEYS: dict[str, _Key] = {
    "kind": _Key(str, (TVL,), _EVERY),
    "world": _Key(str, None, _EVERY),
    "seed": _Key(int, None, _EVERY),
    "learn_config": _Key(str, (SINGLE.name,), _LEARNT),
    "learn_minutes": _Key(float, (LearnParams().minutes,), (TVL, LEARN, QLEARN)),
    "exploration": _Key(str, (None,), _LEARNT),
    "near_m": _Key(float, (None,), _LEARNT),
    "memory": _Key(str, (None,), _LEARNT),
    "config": _Key(str, (SINGLE.name,), (TVL,)),
    "minute": _Key(float, (None,), (TVL,)),
    "behaviour": _Key(str, ("avoid",), _BEHAVING),
    "threshold": _Key(float, (DEFAULT_THRESHOLD,), (TVL,)),
    "goal": _Key(str, (), _BEHAVING),
    "run_minutes": _Key(float, (DEFAULT_RUN_MINUTES,), _RUNS),
    "online": _Key(bool, (False,), (TVL,)),
    "competence_every": _Key(float, (None,), (QLEARN,)),
    "trace": _Key(bool, (False,), (TVL,)),
    # A baseline takes nothing of a method but its reflexes, which the cell gives.
    "method": _Key(str, (DEFAULT_NAME,), _LEARNT),
    "reflexes": _Key(str, (), _RUNS),
    "run_memory": _Key(str, (None,), (TVL,)),
}
_TYPE_NAMES = {str: "text", int: "a whole number", float: "a number", bool: "true or false"}
# World and configuration names become parts of file names in the sweep's directory.
_FILE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")
_RANGE_KEYS = ("from", "to", "step")


def read_grid(path: Path, max_cells: int | None = None, size: str = FULL) -> Grid:
    """The grid of a TOML file at a size, every value checked; BadInput naming the file and
    the key (or the line of a syntax error) at the first fault, or the number of cells when
    it is over `max_cells` (None: no cap), counted before any cell is made."""
    table = read_toml(path, "grid")
    top = {k: v for k, v in table.items() if k not in (*SIZES, PART)}
    parts = table.get(PART, [{}])
    if not isinstance(parts, list) or not all(isinstance(p, dict) for p in parts) or not parts:
        raise BadInput(f"{path}: {PART!r} must be [[{PART}]] tables, each a grid of its own")
    # A size needs a table of its own in the file or in one of its parts.
    overrides = _size_table(path, table, size, not any(size in part for part in parts))
    values_of = []
    for number, part in enumerate(parts, start=1):
        where = f"{path} [[{PART}]] {number}" if PART in table else str(path)
        if PART in part:
            raise BadInput(f"{where}: a part holds grid keys and sizes, not parts")
        own = {k: v for k, v in part.items() if k not in SIZES} if PART in table else top
        # Its own size table has the last word on a part.
        own_size = _size_table(where, part, size, required=False)
        merged = {**top, **own, **overrides, **own_size}
        values_of.append(_part_values(where, merged, {**own, **own_size}))
    methods = {
        e: _method(path, e)
        for values in values_of
        if set(values["kind"]) & set(_LEARNT)
        for e in values["method"]
    }
    worlds = _named(
        path, "world", {e: _world(path, e) for values in values_of for e in values["world"]}
    )
    configs = _named(
        path,
        "config",
        {
            e: _config(path, e)
            for values in values_of
            for key in ("config", "learn_config")
            for e in values[key]
            if e not in (None, SAME)
        },
    )
    by_entry = {
        key: {e: value.name for e, value in named.items()}
        for key, named in (("world", worlds), ("config", configs))
    }
    expanded = []
    for values in values_of:
        for entry, method in methods.items():
            if entry in values["method"]:
                _check_paper_runs(path, entry, method, values)
        goals = {
            by_entry["world"][entry]: _goals_in(path, worlds[entry], values["goal"])
            if "goal" in values["behaviour"]
            else []
            for entry in values["world"]
        }
        expanded.append((values, goals))
    _check_cap(path, sum(_count_cells(v, goals) for v, goals in expanded), max_cells)
    cells = dict.fromkeys(
        cell for values, goals in expanded for cell in _cells(values, goals, by_entry, methods)
    )
    return Grid(
        worlds={world.name: world.text for world in worlds.values()},
        configs={config.name: config for config in configs.values()},
        methods=methods,
        cells=tuple(cells),
        size=size,
    )


def _size_table(
    where: Path | str, table: dict[str, Any], size: str, required: bool = True
) -> dict[str, Any]:
    """The keys a size overrides: none at full size, else the table of that name (the file's
    must be there; a part's may not)."""
    if size not in SIZES:
        raise BadInput(f"--size {size}: not one of {', '.join(SIZES)}")
    for name in SIZES:
        if name == FULL and name in table:
            raise BadInput(f"{where}: no [{FULL}] table: the file as written is the full size")
        if name in table and not isinstance(table[name], dict):
            raise BadInput(f"{where}: {name!r} must be a [{name}] table of grid keys")
    if size == FULL or (size not in table and not required):
        return {}
    if size not in table:
        raise BadInput(f"{where}: no [{size}] table for --size {size}")
    overrides: dict[str, Any] = table[size]
    for key, value in overrides.items():
        if key == PART or key in SIZES or (isinstance(value, dict) and key not in _KEYS):
            raise BadInput(f"{where} [{size}]: a size overrides grid keys, not {key!r}")
    return overrides


def _part_values(
    where: str, table: dict[str, Any], own: dict[str, Any]
) -> dict[str, tuple[Any, ...]]:
    """A part's values of every key, each checked, and each key of its `own` (not those it
    takes from above it) read by one of its kinds of cell."""
    unknown = [key for key in table if key not in _KEYS]
    if unknown:
        raise BadInput(
            f"{where}: unknown key {unknown[0]!r} ({did_you_mean(unknown[0], list(_KEYS))})"
        )
    values = {key: _values(where, table, key) for key in _KEYS}
    for kind in values["kind"]:
        if kind not in KINDS_OF_CELL:
            raise BadInput(
                f"{where}: kind {kind!r} is not one of {', '.join(KINDS_OF_CELL)} "
                f"({did_you_mean(kind, KINDS_OF_CELL)})"
            )
    for key in own:
        if key in _KEYS and not set(_KEYS[key].kinds) & set(values["kind"]):
            kinds = ", ".join(_KEYS[key].kinds)
            raise BadInput(
                f"{where}: {key!r} is for cells of kind {kinds}, and this grid runs "
                f"{', '.join(values['kind'])}"
            )
    _check_values(where, values)
    return values


def _check_values(where: str, values: dict[str, tuple[Any, ...]]) -> None:
    for seed in values["seed"]:
        if not 0 <= seed <= MAX_SEED:
            raise BadInput(f"{where}: seed {seed} is outside 0 to {MAX_SEED}")
    for minutes in values["learn_minutes"]:
        check_minutes(minutes, f"{where}: learn_minutes")
    for minute in values["minute"]:
        if minute is not None:
            check_minutes(minute, f"{where}: minute", zero_allowed=True)
            longest = max(values["learn_minutes"])
            if minute > longest:
                raise BadInput(
                    f"{where}: minute {minute:g} is beyond the longest learning, "
                    f"learn_minutes {longest:g}"
                )
    for minutes in values["run_minutes"]:
        check_run_minutes(minutes, RobotConfig().control_period_s, f"{where}: run_minutes")
    for every in values["competence_every"]:
        if every is not None:
            check_minutes(every, f"{where}: competence_every", zero_allowed=True)
    for threshold in values["threshold"]:
        if not is_threshold(threshold):
            raise BadInput(f"{where}: threshold {threshold:g} is outside (0, 1]")
    _check_words(where, "behaviour", values["behaviour"], BEHAVIOUR_NAMES)
    for config in values["learn_config"]:
        # The learner takes a configuration by name: the shipped ones (or the trained one's).
        if config != SAME and config not in BUILTIN_FAM_CONFIGS:
            raise BadInput(
                f"{where}: learn_config {config!r} is not one of "
                f"{', '.join([*BUILTIN_FAM_CONFIGS, SAME])}"
            )
        if config == SAME:
            for trained in values["config"]:
                if trained not in BUILTIN_FAM_CONFIGS:
                    raise BadInput(
                        f'{where}: learn_config "{SAME}" learns with config {trained!r}, '
                        f"but a learner explores with {', '.join(BUILTIN_FAM_CONFIGS)} only"
                    )
    _check_words(where, "exploration", values["exploration"], EXPLORATION_RULES)
    for near_m in values["near_m"]:
        if near_m is not None:
            method_from_dict({"near_m": near_m}, where)  # BadInput naming the file and key
    _check_words(where, "memory", values["memory"], MEMORY_KINDS)
    for reflexes in values["reflexes"]:
        _check_reflexes(where, reflexes)
    _check_words(where, "run_memory", values["run_memory"], MEMORY_KINDS)
    if values["goal"] and "goal" not in values["behaviour"]:
        raise BadInput(f"{where}: goal is for the goal behaviour, which the grid does not run")
    if ALL_GOALS in values["goal"] and len(values["goal"]) > 1:
        raise BadInput(f'{where}: goal "{ALL_GOALS}" is every goal of the world: give it alone')


def _check_words(where: str, key: str, given: tuple[Any, ...], known: tuple[str, ...]) -> None:
    for word in given:
        if word is not None and word not in known:
            raise BadInput(
                f"{where}: {key} {word!r} is not one of {', '.join(known)} "
                f"({did_you_mean(word, known)})"
            )


def _cells(
    values: dict[str, tuple[Any, ...]],
    goals: dict[str, list[str | None]],
    by_entry: dict[str, dict[str, str]],
    methods: dict[str, Method],
) -> list[Cell]:
    """A part's cells: for each kind, every combination of the keys that kind reads, in the
    order of _KEYS; goals multiply the goal runs alone."""
    cells = []
    for kind in values["kind"]:
        read = {key: values[key] if kind in spec.kinds else None for key, spec in _KEYS.items()}
        read["kind"] = (kind,)
        read["world"] = tuple(by_entry["world"][e] for e in values["world"])
        for key in ("config", "learn_config"):
            if read[key] is not None:
                read[key] = tuple(by_entry["config"].get(e, e) for e in values[key])
        if not read["reflexes"]:
            read["reflexes"] = None  # each method's own; for a baseline, none
        keys = [key for key in _KEYS if key != "goal"]
        for combination in product(*(read[key] or (None,) for key in keys)):
            cell = dict(zip(keys, combination, strict=True))
            cell["online"] = bool(cell["online"])
            cell["trace"] = bool(cell["trace"])
            if cell["learn_config"] == SAME:
                cell["learn_config"] = cell["config"]
            # Not given: a TVL run with its method's own reflexes; a baseline alone, as `tvl
            # baseline` runs it.
            if cell["reflexes"] is None and kind == TVL:
                cell["reflexes"] = reflexes_text(methods[cell["method"]].reflexes)
            elif cell["reflexes"] is None and kind in (DWA, QLEARN):
                cell["reflexes"] = "none"
            behaviour = cell["behaviour"]
            for goal in goals[cell["world"]] if behaviour == "goal" else [None]:
                cells.append(Cell(**cell, goal=goal))
    return cells


# Keys _count_cells counts apart: the kind and the world, and the behaviours with their goals.
_NOT_COUNTED = ("kind", "world", "behaviour", "goal")


def _count_cells(values: dict[str, tuple[Any, ...]], goals: dict[str, list[str | None]]) -> int:
    """The cells _cells makes of a part, from the lengths of its lists, before any is made
    (two parts may make one cell: then the sweep runs it once, and this counts it twice)."""
    total = 0
    for kind in values["kind"]:
        read = [k for k, spec in _KEYS.items() if kind in spec.kinds and k not in _NOT_COUNTED]
        per_world = math.prod(len(values[key]) or 1 for key in read)
        behaviours = values["behaviour"] if kind in _BEHAVING else (None,)
        runs = sum(
            len(goals[world]) if behaviour == "goal" else 1
            for world in goals
            for behaviour in behaviours
        )
        total += per_world * runs
    return total


def _check_cap(path: Path, cells: int, max_cells: int | None) -> None:
    if max_cells is not None and cells > max_cells:
        raise BadInput(
            f"{path}: {cells:,} cells, over the cap of {max_cells:,}; give --max-cells "
            f"{cells} or --yes to run them all"
        )


def _values(where: str, table: dict[str, Any], key: str) -> tuple[Any, ...]:
    """A key's values: the one given, the list, or the range; checked for type and repeats."""
    spec = _KEYS[key]
    if key not in table:
        if spec.default is None:
            raise BadInput(f"{where}: no {key!r}; a grid must give it")
        return spec.default
    given = table[key]
    if isinstance(given, dict):
        given = _range(where, key, given)
    items = given if isinstance(given, list) else [given]
    if not items:
        raise BadInput(f"{where}: {key!r} is an empty list")
    for number, item in enumerate(items, start=1):
        if not _is_a(spec.kind, item):
            which = f"{key!r} item {number}" if isinstance(given, list) else repr(key)
            raise BadInput(f"{where}: {which} is {item!r}, expected {_TYPE_NAMES[spec.kind]}")
    values = tuple(float(item) if spec.kind is float else item for item in items)
    seen: set[Any] = set()  # a set: a grid's lists may be long
    for value in values:
        if value in seen:
            raise BadInput(f"{where}: {key!r} gives {value!r} twice")
        seen.add(value)
    return values


def _range(where: str, key: str, given: dict[str, Any]) -> list[float]:
    """`{ from = A, to = B, step = S }`: A, A + S, ... up to B, included."""
    if _KEYS[key].kind not in (int, float):
        raise BadInput(f"{where}: {key!r} takes text, not a range")
    if set(given) != set(_RANGE_KEYS) or not all(_is_a(float, given[part]) for part in _RANGE_KEYS):
        raise BadInput(f"{where}: {key!r} range must be {{ from = A, to = B, step = S }}")
    start, stop, step = (given[part] for part in _RANGE_KEYS)
    if step <= 0 or stop < start:
        raise BadInput(f"{where}: {key!r} range needs step > 0 and to >= from")
    count = math.floor((stop - start) / step + 1e-9) + 1
    if count > 100_000:
        raise BadInput(f"{where}: {key!r} range has {count:,} values; give a larger step")
    points = [start + i * step for i in range(count)]
    # Whole numbers stay whole for integer keys; others keep the step's decimals.
    return [round(p) if _KEYS[key].kind is int else round(p, 9) for p in points]


def _is_a(kind: type, item: Any) -> bool:
    if kind is bool:
        return isinstance(item, bool)
    if isinstance(item, bool):  # TOML's true and false are Python ints too
        return False
    if kind is float:
        return isinstance(item, int | float) and math.isfinite(item)
    return isinstance(item, kind)


def _check_reflexes(where: str, text: str) -> None:
    try:
        parse_reflexes(text)
    except BadInput:
        raise BadInput(
            f"{where}: reflexes {text!r} is not all, none or names from "
            f"{', '.join(REFLEX_NAMES)}, comma-separated (the paper's whole method is "
            'method = "paper")'
        ) from None


def _method(path: Path, entry: str) -> Method:
    """A preset by name, else a method file beside the grid."""
    return resolve_method(entry, path.parent, f"{path}: method")


def _check_paper_runs(path: Path, entry: str, method: Method, values: dict[str, Any]) -> None:
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


def _world(path: Path, entry: str) -> WorldMap:
    """A world file beside the grid, else a generated world (KIND:SEED), else the bundled
    world of that name."""
    file = path.parent / entry
    if file.is_file():
        return load_world(file)
    kind, colon, seed = entry.partition(":")
    if colon:
        if kind not in KINDS:
            known = did_you_mean(kind, list(KINDS))
            raise BadInput(f"{path}: world {entry!r}: no world kind {kind!r} ({known})")
        if not seed.isdigit() or int(seed) > MAX_SEED:
            raise BadInput(f"{path}: world {entry!r}: KIND:SEED needs a whole-number seed")
        return parse_world(generate_world(kind, None, None, int(seed)), entry)
    try:
        return load_world(bundled_world_path(entry))
    except BadInput:
        raise BadInput(
            f"{path}: world {entry!r}: no such world file {file}, nor a bundled world"
        ) from None


def _config(path: Path, entry: str) -> FamConfig:
    spec = entry if entry in BUILTIN_FAM_CONFIGS else str(path.parent / entry)
    return resolve_fam_config(spec, RobotConfig())


def _named(path: Path, key: str, by_entry: dict[str, Any]) -> dict[str, Any]:
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


def _goals_in(path: Path, world: WorldMap, given: tuple[str, ...]) -> list[str | None]:
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
