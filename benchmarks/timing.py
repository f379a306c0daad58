"""What the benchmarks share: timing whole `tvl` processes, medians, paired ratios against a
baseline timed in the same run, and figures printed beside their targets.

A process's CPU seconds (user + system, the operating system's own accounting) count the
work it did whatever else the machine was running; its wall seconds include waiting for a
shared processor. Targets are judged on CPU seconds and both are printed.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

# The `tvl` installed beside the interpreter running the benchmark.
TVL = str(Path(sys.executable).with_name("tvl"))
# The default pipeline's speed target, for `tvl run` and `tvl learn` with the single and the
# multi FAM alike: simulated seconds per CPU second of the whole process.
TARGET_REALTIME = 1000.0
# The FAM configurations the speed benchmarks time.
TIMED_CONFIGS = ("single", "multi")


@dataclass(frozen=True, slots=True)
class Seconds:
    """How long one whole process took."""

    wall_s: float
    cpu_s: float  # user + system


def run_process(argv: Sequence[str | Path], env: dict[str, str] | None = None) -> Seconds:
    """Run a command to its end (it must succeed) and time it."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(
        [str(a) for a in argv],
        check=True,
        capture_output=True,
        env=None if env is None else {**os.environ, **env},
        timeout=3600,
    )
    wall_s = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_s = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return Seconds(wall_s, cpu_s)


def median_seconds(times: Sequence[Seconds]) -> Seconds:
    return Seconds(
        statistics.median(t.wall_s for t in times), statistics.median(t.cpu_s for t in times)
    )


def paired(
    ours: Callable[[], Seconds], theirs: Callable[[], Seconds] | None, repeats: int
) -> tuple[Seconds, Seconds | None, float | None]:
    """Medians of `ours` and `theirs` run in turn (ours, theirs, ours, ...) and the median of
    the pairs' CPU ratios ours / theirs: pairing keeps the ratio steady while the machine's
    speed drifts. Without `theirs`, only ours."""
    mine: list[Seconds] = []
    other: list[Seconds] = []
    for _ in range(repeats):
        mine.append(ours())
        if theirs is not None:
            other.append(theirs())
    if theirs is None:
        return median_seconds(mine), None, None
    ratio = statistics.median(a.cpu_s / b.cpu_s for a, b in zip(mine, other, strict=True))
    return median_seconds(mine), median_seconds(other), ratio


def paired_commands(
    argv_of: Callable[[str], Sequence[str | Path]], theirs_tvl: str | None, repeats: int
) -> tuple[Seconds, Seconds | None, float | None]:
    """`paired` for one command line, `argv_of(tvl)`, run by this checkout's tvl and, given
    one, another's."""
    return paired(
        lambda: run_process(argv_of(TVL)),
        (lambda: run_process(argv_of(theirs_tvl))) if theirs_tvl else None,
        repeats,
    )


def realtime_figures(
    sim_s: float, ours: Seconds, theirs: Seconds | None, ratio: float | None
) -> dict[str, float | None]:
    """Simulated seconds per CPU and per wall second of ours, and of theirs with the paired
    CPU ratio ours / theirs where there is a baseline: each benchmark's JSON figures."""
    return {
        "realtime_cpu": sim_s / ours.cpu_s,
        "realtime_wall": sim_s / ours.wall_s,
        "against_realtime_cpu": sim_s / theirs.cpu_s if theirs else None,
        "cpu_ratio_against": ratio,
    }


def cpu_seconds(run: Callable[[], object], repeats: int) -> float:
    """Median CPU seconds of `run`, in this process."""
    times = []
    for _ in range(repeats):
        started = time.process_time()
        run()
        times.append(time.process_time() - started)
    return statistics.median(times)


def realtime_against(
    ratio: float | None, against: Path | None, their_realtime: float | None
) -> str:
    """The note comparing a real-time factor with the baseline's, from the paired ratio of
    CPU seconds ours / theirs; empty without a baseline."""
    if ratio is None or their_realtime is None:
        return ""
    return f"{1.0 / ratio:.2f}x the speed of {against} ({their_realtime:,.0f}x), paired"


def realtime_line(
    label: str,
    figures: dict[str, float | None],
    against: Path | None,
    target_x: float | None = None,
    detail: str = "",
) -> str:
    """The printed line of one command's realtime_figures: its real-time factor by CPU, the
    wall-clock one (and any `detail`) beside its label, its target if it has one, and the
    paired note against the baseline."""
    realtime = figures["realtime_cpu"]
    assert realtime is not None
    note = realtime_against(figures["cpu_ratio_against"], against, figures["against_realtime_cpu"])
    wall = figures["realtime_wall"]
    assert wall is not None
    return figure_line(
        f"{label} (wall {wall:,.0f}x{detail})",
        f"{realtime:,.0f}x real time",
        None if target_x is None else f">= {target_x:,.0f}x",
        None if target_x is None else realtime >= target_x,
        note,
    )


def tvl_in(directory: Path) -> str:
    """The `tvl` of another checkout (its .venv) or of a virtual environment."""
    for candidate in (directory / ".venv" / "bin" / "tvl", directory / "bin" / "tvl"):
        if candidate.is_file():
            return str(candidate)
    raise SystemExit(f"{directory}: no .venv/bin/tvl or bin/tvl to time against")


def add_against_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--against",
        type=Path,
        default=None,
        metavar="DIR",
        help="another checkout (with its .venv) or virtual environment whose tvl is timed "
        "in turn with this one, for paired ratios",
    )


def figure_line(
    label: str, value: str, target: str | None, met: bool | None, note: str = ""
) -> str:
    """One printed figure: what it is, its value, its target and whether that is met, and a
    note (a paired ratio against the baseline)."""
    judged = "no target" if target is None else f"target {target}: {'met' if met else 'NOT met'}"
    return f"  {label:<44} {value:>24}   {judged:<28} {note}".rstrip()
