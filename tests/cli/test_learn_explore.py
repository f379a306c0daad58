"""`tvl learn --explore` and coverage on the command line, run in process."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import invoke
from json_schemas import valid

from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import read_log

SQUARE = Path(__file__).resolve().parents[2] / "worlds" / "square.txt"


@pytest.fixture(scope="module")
def novelty_log(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    """A two-minute log learnt with the novelty rule, and what `tvl learn --json` printed."""
    log = tmp_path_factory.mktemp("explore") / "novelty.h5"
    learn = ["learn", str(SQUARE), "--log", str(log), "--minutes", "2", "--seed", "2", "--json"]
    done = invoke(*learn, "--explore", "novelty")
    assert done.returncode == 0, done.stderr
    return log, valid("learn", done.stdout)


@pytest.mark.slow
def test_the_session_records_its_rule_and_trains(novelty_log, invoke_tvl, tmp_path) -> None:
    log, _ = novelty_log
    assert read_log(log).sessions[0].method.exploration == "novelty"
    fam = tmp_path / "fam.h5"
    trained = invoke_tvl("train", log, "-o", fam, "--json")
    assert trained.returncode == 0, trained.stderr
    assert valid("train", trained.stdout)["exemplars"] == read_log(log).exemplar_count
    (session,) = read_fam(fam).provenance["logs"][0]["sessions"]
    assert session["exploration"] == "novelty"


def test_learn_and_replay_agree_on_the_coverage_of_each_minute(novelty_log, invoke_tvl) -> None:
    log, printed = novelty_log
    learnt = [m["coverage"] for m in printed["minutes"]]
    assert len(learnt) == 2 and 0 < learnt[0] <= learnt[1] <= printed["coverage"] <= 1
    replayed = invoke_tvl("replay", log, "--json")
    assert replayed.returncode == 0, replayed.stderr
    summary = valid("replay", replayed.stdout)
    assert [m["coverage"] for m in summary["minutes"]] == learnt
    # One row type for a minute of learning, as learn printed it and as replay reads it back.
    assert summary["minutes"] == printed["minutes"]
    (session,) = summary["sessions"]
    assert (session["session"], session["explore"]) == (printed["session"], "novelty")


def test_an_unknown_rule_is_one_line_on_stderr(invoke_tvl, tmp_path) -> None:
    log = tmp_path / "never.h5"
    refused = invoke_tvl("learn", SQUARE, "--log", log, "--explore", "bogus")
    assert refused.returncode == 2
    (line,) = refused.stderr.splitlines()
    assert line.startswith("tvl: error: ") and "--explore" in line and "bogus" in line
    assert not log.exists()


def test_the_papers_method_fixes_the_rule(invoke_tvl, tmp_path) -> None:
    log = tmp_path / "never.h5"
    refused = invoke_tvl("learn", SQUARE, "--log", log, "--paper", "--explore", "novelty")
    assert refused.returncode == 2
    assert refused.stderr == "tvl: error: --explore cannot be given with --paper, which fixes it\n"
    assert not log.exists()
