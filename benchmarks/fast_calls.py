"""How often ours' FAMs call a trajectory fast or slow wrongly, trajectory by trajectory: at
every choice of an avoid run, the fast set the choice read (of the view it chose) against the
truth there (the oracle velocities, from the map and the true pose the ring was read at).

For each world of a `tvl bench generalization` directory (its worlds/ and the fams/ its ours
rows trained, fams/rooms-sN-s1-m15.0-single-default-DIGEST-CONFIG.h5, DIGEST as
sweep.layout.learning_tag names it, or with `--method FILE` those of the controller of that
method file), each configuration avoids for 5 simulated minutes with
seed 1, as the benchmark's first trial does. *Timid*: of the choices
where a trajectory was truly fast, the share it was rated slow; *dangerous*: of those where
it was truly slow, the share it was rated fast.

    python benchmarks/fast_calls.py DIR [--worlds 1-20] [--configs single,multi,designed]
                                    [--method FILE.toml] [--json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np
from bench_dir import MINUTES, SEED, ours_avoid, ours_fam, seeds, world_path

from tvl_cli.agent.true_velocities import TrueVelocities
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.method import DEFAULT, Method
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.io.methodfile import resolve_method
from tvl_cli.sim.worldmap import load_world


def world_calls(
    bench: Path, seed: int, config: str, method: Method
) -> tuple[np.ndarray, np.ndarray]:
    """(truly fast, rated fast), each (choices, T) bool, at every choice of the avoid run."""
    world = load_world(world_path(bench, seed))
    fam_file, robot = ours_fam(bench, seed, config, method)
    columns = ours_avoid(world, fam_file, robot, method)
    # The ring a choice read was read where the step before it left the robot.
    poses = columns["pose"]
    read_at = np.vstack([np.array([world.start[:3]]), poses[:-1]])
    truth = TrueVelocities(world, robot, DEFAULT)
    fast_from = DEFAULT_THRESHOLD * np.array(robot.v_max_mps)
    choices = np.flatnonzero(~np.isnan(columns["velocities"][:, 0]))
    truly = np.array(
        [
            truth.in_view(tuple(read_at[i]), int(columns["rotation"][i]) % robot.sonar.count)
            >= fast_from
            for i in choices
        ]
    ).reshape(-1, len(fast_from))
    return truly, columns["fast"][choices]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bench", type=Path, help="a tvl bench generalization --out directory")
    parser.add_argument("--worlds", default="1-20", help="rooms seeds A-B of its worlds")
    parser.add_argument("--configs", default="single,multi,designed")
    parser.add_argument("--method", default="default", help="whose FAMs: a preset or method file")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    method = resolve_method(args.method)
    names = [t.name for t in DEFAULT_ROBOT.trajectories]
    figures: dict[str, dict[str, Any]] = {}
    for config in args.configs.split(","):
        found = [world_calls(args.bench, seed, config, method) for seed in seeds(args.worlds)]
        truly = np.concatenate([t for t, _ in found])
        rated = np.concatenate([r for _, r in found])
        figures[config] = {
            "choices": len(truly),
            "timid": dict(zip(names, (truly & ~rated).sum(0) / truly.sum(0), strict=True)),
            "dangerous": dict(zip(names, (~truly & rated).sum(0) / (~truly).sum(0), strict=True)),
        }
    if args.json:
        print(json.dumps(figures, indent=1, default=float))
        return
    print(f"{args.method}'s FAMs avoid: worlds {args.worlds}, seed {SEED}, {MINUTES:g} minutes")
    print("| FAM | call | " + " | ".join(names) + " |")
    print("| --- | --- |" + " --- |" * len(names))
    for config, calls in figures.items():
        for call in ("timid", "dangerous"):
            cells = " | ".join(f"{calls[call][n]:.0%}" for n in names)
            print(f"| {config} | {call} | {cells} |")


if __name__ == "__main__":
    main()
