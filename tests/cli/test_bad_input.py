"""Bad input to train, inspect, learn and run: one clear line on stderr, exit 2, nothing lost."""

from __future__ import annotations

import signal
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import TVL
from method_samples import LIVE_RING

from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.lock import lock_path
from tvl_cli.io.logfile import LogWriter
from tvl_cli.io.logreader import read_log

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
SQUARE = WORLDS / "square.txt"


def _assert_refused(result: subprocess.CompletedProcess[str], *phrases: str) -> None:
    assert result.returncode == 2, result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("tvl: error: ")
    for phrase in phrases:
        assert phrase in lines[0]
    assert "Traceback" not in result.stderr


def _open_log(path: Path, robot: RobotConfig) -> LogWriter:
    return LogWriter.open(
        path,
        world_name="square",
        world_text=SQUARE.read_text(encoding="utf-8"),
        seed=1,
        parameters={},
        robot_config=robot.to_dict(),
        fam_config=SINGLE.to_dict(),
        method=LIVE_RING,
    )


def _log(path: Path, robot: RobotConfig, episodes: int = 1) -> Path:
    with _open_log(path, robot) as writer:
        for index in range(episodes):
            n = 5
            writer.append_episode(
                Episode(
                    index=index,
                    ring_mm=np.full((n, 16), 900, dtype=np.uint16),
                    pose=np.zeros((n, 3)),
                    odometry=np.zeros((n, 3)),
                    arc_m=np.arange(n) * 0.02,
                    trajectory=3,
                    rotation=0,
                    collided=True,
                    bumped=True,
                    end_arc_m=0.1,
                    end_time_s=1.0 + index,
                )
            )
    return path


@pytest.fixture
def fam_file(tmp_path: Path) -> Path:
    path = tmp_path / "fam.h5"
    robot = RobotConfig()
    write_fam(
        path,
        Fam(SINGLE, [t.name for t in robot.trajectories]),
        robot_config=robot,
        method=LIVE_RING,
        provenance={},
    )
    return path


def test_train_refuses_a_file_that_is_not_hdf5(invoke_tvl, tmp_path):
    text = tmp_path / "notes.h5"
    text.write_text("just text")
    _assert_refused(invoke_tvl("train", text, "-o", tmp_path / "f.h5"), str(text), "not an HDF5")
    assert not (tmp_path / "f.h5").exists()


def test_train_refuses_another_format_by_name(invoke_tvl, fam_file, tmp_path):
    result = invoke_tvl("train", fam_file, "-o", tmp_path / "f.h5")
    _assert_refused(result, "is a tvl-fam file, expected a tvl-log")


def test_train_refuses_a_newer_format_version(invoke_tvl, tmp_path):
    log = _log(tmp_path / "log.h5", RobotConfig())
    with h5py.File(log, "r+") as f:
        f.attrs["format_version"] = 99
    result = invoke_tvl("train", log, "-o", tmp_path / "f.h5")
    _assert_refused(result, "format_version 99 is newer")


def test_train_refuses_a_truncated_log(invoke_tvl, tmp_path):
    log = _log(tmp_path / "log.h5", RobotConfig())
    data = log.read_bytes()
    log.write_bytes(data[: len(data) // 2])
    _assert_refused(invoke_tvl("train", log, "-o", tmp_path / "f.h5"), str(log))


def test_train_refuses_a_log_without_exemplars(invoke_tvl, tmp_path):
    log = _log(tmp_path / "log.h5", RobotConfig(), episodes=0)
    _assert_refused(invoke_tvl("train", log, "-o", tmp_path / "f.h5"), "no exemplars")


def test_train_refuses_logs_of_different_robots(invoke_tvl, tmp_path):
    ours = _log(tmp_path / "ours.h5", RobotConfig())
    theirs = _log(tmp_path / "theirs.h5", RobotConfig(radius_m=0.25))
    result = invoke_tvl("train", ours, theirs, "-o", tmp_path / "f.h5")
    _assert_refused(result, str(theirs), "another robot configuration")
    assert not (tmp_path / "f.h5").exists()


def test_train_refuses_a_malformed_user_configuration(invoke_tvl, tmp_path):
    log = _log(tmp_path / "log.h5", RobotConfig())
    config = tmp_path / "mine.json"
    config.write_text('{"name": "mine", "tables": [}')
    _assert_refused(
        invoke_tvl("train", log, "-o", tmp_path / "f.h5", "--config", config), "mine.json"
    )


@pytest.mark.parametrize("threshold", ["0", "1.5", "-0.2"])
def test_run_refuses_a_threshold_outside_0_1(invoke_tvl, fam_file, threshold):
    result = invoke_tvl("run", fam_file, SQUARE, "--behaviour", "avoid", "--threshold", threshold)
    _assert_refused(result, "outside (0, 1]")


@pytest.mark.parametrize("minutes", ["0", "-3"])
def test_run_refuses_minutes_that_are_not_positive(invoke_tvl, fam_file, minutes):
    result = invoke_tvl("run", fam_file, SQUARE, "--behaviour", "avoid", "--minutes", minutes)
    _assert_refused(result, "--minutes", "must be more than 0")


def test_learn_refuses_negative_minutes(invoke_tvl, tmp_path):
    log = tmp_path / "log.h5"
    _assert_refused(
        invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "-1"), "must be more than 0"
    )
    assert not log.exists()


def test_run_refuses_a_goal_outside_the_world(invoke_tvl, fam_file):
    result = invoke_tvl("run", fam_file, SQUARE, "--behaviour", "goal", "--goal", "9,2")
    _assert_refused(result, "outside the world")


def test_run_refuses_a_goal_inside_a_wall(invoke_tvl, fam_file):
    result = invoke_tvl("run", fam_file, SQUARE, "--behaviour", "goal", "--goal", "0.1,2")
    _assert_refused(result, "inside a wall")


def test_run_refuses_a_fam_of_another_robot_than_the_one_asked_for(invoke_tvl, tmp_path):
    other = RobotConfig(radius_m=0.15)
    path = tmp_path / "other.h5"
    write_fam(
        path,
        Fam(SINGLE, [t.name for t in other.trajectories]),
        robot_config=other,
        method=LIVE_RING,
        provenance={},
    )
    result = invoke_tvl("run", path, SQUARE, "--behaviour", "avoid", "--robot", "yamabico")
    assert result.returncode == 2
    assert result.stderr == (
        f"tvl: error: {path}: FAM was learnt on a robot of its own (0.3 m across), not on the "
        "yamabico robot (radius_m 0.15 → 0.2); learn one with that --robot\n"
    )
    # Not asked for a robot, the run drives the FAM's own.
    assert (
        invoke_tvl("run", path, SQUARE, "--behaviour", "avoid", "--minutes", "0.1").returncode == 0
    )


def test_run_refuses_an_existing_png_without_force(invoke_tvl, fam_file, tmp_path):
    png = tmp_path / "path.png"
    png.write_bytes(b"mine")
    result = invoke_tvl("run", fam_file, SQUARE, "--behaviour", "avoid", "--png", png)
    _assert_refused(result, "already exists")
    assert png.read_bytes() == b"mine"


def empty_session_bytes(directory: Path) -> int:
    """The size of a log holding one session that has written no episode yet, as a learner's
    log is before its first write."""
    path = directory / "empty-session.h5"
    with _open_log(path, RobotConfig()):
        size = path.stat().st_size
    path.unlink()
    return size


def start_learning(log: Path, *args: str) -> subprocess.Popen[str]:
    """A `tvl learn` of the square that holds the lock on `log` and has written episodes."""
    before_episodes = empty_session_bytes(log.parent) + 10_000  # bytes: room for attributes
    process = subprocess.Popen(
        [TVL, "learn", str(SQUARE), "--log", str(log), "--minutes", "100000", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        if lock_path(log).exists() and log.exists() and log.stat().st_size > before_episodes:
            return process
        time.sleep(0.01)
    process.kill()
    raise AssertionError("learning never started writing its log")


@pytest.mark.slow  # starts a real `tvl` process
def test_sigint_keeps_every_whole_episode(tmp_path):
    log = tmp_path / "log.h5"
    process = start_learning(log)
    time.sleep(1.0)
    process.send_signal(signal.SIGINT)
    process.communicate(timeout=60)
    assert process.returncode != 0
    (session,) = read_log(log).sessions
    assert session.status == "interrupted: SIGINT"
    table = session.episode_table
    assert len(table) > 0
    assert int(table["count"].sum()) == session.exemplar_count
    assert np.array_equal(np.cumsum(table["count"])[:-1], table["first"][1:])


@pytest.mark.slow  # starts a real `tvl` process
def test_a_second_learner_on_a_locked_log_is_refused(invoke_tvl, tmp_path):
    log = tmp_path / "log.h5"
    process = start_learning(log)
    try:
        result = invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "1")
        _assert_refused(result, str(log), "locked")
    finally:
        process.send_signal(signal.SIGTERM)
        process.communicate(timeout=60)
    (session,) = read_log(log).sessions
    assert session.status == "interrupted: SIGTERM"
    assert int(session.episode_table["count"].sum()) == session.exemplar_count


@pytest.mark.parametrize(
    ("option", "value", "phrase"),
    [
        ("--decel", "0", "--decel 0 must be more than 0"),
        ("--margin", "-0.1", "--margin -0.1 must be"),
        ("--label-ceiling-radius", "-1", "--label-ceiling-radius -1 must be more than 0"),
    ],
)
def test_learn_refuses_bad_labels_before_touching_the_log(
    invoke_tvl, tmp_path, option, value, phrase
):
    log = tmp_path / "log.h5"
    _assert_refused(invoke_tvl("learn", SQUARE, "--log", log, option, value), phrase)
    assert not log.exists()


@pytest.mark.slow
def test_train_refuses_a_log_with_corrupt_data(invoke_tvl, tmp_path):
    log = tmp_path / "log.h5"
    assert invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "2").returncode == 0
    data = bytearray(log.read_bytes())
    middle = len(data) // 3
    data[middle : middle + 4000] = np.random.default_rng(1).bytes(4000)
    log.write_bytes(bytes(data))
    _assert_refused(invoke_tvl("train", log, "-o", tmp_path / "f.h5"), str(log), "corrupt")
    assert not (tmp_path / "f.h5").exists()


def test_run_checks_every_output_directory_before_running(invoke_tvl, fam_file, tmp_path):
    trace = tmp_path / "trace.h5"
    result = invoke_tvl(
        "run", fam_file, SQUARE, "--behaviour", "avoid", "--log", trace,
        "--png", tmp_path / "missing" / "path.png",
    )  # fmt: skip
    _assert_refused(result, "missing", "does not exist")
    assert not trace.exists()


def test_a_usage_error_is_one_line(invoke_tvl, fam_file):
    _assert_refused(invoke_tvl("run", fam_file, SQUARE, "--behaviour", "fly"), "'fly'")


def test_run_refuses_a_goal_for_another_behaviour(invoke_tvl, fam_file):
    result = invoke_tvl("run", fam_file, SQUARE, "--behaviour", "avoid", "--goal", "2,2")
    _assert_refused(result, "--goal is for --behaviour goal only")


def test_demo_refuses_a_file_for_its_directory(invoke_tvl, tmp_path):
    target = tmp_path / "notes.txt"
    target.write_text("keep")
    _assert_refused(invoke_tvl("demo", target), "is a file")
    assert target.read_text() == "keep"


def test_train_refuses_the_same_log_twice(invoke_tvl, tmp_path):
    log = _log(tmp_path / "log.h5", RobotConfig())
    _assert_refused(invoke_tvl("train", log, log, "-o", tmp_path / "f.h5"), "given twice")


def test_train_refuses_a_negative_minute(invoke_tvl, tmp_path):
    log = _log(tmp_path / "log.h5", RobotConfig())
    result = invoke_tvl("train", log, "-o", tmp_path / "f.h5", "--until-minute", "-1")
    _assert_refused(result, "--until-minute -1")


def test_an_initial_velocity_may_not_be_fast(invoke_tvl, tmp_path):
    log = _log(tmp_path / "log.h5", RobotConfig())
    result = invoke_tvl("train", log, "-o", tmp_path / "f.h5", "--init-velocity", "5")
    _assert_refused(result, "--init-velocity", "5.0 is not in the range 0.0<=x<0.35")
