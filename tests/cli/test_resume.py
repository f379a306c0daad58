"""Learning that goes on: a second `tvl learn` on a log continues from it, `--from-fam`
starts from a trained FAM, and `tvl train` trains a repeated session once."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import TVL
from json_schemas import valid
from test_bad_numbers import SQUARE

from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import read_log

pytestmark = pytest.mark.slow  # every test here starts a real `tvl` process


def tvl(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([TVL, *map(str, args)], capture_output=True, text=True, timeout=120)


def learn(log: Path, *more: str | Path) -> None:
    done = tvl("learn", SQUARE, "--log", log, "--minutes", "1", *more)
    assert done.returncode == 0, done.stderr


def tables(path: Path) -> list[np.ndarray]:
    fam = read_fam(path).fam
    return [
        table(t) for t in range(len(fam.config.tables))
        for table in (fam.velocity_table, fam.experience_table)
    ]  # fmt: skip


def test_a_second_session_goes_on_from_the_first(tmp_path: Path) -> None:
    log, online, trained = tmp_path / "l.h5", tmp_path / "online.h5", tmp_path / "trained.h5"
    learn(log)
    learn(log, "--fam", online)
    first, second = read_log(log).sessions
    assert first.seed == second.seed == 1
    # The seed stream goes on: the second session is not the first again.
    assert not np.array_equal(first.episode_table, second.episode_table)
    assert (first.parameters["seed_stream"], second.parameters["seed_stream"]) == (0, 1)
    # It learnt into what the first had learnt: its online FAM is the whole log's.
    assert tvl("train", log, "-o", trained).returncode == 0
    for online_table, trained_table in zip(tables(online), tables(trained), strict=True):
        np.testing.assert_array_equal(online_table, trained_table)


def test_from_fam_starts_a_new_log_from_a_trained_fam(tmp_path: Path) -> None:
    first, second = tmp_path / "a.h5", tmp_path / "b.h5"
    fam_a, fam_b, trained = tmp_path / "fa.h5", tmp_path / "fb.h5", tmp_path / "t.h5"
    learn(first, "--fam", fam_a)
    learn(second, "--from-fam", fam_a, "--fam", fam_b)
    assert tvl("train", first, second, "-o", trained).returncode == 0
    # A FAM file keeps velocities and experience, not the weighted sums behind them, so
    # going on from one matches training on its sources to within a unit in the last place.
    for from_file, trained_table in zip(tables(fam_b), tables(trained), strict=True):
        np.testing.assert_allclose(from_file, trained_table, rtol=1e-12, atol=1e-15)
    started = read_fam(fam_b).provenance["from_fam"]
    assert started["path"] == str(fam_a) and len(started["sha256"]) == 64


def test_from_fam_is_refused_on_a_log_with_sessions_or_another_configuration(
    tmp_path: Path,
) -> None:
    log, fam = tmp_path / "l.h5", tmp_path / "f.h5"
    learn(log, "--fam", fam)
    kept = log.read_bytes()
    done = tvl("learn", SQUARE, "--log", log, "--minutes", "1", "--from-fam", fam)
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert "already holds sessions" in done.stderr
    other = tmp_path / "m.h5"
    done = tvl("learn", SQUARE, "--log", other, "--from-fam", fam, "--config", "multi")
    assert done.returncode == 2 and "not 'multi'" in done.stderr
    assert log.read_bytes() == kept and not other.exists()


def test_train_counts_a_session_found_twice_once(tmp_path: Path) -> None:
    log, copy = tmp_path / "l.h5", tmp_path / "copy.h5"
    learn(log)
    shutil.copyfile(log, copy)
    with h5py.File(copy, "r+") as f:  # the same session, in a file that hashes otherwise
        f.attrs["created"] = "another day"
    once = valid("train", tvl("train", log, "-o", tmp_path / "once.h5", "--json").stdout)
    twice = tvl("train", log, copy, "-o", tmp_path / "twice.h5", "--json")
    assert twice.returncode == 0, twice.stderr
    printed = valid("train", twice.stdout)
    repeat = {
        "log": str(copy),
        "session": "0000",
        "repeats_log": str(log),
        "repeats_session": "0000",
    }
    assert printed["repeated_sessions"] == [repeat]
    assert (printed["episodes"], printed["exemplars"]) == (once["episodes"], once["exemplars"])
