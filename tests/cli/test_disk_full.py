"""Writes the machine refuses part way: one line, exit 1, committed data kept, no temporary
file left, and no crash of HDF5 on the way out."""

from __future__ import annotations

import os
import resource
import signal
import subprocess
from pathlib import Path

import h5py
import pytest
from conftest import TVL
from test_bad_numbers import SQUARE

LAB = SQUARE.with_name("lab.txt")
LIMIT_BYTES = 300_000  # room for a log's start, not for a multi FAM (about 2 MB)

pytestmark = pytest.mark.slow  # every test here starts a real `tvl` process


def tvl_limited(*args: str | Path) -> subprocess.CompletedProcess[str]:
    """`tvl ARGS` allowed files of at most LIMIT_BYTES: writes beyond fail with EFBIG."""

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (LIMIT_BYTES, LIMIT_BYTES))

    return subprocess.run(
        [TVL, *map(str, args)], capture_output=True, text=True, preexec_fn=limit, timeout=300
    )


@pytest.fixture(scope="module")
def log(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("log") / "lab.h5"
    subprocess.run([TVL, "learn", str(LAB), "--log", str(path), "--minutes", "3"], check=True)
    return path


def test_a_fam_too_big_to_write_is_one_line_and_leaves_nothing(log: Path, tmp_path: Path) -> None:
    fam = tmp_path / "fam.h5"
    result = tvl_limited("train", log, "-o", fam, "--config", "multi")
    assert (result.returncode, result.stderr) == (1, f"tvl: error: {fam}: File too large\n")
    assert list(tmp_path.iterdir()) == []


def test_a_run_trace_too_big_to_write_is_one_line_and_leaves_nothing(
    log: Path, tmp_path: Path
) -> None:
    fam, trace = tmp_path / "fam.h5", tmp_path / "run.h5"
    assert subprocess.run([TVL, "train", str(log), "-o", str(fam)]).returncode == 0
    result = tvl_limited(
        "run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "20", "--log", trace
    )
    assert (result.returncode, result.stderr) == (1, f"tvl: error: {trace}: File too large\n")
    assert [p.name for p in tmp_path.iterdir()] == ["fam.h5"]


@pytest.fixture
def small_disk(tmp_path: Path):
    """A 1 MB file system, where the machine allows mounting one (root on Linux)."""
    mount = tmp_path / "disk"
    mount.mkdir()
    made = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(mount)], capture_output=True
    )
    if made.returncode != 0 or os.geteuid() != 0:
        pytest.skip("cannot mount a small file system here")
    yield mount
    subprocess.run(["umount", str(mount)], check=True)


def learn_in_lab(log: Path, minutes: str, *options: str) -> subprocess.CompletedProcess[str]:
    """`tvl learn` in the lab into `log`, its output kept."""
    return subprocess.run(
        [TVL, "learn", str(LAB), "--log", str(log), "--minutes", minutes, *options],
        capture_output=True,
        text=True,
        timeout=600,
    )


def no_space(log: Path) -> tuple[int, str]:
    """What `tvl` exits with, and says, when the disk under `log` is full."""
    return 1, f"tvl: error: {log}: No space left on device\n"


def test_learning_onto_a_full_disk_keeps_the_committed_episodes(small_disk: Path) -> None:
    log = small_disk / "lab.h5"
    result = learn_in_lab(log, "300", "--json")
    assert (result.returncode, result.stderr) == no_space(log)
    assert [p.name for p in small_disk.iterdir()] == ["lab.h5"]
    with h5py.File(log, "r") as f:
        assert f["sessions/0000"].attrs["episodes_written"] > 20


def test_a_new_log_with_no_room_for_its_first_session_leaves_nothing(small_disk: Path) -> None:
    filler = small_disk / "filler"
    filler.write_bytes(bytes(1_000_000 - 20_000))  # leaves a few pages free
    log = small_disk / "lab.h5"
    result = learn_in_lab(log, "1")
    assert (result.returncode, result.stderr) == no_space(log)
    assert [p.name for p in small_disk.iterdir()] == ["filler"]  # no stub, no lock


def test_a_session_with_no_room_to_start_leaves_the_log_as_it_was(small_disk: Path) -> None:
    # A session starts in a copy of the log put in its place whole: with no room for the copy,
    # the log keeps every byte it had.
    log = small_disk / "lab.h5"
    first = learn_in_lab(log, "0.5")
    assert first.returncode == 0, first.stderr
    before = log.read_bytes()
    free = os.statvfs(small_disk).f_bavail * os.statvfs(small_disk).f_frsize
    (small_disk / "filler").write_bytes(bytes(free - len(before) // 2))
    result = learn_in_lab(log, "1")
    assert (result.returncode, result.stderr) == no_space(log)
    assert log.read_bytes() == before
    assert sorted(p.name for p in small_disk.iterdir()) == ["filler", "lab.h5"]
