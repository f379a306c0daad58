"""The keys of a sweep's grid: each key's type, default and the kinds of cell that read it,
and a part's values of every key, read from its TOML table and checked."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from tvl_cli.core.behaviours import BEHAVIOUR_NAMES, DEFAULT_THRESHOLD, is_threshold
from tvl_cli.core.errors import (
    DEFAULT_RUN_MINUTES,
    MAX_SEED,
    BadInput,
    check_minutes,
    check_run_minutes,
    did_you_mean,
)
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import MEMORY_KINDS
from tvl_cli.core.method import (
    DEFAULT_NAME,
    EXPLORATION_RULES,
    REFLEX_NAMES,
    method_from_dict,
    parse_reflexes,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sweep.cell import DWA, KINDS_OF_CELL, LEARN, QLEARN, TVL

# `learn_config = "same"`: the learner explores with the FAM the cell trains.
SAME = "same"
# `goal = "all"`: a goal run to each of the world's goals.
ALL_GOALS = "all"


@dataclass(frozen=True, slots=True)
class Key:
    kind: type  # of its values
    default: tuple[Any, ...] | None  # its values when the grid does not give it; None: must
    kinds: tuple[str, ...]  # the kinds of cell that read it


_EVERY = KINDS_OF_CELL
LEARNT = (TVL, LEARN)
_RUNS = (TVL, DWA, QLEARN)
BEHAVING = (TVL, DWA)
# Each key (a column of Cell) with its type, its default, and the kinds that read it, in the
# order the grid's product nests them: the last varies fastest. `goal` defaults to none
# given: the world's first. `reflexes` to none given: each method's own, none for baselines.
KEYS: dict[str, Key] = {
    "kind": Key(str, (TVL,), _EVERY),
    "world": Key(str, None, _EVERY),
    "seed": Key(int, None, _EVERY),
    "learn_config": Key(str, (SINGLE.name,), LEARNT),
    "learn_minutes": Key(float, (LearnParams().minutes,), (TVL, LEARN, QLEARN)),
    "exploration": Key(str, (None,), LEARNT),
    "near_m": Key(float, (None,), LEARNT),
    "memory": Key(str, (None,), LEARNT),
    "config": Key(str, (SINGLE.name,), (TVL,)),
    "minute": Key(float, (None,), (TVL,)),
    "behaviour": Key(str, ("avoid",), BEHAVING),
    "threshold": Key(float, (DEFAULT_THRESHOLD,), (TVL,)),
    "goal": Key(str, (), BEHAVING),
    "run_minutes": Key(float, (DEFAULT_RUN_MINUTES,), _RUNS),
    "online": Key(bool, (False,), (TVL,)),
    "competence_every": Key(float, (None,), (QLEARN,)),
    "trace": Key(bool, (False,), (TVL,)),
    # A baseline takes nothing of a method but its reflexes, which the cell gives.
    "method": Key(str, (DEFAULT_NAME,), LEARNT),
    "reflexes": Key(str, (), _RUNS),
    "run_memory": Key(str, (None,), (TVL,)),
}
_TYPE_NAMES = {str: "text", int: "a whole number", float: "a number", bool: "true or false"}
_RANGE_KEYS = ("from", "to", "step")


def part_values(
    where: str, table: dict[str, Any], own: dict[str, Any]
) -> dict[str, tuple[Any, ...]]:
    """A part's values of every key, each checked, and each key of its `own` (not those it
    takes from above it) read by one of its kinds of cell."""
    unknown = [key for key in table if key not in KEYS]
    if unknown:
        raise BadInput(
            f"{where}: unknown key {unknown[0]!r} ({did_you_mean(unknown[0], list(KEYS))})"
        )
    values = {key: _values(where, table, key) for key in KEYS}
    for kind in values["kind"]:
        if kind not in KINDS_OF_CELL:
            raise BadInput(
                f"{where}: kind {kind!r} is not one of {', '.join(KINDS_OF_CELL)} "
                f"({did_you_mean(kind, KINDS_OF_CELL)})"
            )
    for key in own:
        if key in KEYS and not set(KEYS[key].kinds) & set(values["kind"]):
            kinds = ", ".join(KEYS[key].kinds)
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
    control_period_s = RobotConfig().control_period_s
    for minutes in values["learn_minutes"]:
        # Learning shorter than a step records nothing; a longer one that finishes no
        # episode is named when it has (sweep.work.learn_log).
        check_run_minutes(minutes, control_period_s, f"{where}: learn_minutes")
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
        check_run_minutes(minutes, control_period_s, f"{where}: run_minutes")
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


def _values(where: str, table: dict[str, Any], key: str) -> tuple[Any, ...]:
    """A key's values: the one given, the list, or the range; checked for type and repeats."""
    spec = KEYS[key]
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
    if KEYS[key].kind not in (int, float):
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
    return [round(p) if KEYS[key].kind is int else round(p, 9) for p in points]


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
