"""Numeric options out of range, on the command line, run in process: one line, exit 2, no file."""

from __future__ import annotations

from pathlib import Path

import pytest
from method_samples import LIVE_RING

from tvl_cli.core.errors import MAX_SIMULATED_MINUTES
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.famfile import write_fam

SQUARE = Path(__file__).resolve().parents[2] / "worlds" / "square.txt"
TOO_LONG = "1e307"  # finite, but its step count would overflow an integer
TOO_BIG_SEED = str(2**70)


def assert_one_line_refusal(result, *phrases: str) -> None:
    assert result.returncode == 2, result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("tvl: error: ")
    for phrase in phrases:
        assert phrase in lines[0], lines[0]


@pytest.fixture(scope="module")
def fam(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("fam") / "fam.h5"
    robot = RobotConfig()
    fam = Fam(SINGLE, [t.name for t in robot.trajectories])
    write_fam(path, fam, robot_config=robot, method=LIVE_RING, provenance={})
    return path


@pytest.mark.parametrize("seed", ["-1", TOO_BIG_SEED])
def test_learn_refuses_a_seed_out_of_range_and_writes_no_log(invoke_tvl, tmp_path, seed):
    log = tmp_path / "log.h5"
    result = invoke_tvl("learn", SQUARE, "--log", log, "--seed", seed)
    assert_one_line_refusal(result, "--seed", seed)
    assert not log.exists()


@pytest.mark.parametrize(
    "command",
    [
        ("baseline", "dwa", SQUARE),
        ("baseline", "qlearn", SQUARE),
    ],
)
def test_baselines_refuse_a_negative_seed(invoke_tvl, command):
    assert_one_line_refusal(invoke_tvl(*command, "--seed", "-1"), "--seed")


def test_run_refuses_a_seed_too_big_to_store(invoke_tvl, fam):
    result = invoke_tvl("run", fam, SQUARE, "--behaviour", "avoid", "--seed", TOO_BIG_SEED)
    assert_one_line_refusal(result, "--seed")


def test_learn_refuses_a_huge_finite_duration_and_writes_no_log(invoke_tvl, tmp_path):
    log = tmp_path / "log.h5"
    result = invoke_tvl("learn", SQUARE, "--log", log, "--minutes", TOO_LONG)
    assert_one_line_refusal(result, "--minutes", f"{MAX_SIMULATED_MINUTES:g}")
    assert not log.exists()


@pytest.mark.parametrize(
    ("command", "option"),
    [
        (("baseline", "dwa", SQUARE), "--minutes"),
        (("baseline", "qlearn", SQUARE), "--minutes"),
        (("baseline", "qlearn", SQUARE), "--learn-minutes"),
    ],
)
def test_baselines_refuse_a_huge_finite_duration(invoke_tvl, command, option):
    assert_one_line_refusal(invoke_tvl(*command, option, TOO_LONG), option)


def test_run_refuses_a_huge_finite_duration(invoke_tvl, fam):
    result = invoke_tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", TOO_LONG)
    assert_one_line_refusal(result, "--minutes")


def test_a_missing_choice_is_one_line_listing_the_choices(invoke_tvl, fam):
    result = invoke_tvl("run", fam, SQUARE)
    assert_one_line_refusal(result, "--behaviour", "avoid, wall-left")


def test_learning_too_short_for_an_episode_keeps_the_log_and_writes_no_fam(invoke_tvl, tmp_path):
    log, fam = tmp_path / "log.h5", tmp_path / "fam.h5"
    result = invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.05", "--fam", fam)
    assert_one_line_refusal(result, str(fam), "no episode finished", str(log))
    assert log.exists() and not fam.exists()


@pytest.mark.parametrize("command", [["run", "FAM"], ["baseline", "dwa"]])
def test_a_run_shorter_than_one_control_step_is_refused(invoke_tvl, fam: Path, command) -> None:
    args = [fam if part == "FAM" else part for part in command]
    result = invoke_tvl(*args, SQUARE, "--behaviour", "avoid", "--minutes", "1e-9")
    assert_one_line_refusal(result, "--minutes 1e-09 is shorter than one control step (0.1 s)")
