"""A cell's work, wherever it runs (a local process, a Dask worker): its rows, one a run, each
the run's metrics as `tvl run --json` prints them, whether it was competent, the contact
autopsy of a FAM-driven run, and the columns the cell's plan tagged it with.

Learning and training go through the verbs' own work (`tvl learn`, `tvl train`), into the
bench's logs/ and fams/, where a cell run again finds them; runs of one cell are driven
together in one RobotBatch (agent.drive_tvl.behave_together), each as it would run alone.
"""

from __future__ import annotations

import hashlib
import time
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.agent.drive_tvl import BehaviourRun, behave_together
from tvl_cli.agent.trace import Columns, TraceRecorder
from tvl_cli.agent.true_velocities import behave_with_true_velocities
from tvl_cli.bench.suite_cells import (
    Cell,
    DwaCell,
    FamFileCell,
    FamPlan,
    LearntCell,
    OracleCell,
    PolicyCell,
    QlearnCell,
    RunPlan,
    cell_id,
)
from tvl_cli.commands.baseline import dwa_session, qlearn_session
from tvl_cli.commands.contact_autopsy import run_autopsy
from tvl_cli.commands.learn import LearnRequest
from tvl_cli.commands.run import run_method, run_record, run_robot
from tvl_cli.commands.train import train_each_from_logs, write_trained
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.competence import is_competent_run
from tvl_cli.core.errors import BadInput
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.method import NOT_GIVEN, Method, MethodChoice, describe_record
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.io.famfile import FamFile, read_fam
from tvl_cli.io.logreader import file_sha256
from tvl_cli.sim.worldmap import WorldMap, load_world
from tvl_cli.sweep.layout import LogRequest, learning_tag
from tvl_cli.sweep.work import learn_log

Row = dict[str, Any]
LOGS, FAMS, WORLDS = "logs", "fams", "worlds"
# What a row says of a cell: its digest, and how many rows it has (the journal holds a cell
# whole or not at all).
CELL, CELL_ROWS, CELL_CPU_S = "cell", "cell_rows", "cell_cpu_s"
# A row's kind, as a sweep's rows name theirs: a FAM-driven run is a TVL run.
KINDS: dict[type, str] = {
    LearntCell: "tvl",
    FamFileCell: "tvl",
    PolicyCell: "controller",
    DwaCell: "dwa",
    OracleCell: "oracle",
    QlearnCell: "qlearn",
}


def world_path(root: Path, name: str) -> Path:
    return root / WORLDS / f"{name}.txt"


def do_cell(cell: Cell, root: Path) -> list[Row]:
    """The cell's rows, in its runs' order, each naming the cell; the CPU seconds the cell
    took on its last row's `cell_cpu_s` (a measure of the machine, not of the runs)."""
    started = time.process_time()
    world = load_world(world_path(root, cell.world))
    kind = KINDS[type(cell)]
    if isinstance(cell, LearntCell):
        rows = _learnt(cell, root, world)
    elif isinstance(cell, FamFileCell):
        rows = _fam_file(cell, world)
    elif isinstance(cell, PolicyCell):
        rows = _policy(cell, world)
    elif isinstance(cell, DwaCell):
        rows = _dwa(cell, root)
    elif isinstance(cell, OracleCell):
        rows = _oracle(cell, world)
    else:
        rows = _qlearn(cell, root)
    named = cell_id(cell)
    done = [
        {
            CELL: named,
            CELL_ROWS: len(rows),
            "kind": kind,
            "world": cell.world,
            "seed": cell.seed,
            **row,
        }
        for row in rows
    ]
    done[-1][CELL_CPU_S] = time.process_time() - started
    return done


def run_row(plan: RunPlan, metrics: RunMetrics, minutes: float) -> Row:
    """A run's row: its plan (behaviour, goal, threshold), its metrics, and competence."""
    return {
        "behaviour": plan.behaviour,
        # As a sweep's rows write a goal: X,Y in metres, exactly.
        "goal": None if plan.goal is None else f"{plan.goal[0]!r},{plan.goal[1]!r}",
        "threshold": plan.threshold,
        "run_minutes": minutes,
        **dict(plan.tags),
        **asdict(metrics),
        "competent": is_competent_run(metrics, plan.behaviour),
    }


def _learnt(cell: LearntCell, root: Path, world: WorldMap) -> list[Row]:
    log = (
        root
        / LOGS
        / (
            f"{cell.world}-s{cell.seed}-m{cell.learn_minutes!r}-{cell.learn_config}"
            f"{learning_tag(cell.method)}.h5"
        )
    )
    if not log.exists():
        learning = LearnRequest(
            world_path(root, cell.world),
            log,
            cell.seed,
            cell.learn_config,
            LearnParams(minutes=cell.learn_minutes),
            cell.method,
        )
        learn_log(LogRequest(learning, "--size"))
    paths: dict[FamPlan, Path] = {}
    for plan in dict.fromkeys(run.fam for run in cell.runs if run.fam is not None):
        snapshot = "" if plan.until_minute is None else f"-at{plan.until_minute!r}"
        oracle = "-oracle-labels" if plan.true_labels else ""
        paths[plan] = (
            root / FAMS / f"{log.stem}-{plan.config.name}{snapshot}{oracle}{_pooled(plan)}.h5"
        )
    _train_missing(log, [plan for plan, path in paths.items() if not path.exists()], paths, cell)
    fams = {plan: (path, read_fam(path)) for plan, path in paths.items()}
    choice = MethodChoice(cell.method, cell.method_name)
    driven = [(run, *fams[run.fam]) for run in cell.runs if run.fam is not None]
    rows = _drive_fams(world, cell.seed, cell.run_minutes, driven, choice)
    return [{**row, "method": cell.method_name} for row in rows]


def _train_missing(
    log: Path, missing: list[FamPlan], paths: dict[FamPlan, Path], cell: LearntCell
) -> None:
    """Train and write the FAMs not yet written, as `tvl train` would each, those from the
    same logs and labels together: the log is read, perceived and labelled once for them
    all (commands.train.train_each_from_logs)."""
    together: dict[tuple[bool, tuple[tuple[str, str], ...], float | None], list[FamPlan]] = {}
    for plan in missing:
        together.setdefault((plan.true_labels, plan.pooled, plan.until_minute), []).append(plan)
    for (true_labels, pooled, until_minute), plans in together.items():
        logs = [log, *(_unchanged(other, digest, "--pool") for other, digest in pooled)]
        trained = train_each_from_logs(
            logs,
            [plan.config for plan in plans],
            cell.method,
            until_minute=until_minute,
            true_labels=true_labels,
        )
        for plan, summary in zip(plans, trained, strict=True):
            write_trained(paths[plan], summary)


def _pooled(plan: FamPlan) -> str:
    """A pooled FAM's file name's tail: the digest of the logs it pools, whose contents the
    plan names."""
    if not plan.pooled:
        return ""
    digests = ",".join(digest for _, digest in plan.pooled)
    return "-pooled-" + hashlib.sha256(digests.encode()).hexdigest()[:12]


def _unchanged(path: str, digest: str, option: str) -> Path:
    """A file given by `option` (a pooled log, a FAM scored), refused if it is no longer the
    file the bench was planned with."""
    if file_sha256(path) != digest:
        raise BadInput(f"{option} {path}: the file changed since the bench began; run it again")
    return Path(path)


def _fam_file(cell: FamFileCell, world: WorldMap) -> list[Row]:
    path = _unchanged(*cell.source, "--controller")
    driven = [(run, path, read_fam(path)) for run in cell.runs]
    return _drive_fams(world, cell.seed, cell.run_minutes, driven, NOT_GIVEN)


def _drive_fams(
    world: WorldMap,
    seed: int,
    minutes: float,
    driven: list[tuple[RunPlan, Path, FamFile]],
    choice: MethodChoice,
) -> list[Row]:
    """Runs of FAMs, driven together where they share their robot and their method (FAMs of
    one log always do), each row with its FAM's configuration and snapshot minute and the
    run's autopsy."""
    rows: list[Row | None] = [None] * len(driven)
    batches: dict[tuple[Any, Method], list[int]] = {}
    for i, (_, path, fam_file) in enumerate(driven):
        robot = run_robot(fam_file.robot_config, None, path, DEFAULT_ROBOT)
        batches.setdefault((robot, run_method(fam_file, choice)), []).append(i)
    for (robot, method), members in batches.items():
        chunks: list[list[Columns]] = [[] for _ in members]
        recorders = [
            TraceRecorder(method.reflexes, robot.sonar.count, [found.append]) for found in chunks
        ]
        runs = [
            BehaviourRun(fam_file.fam, plan.behaviour, seed, plan.goal, recorder, plan.threshold)
            for (plan, _, fam_file), recorder in zip(
                (driven[i] for i in members), recorders, strict=True
            )
        ]
        found = behave_together(
            world, robot, runs, minutes=minutes, method=method, threshold=DEFAULT_THRESHOLD
        )
        for i, recorder, columns, metrics in zip(members, recorders, chunks, found, strict=True):
            recorder.close()
            plan, _, fam_file = driven[i]
            rows[i] = {
                "method": describe_record(run_record(method, fam_file)),
                "config": fam_file.fam.config.name,
                "minute": None if plan.fam is None else plan.fam.until_minute,
                **run_row(plan, metrics, minutes),
                "autopsy": _autopsy(world, robot, method, fam_file, plan, metrics, columns),
            }
    return [row for row in rows if row is not None]


def _autopsy(
    world: WorldMap,
    robot: Any,
    method: Method,
    fam_file: FamFile,
    plan: RunPlan,
    metrics: RunMetrics,
    chunks: list[Columns],
) -> dict[str, Any]:
    """The run's contact autopsy, summed by cause (`tvl explain RUN --contacts`, without the
    list of its contacts)."""
    autopsy = run_autopsy(
        world,
        robot,
        {name: np.concatenate([c[name] for c in chunks]) for name in chunks[0]},
        reflex_names=method.reflexes,
        trajectory_names=tuple(t.name for t in robot.trajectories),
        table_sonars=fam_file.fam.config.sonars_read(),
        goal_xy=plan.goal,
        goal_reached=bool(metrics.goal_reached),
        method=method,
        fam=fam_file.fam,
        threshold=plan.threshold or DEFAULT_THRESHOLD,
    ).to_dict()
    # Of the contacts, what the tally reads: each one's cause, the trajectory being driven,
    # and of the last choice before it the rating, the truth and the experience behind it.
    kept = ("cause", "trajectory", "rated_mps", "true_mps", "experience")
    autopsy["contacts"] = [{k: c[k] for k in kept} for c in autopsy["contacts"]]
    return autopsy


def _policy(cell: PolicyCell, world: WorldMap) -> list[Row]:
    from tvl_cli.gym.scoring import load_controller, score_controller  # the gym extra's

    if cell.source is not None:
        _unchanged(*cell.source, "--controller")
    controller = load_controller(cell.spec)
    rows = []
    for plan in cell.runs:
        # A model made for one task is scored on that task alone; its row of the other is "–".
        if not controller.observes(world, plan.goal, cell.observe):
            continue
        metrics = score_controller(
            controller.make(), world, plan.goal, cell.observe, minutes=cell.run_minutes,
            seed=cell.seed,
        )  # fmt: skip
        rows.append({"method": None, "config": None, **run_row(plan, metrics, cell.run_minutes)})
    if not rows:
        raise BadInput(
            f"--controller {cell.spec}: observes {controller.observation_shape}, which no "
            "task scored gives (avoid: the 16 ranges; goal: and its bearing and distance)"
        )
    return rows


def _dwa(cell: DwaCell, root: Path) -> list[Row]:
    alone = MethodChoice(replace(Method(), reflexes=(), memory=cell.memory))
    rows = []
    for plan in cell.runs:
        report = dwa_session(
            world_path(root, cell.world),
            plan.behaviour,
            plan.goal,
            cell.run_minutes,
            cell.seed,
            method=alone,
            sensor=cell.sensor,
        )
        rows.append(_baseline_row(plan, report.metrics, cell.run_minutes))
    return rows


def _oracle(cell: OracleCell, world: WorldMap) -> list[Row]:
    rows = []
    for plan in cell.runs:
        metrics = behave_with_true_velocities(
            world,
            cell.method.robot(),
            plan.behaviour,
            minutes=cell.run_minutes,
            seed=cell.seed,
            method=cell.method,
            threshold=plan.threshold or DEFAULT_THRESHOLD,
            goal_xy=plan.goal,
        )
        rows.append({"method": None, "config": None, **run_row(plan, metrics, cell.run_minutes)})
    return rows


def _qlearn(cell: QlearnCell, root: Path) -> list[Row]:
    report = qlearn_session(
        world_path(root, cell.world), cell.learn_minutes, cell.run_minutes, cell.seed
    )
    (plan,) = cell.runs
    return [_baseline_row(plan, report.result.evaluation, cell.run_minutes)]


def _baseline_row(plan: RunPlan, metrics: RunMetrics, minutes: float) -> Row:
    return {"method": None, "config": None, **run_row(plan, metrics, minutes)}
