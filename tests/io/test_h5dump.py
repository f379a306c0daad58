"""Files written by this version read cleanly with HDF5's own h5dump, as another user would."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest
from log_samples import ROBOT, open_sample_writer, sample_episode
from method_samples import LIVE_RING

from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.io.famfile import write_fam

pytestmark = pytest.mark.skipif(
    shutil.which("h5dump") is None, reason="h5dump (Debian's hdf5-tools) is not installed"
)


def h5dump(*args: str) -> str:
    done = subprocess.run(["h5dump", *args], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""
    return done.stdout


def sample_log(path: Path) -> Path:
    with open_sample_writer(path) as writer:
        for index in range(3):
            writer.append_episode(sample_episode(index))
        writer.append_minute(minute=1, episodes=3, collisions=2, exemplars=15, delta_v=0.01)
    return path


def sample_fam(path: Path) -> Path:
    fam = Fam(SINGLE, [t.name for t in ROBOT.trajectories])
    write_fam(path, fam, robot_config=ROBOT, method=LIVE_RING, provenance={"logs": []})
    return path


def test_h5dump_reads_a_whole_log(tmp_path: Path) -> None:
    out = h5dump(str(sample_log(tmp_path / "log.h5")))
    assert 'GROUP "/sessions/0000"' in out or 'GROUP "0000"' in out


def test_h5dump_reads_a_log_still_being_written(tmp_path: Path) -> None:
    path = tmp_path / "log.h5"
    writer = open_sample_writer(path)
    writer.append_episode(sample_episode(0))
    try:
        copy = tmp_path / "copy.h5"
        shutil.copyfile(path, copy)  # the writer's HDF5 lock keeps h5dump off the original
        assert 'DATASET "ring_mm"' in h5dump(str(copy))
    finally:
        writer.close()


def test_h5dump_reads_a_whole_fam(tmp_path: Path) -> None:
    out = h5dump(str(sample_fam(tmp_path / "fam.h5")))
    assert 'DATASET "velocity"' in out


def test_h5dump_header_of_a_fam_names_format_axes_and_units(tmp_path: Path) -> None:
    out = h5dump("-A", str(sample_fam(tmp_path / "fam.h5")))
    for text in ('"tvl-fam"', '"front-left"', '"VN", "N", "M", "F", "VF"', '"m/s"', '"T1L"'):
        assert text in out, text
