"""FAM configurations with values a user got wrong, on the command line, run in process: one line
naming the file, exit 2, no log or FAM written."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import invoke
from test_bad_numbers import SQUARE, assert_one_line_refusal

from tvl_cli.core.fam_config import MULTI, SINGLE
from tvl_cli.core.fam_config_json import MAX_CENTRE_M, fam_config_from_json
from tvl_cli.core.robot_config import RobotConfig

FRONT = "tables.0.inputs.0"  # SINGLE's first input: sonars 15, 0, 1, five fuzzy sets


def single_with(path: str, value: object) -> str:
    """SINGLE as JSON, with `value` at a dotted path of keys and indexes ("tables.0.name")."""
    config = json.loads(SINGLE.to_json())
    *parents, last = (int(part) if part.isdigit() else part for part in path.split("."))
    node = config
    for key in parents:
        node = node[key]
    node[last] = value
    return json.dumps(config)


BAD_CONFIGS = {
    "a 5001-digit sonar": (
        single_with(f"{FRONT}.sonars", [0]).replace("[0]", "[1" + "0" * 5000 + "]"),
        "digits",
    ),
    "a name that is a number": (single_with("name", 5), "'name' is 5, expected text"),
    "a table name that is a number": (single_with("tables.0.name", 0), "table 0: 'name' is 0"),
    "fuzzy-set names that are numbers": (
        single_with(f"{FRONT}.partition.names", [1, 2, 3, 4, 5]),
        "'names' holds 1, expected text",
    ),
    "a key given twice": ('{"name": "mine", ' + SINGLE.to_json()[1:], "'name' appears twice"),
    "a negative centre": (
        single_with(f"{FRONT}.partition.centres_m", [-0.5, 0.45, 0.8, 1.3, 2.0]),
        "centre -0.5 is outside the sonar's range",
    ),
    "a centre beyond the sonar's range": (
        single_with(f"{FRONT}.partition.centres_m", [0.2, 0.45, 0.8, 1.3, MAX_CENTRE_M + 1]),
        f"centre {MAX_CENTRE_M + 1!r} is outside",
    ),
}


@pytest.fixture(scope="module")
def log(tmp_path_factory) -> Path:
    """A learning log to train from, made once for the module."""
    path = tmp_path_factory.mktemp("log") / "log.h5"
    assert invoke("learn", SQUARE, "--log", path, "--minutes", "0.5").returncode == 0
    return path


@pytest.mark.parametrize("case", BAD_CONFIGS)
@pytest.mark.parametrize("command", ["learn", "train"])
def test_a_bad_value_is_refused_naming_the_file(invoke_tvl, log, tmp_path, case, command):
    text, phrase = BAD_CONFIGS[case]
    path = tmp_path / "config.json"
    path.write_text(text)
    out = tmp_path / "out.h5"
    if command == "learn":
        result = invoke_tvl("learn", SQUARE, "--log", out, "--config", path)
    else:
        result = invoke_tvl("train", log, "-o", out, "--config", path)
    assert_one_line_refusal(result, f"tvl: error: {path}: ", phrase)
    assert not out.exists()


def test_the_shipped_centres_and_the_ends_of_the_range_are_accepted():
    names = [t.name for t in RobotConfig().trajectories]
    for config in (SINGLE, MULTI):
        assert fam_config_from_json(config.to_json(), names) == config
    ends = single_with(f"{FRONT}.partition.centres_m", [0, 0.45, 0.8, 1.3, MAX_CENTRE_M])
    assert (
        fam_config_from_json(ends, names).tables[0].inputs[0].partition.centres_m[-1]
        == MAX_CENTRE_M
    )
