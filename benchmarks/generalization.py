"""Generalization: how competent the robot is in generated worlds nobody tuned on.

    python benchmarks/generalization.py [--set test|tuning] [--quick] [--trials 3]
                                        [--reflex NAMES | --paper] [--workers 2] [--json]
                                        [--config NAME=FILE.json ...] [--near M]
                                        [--sonar real|edges|ideal] [--decel A]
                                        [--threshold T] [--learn]

For each world (`tvl world new rooms --seed N`) and trial (seed 1, 2, 3): learn 15 simulated
minutes from the world's start, exploring with the single FAM; train a single, a multi and a
designed FAM (the three shipped configurations) from that one log; run avoid, wall-left,
wall-right and goal (to the world's first goal) for 5 simulated minutes with each. The
DWA's avoid run in each world, knowing the map, is the speed reference. A run is competent
with at most 0.2 contacts (collisions and near misses) a minute at a mean speed of at least
0.3 m/s; a goal run must also reach its goal.

The test worlds are rooms seeds 1001-1020 and are for reporting only: develop and tune on
`--set tuning` (seeds 1-20). `--quick` takes the first 5 worlds of the set and 2 trials.
`--paper` runs the paper's whole method (its labels, bump-only collision points, no
reflexes); `--reflex` picks the reflexes of the behaviour runs (all by default). `--config
NAME=FILE.json` (repeatable) adds a configuration of your own (from `tvl design`, say),
trained from the same log as the others. `--near M` sets the learner's sonar collision point
(`tvl learn --near`), `--decel A` the labels' deceleration (`tvl learn --decel`),
`--sonar MODEL` the sonar of learning and runs (`--sonar`), `--threshold T` the runs'
threshold (`tvl run --threshold`), and `--learn` makes every run go on learning while it
behaves, from a copy of the FAM exploring learnt (`tvl run --learn`), for measuring those
levers.
"""

from __future__ import annotations

import argparse
import copy
import json
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, replace
from typing import Any

import numpy as np

from tvl_cli.agent.behave import behave
from tvl_cli.agent.drive import Step, StepSink
from tvl_cli.agent.explore import PAPER_NEAR_M, Learner, LearnParams
from tvl_cli.agent.online import OnlineLearner
from tvl_cli.agent.reflexes import ALL, parse_reflexes
from tvl_cli.agent.trace import Columns, TraceRecorder
from tvl_cli.analysis.autopsy import CAUSES, GOAL_FAILURES, TIME_CLASSES, tally
from tvl_cli.baselines.dwa import run_dwa
from tvl_cli.commands.autopsy import run_autopsy
from tvl_cli.commands.learn import resolve_fam_config
from tvl_cli.core import competence
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD, is_threshold
from tvl_cli.core.config import (
    BUILTIN_FAM_CONFIGS,
    SINGLE,
    SONAR_MODELS,
    FamConfig,
    RobotConfig,
)
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.labels import PAPER_DECEL_MPS2, PAPER_MARGIN_M
from tvl_cli.core.memory import (
    DEFAULT_PATCH_M,
    DEFAULT_RANGE_M,
    DEFAULT_WINDOW_S,
    MEMORY_KINDS,
    NONE,
    MemoryConfig,
)
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.training import TrainParams, train_episode
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import WorldMap, parse_world

KIND = "rooms"
WORLD_SETS = {"test": range(1001, 1021), "tuning": range(1, 21)}
QUICK_WORLDS, QUICK_TRIALS = 5, 2
LEARN_MINUTES = 15.0
RUN_MINUTES = 5.0
BEHAVIOURS = ("avoid", "wall-left", "wall-right", "goal")
# The targets this benchmark is judged against.
MIN_COMPETENT_SHARE = 0.9
MIN_GOAL_SHARE = 0.9
MIN_SPEED_OF_DWA = 0.75


def world_of(seed: int) -> WorldMap:
    return parse_world(generate_world(KIND, None, None, seed), f"{KIND}-s{seed}")


def is_competent(metrics: RunMetrics, behaviour: str) -> bool:
    """The avoid competence test, and for a goal run the goal reached as well."""
    return competence.is_competent(metrics) and (behaviour != "goal" or metrics.goal_reached)


def learn_and_train(
    world: WorldMap,
    seed: int,
    train: TrainParams,
    explore: LearnParams,
    robot: RobotConfig,
    configs: dict[str, FamConfig],
    memory: MemoryConfig,
) -> dict[str, Fam]:
    """Learn with the single FAM, then train each configuration from the same episodes,
    as `tvl train LOG --config C` does from the learning log."""
    names = [t.name for t in robot.trajectories]
    episodes: list[Episode] = []
    learner = Learner(
        world,
        robot,
        Fam(SINGLE, names, train.init_velocity_mps),
        replace(explore, minutes=LEARN_MINUTES),
        train,
        seed,
        memory=memory,
    )
    learner.run(episodes.append, lambda _minute: None)
    fams = {}
    for name, config in configs.items():
        fam = Fam(config, names, train.init_velocity_mps)
        for episode in episodes:
            train_episode(fam, episode, robot, train)
        fams[name] = fam
    return fams


def trial_runs(
    world_seed: int,
    trial: int,
    train: TrainParams,
    explore: LearnParams,
    reflexes: tuple[str, ...],
    configs: dict[str, FamConfig],
    robot: RobotConfig,
    threshold: float,
    learn_while_behaving: bool,
    memory: MemoryConfig,
) -> list[dict[str, Any]]:
    """Every behaviour run of one trial in one world, as rows."""
    world = world_of(world_seed)
    rows = []
    fams = learn_and_train(world, trial, train, explore, robot, configs, memory)
    for config, learnt in fams.items():
        for behaviour in BEHAVIOURS:
            goal = world.goals[0] if behaviour == "goal" and world.goals else None
            if behaviour == "goal" and goal is None:
                continue
            fam, learner = learnt, None
            if learn_while_behaving:
                # Each run starts from what exploring learnt, as `tvl run --learn` from a file.
                fam = copy.deepcopy(learnt)
                learner = OnlineLearner(fam, robot, train, world.start, memory=memory)
            chunks: list[Columns] = []
            recorder = TraceRecorder(reflexes, robot.sonar.count, [chunks.append])
            metrics = behave(
                world,
                robot,
                fam,
                behaviour,
                minutes=RUN_MINUTES,
                seed=trial,
                threshold=threshold,
                goal_xy=goal,
                reflexes=reflexes,
                on_step=_both(recorder, learner),
                memory=memory,
            )
            recorder.close()
            autopsy = run_autopsy(
                world,
                robot,
                {name: np.concatenate([c[name] for c in chunks]) for name in chunks[0]},
                reflex_names=reflexes,
                trajectory_names=tuple(t.name for t in robot.trajectories),
                table_sonars=configs[config].sonars_read(),
                goal_xy=goal,
                goal_reached=metrics.goal_reached,
            )
            rows.append(
                {
                    "world_seed": world_seed,
                    "trial": trial,
                    "config": config,
                    "behaviour": behaviour,
                    "competent": is_competent(metrics, behaviour),
                    **asdict(metrics),
                    "autopsy": autopsy.to_dict(),
                }
            )
    return rows


def _both(recorder: StepSink, learner: StepSink | None) -> StepSink:
    """The recorder, and the learner of a run that learns while it behaves."""
    if learner is None:
        return recorder

    def each(step: Step) -> None:
        recorder(step)
        learner(step)

    return each


def dwa_run(world_seed: int) -> dict[str, Any]:
    """The DWA's avoid run in one world: the same for every trial, since it sees the map."""
    metrics = run_dwa(world_of(world_seed), RobotConfig(), RUN_MINUTES, seed=1)
    return {"world_seed": world_seed, "config": "dwa", "behaviour": "avoid", **asdict(metrics)}


def _mean(values: list[float]) -> float:
    return sum(values) / len(values) if values else float("nan")


def summarise(
    rows: list[dict[str, Any]], dwa: list[dict[str, Any]], configs: dict[str, FamConfig]
) -> dict[str, Any]:
    """Per configuration: competent runs, goals reached, contacts a minute, and avoid speed
    as a share of the DWA's in the same worlds."""
    dwa_speed = _mean([r["mean_speed_mps"] for r in dwa])
    summary: dict[str, Any] = {"dwa_avoid_speed_mps": dwa_speed}
    for config in configs:
        runs = [r for r in rows if r["config"] == config]
        goals = [r for r in runs if r["behaviour"] == "goal"]
        avoid = [r for r in runs if r["behaviour"] == "avoid"]
        summary[config] = {
            "runs": len(runs),
            "competent": sum(r["competent"] for r in runs),
            "competent_by_behaviour": {
                b: f"{sum(r['competent'] for r in runs if r['behaviour'] == b)}"
                f"/{sum(r['behaviour'] == b for r in runs)}"
                for b in BEHAVIOURS
            },
            "goal_runs": len(goals),
            "goals_reached": sum(r["goal_reached"] for r in goals),
            "contacts_per_min": _mean([r["contacts_per_min"] for r in runs]),
            "avoid_speed_mps": _mean([r["mean_speed_mps"] for r in avoid]),
            "avoid_speed_of_dwa": _mean([r["mean_speed_mps"] for r in avoid]) / dwa_speed,
            "autopsy": tally(r["autopsy"] for r in runs),
        }
    return summary


def autopsy_table(summary: dict[str, Any], configs: dict[str, FamConfig]) -> str:
    """Where the contacts came from and where the time went, per configuration."""
    columns = [summary[name]["autopsy"] for name in configs]
    rows: list[tuple[str, ...]] = []
    for cause in CAUSES:
        if any(c["causes"][cause] for c in columns):
            rows.append((f"contacts: {cause}", *(str(c["causes"][cause]) for c in columns)))
    for name in TIME_CLASSES:
        if any(c["time_s"][name] for c in columns):
            shares = [c["time_s"][name] / (sum(c["time_s"].values()) or 1) for c in columns]
            rows.append((f"time: {name}", *(f"{s:.0%}" for s in shares)))
    for reason in GOAL_FAILURES:
        if any(c["goal_failures"][reason] for c in columns):
            rows.append(
                (f"goal missed: {reason}", *(str(c["goal_failures"][reason]) for c in columns))
            )
    return _aligned(("autopsy", *configs), rows)


def table(summary: dict[str, Any], configs: dict[str, FamConfig]) -> str:
    def share(part: int, whole: int) -> str:
        return f"{part}/{whole} ({100 * part / whole:.0f} %)" if whole else "–"

    columns = [summary[name] for name in configs]
    rows = [
        (
            "competent runs",
            *(share(c["competent"], c["runs"]) for c in columns),
            f">= {MIN_COMPETENT_SHARE:.0%}",
        ),
        *((f"  {b}", *(c["competent_by_behaviour"][b] for c in columns), "") for b in BEHAVIOURS),
        (
            "goals reached",
            *(share(c["goals_reached"], c["goal_runs"]) for c in columns),
            f">= {MIN_GOAL_SHARE:.0%}",
        ),
        (
            "contacts/min",
            *(f"{c['contacts_per_min']:.2f}" for c in columns),
            "multi <= single",
        ),
        (
            "avoid speed m/s",
            *(f"{c['avoid_speed_mps']:.2f}" for c in columns),
            f"DWA {summary['dwa_avoid_speed_mps']:.2f}",
        ),
        (
            "avoid speed / DWA's",
            *(f"{c['avoid_speed_of_dwa']:.0%}" for c in columns),
            f">= {MIN_SPEED_OF_DWA:.0%}",
        ),
    ]
    return _aligned(("figure", *configs, "target"), rows)


def _aligned(header: tuple[str, ...], rows: list[tuple[str, ...]]) -> str:
    """A header, a rule and the rows, in columns as wide as their widest cell."""
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = []
    for r in [header, tuple("-" * w for w in widths), *rows]:
        lines.append("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip())
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=sorted(WORLD_SETS), default="test", dest="world_set")
    parser.add_argument("--quick", action="store_true", help="5 worlds, 2 trials")
    parser.add_argument("--trials", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2, help="parallel processes")
    parser.add_argument("--reflex", default=ALL, help="reflexes of the runs: all, none or names")
    parser.add_argument(
        "--paper",
        action="store_true",
        help="the paper's method: its labels, bump-only collision points and no reflexes",
    )
    parser.add_argument(
        "--near",
        type=float,
        default=LearnParams().near_m,
        help="metres: a sonar ahead reading this close marks a collision point while learning",
    )
    parser.add_argument(
        "--decel",
        type=float,
        default=TrainParams().decel_mps2,
        help="m/s²: the deceleration of the training labels",
    )
    parser.add_argument(
        "--sonar", choices=list(SONAR_MODELS), default="real", help="the sonar model throughout"
    )
    parser.add_argument(
        "--threshold",
        type=float,
        default=DEFAULT_THRESHOLD,
        help="the behaviour runs' threshold: fast is at least this fraction of a maximum",
    )
    parser.add_argument(
        "--learn",
        action="store_true",
        help="the behaviour runs learn while behaving, as `tvl run --learn` does",
    )
    parser.add_argument(
        "--memory", choices=MEMORY_KINDS, default=NONE, help="the echo memory throughout"
    )
    parser.add_argument("--memory-window", type=float, default=DEFAULT_WINDOW_S, help="seconds")
    parser.add_argument("--memory-range", type=float, default=DEFAULT_RANGE_M, help="metres")
    parser.add_argument("--memory-patch", type=float, default=DEFAULT_PATCH_M, help="metres")
    parser.add_argument("--worlds", type=int, help="only the first N worlds of the set")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    parser.add_argument(
        "--config",
        action="append",
        default=[],
        metavar="NAME=FILE.json",
        help="also train this FAM configuration from each log (repeatable)",
    )
    args = parser.parse_args()
    configs = dict(BUILTIN_FAM_CONFIGS)  # single, multi and designed, then any --config
    for given in args.config:
        name, _, path = given.partition("=")
        if not name or not path or name in configs:
            parser.error(f"--config {given!r}: expected a new NAME=FILE.json")
        try:
            configs[name] = resolve_fam_config(path, RobotConfig())
        except BadInput as error:
            parser.error(str(error))
    if not is_threshold(args.threshold):
        parser.error(f"--threshold {args.threshold:g} must be in (0, 1]")
    world_seeds = list(WORLD_SETS[args.world_set])
    trials = range(1, args.trials + 1)
    if args.quick:
        world_seeds, trials = world_seeds[:QUICK_WORLDS], range(1, QUICK_TRIALS + 1)
    if args.worlds:
        world_seeds = world_seeds[: args.worlds]
    memory = MemoryConfig(args.memory, args.memory_window, args.memory_range, args.memory_patch)
    train, explore = TrainParams(decel_mps2=args.decel), LearnParams(near_m=args.near)
    if args.paper:
        train = TrainParams(decel_mps2=PAPER_DECEL_MPS2, margin_m=PAPER_MARGIN_M)
        explore = LearnParams(near_m=PAPER_NEAR_M)
        args.reflex = "none"
    reflexes = parse_reflexes(args.reflex)
    started = time.perf_counter()
    robot = RobotConfig(sonar=SONAR_MODELS[args.sonar])
    jobs = [
        (w, t, train, explore, reflexes, configs, robot, args.threshold, args.learn, memory)
        for w in world_seeds
        for t in trials
    ]
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        dwa_jobs = pool.map(dwa_run, world_seeds)
        per_trial = pool.map(trial_runs, *zip(*jobs, strict=True))
        rows = [row for trial in per_trial for row in trial]
        dwa = list(dwa_jobs)
    summary = summarise(rows, dwa, configs)
    if args.json:
        print(json.dumps({"summary": summary, "runs": rows, "dwa": dwa}, indent=2))
        return
    method = "the paper's method" if args.paper else f"reflexes {', '.join(reflexes) or 'none'}"
    print(
        f"{KIND} worlds {world_seeds[0]}-{world_seeds[-1]} ({args.world_set}, "
        f"{len(world_seeds)} worlds), trials {trials.start}-{trials.stop - 1}, learning "
        f"{LEARN_MINUTES:g} min (near {explore.near_m:g} m, decel {train.decel_mps2:g} m/s²), "
        f"runs {RUN_MINUTES:g} min at threshold {args.threshold:g}"
        f"{' learning while behaving' if args.learn else ''}, "
        f"{args.sonar} sonar, memory {memory.kind}, {method} "
        f"({time.perf_counter() - started:.0f} s)"
    )
    print(table(summary, configs))
    print()
    print(autopsy_table(summary, configs))


if __name__ == "__main__":
    main()
