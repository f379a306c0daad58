"""Goals through the echo memory among pillars and narrow passages: does clearing wide
patches while seeking a goal open the way, does escaping by following walls, does turning to
face a fast way toward the goal, and at what cost in contacts?

    python benchmarks/goal_openings.py [--seeds 1-2] [--workers 2] [--json]

The worlds are tuning worlds for goal seeking, outside the generalization benchmark's test
set and other than the paper's Figure 22 world: `tvl world new obstacles` at 6 x 4, 8 x 6
and 9 x 5 m and `tvl world new narrow` at 8 x 5 and 10 x 6 m, each with its own goals.

For each world and seed, through the real `tvl` process: `tvl learn` 15 simulated minutes,
by our method and by the paper's; `tvl train` the single, multi and designed FAMs from each
log; then `tvl run --behaviour goal` for 5 minutes to each of the world's goals with each
FAM. Our FAMs run as learnt (clearing toward the goal), with `--memory-clearing never`,
with `--memory-clearing goal`, with the escape by following walls besides our reflexes,
and with the goal-ward choice besides them; the paper's method keeps no memory and has no
reflex. It
prints goals reached and contacts a minute (over the runs' simulated time) by row and
configuration.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from competence import seed_list

from tvl_cli.core.method import DEFAULT, ESCAPE, GOAL_WARD, reflexes_text
from tvl_cli.sim.worldmap import load_world

WORLDS = {  # name: (kind, width m, height m)
    "obstacles-6x4": ("obstacles", 6, 4),
    "obstacles-8x6": ("obstacles", 8, 6),
    "obstacles-9x5": ("obstacles", 9, 5),
    "narrow-8x5": ("narrow", 8, 5),
    "narrow-10x6": ("narrow", 10, 6),
}
CONFIGS = ("single", "multi", "designed")
LEARN_MINUTES = "15"
RUN_MINUTES = "5"
OURS = reflexes_text(DEFAULT.reflexes)
# (row, method preset the FAMs are learnt by, what `tvl run` is given beyond the FAM's method)
ROWS = (
    ("ours, clearing never", "default", ("--memory-clearing", "never")),
    ("ours, clearing goal", "default", ("--memory-clearing", "goal")),
    ("ours, clearing toward the goal (default)", "default", ()),
    ("ours, escape by following walls", "default", ("--reflex", f"{OURS},{ESCAPE}")),
    ("ours, goal-ward choice", "default", ("--reflex", f"{OURS},{GOAL_WARD}")),
    ("paper's method", "paper", ()),
)
TVL = str(Path(sys.executable).with_name("tvl"))


def tvl(*args: object) -> str:
    done = subprocess.run([TVL, *map(str, args)], capture_output=True, text=True, check=True)
    return done.stdout


def learn_and_train(job: tuple[Path, str, int, str]) -> None:
    work, world, seed, method = job
    log = work / f"{world}-{method}-s{seed}.h5"
    tvl("learn", work / f"{world}.txt", "--method", method, "--minutes", LEARN_MINUTES,
        "--seed", seed, "--log", log)  # fmt: skip
    for config in CONFIGS:
        # The method named again: a command's own choices (train's labels, run's reflexes)
        # are ours unless given, whatever its input was learnt by.
        tvl("train", log, "--config", config, "--method", method,
            "-o", work / f"{log.stem}-{config}.h5")  # fmt: skip


def run(job: tuple[Path, str, int, str, tuple[float, float], str, str]) -> dict:
    work, world, seed, config, goal, method, name = job
    fam = work / f"{world}-{method}-s{seed}-{config}.h5"
    extra = next(flags for row, _, flags in ROWS if row == name)
    out = tvl("run", fam, work / f"{world}.txt", "--behaviour", "goal", "--goal",
              f"{goal[0]:g},{goal[1]:g}", "--minutes", RUN_MINUTES, "--seed", seed, "--csv",
              "--method", method, *extra)  # fmt: skip
    row = list(csv.DictReader(io.StringIO(out)))[-1]
    return {
        "world": world,
        "seed": seed,
        "config": config,
        "row": name,
        "reached": row["goal_reached"] == "true",
        "contacts": int(row["contacts"]),
        "sim_s": float(row["sim_s"]),
    }


def table(runs: list[dict]) -> str:
    lines = [
        "| method | " + " | ".join(CONFIGS) + " | all | contacts/min |",
        "| --- |" + " --- |" * (len(CONFIGS) + 2),
    ]
    for name, _, _ in ROWS:
        mine = [r for r in runs if r["row"] == name]
        cells = []
        for config in (*CONFIGS, None):
            those = [r for r in mine if config is None or r["config"] == config]
            cells.append(f"{sum(r['reached'] for r in those)} of {len(those)}")
        minutes = sum(r["sim_s"] for r in mine) / 60
        rate = sum(r["contacts"] for r in mine) / minutes if minutes else 0.0
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {rate:.3f} |")
    return "\n".join(lines)


def by_world(runs: list[dict]) -> str:
    lines = [
        "| world | " + " | ".join(r[0] for r in ROWS) + " |",
        "| --- |" + " --- |" * len(ROWS),
    ]
    for world in WORLDS:
        cells = []
        for name, _, _ in ROWS:
            those = [r for r in runs if r["world"] == world and r["row"] == name]
            cells.append(f"{sum(r['reached'] for r in those)} of {len(those)}")
        lines.append(f"| {world} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=seed_list, default=[1, 2])
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(args.workers) as pool:
        work = Path(tmp)
        goals = {}
        for name, (kind, width, height) in WORLDS.items():
            tvl("world", "new", kind, "--size", width, height, "-o", work / f"{name}.txt")
            goals[name] = load_world(work / f"{name}.txt").goals
        methods = sorted({method for _, method, _ in ROWS})
        learnt = [(work, w, s, m) for w in WORLDS for s in args.seeds for m in methods]
        list(pool.map(learn_and_train, learnt))
        jobs = [
            (work, w, s, c, goal, method, name)
            for w in WORLDS
            for s in args.seeds
            for c in CONFIGS
            for goal in goals[w]
            for name, method, _ in ROWS
        ]
        runs = list(pool.map(run, jobs))
    if args.json:
        print(json.dumps(runs, indent=1))
        return
    print(f"goals reached, {len(args.seeds)} seeds x {len(CONFIGS)} configurations x each goal")
    print(table(runs))
    print()
    print(by_world(runs))


if __name__ == "__main__":
    main()
