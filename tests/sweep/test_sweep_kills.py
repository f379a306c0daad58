"""`tvl sweep` killed while its workers learn, as a user or `timeout` kills it: kill -9 of the
sweep alone, and SIGTERM to its whole process group. No process of it is left a few seconds
later, and whoever reads its output to the end (a pipe, a `$(…)`, a CI step) is not kept
waiting by a worker that holds it open."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
from conftest import TVL

pytestmark = pytest.mark.slow

# Two cells whose learning lasts long enough (20 simulated minutes, some seconds) to be
# under way in both workers when the sweep is killed.
GRID = 'world = "square"\nseed = [1, 2]\nlearn_minutes = 20\nrun_minutes = 0.1\n'
LEFT_WITHIN_S = 5.0


def live_processes_in_group(group: int) -> list[int]:
    """The processes of a process group that still run (a zombie has ended: it waits only to
    be counted by its parent)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue  # ended while we looked
        # pid (comm) state ppid pgrp ...: comm may hold spaces, so split after its ")".
        state, _, pgrp = stat.rpartition(")")[2].split()[:3]
        if int(pgrp) == group and state != "Z":
            found.append(int(entry.name))
    return found


def workers_of(pid: int) -> list[int]:
    """The pool's worker processes of a sweep, a group's leader."""
    workers = []
    for child in live_processes_in_group(pid):
        try:
            command = Path(f"/proc/{child}/cmdline").read_text()
        except OSError:
            continue  # ended while we looked
        if child != pid and "spawn_main" in command:
            workers.append(child)
    return workers


# Two workers of the local pool, or of a Dask cluster started for the sweep.
POOLS = {"pool": ("--workers", "2"), "dask": ("--scheduler", "local:2")}


def started_sweep(tmp_path: Path, pool: tuple[str, ...] = POOLS["pool"]) -> subprocess.Popen[str]:
    """A sweep of two workers, in a process group of its own, once both are learning."""
    grid = tmp_path / "grid.toml"
    grid.write_text(GRID)
    sweep = subprocess.Popen(
        [TVL, "sweep", str(grid), "--out", str(tmp_path / "out"), *pool],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    logs = tmp_path / "out" / "logs"
    deadline = time.monotonic() + 60.0
    # Each worker learns its log under a temporary name until it is whole.
    while len(workers_of(sweep.pid)) < 2 or len(list(logs.glob(".*.tmp"))) < 2:
        assert sweep.poll() is None, sweep.communicate()
        assert time.monotonic() < deadline, "the sweep's workers did not start learning"
        time.sleep(0.2)
    return sweep


def assert_nothing_left(sweep: subprocess.Popen[str], group: int) -> None:
    # Reading the output to its end returns: no worker holds it open.
    sweep.communicate(timeout=LEFT_WITHIN_S)
    deadline = time.monotonic() + LEFT_WITHIN_S
    while live_processes_in_group(group):
        assert time.monotonic() < deadline, f"left running: {live_processes_in_group(group)}"
        time.sleep(0.1)


@pytest.mark.parametrize("pool", sorted(POOLS))
def test_a_sweep_killed_with_kill_9_leaves_no_worker(tmp_path: Path, pool: str) -> None:
    if pool == "dask":
        pytest.importorskip("distributed")
    sweep = started_sweep(tmp_path, POOLS[pool])
    sweep.kill()
    assert_nothing_left(sweep, sweep.pid)  # a session's leader: its group is its pid


def test_a_sweep_whose_group_gets_sigterm_leaves_no_worker(tmp_path: Path) -> None:
    sweep = started_sweep(tmp_path)
    os.killpg(sweep.pid, signal.SIGTERM)  # as `timeout` ends what it runs
    assert_nothing_left(sweep, sweep.pid)


def test_a_sweep_run_again_after_a_kill_goes_on_to_the_whole_table(tmp_path: Path) -> None:
    sweep = started_sweep(tmp_path)
    sweep.kill()
    assert_nothing_left(sweep, sweep.pid)
    again = subprocess.run(
        [TVL, "sweep", str(tmp_path / "grid.toml"), "--out", str(tmp_path / "out"), "--csv"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert again.returncode == 0, again.stderr
    assert len(again.stdout.splitlines()) == 3  # the header and both cells' rows
