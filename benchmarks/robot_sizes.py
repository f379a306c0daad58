"""Robots of other sizes: does the small profile reach, in a map drawn for its size, the
competence the paper's robot reaches in the bundled worlds?

    python benchmarks/robot_sizes.py [--map ../shared/maps/nav2/tb3_sandbox.yaml]
                                     [--seeds 1-5] [--learn-minutes 15] [--workers 2]
                                     [--paper] [--json]

For each seed and each row: learn --learn-minutes simulated minutes by our method, or the
paper's with --paper (the
online FAM, single configuration, as `tvl learn --fam` writes it), then run avoid for the
competence run's 5 simulated minutes from the world's start and judge it as every benchmark
does (core.competence: at most 0.2 contacts a minute at a mean speed of at least half the
robot's fastest top speed). The rows:

- the paper's robot (yamabico) in the bundled lab and square;
- the turtlebot3 profile in the map (by default Nav2's TurtleBot3 sandbox, which the project
  keeps outside its checkout), imported as `tvl world import MAP --robot turtlebot3` does;
- the paper's robot in that map, the case the profile is for.

It prints, for each row, the runs judged competent, and the means of contacts a minute and
of speed (also as a share of the robot's top speed).
"""

from __future__ import annotations

import argparse
import json
import tempfile
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from competence import seed_list

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.explore import Learner
from tvl_cli.commands.world_import import ImportRequest, import_map
from tvl_cli.core.competence import COMPETENCE_RUN_MINUTES, is_competent
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DEFAULT_INIT_VELOCITY_MPS, SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.method import DEFAULT, PAPER, PAPER_NAME, Method
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT_NAME, ROBOT_PROFILES, TURTLEBOT3_NAME
from tvl_cli.sim.worldmap import load_world

ROOT = Path(__file__).resolve().parent.parent
SANDBOX = ROOT.parent / "shared" / "maps" / "nav2" / "tb3_sandbox.yaml"


def one_run(
    world_file: str, robot_name: str, seed: int, learn_minutes: float, method: Method
) -> dict[str, Any]:
    """Learn in the world by `method`, then judge its avoid run from the world's start."""
    world, robot = load_world(Path(world_file)), method.robot(ROBOT_PROFILES[robot_name])
    fam = Fam(SINGLE, [t.name for t in robot.trajectories], DEFAULT_INIT_VELOCITY_MPS)
    params = replace(LearnParams(), minutes=learn_minutes)
    Learner(world, robot, fam, params, method, seed).run(lambda e: None, lambda m: None)
    metrics = behave(
        world, robot, fam, "avoid", minutes=COMPETENCE_RUN_MINUTES, seed=seed, method=method
    )
    fastest = max(robot.v_max_mps)
    return {
        "seed": seed,
        "competent": is_competent(metrics, fastest),
        "contacts_per_min": metrics.contacts_per_min,
        "mean_speed_mps": metrics.mean_speed_mps,
        "speed_share": metrics.mean_speed_mps / fastest,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--map", type=Path, default=SANDBOX, help="A map_server YAML.")
    parser.add_argument("--seeds", default="1-5")
    parser.add_argument("--learn-minutes", type=float, default=15.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--paper", action="store_true", help="the paper's method, not ours")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    seeds = seed_list(args.seeds)
    method = PAPER if args.paper else DEFAULT
    with tempfile.TemporaryDirectory() as folder:
        imported = Path(folder) / f"{args.map.stem}.txt"
        robot = ROBOT_PROFILES[TURTLEBOT3_NAME]
        import_map(ImportRequest(args.map, imported, robot=robot))
        rows = [
            ("lab", DEFAULT_ROBOT_NAME, ROOT / "worlds" / "lab.txt"),
            ("square", DEFAULT_ROBOT_NAME, ROOT / "worlds" / "square.txt"),
            (args.map.stem, TURTLEBOT3_NAME, imported),
            (args.map.stem, DEFAULT_ROBOT_NAME, imported),
        ]
        with ProcessPoolExecutor(args.workers) as pool:
            futures = {
                (world, name): [
                    pool.submit(one_run, str(path), name, seed, args.learn_minutes, method)
                    for seed in seeds
                ]
                for world, name, path in rows
            }
            results = {key: [f.result() for f in runs] for key, runs in futures.items()}
    if args.json:
        print(
            json.dumps([{"world": w, "robot": r, "runs": runs} for (w, r), runs in results.items()])
        )
        return
    print(
        f"{PAPER_NAME if args.paper else 'our'} method, "
        f"{len(seeds)} seeds, {args.learn_minutes:g} simulated minutes of learning, "
        f"{COMPETENCE_RUN_MINUTES:g}-minute avoid runs\n"
    )
    print("| world | robot | competent | contacts/min | mean speed m/s | share of top speed |")
    print("| --- | --- | --- | --- | --- | --- |")
    for (world, name), runs in results.items():
        competent = sum(r["competent"] for r in runs)
        contacts = np.mean([r["contacts_per_min"] for r in runs])
        speed = np.mean([r["mean_speed_mps"] for r in runs])
        share = np.mean([r["speed_share"] for r in runs])
        print(
            f"| {world} | {name} | {competent} of {len(runs)} | {contacts:.2f} | "
            f"{speed:.2f} | {share:.0%} |"
        )


if __name__ == "__main__":
    main()
