"""Which trajectories ours drives, against the decision rule fed the true velocities: for each
world of a `tvl bench generalization` directory, ours' FAMs
(fams/rooms-sN-s1-m15.0-single-default-DIGEST-CONFIG.h5, trained by its ours rows) and the
oracle velocities each avoid for 5 simulated minutes with seed 1, as the benchmark's first
trial does, and every step is counted by what the robot did: turned on the spot, or drove
which of the seven trajectories.

Where ours is slow, is it turning, or driving tight arcs where the truth would let it drive
straight? The shares are of every step of every world's run; the mean speed is over them.

    python benchmarks/arc_choices.py DIR [--worlds 1-20] [--json]
"""

from __future__ import annotations

import argparse
import json
from functools import partial
from pathlib import Path

import numpy as np
from bench_dir import CONFIGS, MINUTES, SEED, ours_avoid, ours_fam, seeds, traced, world_path

from tvl_cli.agent.true_velocities import behave_with_true_velocities
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.sim.worldmap import load_world

ORACLE = "oracle-velocities"
TURNING = "turning"  # a step on which no trajectory was driven: turning to face a view


def world_steps(bench: Path, seed: int) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each row's steps in the world of rooms seed `seed`, ours' configurations' and the
    oracle's: (trajectory driven, -1 while turning; speed m/s) of every step."""
    world = load_world(world_path(bench, seed))
    runs = {c: ours_avoid(world, *ours_fam(bench, seed, c)) for c in CONFIGS}
    runs[ORACLE] = traced(
        partial(
            behave_with_true_velocities,
            world,
            DEFAULT.robot(),
            "avoid",
            minutes=MINUTES,
            seed=SEED,
            method=DEFAULT,
        )
    )
    return {row: (columns["trajectory"], columns["speed_mps"]) for row, columns in runs.items()}


def shares(trajectories: np.ndarray, speeds: np.ndarray, names: list[str]) -> dict[str, float]:
    """The share of steps turning and on each trajectory, and the mean speed."""
    found = {TURNING: float(np.mean(trajectories < 0))}
    found.update({name: float(np.mean(trajectories == t)) for t, name in enumerate(names)})
    found["mean_speed_mps"] = float(np.mean(speeds))
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bench", type=Path, help="a tvl bench generalization --out directory")
    parser.add_argument("--worlds", default="1-20", help="rooms seeds A-B of its worlds")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    names = [t.name for t in DEFAULT_ROBOT.trajectories]
    rows = (*CONFIGS, ORACLE)
    collected: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {row: [] for row in rows}
    for seed in seeds(args.worlds):
        for row, steps in world_steps(args.bench, seed).items():
            collected[row].append(steps)
    figures = {
        row: shares(
            np.concatenate([t for t, _ in found]), np.concatenate([s for _, s in found]), names
        )
        for row, found in collected.items()
    }
    if args.json:
        print(json.dumps(figures, indent=1))
        return
    print(f"avoid, worlds {args.worlds}, seed {SEED}, {MINUTES:g} minutes each; shares of steps")
    columns = [TURNING, *names]
    print("| row | " + " | ".join(columns) + " | mean m/s |")
    print("| --- |" + " --- |" * (len(columns) + 1))
    for row, found in figures.items():
        cells = " | ".join(f"{found[c]:.0%}" for c in columns)
        print(f"| {row} | {cells} | {found['mean_speed_mps']:.2f} |")


if __name__ == "__main__":
    main()
