"""`tvl learn` killed as it creates a new log: what it leaves is no log or a readable one."""

from __future__ import annotations

import signal
import subprocess
import time
from pathlib import Path

import h5py
from conftest import TVL
from test_bad_numbers import SQUARE


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
