"""What learning logs' sessions record, read as one: the robot and echo memory they share, the
method each was learnt by, which sessions repeat another, and the provenance of a FAM trained
on them."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass, replace
from itertools import takewhile

from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import FamConfig
from tvl_cli.core.memory import DEFAULT_MEMORY, NO_MEMORY, PATCHES, MemoryConfig
from tvl_cli.core.method import DEFAULT, FIELDS, SESSIONS_DIFFER_IN, Method, MethodChoice
from tvl_cli.core.robot_config import RobotConfig, sonar_model_name
from tvl_cli.core.training import SessionEpisodes, TrainParams
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


def session_to_train(session: Session, until_s: float | None = None) -> SessionEpisodes:
    """The session's episodes finished by `until_s` (all, given None) as its learner trained
    them: a session cut short had not ended, its last labels unheard; one learnt while
    behaving holds the stretches a behaviour drove."""
    episodes = finished_episodes(session, until_s)
    return SessionEpisodes(
        episodes,
        ended=len(episodes) == len(session.episode_table),
        behaving=session.kind != KIND_LEARNING,
    )


def common_memory(logs: Sequence[LearningLog]) -> MemoryConfig:
    """The one echo memory all the logs' sessions were learnt through; BadInput if they differ,
    since one FAM reads through one memory."""
    first_with: dict[MemoryConfig, str] = {}  # each memory, and the first session of it
    for log in logs:
        for s in log.sessions:
            where = f"session {s.name}" if len(logs) == 1 else f"{log.path} session {s.name}"
            first_with.setdefault(s.method.memory, where)
    if len(first_with) > 1:
        mixed = "; ".join(f"{where}: {memory_text(m)}" for m, where in first_with.items())
        raise BadInput(
            f"{logs[0].path}: sessions learnt through different echo memories ({mixed}), and "
            "a FAM reads through one: give --memory and its settings (--memory-window, "
            "--memory-range, --memory-patch, --memory-clearing) to train every session through it"
        )
    return next(iter(first_with), NO_MEMORY)


def memory_text(memory: MemoryConfig) -> str:
    """An echo memory in words, every setting that tells it from another."""
    if not memory.remembers:
        return "none (the live ring)"
    patch = f", patch {memory.patch_m:g} m" if memory.kind == PATCHES else ""
    # Said when not ours, as a setting left at its default goes unsaid.
    clearing = f", clearing {memory.clearing}" if memory.clearing != DEFAULT_MEMORY.clearing else ""
    return (
        f"{memory.kind}, window {memory.window_s:g} s, range {memory.range_m:g} m{patch}{clearing}"
    )


# The learning choices of a session that a FAM trained on it keeps as they were: where the
# collision points fell and how exploration chose where to go are in what was recorded.
_LEARNT_AS_RECORDED = ("near_m", "exploration")


def training_method(logs: Sequence[LearningLog], choice: MethodChoice) -> tuple[Method, list[str]]:
    """The method a FAM trained from the logs is made by: the labels, memory and behaving
    choices chosen (ours, reading through the sessions' own memory, unless chosen), the
    collision points and exploration of the first learning session, and the sonar of the
    logs' robot; and the
    fields in which the learning sessions differ from the first (then the first's are
    recorded). Sessions of different memories need a memory chosen."""
    try:
        memory = common_memory(logs)
    except BadInput:
        if choice.method is None and choice.memory.kind is None:
            raise
        memory = NO_MEMORY
    learnt = [s.method for log in logs for s in log.sessions if s.kind == KIND_LEARNING]
    first = learnt[0] if learnt else DEFAULT
    inherited = replace(
        DEFAULT,
        **{n: getattr(first, n) for n in _LEARNT_AS_RECORDED},
        sonar=sonar_model_name(logs[0].sessions[0].robot_config.sonar) or DEFAULT.sonar,
        memory=memory,
    )
    # The chosen method gives the rest: its labels and memory, and the behaving choices it
    # records for the runs of the FAM.
    own = tuple(n for n in FIELDS if n not in (*_LEARNT_AS_RECORDED, "sonar"))
    method = choice.over(inherited, own)
    differing = sorted({n for m in learnt for n in m.differs(first, _LEARNT_AS_RECORDED)})
    return method, differing


def provenance(
    logs: Sequence[LearningLog],
    params: TrainParams,
    config: FamConfig,
    sessions_differ_in: Sequence[str] = (),
) -> dict:
    """Everything needed to rebuild the FAM beside its method: its sources, how its learning
    sessions differ from the first's (whose choices its method keeps), and the training
    settings that are not the method's."""
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
                        "exploration": s.method.exploration if s.kind == KIND_LEARNING else None,
                        "status": s.status,
                        "episodes": len(s.episode_table),
                        "exemplars": s.exemplar_count,
                    }
                    for s in log.sessions
                ],
            }
            for log in logs
        ],
        SESSIONS_DIFFER_IN: list(sessions_differ_in),
        "training": {"config": config.name, **params.settings()},
    }
