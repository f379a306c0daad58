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
from tvl_cli.sweep.runner import DEFAULT_MAX_CELLS, RESULTS

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


def test_a_grid_of_a_million_million_cells_is_refused_at_once(tmp_path: Path) -> None:
    # 10,000 seeds, 10,000 learning lengths and 10,000 thresholds: 10^12 cells, which built
    # one by one would take hours and terabytes.
    numbers = range(1, 10_001)
    path = tmp_path / "huge.toml"
    path.write_text(
        'world = "square"\nbehaviour = "avoid"\n'
        f"seed = {list(numbers)}\n"
        f"learn_minutes = {[n / 100 for n in numbers]}\n"
        f"threshold = {[n / 10_000 for n in numbers]}\n"
    )
    start = time.perf_counter()
    code, _, stderr = sweep(path, "--out", tmp_path / "out")
    assert time.perf_counter() - start < 2.0
    refused(
        code,
        stderr,
        f"{path}: 1,000,000,000,000 cells, over the cap of {DEFAULT_MAX_CELLS:,}",
        "give --max-cells 1000000000000 or --yes",
    )
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
    ],
)  # fmt: skip
def test_a_bad_option_is_refused_before_anything_is_written(
    grid: Path, tmp_path: Path, args: list[str], phrase: str
) -> None:
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
