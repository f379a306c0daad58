"""Which remembered patches make truly fast ways look slow: of the time the slow-time autopsy
puts on the echo memory (a way ahead truly fast, rated fast on the live ring, slow on what
the FAM read through the memory), the share in which the FAM rates a truly fast way fast once
the patches wider than the memory's clearing width either side (core.memory.CLEARED_ABOVE_M:
heard from beyond about 0.9 m) are left out, and the rest, which the near ones make slow.

For each world of a `tvl bench generalization` directory (its worlds/ and fams/), each FAM
configuration drives a real `tvl run --behaviour avoid --log` there; each trace's readings are
then replayed, in order and placed by its odometry, into the run's echo memory and into the
same memory keeping only the echoes heard near enough for a patch no wider than that. A step
is judged straight ahead, as the autopsy judges it (analysis.slow_time), the true velocities
from the map and the true pose.

    python benchmarks/slow_patches.py DIR [--worlds 1-10] [--configs single,multi,designed]
                                      [--minutes 5] [--json]

DIR's FAMs are those its ours rows trained:
fams/rooms-sN-s1-m15.0-single-default-DIGEST-CONFIG.h5 (DIGEST: sweep.layout.learning_tag).
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
from bench_dir import ours_fam_path, seeds, world_path
from timing import TVL, run_process

from tvl_cli.agent.perception import EchoMemory
from tvl_cli.agent.trace import before_each_step
from tvl_cli.agent.true_velocities import TrueVelocities
from tvl_cli.analysis.autopsy import FAST_DRIVE_MPS, MEMORY, slow_cause
from tvl_cli.core.memory import CLEARED_ABOVE_M
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.runfile import read_run
from tvl_cli.sim.worldmap import parse_world

THRESHOLD = 0.85  # the default, as the benchmark runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bench", type=Path, help="a tvl bench generalization --out directory")
    parser.add_argument("--worlds", default="1-10", help="rooms seeds A-B of its worlds")
    parser.add_argument("--configs", default="single,multi,designed")
    parser.add_argument("--minutes", type=float, default=5.0, help="simulated minutes a run")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    figures = {}
    with tempfile.TemporaryDirectory() as name:
        for config in args.configs.split(","):
            totals = {"slow_s": 0.0, "memory_s": 0.0, "wide_s": 0.0}
            for seed in seeds(args.worlds):
                fam = ours_fam_path(args.bench, seed, config)
                world = world_path(args.bench, seed)
                trace = Path(name) / f"{config}-{seed}.h5"
                run_process([TVL, "run", fam, world, "--behaviour", "avoid", "--minutes",
                             args.minutes, "--log", trace])  # fmt: skip
                for key, seconds in memory_time(fam, trace).items():
                    totals[key] += seconds
            figures[config] = totals
    if args.json:
        print(json.dumps({"worlds": args.worlds, "minutes": args.minutes, **figures}))
        return
    print(
        f"avoid runs of {args.minutes:g} simulated minutes in worlds {args.worlds} of "
        f"{args.bench}, threshold {THRESHOLD}: slow time on the echo memory, and the share "
        f"the patches wider than {CLEARED_ABOVE_M:g} m either side make"
    )
    for config, t in figures.items():
        wide = t["wide_s"] / t["memory_s"] if t["memory_s"] else math.nan
        print(
            f"  {config:<9} slow {t['slow_s']:7.1f} s, on the memory {t['memory_s']:7.1f} s: "
            f"wide patches {wide:.0%}, near ones {1 - wide:.0%}"
        )


def memory_time(fam_path: Path, trace_path: Path) -> dict[str, float]:
    """Simulated seconds of a run: slow (below FAST_DRIVE_MPS, no reflex acting), slow on
    the memory, and of that, fast once the wide patches are left out."""
    made = read_fam(fam_path)
    fam, robot, method = made.fam, made.robot_config, made.method
    trace = read_run(trace_path)
    world = parse_world(trace.world_text, trace.world_name)
    a = trace.arrays
    memory = method.memory
    # A patch is as wide as the beam at its range, so keeping the echoes heard no farther than
    # this keeps exactly the patches no wider than CLEARED_ABOVE_M either side.
    near_m = CLEARED_ABOVE_M / math.tan(math.radians(robot.sonar.cone_deg) / 2.0)
    remembered = EchoMemory(memory, robot)
    near = EchoMemory(replace(memory, range_m=min(memory.range_m, near_m)), robot)
    truth = TrueVelocities(world, robot, method)
    fast_from = THRESHOLD * np.array(robot.v_max_mps)  # (T,) m/s
    live = mm_to_ring(a["ring_mm"])  # (N, 16) metres
    read = a["ring_mm"].any(axis=1)
    odometry_before = before_each_step(a["odometry"], world.start)
    pose_before = before_each_step(a["pose"], world.start)
    slow = (a["reflex"] < 0) & (a["speed_mps"] < FAST_DRIVE_MPS)
    dt = robot.control_period_s
    seconds = {"slow_s": 0.0, "memory_s": 0.0, "wide_s": 0.0}
    on_memory = wide = False
    for step in range(len(live)):
        if read[step]:
            odometry = tuple(odometry_before[step])
            virtual = remembered.sense(step, odometry, live[step])
            without_wide = near.sense(step, odometry, live[step])
            if slow[step]:
                # A step that read no ring carries out the last reading's choice: its cause.
                truly_fast = truth.in_view(tuple(pose_before[step]), 0) >= fast_from
                rated_fast = fam.velocities(virtual) >= fast_from
                live_fast = fam.velocities(live[step]) >= fast_from
                on_memory = slow_cause(truly_fast, rated_fast, live_fast) == MEMORY
                wide = on_memory and bool(
                    (truly_fast & (fam.velocities(without_wide) >= fast_from)).any()
                )
        if slow[step]:
            seconds["slow_s"] += dt
            seconds["memory_s"] += dt * on_memory
            seconds["wide_s"] += dt * wide
    return seconds


if __name__ == "__main__":
    main()
