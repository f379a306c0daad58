"""`tvl train`: rebuild a FAM from learning logs alone (log replay)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.agent.perception import perceived_session
from tvl_cli.core.arcs import collision_clearance_m
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DEFAULT_INIT_VELOCITY_MPS, FamConfig
from tvl_cli.core.heard import HeardEpisode
from tvl_cli.core.method import (
    NOT_GIVEN,
    SESSIONS_DIFFER_IN,
    Method,
    MethodChoice,
    as_choice,
    method_record,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import (
    SessionEpisodes,
    TrainParams,
    check_init_velocity,
    train_heard,
    train_params,
    train_sessions_each,
)
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.json_documents import config_input, document, input_file
from tvl_cli.io.log_sessions import (
    RepeatedSession,
    common_robot,
    distinct_sessions,
    provenance,
    session_to_train,
    training_method,
)
from tvl_cli.io.logreader import Session, read_log, refuse_repeated
from tvl_cli.sim.true_arcs import TrueArcs
from tvl_cli.sim.worldmap import parse_world


@dataclass(frozen=True, slots=True)
class TrainRequest:
    """`tvl train`: the logs to train on and the FAM file to write."""

    logs: tuple[Path, ...]
    output: Path
    config: str = "single"  # a built-in FAM configuration's name, or a JSON file
    method: MethodChoice = NOT_GIVEN  # the labels' method (ours when none is chosen)
    until_minute: float | None = None  # only the episodes each session finished by then
    symmetric: bool = True
    init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS
    force: bool = False  # replace an existing output


@dataclass(frozen=True, slots=True)
class TrainSummary:
    fam: Fam
    robot: RobotConfig
    made_by: Method  # every choice that made it: its labels, the memory it reads through
    training: TrainParams  # how its exemplars became entries
    provenance: dict[str, Any]
    exemplars: int
    episodes: int
    rules_touched: int
    rules_total: int
    wall_s: float
    repeated_sessions: list[RepeatedSession] = field(default_factory=list)  # trained once

    def method_record(self) -> dict[str, Any]:
        """Its method as the FAM file and --json record it, with the fields its learning
        sessions differ in named (the first's are recorded)."""
        return method_record(self.made_by, mixed=self.provenance[SESSIONS_DIFFER_IN])


def train_from_logs(
    paths: Sequence[Path],
    config: FamConfig,
    method: Method | MethodChoice = NOT_GIVEN,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    until_minute: float | None = None,
    symmetric: bool = True,
    init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS,
    true_labels: bool = False,
) -> TrainSummary:
    """Train a new FAM on every episode of every log, in log, session and episode order;
    with `until_minute`, only on the episodes each session finished by then (a snapshot of
    what the learner knew at that minute). The labels are the method's (ours when none is
    chosen); the FAM reads through the memory the sessions were learnt through unless the
    method or its settings say otherwise, its virtual rings replayed from the exemplars.

    `true_labels` labels every point's seven trajectories from its session's world and the
    true pose instead (sim.true_arcs): the oracle labels of the generalization benchmark, a
    reference that reads the map, never a method; its provenance says so."""
    (summary,) = train_each_from_logs(
        paths, [config], method, on_progress, until_minute, symmetric, init_velocity_mps,
        true_labels,
    )  # fmt: skip
    return summary


def train_each_from_logs(
    paths: Sequence[Path],
    configs: Sequence[FamConfig],
    method: Method | MethodChoice = NOT_GIVEN,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    until_minute: float | None = None,
    symmetric: bool = True,
    init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS,
    true_labels: bool = False,
) -> list[TrainSummary]:
    """train_from_logs for each of several configurations, bit for bit, with the logs read,
    their rings perceived and their points labelled once for them all; each summary's wall
    time is that of training them together."""
    started = time.perf_counter()
    if until_minute is not None and not (math.isfinite(until_minute) and until_minute >= 0):
        raise BadInput(f"--until-minute {until_minute:g} must be a number of minutes >= 0")
    logs = [read_log(path) for path in paths]
    refuse_repeated([(log.path, log.sha256) for log in logs], "log")
    robot = common_robot(logs)
    made_by, differing = training_method(logs, as_choice(method))
    params = train_params(made_by, symmetric, init_velocity_mps)
    check_init_velocity(params, robot)
    fams = [Fam(c, [t.name for t in robot.trajectories], params.init_velocity_mps) for c in configs]
    sessions, repeats = distinct_sessions(logs)
    until_s = None if until_minute is None else until_minute * 60.0
    chosen = [
        (perceived_session(session_to_train(s, until_s), made_by.memory, robot), s)
        for s in sessions
    ]
    if true_labels:
        total = _train_true(fams, chosen, robot, params, on_progress)
    else:
        learnt = [learnt for learnt, _ in chosen]
        total = train_sessions_each(fams, learnt, robot, params, on_progress)
    wall_s = time.perf_counter() - started
    return [
        TrainSummary(
            fam=fam,
            robot=robot,
            made_by=made_by,
            training=params,
            provenance={
                **provenance(logs, params, fam.config, differing),
                "until_minute": until_minute,
                "repeated_sessions": [r.text() for r in repeats],
                **({"labels_from": ORACLE_LABELS} if true_labels else {}),
            },
            exemplars=total,
            episodes=sum(len(learnt.episodes) for learnt, _ in chosen),
            rules_touched=_rules_touched(fam),
            rules_total=fam.config.rule_count,
            wall_s=wall_s,
            repeated_sessions=repeats,
        )
        for fam in fams
    ]


# What a FAM trained on the oracle labels records of them in its provenance.
ORACLE_LABELS = "the true map and pose: oracle labels, a reference, not a method"


def _rules_touched(fam: Fam) -> int:
    """How many of the FAM's rules were trained: those with experience of any trajectory."""
    tables = range(len(fam.config.tables))
    return sum(int(np.count_nonzero(fam.experience_table(t).sum(axis=1))) for t in tables)


def _train_true(
    fams: Sequence[Fam],
    chosen: list[tuple[SessionEpisodes, Session]],
    robot: RobotConfig,
    params: TrainParams,
    on_progress: Callable[[int, int], None],
) -> int:
    """Train each FAM on every trajectory of every point, labelled (once for them all) from
    its session's world and its true pose (the oracle labels); the exemplars read."""
    total = sum(e.exemplar_count for learnt, _ in chosen for e in learnt.episodes)
    done = 0
    reach = params.reach_m(robot)
    for learnt, session in chosen:
        world = parse_world(session.world_text, session.world_name)
        arcs = TrueArcs(world, robot, collision_clearance_m(robot))
        for episode in learnt.episodes:
            heard = HeardEpisode(episode, arcs.distances_m(episode.pose, reach))
            for fam in fams:
                train_heard(fam, heard, robot, params)
            done += episode.exemplar_count
            on_progress(done, total)
    return total


def write_trained(path: Path, trained: TrainSummary, overwrite: bool = True) -> None:
    """Write a trained FAM as `tvl train` does: with its robot, the method that made it (whose
    echo memory a run then reads through) and its provenance."""
    write_fam(
        path,
        trained.fam,
        robot_config=trained.robot,
        method=trained.made_by,
        provenance=trained.provenance,
        overwrite=overwrite,
    )


@dataclass(frozen=True, slots=True)
class Trained:
    """A FAM file trained and written as a request asked."""

    request: TrainRequest
    summary: TrainSummary

    def document(self) -> dict[str, Any]:
        r, summary = self.request, self.summary
        inputs = {
            "logs": [input_file(log) for log in r.logs],
            **config_input(r.config),
            "training": summary.training.settings(),
            "until_minute": r.until_minute,
            "method": summary.method_record(),
        }
        return document(
            "train",
            inputs,
            outputs={"fam": str(r.output)},
            config=summary.fam.config.name,
            episodes=summary.episodes,
            exemplars=summary.exemplars,
            rules_touched=summary.rules_touched,
            rules_total=summary.rules_total,
            wall_s=summary.wall_s,
            repeated_sessions=[asdict(found) for found in summary.repeated_sessions],
        )


def train(
    request: TrainRequest, on_progress: Callable[[int, int], None] = lambda done, total: None
) -> Trained:
    """Train a FAM of the request's configuration on its logs and write it as a FAM file."""
    config = resolve_fam_config(request.config, RobotConfig())
    summary = train_from_logs(
        request.logs,
        config,
        request.method,
        on_progress,
        request.until_minute,
        request.symmetric,
        request.init_velocity_mps,
    )
    write_trained(request.output, summary, overwrite=request.force)
    return Trained(request, summary)
