"""`tvl train`: rebuild a FAM from learning logs alone (log replay)."""

from __future__ import annotations

import hashlib
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from itertools import takewhile
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.agent.perception import replayed_rings
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import DEFAULT_INIT_VELOCITY_MPS, Fam
from tvl_cli.core.fam_config import FamConfig
from tvl_cli.core.memory import NO_MEMORY, MemoryConfig
from tvl_cli.core.method import (
    DEFAULT,
    LEARNING_FIELDS,
    LEAST_EXPERIENCE,
    NOT_GIVEN,
    Method,
    MethodChoice,
    as_choice,
    method_from_dict,
    method_record,
)
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig, sonar_model_name
from tvl_cli.core.training import TrainParams, train_episode, train_params
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.loglayout import KIND_LEARNING
from tvl_cli.io.logreader import LearningLog, Session, read_log


@dataclass(frozen=True, slots=True)
class RepeatedSession:
    """A log session recorded again (a log copied into another, or one learnt twice from
    the same seed stream), and the session it repeats, which alone was used."""

    log: str
    session: str
    repeats_log: str
    repeats_session: str

    def text(self) -> str:
        """As a FAM's provenance and the summary tables give it."""
        return (
            f"{self.log} session {self.session} repeats {self.repeats_log} session "
            f"{self.repeats_session}"
        )


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
    memory: MemoryConfig  # what the FAM was trained to read through
    method: dict[str, Any]  # method_record of the learning choices that made it
    training: TrainParams  # how its exemplars became entries
    provenance: dict[str, Any]
    exemplars: int
    episodes: int
    rules_touched: int
    rules_total: int
    wall_s: float
    repeated_sessions: list[RepeatedSession] = field(default_factory=list)  # trained once


def common_robot(logs: Sequence[LearningLog]) -> RobotConfig:
    """The one robot configuration of every session; BadInput naming the first that differs."""
    first = logs[0].sessions[0].robot_config
    for log in logs:
        for session in log.sessions:
            if session.robot_config != first:
                raise BadInput(
                    f"{log.path}: session {session.name} was recorded with another robot "
                    f"configuration than {logs[0].path} session {logs[0].sessions[0].name}; "
                    "logs of different robots cannot train one FAM"
                )
    return first


def refuse_repeated(files: Sequence[tuple[Path, str]], what: str) -> None:
    """Refuse one file given twice, by content: (path, SHA-256) pairs, `what` naming the kind
    ("log"). The same log twice would train every exemplar twice; the same FAM twice would
    be compared with itself."""
    seen: dict[str, Path] = {}
    for path, sha256 in files:
        if sha256 in seen:
            raise BadInput(f"{path}: the same {what} as {seen[sha256]}, given twice")
        seen[sha256] = path


def distinct_sessions(
    logs: Sequence[LearningLog],
) -> tuple[list[Session], list[RepeatedSession]]:
    """Every session of the logs in order, but each recorded more than once only the first
    time; and the repeats."""
    first: dict[bytes, tuple[str, str]] = {}
    kept: list[Session] = []
    repeats: list[RepeatedSession] = []
    for log in logs:
        for session in log.sessions:
            # Each episode's start, length, trajectory, ending time and place: two sessions
            # agree on all of them only if one repeats the other.
            key = hashlib.sha256(session.episode_table.tobytes()).digest()
            if len(session.episode_table) and key in first:
                repeats.append(RepeatedSession(str(log.path), session.name, *first[key]))
                continue
            first.setdefault(key, (str(log.path), session.name))
            kept.append(session)
    return kept, repeats


def session_memory(session: Session, where: str) -> MemoryConfig:
    """The echo memory a session was learnt through; none for one that does not say (all
    sessions written before there was a memory)."""
    try:
        return MemoryConfig.from_dict(session.parameters.get("memory") or {})
    except BadInput as error:
        raise BadInput(f"{where} session {session.name}: {error}") from None


def common_memory(logs: Sequence[LearningLog]) -> MemoryConfig:
    """The one echo memory all the logs' sessions were learnt through; BadInput if they differ,
    since one FAM reads through one memory."""
    found = {
        (str(log.path), s.name): session_memory(s, str(log.path))
        for log in logs
        for s in log.sessions
    }
    memories = set(found.values())
    if len(memories) > 1:
        raise BadInput(
            "the sessions were learnt through different echo memories "
            f"({', '.join(sorted(m.kind for m in memories))}); give --memory to choose one"
        )
    return memories.pop() if memories else NO_MEMORY


def explore_rule(parameters: dict[str, Any]) -> str:
    """The exploration rule a log session's parameters name; sessions written before there
    was a choice followed the paper's."""
    return str(parameters.get("explore", LEAST_EXPERIENCE))


def session_method(session: Session, where: str) -> Method:
    """The method a learning session was learnt by: as it records it, or as its parameters
    and robot say (sessions written before the method was recorded)."""
    if session.method is not None:
        return method_from_dict(session.method, f"{where} session {session.name} method")
    parameters = session.parameters
    return Method(
        decel_mps2=float(parameters.get("decel_mps2", DEFAULT.decel_mps2)),
        margin_m=float(parameters.get("margin_m", DEFAULT.margin_m)),
        near_m=float(parameters.get("near_m", DEFAULT.near_m)),
        exploration=explore_rule(parameters),
        sonar=sonar_model_name(session.robot_config.sonar) or DEFAULT.sonar,
        memory=session_memory(session, where),
    )


def training_method(
    logs: Sequence[LearningLog], choice: MethodChoice
) -> tuple[Method, dict[str, Any]]:
    """The method a FAM trained from the logs is made by, and its record: the labels and
    memory chosen (ours, reading through the sessions' own memory, unless chosen); the
    collision points, exploration and sonar of the learning sessions. Sessions of different
    memories need a memory chosen; sessions that learnt differently are named in the record."""
    try:
        memory = common_memory(logs)
    except BadInput:
        if choice.method is None and choice.memory.kind is None:
            raise
        memory = NO_MEMORY
    learnt = [
        session_method(s, str(log.path))
        for log in logs
        for s in log.sessions
        if s.kind == KIND_LEARNING
    ]
    first = learnt[0] if learnt else DEFAULT
    inherited = Method(
        near_m=first.near_m,
        exploration=first.exploration,
        sonar=sonar_model_name(logs[0].sessions[0].robot_config.sonar) or DEFAULT.sonar,
        memory=memory,
    )
    method = choice.over(inherited, ("decel_mps2", "margin_m", "memory"))
    record = method_record(method, LEARNING_FIELDS)
    differing = sorted({n for m in learnt for n in m.differs(first, ("near_m", "exploration"))})
    if differing:
        # The first session's are recorded; the others learnt otherwise.
        record = {**record, "preset": None, "sessions_differ_in": differing}
    return method, record


def perceived_episodes(
    session: Session, memory: MemoryConfig, robot: RobotConfig, until_s: float | None = None
) -> list[Episode]:
    """The session's episodes with what the FAM reads at each exemplar through `memory`: the
    exemplars' readings replayed into the memory in order, as a learner perceived them. With
    `until_s`, only the episodes finished by then: the memory is replayed no further, since
    what it held later cannot change what it read before."""
    episodes = session.episodes()
    if until_s is not None:
        episodes = list(takewhile(lambda e: e.end_time_s <= until_s, episodes))
    if not memory.remembers or not episodes:
        return episodes
    count = sum(e.exemplar_count for e in episodes)
    virtual = replayed_rings(
        memory,
        robot,
        np.concatenate([e.steps(robot.control_period_s) for e in episodes]),
        session.odometry[:count],
        mm_to_ring(session.ring_mm[:count]),
    )
    starts = np.cumsum([0] + [e.exemplar_count for e in episodes])
    return [
        replace(episode, fam_ring_m=virtual[start : start + episode.exemplar_count])
        for episode, start in zip(episodes, starts, strict=False)
    ]


def train_on(
    fam: Fam,
    episodes: Sequence[Episode],
    robot: RobotConfig,
    params: TrainParams,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
) -> int:
    """Train the FAM on the episodes in order, as the online learner did; the exemplars used."""
    total = sum(e.exemplar_count for e in episodes)
    done = 0
    for episode in episodes:
        train_episode(fam, episode, robot, params)
        done += episode.exemplar_count
        on_progress(done, total)
    return total


def provenance(logs: Sequence[LearningLog], params: TrainParams, config: FamConfig) -> dict:
    """Everything needed to rebuild the FAM: its sources and every training parameter."""
    return {
        "logs": [
            {
                "path": str(log.path),
                "sha256": log.sha256,
                "sessions": [
                    {
                        "name": s.name,
                        "world": s.world_name,
                        "seed": s.seed,
                        # How it chose where to learn; a behaving session did not explore.
                        "explore": explore_rule(s.parameters) if s.kind == KIND_LEARNING else None,
                        "status": s.status,
                        "episodes": len(s.episode_table),
                        "exemplars": s.exemplar_count,
                    }
                    for s in log.sessions
                ],
            }
            for log in logs
        ],
        "training": {"config": config.name, **params.to_dict()},
    }


def train_from_logs(
    paths: Sequence[Path],
    config: FamConfig,
    method: Method | MethodChoice = NOT_GIVEN,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
    until_minute: float | None = None,
    symmetric: bool = True,
    init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS,
) -> TrainSummary:
    """Train a new FAM on every episode of every log, in log, session and episode order;
    with `until_minute`, only on the episodes each session finished by then (a snapshot of
    what the learner knew at that minute). The labels are the method's (ours when none is
    chosen); the FAM reads through the memory the sessions were learnt through unless the
    method or its settings say otherwise, its virtual rings replayed from the exemplars."""
    started = time.perf_counter()
    if until_minute is not None and not (math.isfinite(until_minute) and until_minute >= 0):
        raise BadInput(f"--until-minute {until_minute:g} must be a number of minutes >= 0")
    logs = [read_log(path) for path in paths]
    refuse_repeated([(log.path, log.sha256) for log in logs], "log")
    robot = common_robot(logs)
    made_by, record = training_method(logs, as_choice(method))
    memory_read = made_by.memory
    params = train_params(made_by, symmetric, init_velocity_mps)
    fam = Fam(config, [t.name for t in robot.trajectories], params.init_velocity_mps)
    sessions, repeats = distinct_sessions(logs)
    until_s = None if until_minute is None else until_minute * 60.0
    episodes = [e for s in sessions for e in perceived_episodes(s, memory_read, robot, until_s)]
    total = train_on(fam, episodes, robot, params, on_progress)
    tables = range(len(config.tables))
    touched = sum(int(np.count_nonzero(fam.experience_table(t).sum(axis=1))) for t in tables)
    return TrainSummary(
        fam=fam,
        robot=robot,
        memory=memory_read,
        method=record,
        training=params,
        provenance={
            **provenance(logs, params, config),
            "until_minute": until_minute,
            "repeated_sessions": [r.text() for r in repeats],
        },
        exemplars=total,
        episodes=len(episodes),
        rules_touched=touched,
        rules_total=config.rule_count,
        wall_s=time.perf_counter() - started,
        repeated_sessions=repeats,
    )


def write_trained(path: Path, trained: TrainSummary, overwrite: bool = True) -> None:
    """Write a trained FAM as `tvl train` does: with its robot, its provenance and the echo
    memory it was trained to read through, which a run then reads through."""
    write_fam(
        path,
        trained.fam,
        robot_config=trained.robot,
        provenance=trained.provenance,
        memory=trained.memory,
        method=trained.method,
        overwrite=overwrite,
    )


def train(
    request: TrainRequest, on_progress: Callable[[int, int], None] = lambda done, total: None
) -> TrainSummary:
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
    return summary
