"""Scale: memory and time against the number of wall segments and against the run length.

    python benchmarks/scale.py [--segments 10,100,1000,10000] [--minutes 10,100,1000] [--json]

Segments: a 100 x 100 m hall holding N thin `wall:` lines on a lattice; for each N it
times reading the world and building the simulator (with the peak Python memory of that,
by tracemalloc) and one control step with a sonar reading. Run length: whole `tvl run`
processes in the square of M simulated minutes, without and with a trace (`--log`), giving
wall seconds and the peak resident memory of each process. Each series also prints its
growth exponent between the first and last point (1 is linear).
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from tvl_cli.core.drive_command import Command
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import parse_world

ROOT = Path(__file__).resolve().parent.parent
TVL = str(Path(sys.executable).with_name("tvl"))
HALL_CELLS = 400  # 100 m at 0.25 m a cell
STEPS = 50  # control steps timed per world


def hall_with_walls(count: int) -> str:
    """A 100 x 100 m walled hall with `count` thin 0.5 m walls on a lattice, start at a corner."""
    side = math.ceil(math.sqrt(count))
    spacing = 96.0 / side
    walls = [
        f"wall: {2 + i * spacing:.3f} {2 + j * spacing:.3f} {2.5 + i * spacing:.3f} "
        f"{2 + j * spacing:.3f}"
        for i in range(side)
        for j in range(side)
    ][:count]
    grid = ["#" * HALL_CELLS] + ["#" + "." * (HALL_CELLS - 2) + "#"] * (HALL_CELLS - 2)
    grid = [*grid, "#" * HALL_CELLS]
    grid[-3] = "#." + ">" + "." * (HALL_CELLS - 4) + "#"
    return "\n".join(["cell: 0.25", *walls, *grid, ""])


def segment_figures(count: int) -> dict[str, float]:
    text = hall_with_walls(count)
    started = time.perf_counter()
    world = parse_world(text, f"hall-{count}")
    sim = Simulator(world, RobotConfig(), np.random.default_rng(1))
    build_s = time.perf_counter() - started
    tracemalloc.start()  # a second build, traced: tracing slows it down
    Simulator(parse_world(text, f"hall-{count}"), RobotConfig(), np.random.default_rng(1))
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    started = time.perf_counter()
    for _ in range(STEPS):
        sim.read_sonar()
        sim.step(Command(0.0, 0.5))
    step_s = (time.perf_counter() - started) / STEPS
    return {
        "segments": len(world.segments),
        "build_s": build_s,
        "build_peak_mib": peak / 2**20,
        "step_ms": step_s * 1e3,
    }


# Runs its arguments as a command and prints that command's peak resident memory in KiB.
_PEAK_OF_CHILD = (
    "import resource, subprocess, sys; "
    "code = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL).returncode; "
    "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); sys.exit(code)"
)


def run_figures(minutes: float, fam: Path, directory: Path) -> dict[str, float]:
    figures: dict[str, float] = {"minutes": minutes}
    for traced in (False, True):
        trace = ["--log", str(directory / f"run-{minutes:g}.h5"), "--force"] if traced else []
        args = [TVL, "run", str(fam), str(ROOT / "worlds" / "square.txt")]
        args += ["--behaviour", "avoid", "--minutes", f"{minutes:g}", "--json", *trace]
        started = time.perf_counter()
        # Started from a small interpreter: a child forked from this one would count this
        # process's memory as its own until it execs.
        done = subprocess.run(
            [sys.executable, "-S", "-c", _PEAK_OF_CHILD, *args], capture_output=True, text=True
        )
        if done.returncode:
            raise SystemExit(f"tvl run failed: {' '.join(args)}\n{done.stderr}")
        key = "traced" if traced else "plain"
        figures[f"{key}_s"] = time.perf_counter() - started
        figures[f"{key}_peak_mib"] = int(done.stdout.split()[-1]) / 1024  # Linux reports KiB
    return figures


def exponent(points: list[dict[str, float]], x: str, y: str) -> float:
    """The slope of log y against log x between the first and the last point."""
    first, last = points[0], points[-1]
    return math.log(last[y] / first[y]) / math.log(last[x] / first[x])


def numbers(text: str) -> list[float]:
    return [float(part) for part in text.split(",")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--segments", type=numbers, default=numbers("10,100,1000,10000"))
    parser.add_argument("--minutes", type=numbers, default=numbers("10,100,1000"))
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    walls = [segment_figures(int(n)) for n in args.segments]
    with tempfile.TemporaryDirectory() as name:
        directory = Path(name)
        log, fam = directory / "square.h5", directory / "fam.h5"
        square = str(ROOT / "worlds" / "square.txt")
        subprocess.run([TVL, "learn", square, "--log", str(log)], check=True, capture_output=True)
        subprocess.run([TVL, "train", str(log), "-o", str(fam)], check=True, capture_output=True)
        runs = [run_figures(m, fam, directory) for m in args.minutes]
    growth = {
        "build_s_per_segment": exponent(walls, "segments", "build_s"),
        "build_memory_per_segment": exponent(walls, "segments", "build_peak_mib"),
        "step_per_segment": exponent(walls, "segments", "step_ms"),
        "run_time_per_minute": exponent(runs, "minutes", "plain_s"),
        "traced_run_time_per_minute": exponent(runs, "minutes", "traced_s"),
    }
    if args.json:
        print(json.dumps({"segments": walls, "runs": runs, "growth": growth}, indent=2))
        return
    print("segments  build s  build peak MiB  step ms")
    for w in walls:
        print(
            f"{w['segments']:8.0f}  {w['build_s']:7.3f}  {w['build_peak_mib']:14.1f}"
            f"  {w['step_ms']:7.2f}"
        )
    print("\nminutes  run s  peak MiB  with --log: s  peak MiB")
    for r in runs:
        print(
            f"{r['minutes']:7g}  {r['plain_s']:5.1f}  {r['plain_peak_mib']:8.1f}"
            f"  {r['traced_s']:13.1f}  {r['traced_peak_mib']:8.1f}"
        )
    exponents = ", ".join(f"{k} {v:.2f}" for k, v in growth.items())
    print(f"\ngrowth exponents (1 = linear): {exponents}")


if __name__ == "__main__":
    main()
