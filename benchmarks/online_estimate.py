"""How good the collision points of learning while behaving are (`tvl run --learn`).

    python benchmarks/online_estimate.py [--worlds 1001-1005] [--trials 2] [--minutes 5]
                                         [--before 2] [--after 3] [--workers 2] [--json]

For each generated rooms world (`tvl world new rooms --seed N`, the generalization test
seeds) and trial: learn 15 simulated minutes by exploring, then avoid for --minutes with
every reflex while learning (agent.online, its estimates made from the sonar returns read
from --before seconds before a stretch ended to --after seconds after). Each
stretch the run learnt is then set against the truth: the collision point of its
trajectory, from where the stretch started, on the world's true geometry. Its labels are
compared exemplar by exemplar with the labels the true point gives. Distances are capped
where labels stop changing (margin + v_max² / 2a: 1.95 m for T0), so a far estimate of a
far wall is no error.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from typing import Any

import numpy as np
from competence import seed_list

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.explore import Learner
from tvl_cli.agent.online import (
    ECHO_AFTER_S,
    ECHO_BEFORE_S,
    ENDINGS,
    OnlineLearner,
)
from tvl_cli.core.arcs import first_contact_m
from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.labels import velocity_labels
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import TrainParams, episode_labels, train_params
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import WorldMap, parse_world

LEARN_MINUTES = 15.0
WALL_SPACING_M = 0.01  # the true geometry as points this close: far finer than the ring's noise
TOO_FAR_MPS = 0.1  # a label this much too fast (or slow) counts as wrong


def wall_points(world: WorldMap) -> np.ndarray:
    """(K, 2) metres: the world's walls, pillars and ring walls as points WALL_SPACING_M apart."""
    parts = []
    for x1, y1, x2, y2 in world.segments:
        n = max(2, math.ceil(math.hypot(x2 - x1, y2 - y1) / WALL_SPACING_M) + 1)
        t = np.linspace(0.0, 1.0, n)[:, None]
        parts.append(np.array([x1, y1]) * (1 - t) + np.array([x2, y2]) * t)
    for x, y, r in (*world.discs, *world.rings):
        angle = np.linspace(0.0, 2 * math.pi, max(8, math.ceil(2 * math.pi * r / WALL_SPACING_M)))
        parts.append(np.stack([x + r * np.cos(angle), y + r * np.sin(angle)], axis=1))
    return np.concatenate(parts)


def horizon_m(robot: RobotConfig, trajectory: int, params: TrainParams) -> float:
    """Beyond this distance to the collision point every label is the trajectory's maximum."""
    v_max = robot.trajectories[trajectory].v_max_mps
    return params.margin_m + v_max**2 / (2 * params.decel_mps2)


def trial(job: tuple[int, int, float, float, float]) -> dict[str, Any]:
    world_seed, seed, minutes, before_s, after_s = job
    # Our method on the live ring, as this estimate was first measured.
    robot, method = RobotConfig(), replace(DEFAULT, memory=NO_MEMORY)
    params = train_params(method)
    world = parse_world(generate_world("rooms", None, None, world_seed), f"rooms-s{world_seed}")
    fam = Fam(SINGLE, [t.name for t in robot.trajectories])
    learner = Learner(world, robot, fam, LearnParams(minutes=LEARN_MINUTES), method, seed)
    learner.run(lambda _episode: None, lambda _minute: None)
    episodes: list[Episode] = []
    online = OnlineLearner(fam, robot, params, world.start, episodes.append, before_s, after_s)
    metrics = behave(
        world, robot, fam, "avoid", minutes=minutes, seed=seed, on_step=online, method=method
    )
    online.finish(metrics.sim_s)
    walls = wall_points(world)
    distance_errors, label_errors = [], []
    for episode in episodes:
        if episode.bumped:
            continue  # a bump is the truth itself
        curvature = robot.trajectories[episode.trajectory].curvature_per_m
        start = tuple(episode.pose[0])
        true_end = episode.arc_m[0] + first_contact_m(start, curvature, walls, robot.radius_m)
        cap = horizon_m(robot, episode.trajectory, params)
        estimated = episode.end_arc_m if episode.collided else math.inf
        to_go = episode.arc_m[0]
        distance_errors.append(min(estimated - to_go, cap) - min(true_end - to_go, cap))
        v_max = robot.trajectories[episode.trajectory].v_max_mps
        truth = velocity_labels(true_end - episode.arc_m, v_max, params.decel_mps2, params.margin_m)
        label_errors.append(episode_labels(episode, robot, params) - truth)
    labels = np.concatenate(label_errors) if label_errors else np.zeros(0)
    return {
        "world_seed": world_seed,
        "seed": seed,
        "endings": online.summary().endings,
        "stretches": len(distance_errors),
        "distance_errors_m": distance_errors,
        "label_errors_mps": labels.tolist(),
    }


def summarise(trials: list[dict[str, Any]]) -> dict[str, Any]:
    distance = np.array([e for t in trials for e in t["distance_errors_m"]])
    labels = np.array([e for t in trials for e in t["label_errors_mps"]])
    endings = {how: sum(t["endings"][how] for t in trials) for how in ENDINGS}
    return {
        "stretches": len(distance),
        "endings": endings,
        "mean_abs_distance_error_m": float(np.abs(distance).mean()),
        "distance_too_far_03m": float((distance > 0.3).mean()),
        "distance_too_near_03m": float((distance < -0.3).mean()),
        "exemplars": len(labels),
        "mean_abs_label_error_mps": float(np.abs(labels).mean()),
        "labels_too_fast": float((labels > TOO_FAR_MPS).mean()),
        "labels_too_slow": float((labels < -TOO_FAR_MPS).mean()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", default="1001-1005", help="rooms seeds, e.g. 1001-1005")
    parser.add_argument("--trials", type=int, default=2)
    parser.add_argument("--minutes", type=float, default=5.0, help="of each avoid run")
    parser.add_argument("--before", type=float, default=ECHO_BEFORE_S, help="seconds")
    parser.add_argument("--after", type=float, default=ECHO_AFTER_S, help="seconds")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    started = time.perf_counter()
    jobs = [
        (world, seed, args.minutes, args.before, args.after)
        for world in seed_list(args.worlds)
        for seed in range(1, args.trials + 1)
    ]
    with ProcessPoolExecutor(args.workers) as pool:
        trials = list(pool.map(trial, jobs))
    summary = summarise(trials)
    if args.json:
        print(json.dumps({"before_s": args.before, "after_s": args.after, **summary}, indent=1))
        return
    print(
        f"returns from {args.before:g} s before to {args.after:g} s after; rooms {args.worlds}, "
        f"{args.trials} trials, avoid {args.minutes:g} min after {LEARN_MINUTES:g} min exploring"
    )
    print(
        f"stretches learnt: {summary['stretches']} (bumps left out); endings {summary['endings']}"
    )
    print(
        f"distance to the collision point: mean |error| {summary['mean_abs_distance_error_m']:.2f}"
        f" m; over 0.3 m too far {summary['distance_too_far_03m']:.0%}, too near "
        f"{summary['distance_too_near_03m']:.0%}"
    )
    print(
        f"labels of {summary['exemplars']} exemplars: mean |error| "
        f"{summary['mean_abs_label_error_mps']:.3f} m/s; over {TOO_FAR_MPS:g} m/s too fast "
        f"{summary['labels_too_fast']:.0%}, too slow {summary['labels_too_slow']:.0%}"
    )
    print(f"({time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
