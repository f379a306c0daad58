"""`tvl learn` killed at any moment, from the log's creation to its closing compression:
what it leaves is no log or a readable one, and the next write clears any leftover."""

from __future__ import annotations

import random
import shutil
import signal
import subprocess
import time
from pathlib import Path

import h5py
import pytest
from conftest import TVL
from json_schemas import valid
from test_bad_input import start_learning
from test_bad_numbers import SQUARE

from tvl_cli.core.errors import BadInput
from tvl_cli.io.logreader import read_log

# Every test here starts the real `tvl` and waits on it.
pytestmark = pytest.mark.slow


# Up to this long after the log appears or changes: the few milliseconds in which a session is
# being started in it (when sessions were started in the log itself, a kill then now and then
# left a log HDF5 could not open).
KILL_WITHIN_S = 0.004


def test_a_kill_as_the_log_appears_leaves_a_log_the_next_learn_continues(
    run_tvl, tmp_path: Path
) -> None:
    delays = random.Random(3)
    for attempt in range(10):
        log = tmp_path / f"log{attempt}.h5"
        process = subprocess.Popen(
            [TVL, "learn", str(SQUARE), "--log", str(log), "--minutes", "5"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + 60
        while not log.exists() and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.0002)
        time.sleep(delays.uniform(0.0, KILL_WITHIN_S))
        process.send_signal(signal.SIGKILL)
        process.wait()
        assert log.exists()
        with h5py.File(log, "r") as f:
            assert f.attrs["format"] == "tvl-log"
        again = run_tvl("learn", SQUARE, "--log", log, "--minutes", "0.5")
        assert again.returncode == 0, again.stderr


def test_a_kill_as_a_session_starts_keeps_every_session_before_it(run_tvl, tmp_path: Path) -> None:
    first = tmp_path / "first.h5"
    assert run_tvl("learn", SQUARE, "--log", first, "--minutes", "0.5").returncode == 0
    before = read_log(first).exemplar_count
    delays = random.Random(5)
    for attempt in range(6):
        log = tmp_path / f"log{attempt}.h5"
        shutil.copy(first, log)
        unchanged = _identity(log)
        process = subprocess.Popen(
            [TVL, "learn", str(SQUARE), "--log", str(log), "--minutes", "5"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + 60
        while _identity(log) == unchanged and process.poll() is None:
            assert time.monotonic() < deadline
            time.sleep(0.0002)
        time.sleep(delays.uniform(0.0, KILL_WITHIN_S))
        process.send_signal(signal.SIGKILL)
        process.wait()
        assert read_log(log).exemplar_count >= before


def _identity(path: Path) -> tuple[int, int, int]:
    """What changes when a file is written or replaced: its inode, time and size."""
    status = path.stat()
    return status.st_ino, status.st_mtime_ns, status.st_size


def test_kills_at_any_moment_leave_a_readable_log_and_no_leftovers_after_the_next_write(
    run_tvl, tmp_path: Path
) -> None:
    # Delays from just after start-up to past the end of learning, when the log is being
    # compressed and renamed into place; drawn once, from a fixed seed.
    delays = random.Random(7).sample([0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.3], 6)
    for attempt, delay in enumerate(delays):
        log = tmp_path / f"log{attempt}.h5"
        process = subprocess.Popen(
            [TVL, "learn", str(SQUARE), "--log", str(log), "--minutes", "3"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        time.sleep(delay)
        process.send_signal(signal.SIGKILL)
        process.wait()
        if log.exists():
            try:
                read_log(log)
            except BadInput as refusal:  # killed before any episode was committed
                assert "no exemplars" in str(refusal)
        again = run_tvl("learn", SQUARE, "--log", log, "--minutes", "0.5")
        assert again.returncode == 0, again.stderr
        assert read_log(log).exemplar_count > 0
        assert [p.name for p in tmp_path.iterdir() if p.name.startswith(f".{log.name}")] == []


@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM])
def test_a_stopped_learner_keeps_every_episode_it_finished(tmp_path: Path, stop) -> None:
    # Learning writes episodes a few at a time; stopping it writes those it still holds.
    log = tmp_path / "log.h5"
    process = start_learning(log, "--json")
    process.send_signal(stop)
    printed, _ = process.communicate(timeout=60)
    summary = valid("learn", printed)
    assert summary["status"] == f"interrupted: {stop.name}"
    (session,) = read_log(log).sessions
    assert len(session.episode_table) == summary["episodes"] > 0
    assert session.exemplar_count == summary["exemplars"]


def test_a_log_killed_in_its_first_session_through_a_memory_appends_and_trains(
    run_tvl, tmp_path: Path
) -> None:
    # What is kept of the killed session is read as it was learnt, through its memory: the
    # same learner appends to it, and the log trains, with no option but the memory's.
    memory = ("--memory", "points", "--memory-window", "60")
    # Ten simulated hours: far more than learning gets through before the kill, however fast.
    for attempt, delay in enumerate((1.5, 3.0)):
        log, fam = tmp_path / f"log{attempt}.h5", tmp_path / f"fam{attempt}.h5"
        process = subprocess.Popen(
            [TVL, "learn", str(SQUARE), "--log", str(log), "--minutes", "600", *memory],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + 60
        while not log.exists() and time.monotonic() < deadline:
            time.sleep(0.01)
        time.sleep(delay)
        process.send_signal(signal.SIGKILL)
        process.wait()
        appended = run_tvl(
            "learn", SQUARE, "--log", log, "--minutes", "0.5", "--seed", "2", *memory
        )
        assert appended.returncode == 0, appended.stderr
        trained = run_tvl("train", log, "-o", fam)
        assert trained.returncode == 0, trained.stderr
        assert read_log(log).sessions[0].status == "interrupted: not closed"
