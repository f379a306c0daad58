"""Learning speed: simulated seconds per wall second of `tvl learn` in the lab.

Runs the real command (log writing, online FAM, progress and all) once per configuration
and divides the simulated time by the wall time of the whole process.

    python benchmarks/learn_speed.py [--minutes 15] [--json]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LAB = Path(__file__).resolve().parent.parent / "worlds" / "lab.txt"
TVL = str(Path(sys.executable).with_name("tvl"))


def realtime_factor(config: str, minutes: float, directory: Path) -> float:
    """Simulated seconds per wall second of one `tvl learn` process."""
    log = directory / f"{config}.h5"
    started = time.perf_counter()
    result = subprocess.run(
        [TVL, "learn", str(LAB), "--log", str(log), "--minutes", str(minutes),
         "--config", config, "--json"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    wall_s = time.perf_counter() - started
    return json.loads(result.stdout)["sim_minutes"] * 60.0 / wall_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=15.0, help="simulated minutes")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as directory:
        figures = {
            f"{config}_realtime_factor": realtime_factor(config, args.minutes, Path(directory))
            for config in ("single", "multi")
        }
    if args.json:
        print(json.dumps(figures))
        return
    for name, value in figures.items():
        config = name.split("_")[0]
        seconds = args.minutes * 60 / value
        print(
            f"{config:>6}: {value:6.0f}x real time "
            f"({args.minutes:g} simulated min in {seconds:.1f} s wall, lab)"
        )


if __name__ == "__main__":
    main()
