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
import os
from dataclasses import dataclass
from itertools import product
from pathlib import Path
from typing import Any

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import FamConfig
from tvl_cli.core.method import Method, reflexes_text
from tvl_cli.io.tomlfile import read_toml
from tvl_cli.sim.worldmap import WorldMap
from tvl_cli.sweep.cell import DWA, QLEARN, TVL, Cell
from tvl_cli.sweep.grid_entries import (
    check_paper_runs,
    config_entry,
    goals_in,
    method_entry,
    named,
    world_entry,
)
from tvl_cli.sweep.grid_keys import ALL_GOALS, BEHAVING, KEYS, LEARNT, SAME, part_values

# The sizes a grid file is run at: as written (the paper's trial counts), or a table of it.
FULL, QUICK, TINY = "full", "quick", "tiny"
SIZES = (TINY, QUICK, FULL)
# A `[[part]]`: a grid of its own under the file's keys.
PART = "part"
# What a cell takes of memory while a sweep runs: about 0.3 KB listed and 3 KB more while its
# work waits its turn (measured for a TVL run: the request, its future and their records).
CELL_BYTES = 4096
# Where the machine does not say how much memory it has: what a laptop holds.
ASSUMED_MEMORY_BYTES = 8 << 30

Values = dict[str, tuple[Any, ...]]  # a part's values of each key
Goals = dict[str, list[str | None]]  # the goals of goal runs in each world, by its name


@dataclass(frozen=True, slots=True)
class Grid:
    worlds: dict[str, str]  # name -> the world file's text, which the sweep runs a copy of
    configs: dict[str, FamConfig]  # by name
    methods: dict[str, Method]  # by the grid's entry
    cells: tuple[Cell, ...]  # in the grid's order: the last key varies fastest
    size: str = FULL


def read_grid(path: Path, max_cells: int | None = None, size: str = FULL) -> Grid:
    """The grid of a TOML file at a size, every value checked; BadInput naming the file and
    the key (or the line of a syntax error) at the first fault, or the number of cells when
    it is over `max_cells` (None: no cap) or over what memory holds, counted before any cell
    is made (and before any world is read, as far as the goals to seek let it be)."""
    values_of = _read_parts(path, read_toml(path, "grid"), size)
    fewest = sum(_count_cells(values, _fewest_goals(values)) for values in values_of)
    _check_cap(path, fewest, max_cells, exact=all(map(_goals_given, values_of)))
    methods = {
        e: method_entry(path, e)
        for values in values_of
        if set(values["kind"]) & set(LEARNT)
        for e in values["method"]
    }
    worlds = named(
        path, "world", {e: world_entry(path, e) for values in values_of for e in values["world"]}
    )
    configs = named(
        path,
        "config",
        {
            e: config_entry(path, e)
            for values in values_of
            for key in ("config", "learn_config")
            for e in values[key]
            if e not in (None, SAME)
        },
    )
    by_entry = {
        key: {e: value.name for e, value in named_by.items()}
        for key, named_by in (("world", worlds), ("config", configs))
    }
    expanded = []
    for values in values_of:
        for entry, method in methods.items():
            if entry in values["method"]:
                check_paper_runs(path, entry, method, values)
        expanded.append((values, _goals(path, values, worlds, by_entry["world"])))
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


def _read_parts(path: Path, table: dict[str, Any], size: str) -> list[Values]:
    """Each part's values of every key at a size (the file as one part if it has none)."""
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
        values_of.append(part_values(where, merged, {**own, **own_size}))
    return values_of


def _goals(path: Path, values: Values, worlds: dict[str, WorldMap], names: dict[str, str]) -> Goals:
    """The goals a part's goal runs seek in each of its worlds (none without goal runs)."""
    return {
        names[entry]: goals_in(path, worlds[entry], values["goal"])
        if "goal" in values["behaviour"]
        else []
        for entry in values["world"]
    }


def _goals_given(values: Values) -> bool:
    """Whether a part names every goal its goal runs seek (or has none), so that its cells
    are counted before its worlds are read."""
    goals = values["goal"]
    return "goal" not in values["behaviour"] or (bool(goals) and ALL_GOALS not in goals)


def _fewest_goals(values: Values) -> Goals:
    """As many goals as a part's goal runs seek in each world at the least, before the worlds
    are read: those it gives, or one (the world's first, or "all" of a world's goals)."""
    given = [goal for goal in values["goal"] if goal != ALL_GOALS]
    fewest: list[str | None] = [None] * max(len(given), 1)
    return {entry: fewest if "goal" in values["behaviour"] else [] for entry in values["world"]}


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
        if key == PART or key in SIZES or (isinstance(value, dict) and key not in KEYS):
            raise BadInput(f"{where} [{size}]: a size overrides grid keys, not {key!r}")
    return overrides


def _cells(
    values: dict[str, tuple[Any, ...]],
    goals: dict[str, list[str | None]],
    by_entry: dict[str, dict[str, str]],
    methods: dict[str, Method],
) -> list[Cell]:
    """A part's cells: for each kind, every combination of the keys that kind reads, in the
    order of KEYS; goals multiply the goal runs alone."""
    cells = []
    for kind in values["kind"]:
        read = {key: values[key] if kind in spec.kinds else None for key, spec in KEYS.items()}
        read["kind"] = (kind,)
        read["world"] = tuple(by_entry["world"][e] for e in values["world"])
        for key in ("config", "learn_config"):
            if read[key] is not None:
                read[key] = tuple(by_entry["config"].get(e, e) for e in values[key])
        if not read["reflexes"]:
            read["reflexes"] = None  # each method's own; for a baseline, none
        keys = [key for key in KEYS if key != "goal"]
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
        read = [k for k, spec in KEYS.items() if kind in spec.kinds and k not in _NOT_COUNTED]
        per_world = math.prod(len(values[key]) or 1 for key in read)
        behaviours = values["behaviour"] if kind in BEHAVING else (None,)
        runs = sum(
            len(goals[world]) if behaviour == "goal" else 1
            for world in goals
            for behaviour in behaviours
        )
        total += per_world * runs
    return total


def _check_cap(path: Path, cells: int, max_cells: int | None, exact: bool = True) -> None:
    """BadInput if a grid's cells (or, not `exact`, the fewest it has) are more than memory
    holds, --yes or not, or more than `max_cells`."""
    counted = f"{cells:,}" if exact else f"at least {cells:,}"
    memory_bytes = _memory_bytes()
    if cells > memory_bytes // CELL_BYTES:
        raise BadInput(
            f"{path}: {counted} cells, more than memory holds: a sweep keeps each (about "
            f"{CELL_BYTES // 1024} KB), and this machine has {memory_bytes / (1 << 30):.1f} GiB "
            f"for {memory_bytes // CELL_BYTES:,}; split the grid"
        )
    if max_cells is not None and cells > max_cells:
        raise BadInput(
            f"{path}: {counted} cells, over the cap of {max_cells:,}; give --max-cells "
            f"{cells} or --yes to run them all"
        )


def _memory_bytes() -> int:
    """The machine's memory, as its system says (a laptop's where it does not)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):  # no sysconf, or no such name here
        return ASSUMED_MEMORY_BYTES
