"""`tvl learn` killed at any moment, from the log's creation to its closing compression:
what it leaves is no log or a readable one, and the next write clears any leftover."""

from __future__ import annotations

import random
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


def test_a_kill_as_the_log_appears_leaves_a_log_the_next_learn_continues(
    run_tvl, tmp_path: Path
) -> None:
    for attempt in range(5):
        log = tmp_path / f"log{attempt}.h5"
        process = subprocess.Popen(
            [TVL, "learn", str(SQUARE), "--log", str(log), "--minutes", "5"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + 60
        while not log.exists() and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.0005)
        process.send_signal(signal.SIGKILL)
        process.wait()
        assert log.exists()
        with h5py.File(log, "r") as f:
            assert f.attrs["format"] == "tvl-log"
        again = run_tvl("learn", SQUARE, "--log", log, "--minutes", "0.5")
        assert again.returncode == 0, again.stderr


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
