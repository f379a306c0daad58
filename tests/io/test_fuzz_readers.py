"""Fuzzing the two text readers users feed by hand: any input parses or is refused as bad
input, never another exception or a hang. TVL_FUZZ_EXAMPLES=N runs longer (default 150)."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config_json import fam_config_from_json
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import static_geometry
from tvl_cli.sim.worldmap import parse_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
MAPS = [path.read_text(encoding="utf-8") for path in sorted(WORLDS.glob("*.txt"))]
FUZZ = settings(
    max_examples=int(os.environ.get("TVL_FUZZ_EXAMPLES", "150")),
    deadline=2000,  # milliseconds: a map that takes longer to read counts as a hang
    suppress_health_check=[HealthCheck.too_slow],
)
NUMBER = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-(10**30), 10**30).map(str),
    st.sampled_from(["1e-320", "1e308", "-0", "0.01", "10", "nan", "inf"]),
)
HEADER = st.builds(
    lambda key, numbers: f"{key}: {' '.join(numbers)}\n",
    st.sampled_from(["cell", "disc", "ring", "goal", "wall", "name", "version", "colour"]),
    st.lists(NUMBER, max_size=6),
)
SCRAP = st.text(alphabet="#.><^vGo :-0123456789e\n;", max_size=24)


@pytest.mark.slow  # over a second
@FUZZ
@given(st.data())
def test_a_mutated_map_parses_or_is_refused(data: st.DataObject) -> None:
    text = data.draw(st.sampled_from(MAPS))
    start = data.draw(st.integers(0, len(text)))
    end = data.draw(st.integers(start, min(len(text), start + 30)))
    text = text[:start] + data.draw(st.one_of(SCRAP, HEADER)) + text[end:]
    if data.draw(st.booleans()):
        text = data.draw(HEADER) + text
    try:
        world = parse_world(text, "fuzz.txt")
    except BadInput as refusal:
        assert str(refusal).startswith("fuzz.txt")  # the refusal names the file
        return
    assert math.isfinite(world.width_m * world.height_m)
    static_geometry(world)  # what parses, the simulator can build


JSON = st.recursive(
    st.none() | st.booleans() | st.floats() | st.integers() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner),
    max_leaves=30,
)
CONFIG_KEYS = st.sampled_from(["name", "tables", "inputs", "trajectories", "sonars", "partition"])


@pytest.mark.slow  # over a second
@FUZZ
@given(st.one_of(JSON, st.dictionaries(CONFIG_KEYS, JSON, max_size=4)))
def test_any_json_is_a_fam_configuration_or_refused(value: object) -> None:
    names = [t.name for t in RobotConfig().trajectories]
    try:
        config = fam_config_from_json(json.dumps(value), names, "fuzz.json")
    except BadInput as refusal:
        assert str(refusal).startswith("fuzz.json")  # the refusal names the file
        return
    stored = sorted(name for table in config.tables for name in table.trajectories)
    assert stored == sorted(names)
