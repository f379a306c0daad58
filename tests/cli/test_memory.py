"""The echo memory on the command line: learnt through, recorded in logs and FAM files,
replayed by `tvl train` from any log, read through by `tvl run`, and never by `--paper`."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from json_schemas import valid

from tvl_cli.cli.main import main
from tvl_cli.core.memory import NO_MEMORY, MemoryConfig
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import read_log
from tvl_cli.io.runfile import read_run

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
LAB = ROOT / "worlds" / "lab.txt"
PATCHES_20 = MemoryConfig("patches", window_s=20.0, range_m=3.0)
MEMORY_OPTIONS = ["--memory", "patches", "--memory-window", "20", "--memory-range", "3"]


def tvl(*args: object) -> str:
    done = CliRunner().invoke(main, [str(a) for a in args])
    assert done.exit_code == 0, done.output
    return done.output


def refused(*args: object) -> str:
    done = CliRunner().invoke(main, [str(a) for a in args])
    assert done.exit_code == 2, done.output
    return done.output


@pytest.fixture(scope="module")
def learnt(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """Two minutes in the lab through a memory: the log and the online FAM."""
    top = tmp_path_factory.mktemp("memory")
    log, fam = top / "lab.h5", top / "online.h5"
    tvl("learn", LAB, "--log", log, "--minutes", 2, "--fam", fam, *MEMORY_OPTIONS)
    return log, fam


def test_learning_records_its_memory_in_the_log_and_the_fam(learnt: tuple[Path, Path]) -> None:
    log, fam = learnt
    (session,) = read_log(log).sessions
    assert session.method.memory == PATCHES_20
    assert read_fam(fam).method.memory == PATCHES_20


def test_train_rebuilds_the_online_fam_through_the_logs_memory(
    learnt: tuple[Path, Path], tmp_path: Path
) -> None:
    log, online = learnt
    rebuilt = tmp_path / "rebuilt.h5"
    tvl("train", log, "-o", rebuilt)
    first, second = read_fam(online), read_fam(rebuilt)
    assert second.method.memory == PATCHES_20
    np.testing.assert_array_equal(first.fam.velocity_table(0), second.fam.velocity_table(0))
    np.testing.assert_array_equal(first.fam.experience_table(0), second.fam.experience_table(0))


@pytest.mark.slow
def test_a_log_learnt_with_a_memory_trains_a_fam_without_one_and_back(
    learnt: tuple[Path, Path], tmp_path: Path
) -> None:
    log, online = learnt
    plain = tmp_path / "plain.h5"
    tvl("train", log, "-o", plain, "--memory", "none")
    assert read_fam(plain).method.memory == NO_MEMORY
    # Without the memory the FAM trains on the live rings, which differ.
    assert not np.array_equal(
        read_fam(plain).fam.velocity_table(0), read_fam(online).fam.velocity_table(0)
    )
    # And the example log, learnt before there was a memory, trains a FAM that has one.
    remembering = tmp_path / "remembering.h5"
    tvl("train", ROOT / "logs" / "square-s1.h5", "-o", remembering, *MEMORY_OPTIONS)
    assert read_fam(remembering).method.memory == PATCHES_20


@pytest.mark.slow
def test_a_run_reads_through_its_fams_memory_unless_told(
    learnt: tuple[Path, Path], tmp_path: Path
) -> None:
    _, fam = learnt
    kept, changed, paper = tmp_path / "kept.h5", tmp_path / "changed.h5", tmp_path / "paper.h5"
    tvl("run", fam, LAB, "--behaviour", "avoid", "--minutes", 0.5, "--log", kept)
    tvl(
        "run",
        fam,
        LAB,
        "--behaviour",
        "avoid",
        "--minutes",
        0.5,
        "--log",
        changed,
        "--memory-window",
        5,
    )
    tvl("run", fam, LAB, "--behaviour", "avoid", "--minutes", 0.5, "--log", paper, "--paper")
    memory = {
        name: read_run(path).method.memory
        for name, path in (("kept", kept), ("changed", changed), ("paper", paper))
    }
    assert memory["kept"] == PATCHES_20
    assert memory["changed"] == MemoryConfig("patches", window_s=5.0, range_m=3.0)
    assert memory["paper"] == NO_MEMORY
    trace = read_run(kept).arrays
    read = trace["ring_mm"].any(axis=1)
    assert (trace["perceived_mm"][read] <= trace["ring_mm"][read]).all()
    assert (trace["perceived_mm"][read] < trace["ring_mm"][read]).any()
    printed = tvl("explain", kept, "--step", int(np.flatnonzero(read)[-1]), "--json")
    explained = valid("explain", printed)["step"]
    assert explained["perceived_m"] is not None and len(explained["perceived_m"]) == 16


def test_the_paper_refuses_a_memory_beside_it(tmp_path: Path) -> None:
    output = refused("learn", SQUARE, "--log", tmp_path / "l.h5", "--paper", "--memory", "points")
    assert "--memory cannot be given with --paper" in output


def test_the_paper_refuses_clearing_and_a_bad_clearing_is_one_line(tmp_path: Path) -> None:
    output = refused("learn", SQUARE, "--log", tmp_path / "l.h5", "--paper",
                     "--memory-clearing", "goal")  # fmt: skip
    assert "--memory-clearing cannot be given with --paper" in output
    output = refused("learn", SQUARE, "--log", tmp_path / "l.h5", "--memory-clearing", "often")
    assert "'often' is not one of 'never', 'goal', 'toward-goal', 'always'" in output
    assert not (tmp_path / "l.h5").exists()


@pytest.mark.slow
@pytest.mark.parametrize("clearing", ["never", "always"])
def test_a_fam_records_its_clearing_and_a_run_keeps_it_unless_told(
    clearing: str, tmp_path: Path
) -> None:
    fam = tmp_path / "fam.h5"
    clearing_options = ("--memory", "patches", "--memory-clearing", clearing)
    tvl("train", ROOT / "logs" / "square-s1.h5", "-o", fam, *clearing_options)
    assert read_fam(fam).method.memory.clearing == clearing
    kept, told = tmp_path / "kept.h5", tmp_path / "told.h5"
    run = ("run", fam, ROOT / "worlds" / "obstacles.txt", "--behaviour", "goal", "--minutes", 0.2)
    tvl(*run, "--log", kept)
    tvl(*run, "--log", told, "--memory-clearing", "goal")
    assert read_run(kept).method.memory.clearing == clearing
    assert read_run(told).method.memory.clearing == "goal"


def test_bad_memory_settings_are_one_line(tmp_path: Path) -> None:
    output = refused(
        "learn", SQUARE, "--log", tmp_path / "l.h5", "--memory", "patches", "--memory-window", 0
    )
    assert "--memory-window 0 must be more than 0" in output
    assert not (tmp_path / "l.h5").exists()


@pytest.mark.slow
@pytest.mark.parametrize(
    "appended",
    [[], ["--memory", "points"], ["--memory-window", "60"]],
    ids=["ours (patches)", "points of another window", "patches of a minute"],
)
def test_a_log_whose_sessions_mix_memories_says_so_and_how_to_train_it(
    invoke_tvl, tmp_path: Path, appended: list[str]
) -> None:
    # The first session as `tvl learn --memory points --memory-window 60` made it, another
    # appended through another memory: the log is whole, and mixes two memories.
    log, fam = tmp_path / "log.h5", tmp_path / "fam.h5"
    first = ["--memory", "points", "--memory-window", "60"]
    tvl("learn", SQUARE, "--log", log, "--minutes", "0.3", *first)
    tvl("learn", SQUARE, "--log", log, "--minutes", "0.3", "--seed", "2", *appended)
    trained = invoke_tvl("train", log, "-o", fam)
    assert trained.returncode == 2 and len(trained.stderr.splitlines()) == 1, trained.stderr
    assert trained.stderr.startswith(
        f"tvl: error: {log}: sessions learnt through different echo memories (session 0000: "
        "points, window 60 s, range 4 m; session 0001: "
    )
    assert "give --memory and its settings (--memory-window" in trained.stderr
    assert not fam.exists()
    # As it says: every session through the first's memory.
    tvl("train", log, "-o", fam, *first)
    assert read_fam(fam).method.memory == MemoryConfig("points", window_s=60.0)
