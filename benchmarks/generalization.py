"""Generalization: how competent the robot is in generated worlds nobody tuned on.

    python benchmarks/generalization.py [--set test|tuning] [--quick] [--trials 3]
                                        [--worlds N|A-B] [--reflex NAMES | --paper] [--workers 2]
                                        [--json] [--config NAME=FILE.json ...] [--near M]
                                        [--sonar real|edges|ideal] [--decel A] [--labels R]
                                        [--threshold T] [--learn]
                                        [--memory KIND] [--memory-window S]
                                        [--memory-range M] [--memory-patch M]
                                        [--roughness R | --rough-share S] [--no-ceiling]

For each world (`tvl world new rooms --seed N`) and trial (seed 1, 2, 3): learn 15 simulated
minutes from the world's start, exploring with the single FAM; train a single, a multi and a
designed FAM (the three shipped configurations) from that one log; run avoid, wall-left,
wall-right and goal (to the world's first goal) for 5 simulated minutes with each. A run is
competent with at most 0.2 contacts (collisions and near misses) a minute at a mean speed of
at least 0.3 m/s; a goal run must also reach its goal. Each run's contacts are put to their
causes by the contact autopsy (`tvl explain RUN --contacts`), printed per configuration with
where the runs' time went.

Beside the runs, the same learning and runs with an ideal sonar (nearest hit at any angle, no
noise, no memory): the method's ceiling with a perfect sensor. And the references: the DWA
that knows the map (its avoid run in each world is the speed reference), and the DWA driven
by the sonar ring alone, with and without the runs' echo memory, avoiding and seeking the
goal with each trial's seed.

The test worlds are rooms seeds 1001-1020 and are for reporting only: develop and tune on
`--set tuning` (seeds 1-20). `--quick` takes the first 5 worlds of the set and 2 trials,
`--worlds N` the first N, `--worlds A-B` the A-th to B-th. `--paper` runs the paper's whole
method (its labels, bump-only collision points, no reflexes, no memory); `--reflex` picks
the reflexes of the behaviour runs (all by default). `--config NAME=FILE.json` (repeatable)
adds a configuration of your own (from `tvl design`, say), trained from the same log as the
others. `--near M` sets the learner's sonar collision point (`tvl learn --near`), `--decel
A` the labels' deceleration, `--sonar MODEL` the sonar of learning and runs, `--threshold T`
the runs' threshold, `--memory ...` the echo memory of learning and runs (`tvl learn
--memory`), and `--learn` makes every run go on learning while it behaves, from a copy of
the FAM exploring learnt (`tvl run --learn`). `--roughness R` makes every wall of every
world rough; `--rough-share S` makes that share of each world's rooms rough (`tvl world new
rooms --rough S`), the rest smooth."""

from __future__ import annotations

import argparse
import copy
import json
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

from tvl_cli.agent.drive import Step, StepSink
from tvl_cli.agent.drive_tvl import BehaviourRun, behave_together
from tvl_cli.agent.explore import Learner, LearnParams
from tvl_cli.agent.online import OnlineLearner
from tvl_cli.agent.trace import Columns, TraceRecorder
from tvl_cli.analysis.autopsy import CAUSES, GOAL_FAILURES, TIME_CLASSES, tally
from tvl_cli.baselines.dwa import MAP, RING, run_dwa
from tvl_cli.commands.autopsy import run_autopsy
from tvl_cli.core import competence
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import DEFAULT_INIT_VELOCITY_MPS, Fam
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, SINGLE, FamConfig
from tvl_cli.core.labels import LABEL_RULES
from tvl_cli.core.memory import MEMORY_KINDS, NO_MEMORY, MemoryConfig
from tvl_cli.core.method import ALL, DEFAULT, PAPER, Method, parse_reflexes
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import SONAR_MODELS, RobotConfig
from tvl_cli.core.training import SessionEpisodes, TrainParams, train_params, train_sessions
from tvl_cli.core.trajectory_choice import DEFAULT_THRESHOLD, is_threshold
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.sim.worldgen import DEFAULT_ROUGHNESS, SMOOTH, Materials, generate_world
from tvl_cli.sim.worldmap import WorldMap, parse_world

KIND = "rooms"
WORLD_SETS = {"test": range(1001, 1021), "tuning": range(1, 21)}
QUICK_WORLDS, QUICK_TRIALS = 5, 2
LEARN_MINUTES = 15.0
RUN_MINUTES = 5.0
BEHAVIOURS = ("avoid", "wall-left", "wall-right", "goal")
DWA_BEHAVIOURS = ("avoid", "goal")
# The targets this benchmark is judged against.
MIN_COMPETENT_SHARE = 0.9
MIN_GOAL_SHARE = 0.9
MIN_SPEED_OF_DWA = 0.75
MAX_BELOW_CEILING = 0.05  # each configuration within 5 percentage points of its ceiling
# The two ways of perceiving each trial is learnt and run with.
RUNS, CEILING = "runs", "ceiling"


@dataclass(frozen=True, slots=True)
class Walls:
    """What the worlds' walls are made of: all of one roughness, or a share of rough rooms."""

    roughness: float = 0.0
    materials: Materials = SMOOTH


def world_of(seed: int, walls: Walls = Walls()) -> WorldMap:
    text = generate_world(KIND, None, None, seed, walls.materials)
    if walls.roughness:
        text = f"roughness: {walls.roughness:g}\n{text}"
    return parse_world(text, f"{KIND}-s{seed}")


@dataclass(frozen=True, slots=True)
class Setup:
    """How one trial is learnt and run."""

    name: str  # RUNS or CEILING
    method: Method
    configs: dict[str, FamConfig]
    threshold: float
    learn_while_behaving: bool
    walls: Walls

    @property
    def robot(self) -> RobotConfig:
        return self.method.robot()

    @property
    def train(self) -> TrainParams:
        return train_params(self.method)


def is_competent(metrics: RunMetrics, behaviour: str) -> bool:
    """The avoid competence test, and for a goal run the goal reached as well."""
    return competence.is_competent(metrics) and (behaviour != "goal" or metrics.goal_reached)


def learn_and_train(world: WorldMap, seed: int, setup: Setup) -> dict[str, Fam]:
    """Learn with the single FAM, then train each configuration from the same episodes,
    as `tvl train LOG --config C` does from the learning log."""
    names = [t.name for t in setup.robot.trajectories]
    episodes: list[Episode] = []
    learner = Learner(
        world,
        setup.robot,
        Fam(SINGLE, names, DEFAULT_INIT_VELOCITY_MPS),
        LearnParams(minutes=LEARN_MINUTES),
        setup.method,
        seed,
    )
    learner.run(episodes.append, lambda _minute: None)
    fams = {}
    for name, config in setup.configs.items():
        fam = Fam(config, names, DEFAULT_INIT_VELOCITY_MPS)
        train_sessions(fam, [SessionEpisodes(episodes, ended=True)], setup.robot, setup.train)
        fams[name] = fam
    return fams


def trial_runs(world_seed: int, trial: int, setup: Setup) -> list[dict[str, Any]]:
    """Every behaviour run of one trial in one world, as rows. The runs share the world and
    the trial's seed, so they are driven together in one RobotBatch, each as it would be
    driven alone (agent.drive_tvl.behave_together)."""
    world = world_of(world_seed, setup.walls)
    robot, method = setup.robot, setup.method
    planned: list[tuple[str, str, tuple[float, float] | None, list[Columns]]] = []
    runs: list[BehaviourRun] = []
    recorders: list[TraceRecorder] = []
    fams_by_config = learn_and_train(world, trial, setup)
    for config, learnt in fams_by_config.items():
        for behaviour in BEHAVIOURS:
            goal = world.goals[0] if behaviour == "goal" and world.goals else None
            if behaviour == "goal" and goal is None:
                continue
            fam, learner = learnt, None
            if setup.learn_while_behaving:
                # Each run starts from what exploring learnt, as `tvl run --learn` from a file.
                fam = copy.deepcopy(learnt)
                learner = OnlineLearner(fam, robot, setup.train, world.start, memory=method.memory)
            chunks: list[Columns] = []
            recorder = TraceRecorder(method.reflexes, robot.sonar.count, [chunks.append])
            planned.append((config, behaviour, goal, chunks))
            runs.append(BehaviourRun(fam, behaviour, trial, goal, _both(recorder, learner)))
            recorders.append(recorder)
    all_metrics = behave_together(
        world, robot, runs, minutes=RUN_MINUTES, method=method, threshold=setup.threshold
    )
    rows = []
    for (config, behaviour, goal, chunks), recorder, metrics in zip(
        planned, recorders, all_metrics, strict=True
    ):
        recorder.close()
        autopsy = run_autopsy(
            world,
            robot,
            {name: np.concatenate([c[name] for c in chunks]) for name in chunks[0]},
            reflex_names=method.reflexes,
            trajectory_names=tuple(t.name for t in robot.trajectories),
            table_sonars=setup.configs[config].sonars_read(),
            goal_xy=goal,
            goal_reached=metrics.goal_reached,
            method=method,
            fam=fams_by_config[config],
        )
        rows.append(
            {
                "perception": setup.name,
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


def dwa_runs(
    world_seed: int, trial: int, reference: str, memory: MemoryConfig, walls: Walls
) -> list[dict[str, Any]]:
    """A DWA's runs in one world: `dwa-map` avoids once (it sees the map, so every trial is
    the same); the ring-driven ones avoid and seek the goal with the trial's seed."""
    world = world_of(world_seed, walls)
    robot = RobotConfig()
    sensor = MAP if reference == "dwa-map" else RING
    rows = []
    for behaviour in ("avoid",) if sensor == MAP else DWA_BEHAVIOURS:
        goal = world.goals[0] if behaviour == "goal" else None
        metrics = run_dwa(
            world, robot, RUN_MINUTES, seed=trial, goal_xy=goal, sensor=sensor, memory=memory
        )
        rows.append(
            {
                "world_seed": world_seed,
                "trial": trial,
                "config": reference,
                "behaviour": behaviour,
                "competent": is_competent(metrics, behaviour),
                **asdict(metrics),
            }
        )
    return rows


def _mean(values: list[float]) -> float:
    return sum(values) / len(values) if values else float("nan")


def _figures(runs: list[dict[str, Any]], dwa_speed: float) -> dict[str, Any]:
    """Competent runs (by behaviour), goals reached, contacts a minute and avoid speed."""
    goals = [r for r in runs if r["behaviour"] == "goal"]
    avoid = [r for r in runs if r["behaviour"] == "avoid"]
    behaviours = [b for b in BEHAVIOURS if any(r["behaviour"] == b for r in runs)]
    return {
        "runs": len(runs),
        "competent": sum(r["competent"] for r in runs),
        "competent_by_behaviour": {
            b: f"{sum(r['competent'] for r in runs if r['behaviour'] == b)}"
            f"/{sum(r['behaviour'] == b for r in runs)}"
            for b in behaviours
        },
        "goal_runs": len(goals),
        "goals_reached": sum(r["goal_reached"] for r in goals),
        "contacts_per_min": _mean([r["contacts_per_min"] for r in runs]),
        "avoid_speed_mps": _mean([r["mean_speed_mps"] for r in avoid]),
        "avoid_speed_of_dwa": _mean([r["mean_speed_mps"] for r in avoid]) / dwa_speed,
    }


def summarise(
    rows: list[dict[str, Any]], references: list[dict[str, Any]], configs: dict[str, FamConfig]
) -> dict[str, Any]:
    """Per configuration, for the runs and their ceiling: competent runs, goals reached,
    contacts a minute, avoid speed as a share of the map-knowing DWA's in the same worlds,
    and the runs' autopsies summed; and the same figures of each reference."""
    dwa_speed = _mean([r["mean_speed_mps"] for r in references if r["config"] == "dwa-map"])
    summary: dict[str, Any] = {"dwa_avoid_speed_mps": dwa_speed}
    for perception in (RUNS, CEILING):
        mine = [r for r in rows if r["perception"] == perception]
        if not mine:
            continue
        summary[perception] = {}
        for config in configs:
            runs = [r for r in mine if r["config"] == config]
            summary[perception][config] = {
                **_figures(runs, dwa_speed),
                "autopsy": tally(r["autopsy"] for r in runs),
            }
    names = dict.fromkeys(r["config"] for r in references)
    summary["references"] = {
        name: _figures([r for r in references if r["config"] == name], dwa_speed) for name in names
    }
    return summary


def _share(part: int, whole: int) -> str:
    return f"{part}/{whole} ({100 * part / whole:.0f} %)" if whole else "–"


def table(summary: dict[str, Any], configs: dict[str, FamConfig]) -> str:
    """The runs' figures beside their targets, with the ceiling's competence below."""
    columns = [summary[RUNS][name] for name in configs]
    rows = [
        (
            "competent runs",
            *(_share(c["competent"], c["runs"]) for c in columns),
            f">= {MIN_COMPETENT_SHARE:.0%}",
        ),
        *((f"  {b}", *(c["competent_by_behaviour"][b] for c in columns), "") for b in BEHAVIOURS),
        (
            "goals reached",
            *(_share(c["goals_reached"], c["goal_runs"]) for c in columns),
            f">= {MIN_GOAL_SHARE:.0%}",
        ),
        ("contacts/min", *(f"{c['contacts_per_min']:.2f}" for c in columns), "multi <= single"),
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
    if CEILING in summary:
        ceiling = [summary[CEILING][name] for name in configs]
        rows += [
            (
                "ceiling: competent",
                *(_share(c["competent"], c["runs"]) for c in ceiling),
                f"runs within {MAX_BELOW_CEILING:.0%} of it",
            ),
            (
                "ceiling: contacts/min",
                *(f"{c['contacts_per_min']:.2f}" for c in ceiling),
                "",
            ),
            (
                "runs - ceiling",
                *(
                    f"{100 * (r['competent'] / r['runs'] - c['competent'] / c['runs']):+.0f} pp"
                    for r, c in zip(columns, ceiling, strict=True)
                ),
                f">= -{100 * MAX_BELOW_CEILING:.0f} pp",
            ),
        ]
    return _aligned(("figure", *configs, "target"), rows)


def references_table(summary: dict[str, Any]) -> str:
    """The DWAs' figures in the same worlds."""
    rows = []
    for name, c in summary["references"].items():
        by_behaviour = c["competent_by_behaviour"]
        rows.append(
            (
                name,
                by_behaviour.get("avoid", "–"),
                _share(c["goals_reached"], c["goal_runs"]),
                f"{c['contacts_per_min']:.2f}",
                f"{c['avoid_speed_mps']:.2f}",
            )
        )
    return _aligned(
        ("reference", "avoid competent", "goals reached", "contacts/min", "avoid m/s"), rows
    )


def autopsy_table(summary: dict[str, Any], configs: dict[str, FamConfig]) -> str:
    """Where the runs' contacts came from and where their time went, per configuration."""
    columns = [summary[RUNS][name]["autopsy"] for name in configs]
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


def _aligned(header: tuple[str, ...], rows: list[tuple[str, ...]]) -> str:
    """A header, a rule and the rows, in columns as wide as their widest cell."""
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = []
    for r in [header, tuple("-" * w for w in widths), *rows]:
        lines.append("  ".join(cell.ljust(w) for cell, w in zip(r, widths, strict=True)).rstrip())
    return "\n".join(lines)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=sorted(WORLD_SETS), default="test", dest="world_set")
    parser.add_argument("--quick", action="store_true", help="5 worlds, 2 trials")
    parser.add_argument(
        "--worlds",
        type=_world_span,
        help="only the first N worlds of the set, or its worlds A to B (11-20)",
    )
    parser.add_argument("--trials", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2, help="parallel processes")
    parser.add_argument("--reflex", default=ALL, help="reflexes of the runs: all, none or names")
    parser.add_argument(
        "--paper",
        action="store_true",
        help="the paper's method (core.method.PAPER) in place of the options of the method",
    )
    parser.add_argument(
        "--near",
        type=float,
        default=DEFAULT.near_m,
        help="metres: a sonar ahead reading this close marks a collision point while learning",
    )
    parser.add_argument(
        "--decel",
        type=float,
        default=DEFAULT.decel_mps2,
        help="m/s²: the deceleration of the training labels",
    )
    parser.add_argument(
        "--labels",
        choices=LABEL_RULES,
        default=DEFAULT.labels,
        help="what each recorded point labels (core.labels.LABEL_RULES)",
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
        "--memory", choices=MEMORY_KINDS, default=DEFAULT.memory.kind, help="the echo memory"
    )
    parser.add_argument("--memory-window", type=float, help="seconds of echoes remembered")
    parser.add_argument("--memory-range", type=float, help="metres: farther echoes are not")
    parser.add_argument("--memory-patch", type=float, help="metres: the narrowest patch")
    walls = parser.add_mutually_exclusive_group()
    walls.add_argument("--roughness", type=float, default=0.0, help="every wall this rough")
    walls.add_argument(
        "--rough-share",
        type=float,
        default=0.0,
        help=f"this share of the rooms rough ({DEFAULT_ROUGHNESS:g}), the rest smooth",
    )
    parser.add_argument(
        "--no-ceiling", action="store_true", help="skip the ideal-sonar ceiling's runs"
    )
    parser.add_argument(
        "--map-reference-only",
        action="store_true",
        help="skip the ring-driven DWA references (the map's DWA still sets the speed reference)",
    )
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    parser.add_argument(
        "--config",
        action="append",
        default=[],
        metavar="NAME=FILE.json",
        help="also train this FAM configuration from each log (repeatable)",
    )
    return parser


def _memory(args: argparse.Namespace) -> MemoryConfig:
    """The memory the options name, each setting not given as the default memory has it."""
    given = {
        "kind": args.memory,
        "window_s": args.memory_window,
        "range_m": args.memory_range,
        "patch_m": args.memory_patch,
    }
    base = DEFAULT.memory.to_dict()
    return MemoryConfig(**{k: v if v is not None else base[k] for k, v in given.items()})


def _world_span(text: str) -> tuple[int, int]:
    """`--worlds N` (the first N) or `A-B` (the set's A-th to B-th world, from 1)."""
    first, _, last = text.rpartition("-") if "-" in text else ("1", "", text)
    try:
        span = int(first), int(last)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not N or A-B") from None
    if not 1 <= span[0] <= span[1]:
        raise argparse.ArgumentTypeError(f"{text!r}: worlds count from 1, A before B")
    return span


def main() -> None:
    parser = _parser()
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
        first, last = args.worlds
        world_seeds = world_seeds[first - 1 : last]
    try:
        memory = _memory(args)
        walls = Walls(args.roughness, Materials(args.rough_share) if args.rough_share else SMOOTH)
    except BadInput as error:
        parser.error(str(error))
    ours = replace(
        DEFAULT,
        decel_mps2=args.decel,
        labels=args.labels,
        near_m=args.near,
        reflexes=parse_reflexes(args.reflex),
        memory=memory,
    )
    # The sonar model is the benchmark's, whichever the method.
    method = replace(PAPER if args.paper else ours, sonar=args.sonar)
    memory, reflexes = method.memory, method.reflexes
    started = time.perf_counter()
    runs = Setup(RUNS, method, configs, args.threshold, args.learn, walls)
    # The same method with a sensor that hears everything, no memory needed.
    ceiling = replace(runs, name=CEILING, method=replace(method, sonar="ideal", memory=NO_MEMORY))
    setups = [runs] if args.no_ceiling else [runs, ceiling]
    jobs = [(w, t, setup) for setup in setups for w in world_seeds for t in trials]
    references = [(w, 1, "dwa-map", NO_MEMORY, walls) for w in world_seeds]
    rings: dict[str, MemoryConfig] = {}
    if not args.map_reference_only:
        rings = {"dwa-ring": NO_MEMORY} | ({"dwa-ring-memory": memory} if memory.remembers else {})
    references += [
        (w, t, name, remembered, walls)
        for name, remembered in rings.items()
        for w in world_seeds
        for t in trials
    ]
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        reference_jobs = pool.map(dwa_runs, *zip(*references, strict=True))
        per_trial = pool.map(trial_runs, *zip(*jobs, strict=True))
        rows = [row for trial in per_trial for row in trial]
        reference_rows = [row for job in reference_jobs for row in job]
    summary = summarise(rows, reference_rows, configs)
    if args.json:
        print(json.dumps({"summary": summary, "runs": rows, "references": reference_rows}))
        return
    described = "the paper's method" if args.paper else f"reflexes {', '.join(reflexes) or 'none'}"
    made_of = (
        f"walls of roughness {args.roughness:g}"
        if args.roughness
        else f"{args.rough_share:.0%} of rooms rough"
        if args.rough_share
        else "smooth walls"
    )
    print(
        f"{KIND} worlds {world_seeds[0]}-{world_seeds[-1]} ({args.world_set}, "
        f"{len(world_seeds)} worlds, {made_of}), trials {trials.start}-{trials.stop - 1}, "
        f"learning {LEARN_MINUTES:g} min (near {method.near_m:g} m, decel "
        f"{method.decel_mps2:g} m/s²), runs {RUN_MINUTES:g} min at threshold {args.threshold:g}"
        f"{' learning while behaving' if args.learn else ''}, {args.sonar} sonar, memory "
        f"{memory.kind}"
        f"{f' ({memory.window_s:g} s, {memory.range_m:g} m)' if memory.remembers else ''}, "
        f"{described} ({time.perf_counter() - started:.0f} s)"
    )
    print(table(summary, configs))
    print()
    print(references_table(summary))
    print()
    print(autopsy_table(summary, configs))


if __name__ == "__main__":
    main()
