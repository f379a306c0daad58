"""DWA speed: simulated seconds per second of whole `tvl baseline dwa` processes, by the map,
by the sonar ring's last reading and by the ring through our echo memory, in a generated
rooms world (the generalization benchmark's kind, where the ring DWA through the memory is
its costliest reference row).

Times `tvl baseline dwa WORLD --sensor S [--memory patches]` of M simulated minutes R times
and takes the medians. The real-time factor is simulated seconds per CPU second of the whole process
(start-up included), the wall-clock one printed beside it. With --against DIR, that
checkout's tvl runs the same commands in turn with this one and each figure gets the paired
ratio of their CPU seconds.

    python benchmarks/dwa_speed.py [--minutes 5] [--repeats 3] [--seed 1]
                                   [--against DIR] [--json]
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

from timing import (
    TVL,
    add_against_option,
    paired_commands,
    realtime_figures,
    realtime_line,
    run_process,
    tvl_in,
)

# Each way of knowing the obstacles, by the options that choose it.
SENSINGS = {
    "--sensor map": ["--sensor", "map"],
    "--sensor ring": ["--sensor", "ring"],
    "--sensor ring --memory patches": ["--sensor", "ring", "--memory", "patches"],
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=5.0, help="simulated minutes a run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; medians count")
    parser.add_argument("--seed", type=int, default=1, help="the rooms world's seed")
    add_against_option(parser)
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    theirs_tvl = tvl_in(args.against) if args.against else None
    sim_s = args.minutes * 60.0
    figures: dict[str, dict[str, float | None]] = {}
    with tempfile.TemporaryDirectory() as name:
        world = Path(name) / "rooms.txt"
        run_process([TVL, "world", "new", "rooms", "--seed", args.seed, "-o", world])
        for sensing, options in SENSINGS.items():

            def run(tvl: str, options: list[str] = options) -> list[str | Path]:
                return [tvl, "baseline", "dwa", world, *options, "--minutes", args.minutes]

            ours, theirs, ratio = paired_commands(run, theirs_tvl, args.repeats)
            figures[sensing] = realtime_figures(sim_s, ours, theirs, ratio)
    if args.json:
        print(json.dumps({"minutes": args.minutes, "seed": args.seed, **figures}))
        return
    print(
        f"tvl baseline dwa in rooms world {args.seed}, {args.minutes:g} simulated minutes, "
        f"whole process, median of {args.repeats} (real time: simulated s per CPU s)"
    )
    for sensing, f in figures.items():
        print(realtime_line(sensing, f, args.against))


if __name__ == "__main__":
    main()
