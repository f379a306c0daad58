"""How far the labels a log gives are from those of the true map: the paper's (the driven
trajectory's, from its bump) and the heard ones (every trajectory's, from the echoes heard
around each point; core.heard).

    python benchmarks/label_accuracy.py [--set tuning|test] [--worlds A-B] [--minutes 15]
                                        [--window S ...] [--workers 2] [--json]

For each generated rooms world and seed 1: learn --minutes by our method, then label every
recorded point's trajectories from the log alone, and again from the true map and true pose
(sim.true_arcs, the oracle labels). Printed per rule: how many labels it gives per point,
their mean error against the truth (m/s), and at threshold 0.85 the share of labels that
call a slow way fast (dangerous) and a fast way slow (timid), over the labels the rule gives.
`--window S` (repeatable) labels with other windows of echoes before and after each point.
"""

from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from tvl_cli.agent.explore import Learner
from tvl_cli.bench.generalization_suite import WORLD_SETS
from tvl_cli.core.arcs import collision_clearance_m
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.heard import DEFAULT_WINDOW_S, heard_episodes
from tvl_cli.core.labels import label_reach_m, velocity_labels
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.method import DEFAULT
from tvl_cli.sim.true_arcs import TrueArcs
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import parse_world


def world_labels(job: tuple[int, float, tuple[float, ...]]) -> dict[str, Any]:
    world_seed, minutes, windows = job
    world = parse_world(generate_world("rooms", None, None, world_seed), f"rooms-s{world_seed}")
    robot, method = DEFAULT.robot(), DEFAULT
    episodes = []
    learner = Learner(
        world, robot, Fam(SINGLE, [t.name for t in robot.trajectories]),
        LearnParams(minutes=minutes), method, seed=1,
    )  # fmt: skip
    learner.run(episodes.append, lambda minute: None)
    v_max = np.array(robot.v_max_mps)
    decel, margin = method.decel_mps2, method.margin_m
    reach = label_reach_m(max(v_max), decel, margin)  # both the truth's and the heard labels'
    poses = np.concatenate([e.pose for e in episodes])
    arcs = TrueArcs(world, robot, collision_clearance_m(robot))
    truth = arcs.velocities_mps(arcs.distances_m(poses, reach), decel, margin)
    driven = np.concatenate([np.full(e.exemplar_count, e.trajectory) for e in episodes])
    rows = np.arange(len(poses))
    bump = np.full(truth.shape, np.nan)
    bump[rows, driven] = velocity_labels(
        np.concatenate([e.distances_m() for e in episodes]), v_max[driven], decel, margin
    )
    found = {"exemplars": len(poses), "bump": bump}
    for window in windows:
        heard = heard_episodes(episodes, robot, ended=True, reach_m=reach, window_s=window)
        distances = np.concatenate([h.distances_m for h in heard])
        found[f"heard {window:g} s"] = velocity_labels(distances, v_max, decel, margin)
    return {"truth": truth, **found}


def scores(labels: np.ndarray, truth: np.ndarray, v_max: np.ndarray) -> dict[str, float]:
    given = ~np.isnan(labels)
    fast_label = labels >= DEFAULT_THRESHOLD * v_max
    fast_truth = truth >= DEFAULT_THRESHOLD * v_max
    return {
        "labels_per_point": float(given.sum() / len(labels)),
        "mean_error_mps": float(np.abs(labels - truth)[given].mean()),
        "dangerous": float((fast_label & ~fast_truth)[given].mean()),
        "timid": float((~fast_label & fast_truth)[given].mean()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--set", choices=WORLD_SETS, default="tuning")
    parser.add_argument("--worlds", default="1-5", help="A-B: the A-th to B-th of the set")
    parser.add_argument("--minutes", type=float, default=15.0)
    parser.add_argument("--window", type=float, action="append")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    first, last = (int(n) for n in args.worlds.split("-"))
    seeds = list(WORLD_SETS[args.set])[first - 1 : last]
    windows = tuple(args.window or [DEFAULT_WINDOW_S])
    with ProcessPoolExecutor(args.workers) as pool:
        found = list(pool.map(world_labels, [(s, args.minutes, windows) for s in seeds]))
    v_max = np.array(DEFAULT.robot().v_max_mps)
    truth = np.concatenate([f["truth"] for f in found])
    rules = [k for k in found[0] if k not in ("truth", "exemplars")]
    table = {rule: scores(np.concatenate([f[rule] for f in found]), truth, v_max) for rule in rules}
    if args.json:
        print(json.dumps({"worlds": seeds, "exemplars": len(truth), "rules": table}, indent=1))
        return
    print(f"rooms worlds {seeds[0]}-{seeds[-1]}, {len(truth):,} recorded points")
    print(f"{'labels':<16}{'per point':>10}{'error m/s':>11}{'dangerous':>11}{'timid':>8}")
    for rule, s in table.items():
        print(
            f"{rule:<16}{s['labels_per_point']:>10.2f}{s['mean_error_mps']:>11.3f}"
            f"{s['dangerous']:>11.1%}{s['timid']:>8.1%}"
        )


if __name__ == "__main__":
    main()
