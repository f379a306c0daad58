"""GIF speed: CPU milliseconds a frame of `tvl replay RUN --gif`, against a 20 ms target.

Trains a single FAM from the example log logs/lab-s1.h5 and runs it 2 simulated minutes in
the lab with a trace (not timed). Then times `tvl replay RUN --gif OUT --every E` (1,200
steps, every 6th a frame: 200 frames) and `tvl replay RUN` without the GIF, R times each;
the difference of their median CPU seconds, over the frames, is what a frame costs, the
process's start-up and the summary left out. With --against DIR, that checkout's tvl draws
the same GIF in turn with this one. Measured so on a 2-core machine shared with other
work: 10.0 ms a frame, where a checkout from before frames were blitted (up to commit
d2a4fe1), drawing each frame whole with matplotlib, took 98.7 ms.

    python benchmarks/gif_speed.py [--every 6] [--repeats 3] [--against DIR] [--json]
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

from timing import TVL, add_against_option, figure_line, paired, run_process, tvl_in

ROOT = Path(__file__).resolve().parent.parent
LAB = ROOT / "worlds" / "lab.txt"
EXAMPLE_LOG = ROOT / "logs" / "lab-s1.h5"
RUN_MINUTES = 2.0
STEPS = 1200  # RUN_MINUTES of 0.1 s control steps
TARGET_MS_PER_FRAME = 20.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--every", type=int, default=6, help="a frame every E steps")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; medians count")
    add_against_option(parser)
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    theirs_tvl = tvl_in(args.against) if args.against else None
    frames = -(-STEPS // args.every)
    with tempfile.TemporaryDirectory() as name:
        directory = Path(name)
        fam, trace, gif = directory / "fam.h5", directory / "run.h5", directory / "run.gif"
        run_process([TVL, "train", EXAMPLE_LOG, "-o", fam])
        run_process(
            [TVL, "run", fam, LAB, "--behaviour", "avoid", "--minutes", RUN_MINUTES, "--log", trace]
        )

        def animate(tvl: str) -> list[str | Path]:
            return [tvl, "replay", trace, "--gif", gif, "--every", args.every, "--force"]

        def ms_per_frame(tvl: str | None) -> float | None:
            if tvl is None:
                return None
            with_gif, without, _ = paired(
                lambda: run_process(animate(tvl)),
                lambda: run_process([tvl, "replay", trace]),
                args.repeats,
            )
            assert without is not None
            return (with_gif.cpu_s - without.cpu_s) / frames * 1000.0

        ours, theirs = ms_per_frame(TVL), ms_per_frame(theirs_tvl)
    assert ours is not None
    if args.json:
        print(json.dumps({"frames": frames, "ms_per_frame_cpu": ours, "against": theirs}))
        return
    note = f"{theirs / ours:.1f}x faster than {args.against} ({theirs:.1f} ms)" if theirs else ""
    print(f"tvl replay --gif, a 2-minute run in the lab, {frames} frames, CPU:")
    print(
        figure_line(
            "milliseconds a frame",
            f"{ours:.1f} ms",
            f"<= {TARGET_MS_PER_FRAME:g} ms",
            ours <= TARGET_MS_PER_FRAME,
            note,
        )
    )


if __name__ == "__main__":
    main()
