"""FAM configurations a user got wrong, on the command line, run in process: one line, exit 2."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_bad_numbers import SQUARE, assert_one_line_refusal

from tvl_cli.core.fam_config import SINGLE


def single_with(change) -> dict:
    config = json.loads(SINGLE.to_json())
    change(config)
    return config


def set_first_sonar(config: dict) -> None:
    config["tables"][0]["inputs"][0]["sonars"][0] = 1.7


def misspell_a_table_key(config: dict) -> None:
    config["tables"][0]["setz"] = 1


BAD_CONFIGS = {
    "a fractional sonar": (single_with(set_first_sonar), "table 0 input 0: sonar 1.7"),
    "an unknown key": (single_with(misspell_a_table_key), "table 0: unknown key 'setz'"),
}


@pytest.mark.parametrize("case", BAD_CONFIGS)
@pytest.mark.parametrize("command", ["learn", "train"])
def test_a_bad_configuration_is_refused_before_any_file_is_written(
    invoke_tvl, tmp_path: Path, case: str, command: str
) -> None:
    config, phrase = BAD_CONFIGS[case]
    path = tmp_path / "config.json"
    path.write_text(json.dumps(config))
    out = tmp_path / "out.h5"
    if command == "learn":
        result = invoke_tvl("learn", SQUARE, "--log", out, "--config", path)
    else:
        log = tmp_path / "log.h5"
        assert invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.5").returncode == 0
        result = invoke_tvl("train", log, "-o", out, "--config", path)
    assert_one_line_refusal(result, str(path), phrase)
    assert not out.exists()


@pytest.mark.parametrize(
    "text",
    [
        "[" * 100_000 + "]" * 100_000,
        '{"name": "deep", "tables": ' + "[" * 40 + "]" * 40 + "}",
        '{"name": "deep", "tables": [' + '{"a": ' * 3_000 + "1" + "}" * 3_000 + "]}",
    ],
    ids=["lists 100,000 deep", "lists 40 deep", "objects 3,000 deep"],
)
def test_json_nested_beyond_reason_is_one_line(invoke_tvl, tmp_path: Path, text: str) -> None:
    path = tmp_path / "deep.json"
    path.write_text(text)
    result = invoke_tvl("learn", SQUARE, "--log", tmp_path / "log.h5", "--config", path)
    assert_one_line_refusal(result, str(path), "nested too deeply")
    assert not (tmp_path / "log.h5").exists()
