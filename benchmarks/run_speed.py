"""Run speed: simulated seconds per second of whole `tvl run` processes in the lab.

Trains a single and a multi FAM from the example log logs/lab-s1.h5 (15 simulated minutes
of learning in the lab, not timed); then times `tvl run --behaviour avoid` of 30 simulated
minutes in the lab with each, R times, and takes the medians. The real-time factor is
simulated seconds per CPU second of the whole process (start-up included), the wall-clock
one printed beside it, with the CPU microseconds a control step. With --against DIR, that
checkout's tvl runs the same commands in turn with this one and each figure gets the
paired ratio of their CPU seconds. `--memory KIND` trains the FAMs to read through that echo
memory (`tvl train --memory`; the example log was learnt through none, so without it the
FAMs remember nothing).

    python benchmarks/run_speed.py [--minutes 30] [--repeats 3] [--memory KIND]
                                   [--against DIR] [--json]
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

from timing import (
    TARGET_REALTIME,
    TIMED_CONFIGS,
    TVL,
    add_against_option,
    paired_commands,
    realtime_figures,
    realtime_line,
    run_process,
    tvl_in,
)

ROOT = Path(__file__).resolve().parent.parent
LAB = ROOT / "worlds" / "lab.txt"
EXAMPLE_LOG = ROOT / "logs" / "lab-s1.h5"
CONTROL_PERIOD_S = 0.1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=30.0, help="simulated minutes a run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; medians count")
    parser.add_argument("--memory", help="the echo memory the FAMs read through")
    add_against_option(parser)
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    theirs_tvl = tvl_in(args.against) if args.against else None
    sim_s = args.minutes * 60.0
    steps = sim_s / CONTROL_PERIOD_S
    figures: dict[str, dict[str, float | None]] = {}
    with tempfile.TemporaryDirectory() as name:
        directory = Path(name)
        for config in TIMED_CONFIGS:
            fam = directory / f"{config}.h5"
            remembering = ["--memory", args.memory] if args.memory else []
            run_process([TVL, "train", EXAMPLE_LOG, "-o", fam, "--config", config, *remembering])

            def run(tvl: str, fam: Path = fam) -> list[str | Path]:
                return [tvl, "run", fam, LAB, "--behaviour", "avoid", "--minutes", args.minutes]

            ours, theirs, ratio = paired_commands(run, theirs_tvl, args.repeats)
            figures[config] = {
                **realtime_figures(sim_s, ours, theirs, ratio),
                "us_per_step_cpu": ours.cpu_s / steps * 1e6,
            }
    if args.json:
        print(json.dumps({"minutes": args.minutes, "memory": args.memory, **figures}))
        return
    remembering = f", --memory {args.memory}" if args.memory else ""
    print(
        f"tvl run in the lab, {args.minutes:g} simulated minutes{remembering}, whole process, "
        f"median of {args.repeats} (real time: simulated s per CPU s)"
    )
    for config, f in figures.items():
        step = f", {f['us_per_step_cpu']:.0f} µs a step"
        print(realtime_line(config, f, args.against, TARGET_REALTIME, step))


if __name__ == "__main__":
    main()
