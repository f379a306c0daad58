"""Which trajectories ours drives, against the decision rule fed the true velocities: for each
world of a `tvl bench generalization` directory, ours' FAMs
(fams/rooms-sN-s1-m15.0-single-default-DIGEST-CONFIG.h5, trained by its ours rows) and the
oracle velocities each avoid for 5 simulated minutes with seed 1, as the benchmark's first
trial does, and every step is counted by what the robot did: turned on the spot, or drove
which of the seven trajectories.

Where ours is slow, is it turning, or driving tight arcs where the truth would let it drive
straight? The shares are of every step of every world's run; the mean speed is over them.

And why it drives them: at every step of ours' runs that read the ring, each trajectory of the
view ahead is judged truly fast or not (the oracle velocities, from the map and the pose the
ring was read at), and rated fast or not by the run's FAM, on what it read through the echo
memory and on the live ring alone, at the default threshold: the live ring's ratings say what
the same FAM makes of the ring without the remembered patches, which it was not trained on.

    python benchmarks/arc_choices.py DIR [--worlds 1-20] [--json]
"""

from __future__ import annotations

import argparse
import json
from functools import partial
from pathlib import Path

import numpy as np
from bench_dir import CONFIGS, MINUTES, SEED, ours_avoid, ours_fam, seeds, traced, world_path

from tvl_cli.agent.trace import before_each_step
from tvl_cli.agent.true_velocities import TrueVelocities, behave_with_true_velocities
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.fam import Fam
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.sim.worldmap import WorldMap, load_world

ORACLE = "oracle-velocities"
TURNING = "turning"  # a step on which no trajectory was driven: turning to face a view
# What each read step of ours' runs counts, per trajectory of the view ahead.
TRULY_FAST = "truly fast"
RATED_THROUGH_MEMORY = "truly fast, rated fast through the memory"
RATED_ON_LIVE_RING = "truly fast, rated fast on the live ring"
TRULY_SLOW = "truly slow"
SLOW_RATED_THROUGH_MEMORY = "truly slow, rated fast through the memory"
SLOW_RATED_ON_LIVE_RING = "truly slow, rated fast on the live ring"


def ratings_against_truth(
    world: WorldMap, fam: Fam, robot: RobotConfig, columns: dict[str, np.ndarray]
) -> dict[str, np.ndarray]:
    """The steps of a traced run of `fam` driving `robot` that read the ring: each count
    above, (T,) per trajectory of the view ahead."""
    truth = TrueVelocities(world, robot, DEFAULT)
    fast_from = DEFAULT_THRESHOLD * np.array(robot.v_max_mps)  # (T,) m/s
    read = columns["ring_mm"].any(axis=1)
    poses = before_each_step(columns["pose"], world.start)[read]
    truly = np.array([truth.in_view(tuple(pose), 0) for pose in poses]) >= fast_from
    through_memory = fam.velocities(mm_to_ring(columns["perceived_mm"][read])) >= fast_from
    live = fam.velocities(mm_to_ring(columns["ring_mm"][read])) >= fast_from
    return {
        TRULY_FAST: truly.sum(axis=0),
        RATED_THROUGH_MEMORY: (truly & through_memory).sum(axis=0),
        RATED_ON_LIVE_RING: (truly & live).sum(axis=0),
        TRULY_SLOW: (~truly).sum(axis=0),
        SLOW_RATED_THROUGH_MEMORY: (~truly & through_memory).sum(axis=0),
        SLOW_RATED_ON_LIVE_RING: (~truly & live).sum(axis=0),
    }


def world_steps(
    bench: Path, seed: int
) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], dict[str, dict[str, np.ndarray]]]:
    """Each row's steps in the world of rooms seed `seed`, ours' configurations' and the
    oracle's: (trajectory driven, -1 while turning; speed m/s) of every step; and each of
    ours' configurations' ratings_against_truth."""
    world = load_world(world_path(bench, seed))
    fams = {c: ours_fam(bench, seed, c) for c in CONFIGS}
    runs = {c: ours_avoid(world, *fams[c]) for c in CONFIGS}
    ratings = {
        config: ratings_against_truth(world, fam_file.fam, robot, runs[config])
        for config, (fam_file, robot) in fams.items()
    }
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
    steps = {row: (columns["trajectory"], columns["speed_mps"]) for row, columns in runs.items()}
    return steps, ratings


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
    counted: dict[str, dict[str, np.ndarray]] = {config: {} for config in CONFIGS}
    for seed in seeds(args.worlds):
        world_runs, ratings = world_steps(args.bench, seed)
        for row, steps in world_runs.items():
            collected[row].append(steps)
        for config, counts in ratings.items():
            for name, count in counts.items():
                counted[config][name] = counted[config].get(name, 0) + count
    figures = {
        row: shares(
            np.concatenate([t for t, _ in found]), np.concatenate([s for _, s in found]), names
        )
        for row, found in collected.items()
    }
    rated = {config: rated_shares(counts, names) for config, counts in counted.items()}
    if args.json:
        print(json.dumps({"steps": figures, "ratings": rated}, indent=1))
        return
    print(f"avoid, worlds {args.worlds}, seed {SEED}, {MINUTES:g} minutes each; shares of steps")
    columns = [TURNING, *names]
    print("| row | " + " | ".join(columns) + " | mean m/s |")
    print("| --- |" + " --- |" * (len(columns) + 1))
    for row, found in figures.items():
        cells = " | ".join(f"{found[c]:.0%}" for c in columns)
        print(f"| {row} | {cells} | {found['mean_speed_mps']:.2f} |")
    print()
    print("ours' steps that read the ring, the view ahead: the share on which each way was truly")
    print("fast, and the share of those and of the truly slow that the FAM rated fast")
    print("| row | | " + " | ".join(names) + " |")
    print("| --- | --- |" + " --- |" * len(names))
    for config, shares_of in rated.items():
        for measure, share in shares_of.items():
            cells = " | ".join("–" if share[n] is None else f"{share[n]:.0%}" for n in names)
            print(f"| {config} | {measure} | {cells} |")


def rated_shares(by: dict[str, np.ndarray], names: list[str]) -> dict[str, dict[str, float | None]]:
    """Counts (ratings_against_truth's, summed) as shares: how often each way was truly fast,
    and how often the FAM rated it fast when it was and when it was not (None: no such
    step)."""
    steps = by[TRULY_FAST] + by[TRULY_SLOW]
    shares_of = {
        "truly fast, of the steps": (by[TRULY_FAST], steps),
        "rated fast through the memory, of those": (by[RATED_THROUGH_MEMORY], by[TRULY_FAST]),
        "rated fast on the live ring, of those": (by[RATED_ON_LIVE_RING], by[TRULY_FAST]),
        "rated fast through the memory, of the truly slow": (
            by[SLOW_RATED_THROUGH_MEMORY],
            by[TRULY_SLOW],
        ),
        "rated fast on the live ring, of the truly slow": (
            by[SLOW_RATED_ON_LIVE_RING],
            by[TRULY_SLOW],
        ),
    }
    return {
        measure: {
            name: float(part / whole) if whole else None
            for name, part, whole in zip(names, parts, wholes, strict=True)
        }
        for measure, (parts, wholes) in shares_of.items()
    }


if __name__ == "__main__":
    main()
