"""What the robot achieves after learning (issue 4), with the paper's figures beside ours.

    python benchmarks/competence.py [--seeds 1-5] [--learn-minutes 15] [--run-minutes 10]
                                    [--workers 2] [--reflex NAMES | --paper] [--json]

For each seed: learn 15 simulated minutes in worlds/square.txt with the single FAM, then run
10 simulated minutes of each behaviour from the world's start: avoid, wall-left and
wall-right at threshold 0.85, both wall followings again at 0.65 and 0.95, and avoid in
worlds/circle.txt with the square's FAM. Then learn 20 minutes in worlds/obstacles.txt and
seek each of its goals in turn (a run of up to --run-minutes each). Seeds run in parallel
processes. `--decel` and `--margin` change the training labels, to see how the defaults
were chosen; `--memory` the echo memory (ours by default; `none` reads the live ring);
`--reflex` picks the reflexes the runs use (all by default) and `--paper` runs
the paper's method alone, with its labels and bump-only collision points. Contacts are
collisions and near misses together. The figures are means over the seeds; per-seed figures
are in --json.
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.explore import Learner
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DEFAULT_INIT_VELOCITY_MPS, SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import MEMORY_KINDS
from tvl_cli.core.method import ALL, DEFAULT, PAPER, Method, parse_reflexes
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import WorldMap, load_world

WORLDS = Path(__file__).resolve().parent.parent / "worlds"
THRESHOLD = 0.85
LOW, HIGH = 0.65, 0.95  # the paper's Figure 21 range
GOAL_LEARN_MINUTES_PER_SQUARE_MINUTE = 20 / 15  # obstacles: 20 minutes against the square's 15
WALLS = ("wall-left", "wall-right")


def learn(
    world: WorldMap,
    minutes: float,
    seed: int,
    method: Method,
    explore: LearnParams,
    robot: RobotConfig,
) -> Fam:
    fam = Fam(SINGLE, [t.name for t in robot.trajectories], DEFAULT_INIT_VELOCITY_MPS)
    learner = Learner(world, robot, fam, replace(explore, minutes=minutes), method, seed)
    learner.run(lambda _episode: None, lambda _minute: None)
    return fam


def run(
    world: WorldMap,
    fam: Fam,
    behaviour: str,
    threshold: float,
    minutes: float,
    seed: int,
    robot: RobotConfig,
    method: Method,
    goal: tuple[float, float] | None = None,
) -> dict[str, Any]:
    metrics = behave(
        world,
        robot,
        fam,
        behaviour,
        minutes=minutes,
        seed=seed,
        threshold=threshold,
        goal_xy=goal,
        method=method,
    )
    return {**asdict(metrics), "near_misses_per_min": metrics.near_misses / (metrics.sim_s / 60)}


def seed_figures(
    seed: int,
    learn_minutes: float,
    run_minutes: float,
    method: Method,
    explore: LearnParams | None = None,
) -> dict[str, Any]:
    """Every run of the protocol for one seed: {"square": {...}, "circle": .., "goals": [..]}."""
    robot = RobotConfig()
    explore = explore or LearnParams()
    square, circle, obstacles = (
        load_world(WORLDS / f"{n}.txt") for n in ("square", "circle", "obstacles")
    )

    def one_run(
        world: WorldMap,
        fam: Fam,
        behaviour: str,
        threshold: float = THRESHOLD,
        goal: tuple[float, float] | None = None,
    ) -> dict[str, Any]:
        return run(world, fam, behaviour, threshold, run_minutes, seed, robot, method, goal)

    fam = learn(square, learn_minutes, seed, method, explore, robot)
    runs: dict[str, Any] = {"avoid@0.85": one_run(square, fam, "avoid")}
    for behaviour in WALLS:
        for threshold in (LOW, THRESHOLD, HIGH):
            runs[f"{behaviour}@{threshold:g}"] = one_run(square, fam, behaviour, threshold)
    circle_run = one_run(circle, fam, "avoid")
    goal_fam = learn(
        obstacles,
        learn_minutes * GOAL_LEARN_MINUTES_PER_SQUARE_MINUTE,
        seed,
        method,
        explore,
        robot,
    )
    goals = [one_run(obstacles, goal_fam, "goal", goal=goal) for goal in obstacles.goals]
    return {"seed": seed, "square": runs, "circle": circle_run, "goals": goals}


def _mean(values: list[float | None]) -> float | None:
    present = [v for v in values if v is not None]
    return float(np.mean(present)) if present else None


def summarise(per_seed: list[dict[str, Any]], reflexes: tuple[str, ...]) -> dict[str, Any]:
    """Means over seeds of the figures the targets speak of."""

    def square(key: str, field: str) -> float | None:
        return _mean([s["square"][key][field] for s in per_seed])

    def walls(threshold: float, field: str) -> float | None:
        return _mean([square(f"{b}@{threshold:g}", field) for b in WALLS])

    goal_count = len(per_seed[0]["goals"]) if per_seed else 0
    return {
        "seeds": [s["seed"] for s in per_seed],
        "reflexes": list(reflexes),
        "avoid_contacts_per_min": square("avoid@0.85", "contacts_per_min"),
        "avoid_mean_speed_mps": square("avoid@0.85", "mean_speed_mps"),
        "avoid_near_misses_per_min": square("avoid@0.85", "near_misses_per_min"),
        **{
            f"{b.replace('-', '_')}_{f}": square(f"{b}@0.85", k)
            for b in WALLS
            for f, k in (
                ("contacts_per_min", "contacts_per_min"),
                ("wall_clearance_m", "mean_wall_clearance_m"),
                ("mean_speed_mps", "mean_speed_mps"),
            )
        },
        "wall_clearance_m_at_0.65": walls(LOW, "mean_wall_clearance_m"),
        "wall_clearance_m_at_0.95": walls(HIGH, "mean_wall_clearance_m"),
        "wall_speed_mps_at_0.65": walls(LOW, "mean_speed_mps"),
        "wall_speed_mps_at_0.95": walls(HIGH, "mean_speed_mps"),
        "wall_contacts_per_min_at_0.65": walls(LOW, "contacts_per_min"),
        "wall_contacts_per_min_at_0.95": walls(HIGH, "contacts_per_min"),
        "circle_avoid_contacts_per_min": _mean([s["circle"]["contacts_per_min"] for s in per_seed]),
        "circle_avoid_near_misses_per_min": _mean(
            [s["circle"]["near_misses_per_min"] for s in per_seed]
        ),
        "goal_first_reached_seeds": sum(s["goals"][0]["goal_reached"] for s in per_seed),
        "goal_reached_per_goal": [
            sum(s["goals"][g]["goal_reached"] for s in per_seed) for g in range(goal_count)
        ],
    }


def _f(value: float | None, digits: int = 2) -> str:
    return "n/a" if value is None else f"{value:.{digits}f}"


def _low_high(summary: dict[str, Any], figure: str) -> str:
    return f"{_f(summary[f'{figure}_at_{LOW:g}'])} -> {_f(summary[f'{figure}_at_{HIGH:g}'])}"


def table(summary: dict[str, Any]) -> str:
    """Our figures, the issue's target and the paper's figure, one row each."""
    s = summary
    n = len(s["seeds"])

    per_goal = ", ".join(f"{k}/{n}" for k in s["goal_reached_per_goal"])
    rows = [
        (
            "avoid: contacts/min (square, 0.85)",
            _f(s["avoid_contacts_per_min"]),
            "<= 0.2",
            "none after < 9 min learning",
        ),
        ("avoid: mean speed m/s", _f(s["avoid_mean_speed_mps"]), ">= 0.30", "-"),
        ("avoid: near misses/min", _f(s["avoid_near_misses_per_min"]), "-", "-"),
    ]
    for b in WALLS:
        key = b.replace("-", "_")
        rows += [
            (
                f"{b}: contacts/min (0.85)",
                _f(s[f"{key}_contacts_per_min"]),
                "<= 0.2",
                "competent < 15 min",
            ),
            (
                f"{b}: wall clearance m (0.85)",
                _f(s[f"{key}_wall_clearance_m"]),
                "0.25-0.8",
                "0.32-0.67 over 0.65-0.95",
            ),
        ]
    rows += [
        (
            "wall: clearance m, 0.65 -> 0.95",
            _low_high(s, "wall_clearance_m"),
            "grows",
            "0.32 -> 0.67",
        ),
        (
            "wall: mean speed m/s, 0.65 -> 0.95",
            _low_high(s, "wall_speed_mps"),
            "grows",
            "0.32 -> 0.45",
        ),
        (
            "wall: contacts/min, 0.65 -> 0.95",
            _low_high(s, "wall_contacts_per_min"),
            "-",
            "more collisions when low",
        ),
        (
            "circle, square's FAM: avoid contacts/min",
            _f(s["circle_avoid_contacts_per_min"]),
            "<= 0.5",
            "works reasonably well",
        ),
        (
            "circle, square's FAM: avoid near misses/min",
            _f(s["circle_avoid_near_misses_per_min"]),
            "-",
            "-",
        ),
        (
            "goal (obstacles): first goal reached",
            f"{s['goal_first_reached_seeds']}/{n}",
            ">= 4/5",
            "3 of 4 goals",
        ),
        ("goal (obstacles): each goal reached", per_goal, "-", "3 of 4 goals"),
    ]
    header = ("figure", "ours", "target", "paper")
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(4)]
    lines = []
    for r in [header, tuple("-" * w for w in widths), *rows]:
        lines.append("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip())
    return "\n".join(lines)


def seed_list(text: str) -> list[int]:
    """The seeds (or world seeds) of "1-5" or "1,3,4"."""
    seeds: list[int] = []
    for part in text.split(","):
        first, _, last = part.partition("-")
        seeds += list(range(int(first), int(last or first) + 1))
    return seeds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=seed_list, default=seed_list("1-5"), help="e.g. 1-5 or 1,2")
    parser.add_argument("--learn-minutes", type=float, default=15.0)
    parser.add_argument("--run-minutes", type=float, default=10.0)
    parser.add_argument("--workers", type=int, default=2, help="parallel processes")
    parser.add_argument("--decel", type=float, default=DEFAULT.decel_mps2, help="m/s²")
    parser.add_argument("--margin", type=float, default=DEFAULT.margin_m, help="m")
    parser.add_argument(
        "--near", type=float, default=DEFAULT.near_m, help="m, 0: collisions are bumps"
    )
    parser.add_argument(
        "--learn-speed", type=float, default=LearnParams().learn_speed_mps, help="m/s"
    )
    parser.add_argument("--reflex", default=ALL, help="reflexes of the runs: all, none or names")
    parser.add_argument(
        "--memory",
        choices=MEMORY_KINDS,
        default=DEFAULT.memory.kind,
        help="the echo memory learning and the runs read through (default: ours)",
    )
    parser.add_argument(
        "--paper",
        action="store_true",
        help="the paper's method (core.method.PAPER) in place of the options above",
    )
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    method = (
        PAPER
        if args.paper
        else replace(
            DEFAULT,
            decel_mps2=args.decel,
            margin_m=args.margin,
            near_m=args.near,
            reflexes=parse_reflexes(args.reflex),
            memory=replace(DEFAULT.memory, kind=args.memory),
        )
    )
    reflexes = method.reflexes
    explore = LearnParams(learn_speed_mps=args.learn_speed)
    started = time.perf_counter()
    jobs = [(seed, args.learn_minutes, args.run_minutes, method, explore) for seed in args.seeds]
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        per_seed = list(pool.map(seed_figures, *zip(*jobs, strict=True)))
    summary = summarise(per_seed, reflexes)
    if args.json:
        print(json.dumps({"summary": summary, "per_seed": per_seed}, indent=2))
        return
    print(
        f"seeds {args.seeds}, learning {args.learn_minutes:g} min, runs {args.run_minutes:g} min, "
        f"decel {method.decel_mps2:g} m/s², margin {method.margin_m:g} m, "
        f"near {method.near_m:g} m, "
        f"learning speed {args.learn_speed:g} m/s, "
        f"reflexes {', '.join(reflexes) or 'none'}, memory {method.memory.kind} "
        f"({time.perf_counter() - started:.0f} s)"
    )
    print(table(summary))


if __name__ == "__main__":
    main()
