"""Fuzzing the settings files users write by hand or by script: method TOML, robot TOML, sweep
grids and FAM configuration JSON. Any text, nested to any depth (lists, tables, dotted keys,
JSON arrays and objects, from a few levels to 100,000) or blown up (numbers of thousands of
digits, long strings, many keys), is read or refused as bad input naming the file: never
another exception, nor a hang.

The fast tier runs TVL_FUZZ_EXAMPLES examples of each (50 unless set); the slow tier runs each
again at TVL_FUZZ_LONG_EXAMPLES (10,000 unless set). A reader of another format (a map's
YAML) is fuzzed the same way by giving `deeply_nested` its own brackets.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tvl_cli.core.behaviours import is_threshold
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS
from tvl_cli.core.fam_config_json import fam_config_from_json
from tvl_cli.core.labels import velocity_labels
from tvl_cli.core.method import FIELDS, method_from_dict
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.robotfile import robot_from_table
from tvl_cli.io.tomlfile import loads_toml
from tvl_cli.sweep.grid import read_grid
from tvl_cli.sweep.runner import DEFAULT_MAX_CELLS


def fuzz(examples: int) -> Callable[[Callable[..., None]], Callable[..., None]]:
    return settings(
        max_examples=examples,
        # Milliseconds: a file that takes longer to read counts as a hang. Far above a read's
        # tens of milliseconds, for the cores other work shares (a file nested 100,000 deep
        # took tomllib minutes before it was counted first).
        deadline=10_000,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


FAST = fuzz(int(os.environ.get("TVL_FUZZ_EXAMPLES", "50")))
# Ten thousand of each in the slow tier (TVL_FUZZ_LONG_EXAMPLES sets another count).
LONG = fuzz(int(os.environ.get("TVL_FUZZ_LONG_EXAMPLES", "10000")))
# Depths about the cap (core.nesting.MAX_NESTING, 32), and far beyond any parser's recursion.
DEPTH = st.one_of(st.integers(0, 40), st.sampled_from([31, 32, 33, 1_000, 5_000, 100_000]))


def deeply_nested(opening: str, closing: str, depth: int, inner: str = "1") -> str:
    """`inner` within `depth` pairs of brackets: a list, a table or an object nested deep."""
    return opening * depth + inner + closing * depth


# --- TOML --------------------------------------------------------------------------------


def toml_float(x: float) -> str:
    if math.isnan(x):
        return "nan"
    return ("inf" if x > 0 else "-inf") if math.isinf(x) else repr(x)


# Values a TOML file may hold where a number or a word is asked for, made beforehand (a
# recursive strategy draws each anew and takes most of an example's time): numbers beyond
# range and not finite, words, text of every escape and length, and lists and tables within
# one another.
TOML_TEXTS = [
    "0", "1", "-1", "0.5", "20", "1e20", "1e308", "-1e308", "1e-320", "inf", "-inf", "nan",
    "99999999999999999999", "true", "false", "1979-05-27T07:32:00Z", "07:32:00",
    '""', '"20"', '"square"', '"all"', '"none"', '"\\u00e9t\\u00e9"', "'literal'",
    '"""multi\nline"""', json.dumps("x" * 10_000),
    "[]", "[1, 2]", "[1.5, 2.5]", '["a", 1]', "[[1], [2]]", "[[[[[[[[1]]]]]]]]",
    "{}", "{ a = 1 }", '{ kind = "patches" }', "{ a = { b = { c = [1, { d = 2 }] } } }",
]  # fmt: skip
TOML_VALUE = st.one_of(
    st.sampled_from(TOML_TEXTS),
    st.floats(allow_nan=True, allow_infinity=True).map(toml_float),
    st.integers(-(10**20), 10**20).map(str),
)


@st.composite
def toml_blow_up(draw: st.DrawFn, key: str) -> str:
    """A line nesting `key`'s value deep, or a dotted key or header of many parts (tomllib
    takes time quadratic in their number), or many keys."""
    depth = draw(DEPTH)
    kind = draw(st.sampled_from(["list", "table", "dotted", "header", "keys"]))
    if kind == "list":
        return f"{key} = {deeply_nested('[', ']', depth)}"
    if kind == "table":
        return f"{key} = {deeply_nested('{ a = ', ' }', depth)}"
    if kind == "dotted":
        return key + ".a" * depth + " = 1"
    if kind == "header":
        return "[" + ".".join([key, *["a"] * depth]) + "]"
    return "\n".join(f"k{n} = {n}" for n in range(min(depth, 2_000)))


@st.composite
def toml_document(draw: st.DrawFn, keys: list[str], valued: dict[str, st.SearchStrategy]) -> str:
    """Lines of `key = value` (the known keys' values from `valued`, else any TOML value),
    sometimes with a line blown up, shuffled."""
    lines = []
    for key in draw(st.lists(st.sampled_from([*keys, "colour"]), max_size=6, unique=True)):
        value = draw(st.one_of(valued[key], TOML_VALUE) if key in valued else TOML_VALUE)
        lines.append(f"{key} = {value}")
    if draw(st.booleans()):
        lines.append(draw(toml_blow_up(draw(st.sampled_from([*keys, "x"])))))
    return "\n".join(draw(st.permutations(lines))) + "\n"


def inline_table(
    optional: tuple[str, ...], required: dict[str, st.SearchStrategy[str]] | None = None
) -> st.SearchStrategy[str]:
    """An inline table (`{ a = 1, b = "x" }`) of the `required` keys' values and some of the
    `optional` keys, each any TOML value."""
    return st.fixed_dictionaries(
        required or {}, optional={key: TOML_VALUE for key in optional}
    ).map(lambda table: "{" + ", ".join(f"{k} = {v}" for k, v in table.items()) + "}")


# --- method files ------------------------------------------------------------------------

MEMORY = inline_table(
    ("window_s", "range_m", "patch_m"),
    {"kind": st.sampled_from(['"none"', '"points"', '"patches"', "1"])},
)
METHOD_VALUES = {
    "decel_mps2": TOML_VALUE,
    "margin_m": TOML_VALUE,
    "near_m": TOML_VALUE,
    "exploration": st.sampled_from(['"least-experience"', '"novelty"', '"greedy"']),
    "reflexes": st.sampled_from(['"all"', '"none"', '["bump", "tie"]', '["bumpy"]', "[]"]),
    "sonar": st.sampled_from(['"real"', '"ideal"', '"laser"']),
    "memory": MEMORY,
}
METHOD_TOML = toml_document(list(FIELDS), METHOD_VALUES)


T = TypeVar("T")


def read_unless_refused(text: str, read: Callable[[dict[str, Any], str], T]) -> T | None:
    """What `read` makes of the TOML text, or None where it is refused: as bad input naming
    the file, and never otherwise."""
    try:
        return read(loads_toml(text, "fuzz.toml"), "fuzz.toml")
    except BadInput as refusal:
        assert str(refusal).startswith("fuzz.toml"), refusal  # the refusal names the file
        return None


def method_is_read_or_refused(text: str) -> None:
    method = read_unless_refused(text, method_from_dict)
    if method is None:
        return
    # What is read, training can label with: finite speeds, as the labels say.
    labels = velocity_labels(np.array([0.0, 0.5, 3.0, np.inf]), 0.6, method.decel_mps2,
                             method.margin_m)  # fmt: skip
    assert np.isfinite(labels).all()


@FAST
@given(METHOD_TOML)
def test_a_method_file_is_read_or_refused(text: str) -> None:
    method_is_read_or_refused(text)


@pytest.mark.slow
@LONG
@given(METHOD_TOML)
def test_a_method_file_is_read_or_refused_at_length(text: str) -> None:
    method_is_read_or_refused(text)


# --- robot files -------------------------------------------------------------------------


ROBOT_VALUES = {
    "base": st.sampled_from(['"yamabico"', '"turtlebot3"', '"burger"', "1"]),
    "radius_m": TOML_VALUE,
    "spin_rate_radps": TOML_VALUE,
    "odometry_noise_fraction": TOML_VALUE,
    "trajectories": st.one_of(
        inline_table(("radii_m", "v_max_mps", "count")),
        st.sampled_from(["{ radii_m = [0.3, 0.6, 1.2] }", "{ v_max_mps = [0.1, 0.2, 0.3, 0.4] }"]),
    ),
    "sonar": inline_table(("min_range_m", "max_range_m", "cone_deg", "noise_sigma_m", "count")),
}
ROBOT_TOML = toml_document(list(ROBOT_VALUES), ROBOT_VALUES)


def robot_is_read_or_refused(text: str) -> None:
    robot = read_unless_refused(text, robot_from_table)
    if robot is None:
        return
    # What is read is a robot a log can record and read back as one that moves and senses.
    assert RobotConfig.from_dict(robot.to_dict()) == robot


@FAST
@given(ROBOT_TOML)
def test_a_robot_file_is_read_or_refused(text: str) -> None:
    robot_is_read_or_refused(text)


@pytest.mark.slow
@LONG
@given(ROBOT_TOML)
def test_a_robot_file_is_read_or_refused_at_length(text: str) -> None:
    robot_is_read_or_refused(text)


# --- sweep grids -------------------------------------------------------------------------

GRID_VALUES = {
    "world": st.sampled_from(['"square"', '["square", "circle"]', '"nowhere"', "5", '""']),
    "seed": st.sampled_from(["1", "[1, 2]", "-1", "1.5", "{ from = 1, to = 3, step = 1 }"]),
    "kind": st.sampled_from(['"tvl"', '["learn", "dwa"]', '"qlearn"', '"walk"']),
    "behaviour": st.sampled_from(['"avoid"', '["wall-left", "goal"]', '"dance"']),
    "method": st.sampled_from(['"default"', '"paper"', '"mine.toml"']),
    "config": st.sampled_from(['"single"', '["single", "multi"]', '"mine.json"']),
    "goal": st.sampled_from(['"all"', '"1.0,1.0"', '"99,99"', '"x"']),
    "threshold": st.one_of(TOML_VALUE, st.just("{ from = 0.5, to = 1.0, step = 1e-9 }")),
    "learn_minutes": TOML_VALUE,
    "run_minutes": TOML_VALUE,
    "minute": TOML_VALUE,
}
GRID_TOML = toml_document(
    [
        "world", "seed", "kind", "behaviour", "method", "config", "goal", "threshold",
        "learn_minutes", "run_minutes", "minute", "online", "trace", "reflexes",
    ],
    GRID_VALUES,
)  # fmt: skip


def grid_is_read_or_refused(text: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "grid.toml"
        path.write_text(text, encoding="utf-8")
        try:
            grid = read_grid(path, DEFAULT_MAX_CELLS)
        except BadInput as refusal:
            assert str(refusal).startswith(str(path)), refusal  # the refusal names the file
            return
    # What is read, a sweep can run: within the cap, every threshold within (0, 1].
    assert 0 < len(grid.cells) <= DEFAULT_MAX_CELLS
    assert all(c.threshold is None or is_threshold(c.threshold) for c in grid.cells)


@FAST
@given(GRID_TOML)
def test_a_grid_is_read_or_refused(text: str) -> None:
    grid_is_read_or_refused(text)


@pytest.mark.slow
@LONG
@given(GRID_TOML)
def test_a_grid_is_read_or_refused_at_length(text: str) -> None:
    grid_is_read_or_refused(text)


# --- FAM configurations --------------------------------------------------------------------

JSON_VALUE = st.recursive(
    st.none() | st.booleans() | st.floats() | st.integers() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner),
    max_leaves=30,
)
SHIPPED = [config.to_dict() for config in BUILTIN_FAM_CONFIGS.values()]


@st.composite
def config_json(draw: st.DrawFn) -> str:
    """A shipped configuration with a value somewhere in it replaced (by any JSON value, or one
    nested deep), or JSON nested deep, or with a number of thousands of digits."""
    kind = draw(st.sampled_from(["replaced", "nested", "digits"]))
    if kind == "nested":
        pair = draw(st.sampled_from([("[", "]"), ('{"a": ', "}")]))
        return deeply_nested(*pair, draw(DEPTH))
    config = json.loads(json.dumps(draw(st.sampled_from(SHIPPED))))
    node: object = config
    place: dict | list = config  # the value replaced is place[key]
    key: str | int = "name"
    for _ in range(draw(st.integers(1, 7))):  # down a path of the configuration's own keys
        if not isinstance(node, dict | list) or not node:
            break
        children = list(node.items()) if isinstance(node, dict) else list(enumerate(node))
        place, (key, node) = node, draw(st.sampled_from(children))
    if kind == "digits":
        value: object = "@DIGITS@"
    elif draw(st.booleans()):
        value = draw(JSON_VALUE)
    else:
        value = "@DEEP@"
    place[key] = value  # type: ignore[index]
    text = json.dumps(config)
    text = text.replace('"@DIGITS@"', "1" * draw(st.sampled_from([10, 4_300, 5_000, 100_000])))
    return text.replace('"@DEEP@"', deeply_nested("[", "]", draw(DEPTH)))


TRAJECTORIES = [t.name for t in RobotConfig().trajectories]


def config_is_read_or_refused(text: str) -> None:
    try:
        config = fam_config_from_json(text, TRAJECTORIES, "fuzz.json")
    except BadInput as refusal:
        assert str(refusal).startswith("fuzz.json"), refusal  # the refusal names the file
        return
    stored = sorted(name for table in config.tables for name in table.trajectories)
    assert stored == sorted(TRAJECTORIES)


@FAST
@given(config_json())
def test_a_fam_configuration_is_read_or_refused(text: str) -> None:
    config_is_read_or_refused(text)


@pytest.mark.slow
@LONG
@given(config_json())
def test_a_fam_configuration_is_read_or_refused_at_length(text: str) -> None:
    config_is_read_or_refused(text)
