"""Run speed: simulated seconds per wall second of `tvl run` in the lab, whole process.

Learns 15 simulated minutes in worlds/lab.txt (not timed), trains a single and a multi FAM
from the log, then times one `tvl run --behaviour avoid` of 30 simulated minutes with each,
and one `tvl learn` of 30 simulated minutes with each configuration, so the behaving loop and
the learning loop are measured in the same run on the same machine. Each figure is also given
as wall microseconds per control step of the whole process (start-up included).

    python benchmarks/run_speed.py [--minutes 30] [--json]
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
CONTROL_PERIOD_S = 0.1
FAM_LEARN_MINUTES = 15.0


def timed(*args: str | Path) -> tuple[float, str]:
    """Wall seconds of one `tvl` process, and what it printed."""
    started = time.perf_counter()
    result = subprocess.run(
        [TVL, *map(str, args)], capture_output=True, text=True, check=True, timeout=3600
    )
    return time.perf_counter() - started, result.stdout


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=30.0, help="simulated minutes")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    sim_s = args.minutes * 60.0
    figures: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as name:
        directory = Path(name)
        log = directory / "lab.h5"
        timed("learn", LAB, "--log", log, "--minutes", FAM_LEARN_MINUTES)
        for config in ("single", "multi"):
            fam = directory / f"{config}.h5"
            timed("train", log, "-o", fam, "--config", config)
            run_s, _ = timed(
                "run", fam, LAB, "--behaviour", "avoid", "--minutes", args.minutes, "--json"
            )
            learn_log = directory / f"learn-{config}.h5"
            learn_s, _ = timed(
                "learn", LAB, "--log", learn_log, "--minutes", args.minutes, "--config", config
            )
            figures[f"run_{config}_realtime_factor"] = sim_s / run_s
            figures[f"learn_{config}_realtime_factor"] = sim_s / learn_s
            steps = sim_s / CONTROL_PERIOD_S
            figures[f"run_{config}_us_per_step"] = run_s / steps * 1e6
            figures[f"learn_{config}_us_per_step"] = learn_s / steps * 1e6
    if args.json:
        print(json.dumps(figures))
        return
    print(f"lab, {args.minutes:g} simulated minutes, whole process")
    for config in ("single", "multi"):
        for verb in ("run", "learn"):
            factor = figures[f"{verb}_{config}_realtime_factor"]
            per_step = figures[f"{verb}_{config}_us_per_step"]
            print(f"  tvl {verb:<5} {config:<6} {factor:6.0f}x real time, {per_step:5.0f} µs/step")


if __name__ == "__main__":
    main()
