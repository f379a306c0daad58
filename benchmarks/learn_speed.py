"""Learning speed: simulated seconds per second of whole `tvl learn` processes in the lab.

Runs the real command (log writing, online FAM and all) with each configuration, R times,
and takes the medians. The real-time factor is simulated seconds per CPU second of the
whole process (start-up included), the wall-clock one printed beside it. With --against
DIR, that checkout's tvl learns the same in turn with this one and each figure gets the
paired ratio of their CPU seconds.

`--memory KIND` learns through that echo memory (`tvl learn`'s own default without it).

    python benchmarks/learn_speed.py [--minutes 30] [--repeats 3] [--memory KIND]
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
    Seconds,
    add_against_option,
    paired,
    realtime_figures,
    realtime_line,
    run_process,
    tvl_in,
)

LAB = Path(__file__).resolve().parent.parent / "worlds" / "lab.txt"


def learn(tvl: str, config: str, minutes: float, memory: str | None) -> Seconds:
    """One `tvl learn` into a new log."""
    with tempfile.TemporaryDirectory() as directory:
        log = Path(directory) / "lab.h5"
        remembering = ["--memory", memory] if memory else []
        return run_process([tvl, "learn", LAB, "--log", log, "--minutes", minutes,
                            "--config", config, *remembering])  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=30.0, help="simulated minutes")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; medians count")
    parser.add_argument("--memory", help="the echo memory learnt through (default: tvl's)")
    add_against_option(parser)
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    theirs_tvl = tvl_in(args.against) if args.against else None
    sim_s = args.minutes * 60.0
    figures: dict[str, dict[str, float | None]] = {}
    for config in TIMED_CONFIGS:
        ours, theirs, ratio = paired(
            lambda config=config: learn(TVL, config, args.minutes, args.memory),
            (lambda config=config: learn(theirs_tvl, config, args.minutes, args.memory))
            if theirs_tvl
            else None,
            args.repeats,
        )
        figures[config] = realtime_figures(sim_s, ours, theirs, ratio)
    if args.json:
        print(json.dumps({"minutes": args.minutes, "memory": args.memory, **figures}))
        return
    remembering = f"--memory {args.memory}" if args.memory else "the default memory"
    print(
        f"tvl learn in the lab, {args.minutes:g} simulated minutes, {remembering}, "
        f"whole process, median of {args.repeats} (real time: simulated s per CPU s)"
    )
    for config, f in figures.items():
        print(realtime_line(config, f, args.against, TARGET_REALTIME))


if __name__ == "__main__":
    main()
