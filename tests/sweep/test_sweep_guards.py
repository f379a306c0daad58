"""What `tvl sweep` refuses before any cell is made, each in one line: a grid over its cap
(counted, not built), a plot or measure it does not know, a scheduler that is no scheduler,
and a directory another sweep is running in."""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner

from tvl_cli.cli.main import main
from tvl_cli.sweep.runner import RESULTS

SMALL = 'world = "square"\nseed = [1, 2]\nbehaviour = "avoid"\nlearn_minutes = 0.1\n'


def sweep(*args: object) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, ["sweep", *map(str, args)])
    return done.exit_code, done.stdout, done.stderr


def refused(code: int, stderr: str, *phrases: str, status: int = 2) -> None:
    assert code == status, stderr
    assert stderr.count("\n") == 1 and stderr.startswith("tvl: error: "), stderr
    for phrase in phrases:
        assert phrase in stderr, stderr


@pytest.fixture
def grid(tmp_path: Path) -> Path:
    path = tmp_path / "grid.toml"
    path.write_text(SMALL)
    return path


@pytest.mark.parametrize("yes", [(), ("--yes",)], ids=["capped", "--yes"])
def test_a_grid_of_a_million_million_cells_is_refused_at_once(
    tmp_path: Path, yes: tuple[str, ...]
) -> None:
    # 10,000 seeds, 10,000 learning lengths and 10,000 thresholds: 10^12 cells, which built
    # one by one would take hours and terabytes, so that --yes cannot lift the refusal.
    numbers = range(1, 10_001)
    path = tmp_path / "huge.toml"
    path.write_text(
        'world = "square"\nbehaviour = "avoid"\n'
        f"seed = {list(numbers)}\n"
        f"learn_minutes = {[n / 100 for n in numbers]}\n"
        f"threshold = {[n / 10_000 for n in numbers]}\n"
    )
    start = time.perf_counter()
    code, _, stderr = sweep(path, "--out", tmp_path / "out", *yes)
    assert time.perf_counter() - start < 2.0
    refused(code, stderr, f"{path}: 1,000,000,000,000 cells, more than memory holds")
    assert "--yes" not in stderr and "split the grid" in stderr
    assert not (tmp_path / "out").exists()


def test_goal_runs_to_all_of_each_worlds_goals_are_counted_before_the_worlds_are_read(
    tmp_path: Path,
) -> None:
    # 20,000 generated worlds would take hours to make: at least one goal run each, at 10
    # seeds and 5 thresholds, is already over the cap, counted before the first is made.
    path = tmp_path / "worlds.toml"
    path.write_text(
        "world = " + str([f"rooms:{n}" for n in range(20_000)]) + "\n"
        'seed = { from = 1, to = 10, step = 1 }\nbehaviour = "goal"\ngoal = "all"\n'
        "threshold = [0.6, 0.7, 0.8, 0.9, 1.0]\n"
    )
    start = time.perf_counter()
    code, _, stderr = sweep(path, "--out", tmp_path / "out")
    assert time.perf_counter() - start < 5.0
    refused(code, stderr, f"{path}: at least 1,000,000 cells, over the cap of 10,000")
    assert not (tmp_path / "out").exists()


def test_a_lower_cap_refuses_a_small_grid(grid: Path, tmp_path: Path) -> None:
    code, _, stderr = sweep(grid, "--out", tmp_path / "out", "--max-cells", "1")
    refused(code, stderr, "2 cells, over the cap of 1")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "args, phrase",
    [
        (["--plot", "x=treshold,y=mean_speed_mps"],
         "no grid key 'treshold' (did you mean 'threshold'?)"),
        (["--plot", "x=threshold,y=speed"], "no measure 'speed' (did you mean 'mean_speed_mps'?)"),
        (["--measures", "contacts_per_min,wall_clearance"],
         "did you mean 'mean_wall_clearance_m'?"),
        (["-o", "plot.png"], "-o/--plot-out is the plot's file; give --plot too"),
        (["--plot", "x=config,y=sim_s", "-o", "plot.bmp"], ".bmp is no picture format tvl writes"),
        (["--plot", "x=config,y=sim_s", "-o", "nowhere/plot.png"],
         "directory nowhere does not exist"),
        (["--scheduler", "local:0"], "--scheduler local:0: give local, or local:N"),
        (["--scheduler", "local:two"], "--scheduler local:two: give local, or local:N"),
        (["--scheduler", "local:2", "--workers", "2"], "give --workers or --scheduler, not both"),
        (["--scheduler-timeout", "nan"], "--scheduler-timeout nan must be more than 0 and at most"),
        (["--scheduler-timeout", "inf"], "--scheduler-timeout inf must be more than 0 and at most"),
        (["--scheduler-timeout", "1e308"], "--scheduler-timeout 1e+308 must be more than 0"),
        (["--scheduler", "tcp://127.0.0.1:99999"], "port 99999 is outside 1 to 65535"),
        (["--plot", "x=config,y=sim_s", "-o", "UNWRITABLE/plot.png"], "/plot.png: cannot write"),
    ],
)  # fmt: skip
def test_a_bad_option_is_refused_before_anything_is_written(
    grid: Path, tmp_path: Path, args: list[str], phrase: str, request: pytest.FixtureRequest
) -> None:
    if "tcp://" in " ".join(args):
        pytest.importorskip("distributed")
    if "UNWRITABLE/plot.png" in args:  # a folder no file can be made in
        folder = request.getfixturevalue("unwritable_folder")
        args = [arg.replace("UNWRITABLE", str(folder)) for arg in args]
    code, _, stderr = sweep(grid, "--out", tmp_path / "out", *args)
    refused(code, stderr, phrase)
    assert not (tmp_path / "out").exists()


@pytest.fixture
def held(tmp_path: Path) -> Iterator[tuple[Path, int]]:
    """A sweep directory whose lock another process holds, as a running sweep does; the
    directory and that process's pid."""
    out = tmp_path / "out"
    out.mkdir()
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys; from pathlib import Path; from tvl_cli.io.lock import WriterLock; "
            f"WriterLock.acquire(Path({str(out / RESULTS)!r})); print('held', flush=True); "
            "sys.stdin.read()",
        ],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline() == "held\n"
        yield out, holder.pid
    finally:
        holder.communicate("")  # its stdin closed, it exits and drops the lock


def test_a_second_sweep_in_a_running_sweeps_directory_is_refused(
    grid: Path, held: tuple[Path, int]
) -> None:
    out, pid = held
    code, _, stderr = sweep(grid, "--out", out)
    refused(code, stderr, f"locked by another tvl sweep in this directory (pid {pid})")
    assert sorted(p.name for p in out.iterdir()) == [f"{RESULTS}.lock"]  # nothing of its own


def test_yes_lifts_the_cap_but_not_the_lock(grid: Path, held: tuple[Path, int]) -> None:
    out, pid = held
    code, _, stderr = sweep(grid, "--out", out, "--max-cells", "1", "--yes")
    refused(code, stderr, f"(pid {pid})")


@pytest.mark.parametrize(
    "text, phrase",
    [
        (SMALL.replace("learn_minutes = 0.1", "learn_minutes = 1e-9"),
         "learn_minutes 1e-09 is shorter than one control step"),
        (SMALL + "threshold = " + "[" * 100_000 + "]" * 100_000 + "\n",
         ":5: nested too deeply (more than 32"),
        (SMALL + "threshold" + ".a" * 100_000 + " = 1\n", ":5: nested too deeply (more than 32"),
    ],
    ids=["learning shorter than a step", "a threshold list 100,000 deep", "a key 100,000 deep"],
)  # fmt: skip
def test_a_grid_that_cannot_be_is_refused_naming_it_and_the_key(
    tmp_path: Path, text: str, phrase: str
) -> None:
    path = tmp_path / "grid.toml"
    path.write_text(text)
    code, _, stderr = sweep(path, "--out", tmp_path / "out")
    refused(code, stderr, f"{path}", phrase)
    assert not (tmp_path / "out").exists()


@pytest.mark.slow  # a worker process learns
def test_learning_too_short_for_an_episode_is_named_by_its_grid_key(tmp_path: Path) -> None:
    # Three simulated seconds finish no episode: nothing to train, said of the grid's key,
    # and no sweep directory left behind with a log that could not be trained.
    path = tmp_path / "grid.toml"
    path.write_text(SMALL.replace("learn_minutes = 0.1", "learn_minutes = 0.05"))
    code, _, stderr = sweep(path, "--out", tmp_path / "results" / "out", "--workers", "1")
    refused(code, stderr, f"{path}: learn_minutes 0.05: learning in world 'square' (seed 1)",
            "finished no episode", "give more learn_minutes")  # fmt: skip
    assert not (tmp_path / "results").exists()


def test_a_sweep_refused_in_a_directory_that_was_there_leaves_it_as_it_was(
    grid: Path, tmp_path: Path
) -> None:
    # A directory of another study whose world of the same name differs: refused before any
    # work, and the folders the sweep began to make in it are taken back.
    out = tmp_path / "out"
    (out / "worlds").mkdir(parents=True)
    (out / "worlds" / "square.txt").write_text("another world\n")
    before = sorted(str(p.relative_to(out)) for p in out.rglob("*"))
    code, _, stderr = sweep(grid, "--out", out)
    refused(code, stderr, "another world named 'square' than the one asked for")
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == before
    assert (out / "worlds" / "square.txt").read_text() == "another world\n"
