"""Does a weaker echo memory at run time make ours faster? Ours' FAMs, trained through the
default memory, run in the same worlds with another memory at run time only (`tvl run
--memory-clearing always`, `--memory-window 10`, `--memory points`, `--memory none`), learning
and training untouched.

The slow-time autopsy puts 10 to 16 % of ours' time on the memory: the way ahead truly fast,
rated fast on the live ring, slow on the virtual ring the FAM reads. If the memory held the
robot back, remembering less while driving would make it faster; this measures whether it
does, and what it costs in contacts.

For each world of a `tvl bench generalization` directory (its worlds/ and the fams/ its ours
rows trained, fams/rooms-sN-s1-m15.0-single-default-DIGEST-CONFIG.h5), each configuration
drives avoid, wall-left, wall-right and goal (the world's goal) for 5 simulated minutes
with seed 1, as the benchmark's first trial does, once with each run-time memory; `default`
is the memory the FAMs were trained through, whose runs are the benchmark's own. Runs are
judged as the benchmark judges them (core.competence.is_competent_run).

    python benchmarks/runtime_memory.py DIR [--worlds 1-20] [--workers 2] [--json]
"""

from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from itertools import repeat
from pathlib import Path
from typing import Any

from bench_dir import CONFIGS, MINUTES, SEED, ours_fam, seeds, world_path

from tvl_cli.agent.drive_tvl import BehaviourRun, behave_together
from tvl_cli.bench.generalization_suite import BEHAVIOURS
from tvl_cli.core.competence import is_competent_run
from tvl_cli.core.memory import MemoryConfig
from tvl_cli.core.method import DEFAULT
from tvl_cli.sim.worldmap import load_world

MEMORIES: dict[str, MemoryConfig] = {
    "default": DEFAULT.memory,
    "clearing-always": replace(DEFAULT.memory, clearing="always"),
    "window-10": replace(DEFAULT.memory, window_s=10.0),
    "points": replace(DEFAULT.memory, kind="points"),
    "none": MemoryConfig(),
}


def world_runs(bench: Path, seed: int, memory: str) -> list[dict[str, Any]]:
    """Every run of the world of rooms seed `seed` with the run-time memory `memory`."""
    world = load_world(world_path(bench, seed))
    goal = world.goals[0] if world.goals else None
    method = replace(DEFAULT, memory=MEMORIES[memory])
    rows = []
    for config in CONFIGS:
        fam_file, robot = ours_fam(bench, seed, config)
        runs = [
            BehaviourRun(fam_file.fam, b, SEED, goal if b == "goal" else None) for b in BEHAVIOURS
        ]
        found = behave_together(world, robot, runs, minutes=MINUTES, method=method)
        for run, metrics in zip(runs, found, strict=True):
            rows.append(
                {
                    "config": config,
                    "behaviour": run.behaviour,
                    "competent": is_competent_run(metrics, run.behaviour),
                    "contacts_per_min": metrics.contacts_per_min,
                    "mean_speed_mps": metrics.mean_speed_mps,
                    "goal_reached": bool(metrics.goal_reached),
                }
            )
    return rows


def summary(rows: list[dict[str, Any]]) -> dict[str, dict[str, float]]:
    """Per configuration: competent runs, runs, contacts a minute, goals, avoid speed."""
    found = {}
    for config in CONFIGS:
        mine = [r for r in rows if r["config"] == config]
        avoid = [r["mean_speed_mps"] for r in mine if r["behaviour"] == "avoid"]
        found[config] = {
            "competent": sum(r["competent"] for r in mine),
            "runs": len(mine),
            "contacts_per_min": sum(r["contacts_per_min"] for r in mine) / len(mine),
            "goals": sum(r["goal_reached"] for r in mine if r["behaviour"] == "goal"),
            "avoid_mps": sum(avoid) / len(avoid),
        }
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bench", type=Path, help="a tvl bench generalization --out directory")
    parser.add_argument("--worlds", default="1-20", help="rooms seeds A-B of its worlds")
    parser.add_argument("--workers", type=int, default=2, help="local processes")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    jobs = [(seed, memory) for memory in MEMORIES for seed in seeds(args.worlds)]
    rows: dict[str, list[dict[str, Any]]] = {memory: [] for memory in MEMORIES}
    with ProcessPoolExecutor(args.workers) as pool:
        seeds_asked, memories_asked = [s for s, _ in jobs], [m for _, m in jobs]
        done = pool.map(world_runs, repeat(args.bench), seeds_asked, memories_asked)
        for (_, memory), found in zip(jobs, done, strict=True):
            rows[memory] += found
    figures = {memory: summary(found) for memory, found in rows.items()}
    if args.json:
        print(json.dumps(figures, indent=1))
        return
    print(f"worlds {args.worlds}, seed {SEED}, {MINUTES:g}-minute runs; single / multi / designed")
    print("| run-time memory | competent | contacts/min | goals | avoid m/s |")
    print("| --- | --- | --- | --- | --- |")
    for memory, by_config in figures.items():
        cells = [
            " / ".join(f"{by_config[c][key]:{form}}" for c in CONFIGS)
            for key, form in (
                ("competent", "d"),
                ("contacts_per_min", ".2f"),
                ("goals", "d"),
                ("avoid_mps", ".2f"),
            )
        ]
        runs = by_config[CONFIGS[0]]["runs"]
        print(f"| {memory} | {cells[0]} of {runs} | {' | '.join(cells[1:])} |")


if __name__ == "__main__":
    main()
