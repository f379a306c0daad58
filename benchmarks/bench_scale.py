"""How `tvl bench generalization` spreads over workers, and what the full suite would take.

    python benchmarks/bench_scale.py [--size tiny|quick] [--worlds N|A-B] [--json]

Runs the suite at a size into fresh directories on a Dask LocalCluster of 1 worker, then of 2
(`--scheduler local:1`, `local:2`), and prints each one's wall time, the speed-up of 2
workers against 1 (the target: near-linear, 2.0), and the CPU seconds its cells took. From the
cells' CPU seconds it projects the full suite (20 test worlds, 3 trials, every reference)
on 2 cores: the CPU seconds of a world's trial at this size, times 60 trials, over 2 cores,
against the 15-minute target. A projection, not a measurement: the full suite's worlds are
not those measured, and a quick or tiny size runs shorter (tiny) or as long (quick) as the
full size's runs.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from timing import TVL

FULL_TRIALS = 20 * 3  # the full suite's worlds times its trials
CORES = 2
TARGET_MIN = 15.0


def bench(out: Path, size: str, worlds: str | None, scheduler: str) -> tuple[float, dict]:
    command = [TVL, "bench", "generalization", "--size", size, "--out", str(out),
               "--scheduler", scheduler, "--json"]  # fmt: skip
    if worlds:
        command += ["--worlds", worlds]
    started = time.perf_counter()
    printed = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return time.perf_counter() - started, json.loads(printed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", choices=("tiny", "quick"), default="tiny")
    parser.add_argument("--worlds", default=None, help="N or A-B of the test set")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    found: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as scratch:
        for workers in (1, 2):
            wall_s, document = bench(
                Path(scratch) / f"w{workers}", args.size, args.worlds, f"local:{workers}"
            )
            found[f"workers_{workers}"] = {"wall_s": wall_s, "cpu_s": document["cpu_s"]}
            trials = len(document["inputs"]["worlds"]) * len(document["inputs"]["trials"])
    speedup = found["workers_1"]["wall_s"] / found["workers_2"]["wall_s"]
    per_trial_cpu_s = found["workers_2"]["cpu_s"] / trials
    projected_min = per_trial_cpu_s * FULL_TRIALS / CORES / 60.0
    found.update(speedup=speedup, per_trial_cpu_s=per_trial_cpu_s, projected_min=projected_min)
    if args.json:
        print(json.dumps(found, indent=1))
        return
    for workers in (1, 2):
        seen = found[f"workers_{workers}"]
        print(
            f"{workers} worker{'s' if workers > 1 else ''}: {seen['wall_s']:.0f} s wall, "
            f"{seen['cpu_s']:.0f} s of CPU in the cells"
        )
    print(f"2 workers against 1: {speedup:.2f}x (target: near 2x)")
    if args.size != "quick":
        print("(the full suite's projection needs --size quick: its runs are the full size's)")
        return
    met = "met" if projected_min <= TARGET_MIN else "not met"
    print(
        f"full suite on {CORES} cores, projected from {per_trial_cpu_s:.0f} CPU s a world's "
        f"trial at --size {args.size}: {projected_min:.0f} min (target <= {TARGET_MIN:g}: {met})"
    )


if __name__ == "__main__":
    main()
