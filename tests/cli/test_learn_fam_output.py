"""`tvl learn --fam F` whose FAM cannot be written: refused before learning when that can be
known (names HDF5 cannot hold, a folder that takes no file), with no log written; and when
it cannot (no episode finished), the one line says the log keeps its session."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_bad_numbers import SQUARE, assert_one_line_refusal

from tvl_cli.core.fam_config import SINGLE
from tvl_cli.io.logreader import read_log


def config_naming(tmp_path: Path, where: str) -> Path:
    """The single FAM's configuration with a table's or an input's name holding a '/'."""
    config = json.loads(SINGLE.to_json())
    if where == "table":
        config["tables"][0]["name"] = "front/left"
    else:
        config["tables"][0]["inputs"][0]["name"] = "fr/ont"
    path = tmp_path / "slashed.json"
    path.write_text(json.dumps(config))
    return path


@pytest.mark.parametrize("where", ["table", "input"])
def test_names_a_fam_file_cannot_hold_are_refused_before_learning(
    invoke_tvl, tmp_path: Path, where: str
) -> None:
    config = config_naming(tmp_path, where)
    log, fam = tmp_path / "log.h5", tmp_path / "fam.h5"
    result = invoke_tvl("learn", SQUARE, "--log", log, "--fam", fam, "--config", config,
                        "--minutes", "0.5")  # fmt: skip
    assert_one_line_refusal(result, f"{config}: {where} name", "cannot be stored in a FAM file")
    assert not log.exists() and not fam.exists()


def test_a_fam_into_a_folder_that_takes_no_file_is_refused_before_learning(
    invoke_tvl, tmp_path: Path, unwritable_folder: Path
) -> None:
    log, fam = tmp_path / "log.h5", unwritable_folder / "fam.h5"
    result = invoke_tvl("learn", SQUARE, "--log", log, "--fam", fam, "--minutes", "0.5")
    assert_one_line_refusal(result, f"{fam}: cannot write")
    assert not log.exists()


def test_no_episode_finished_says_the_log_keeps_its_session(invoke_tvl, tmp_path: Path) -> None:
    log, fam = tmp_path / "log.h5", tmp_path / "fam.h5"
    result = invoke_tvl("learn", SQUARE, "--log", log, "--fam", fam, "--minutes", "0.05")
    assert_one_line_refusal(
        result, f"{fam}: not written: no episode finished", f"the log {log} keeps the session"
    )
    assert not fam.exists()
    (session,) = read_log(log, empty_allowed=True).sessions
    assert len(session.episode_table) == 0
