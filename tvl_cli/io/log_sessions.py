"""What learning logs' sessions record, read as one: the robot and echo memory they share, the
method each was learnt by, which sessions repeat another, and the provenance of a FAM trained
on them."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import takewhile
from typing import Any

from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import FamConfig
from tvl_cli.core.memory import NO_MEMORY, PATCHES, MemoryConfig
from tvl_cli.core.method import (
    DEFAULT,
    LEARNING_FIELDS,
    LEAST_EXPERIENCE,
    Method,
    MethodChoice,
    method_from_dict,
    method_record,
)
from tvl_cli.core.robot_config import RobotConfig, sonar_model_name
from tvl_cli.core.training import TrainParams
from tvl_cli.io.loglayout import KIND_LEARNING
from tvl_cli.io.logreader import LearningLog, Session


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


def finished_episodes(session: Session, until_s: float | None = None) -> list[Episode]:
    """The session's episodes; with `until_s`, only those finished by then (a snapshot of
    what the learner knew at that time)."""
    episodes = session.episodes()
    if until_s is None:
        return episodes
    return list(takewhile(lambda e: e.end_time_s <= until_s, episodes))


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
    first_with: dict[MemoryConfig, str] = {}  # each memory, and the first session of it
    for log in logs:
        for s in log.sessions:
            where = f"session {s.name}" if len(logs) == 1 else f"{log.path} session {s.name}"
            first_with.setdefault(session_memory(s, str(log.path)), where)
    if len(first_with) > 1:
        mixed = "; ".join(f"{where}: {memory_text(m)}" for m, where in first_with.items())
        raise BadInput(
            f"{logs[0].path}: sessions learnt through different echo memories ({mixed}), and "
            "a FAM reads through one: give --memory and its settings (--memory-window, "
            "--memory-range, --memory-patch) to train every session through it"
        )
    return next(iter(first_with), NO_MEMORY)


def memory_text(memory: MemoryConfig) -> str:
    """An echo memory in words, every setting that tells it from another."""
    if not memory.remembers:
        return "none (the live ring)"
    patch = f", patch {memory.patch_m:g} m" if memory.kind == PATCHES else ""
    return f"{memory.kind}, window {memory.window_s:g} s, range {memory.range_m:g} m{patch}"


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
