"""`tvl learn` end to end: a world file in, a log session (and optionally a FAM file) out,
surviving Ctrl-C and SIGTERM with every finished episode kept."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from tvl_cli.agent.drive import StepSink
from tvl_cli.agent.explore import Learner, LearnSummary, MinuteStats
from tvl_cli.agent.perception import perceived_episodes
from tvl_cli.analysis.coverage import CoverageTracker, world_floor
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DEFAULT_INIT_VELOCITY_MPS, FamConfig
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import MemoryConfig
from tvl_cli.core.method import DEFAULT, Method, method_record
from tvl_cli.core.robot_config import RobotConfig, sonar_model_name
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT, body_of, profile_name, robot_name
from tvl_cli.core.training import (
    SessionEpisodes,
    TrainParams,
    check_init_velocity,
    train_params,
    train_sessions,
)
from tvl_cli.io.atomic import check_writable
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.famfile import check_storable, read_fam, write_fam
from tvl_cli.io.interrupts import catching_signals
from tvl_cli.io.json_documents import (
    config_input,
    document,
    optional_file,
    output_path,
    world_input,
)
from tvl_cli.io.log_sessions import distinct_sessions, provenance
from tvl_cli.io.logfile import LogWriter
from tvl_cli.io.loglayout import KIND_LEARNING, ended_status
from tvl_cli.io.logreader import LearningLog, file_sha256, read_log
from tvl_cli.sim.worldmap import WorldMap, world_of

# Learning writes its episodes to the log a few at a time, once those held span this many
# simulated seconds (and at every minute's row, and when it stops): one write instead of
# several, and a kill loses at most the episodes of this last stretch.
LOG_WRITE_EVERY_S = 30.0


@dataclass(frozen=True, slots=True)
class LearnRequest:
    world: Path | WorldMap  # a world file, or a world made here (a generated one)
    log: Path
    seed: int
    config: str
    learn: LearnParams
    method: Method = DEFAULT  # its learning choices: labels, collision points, exploration,
    # sonar and echo memory
    fam_out: Path | None = None
    from_fam: Path | None = None  # start from this trained FAM (a new log only)
    symmetric: bool = True  # train each trajectory on its mirror image too (`--no-symmetric`)
    init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS  # every entry before training
    body: RobotConfig = DEFAULT_ROBOT  # the robot learning (`--robot`); the method's sonar
    # model hears its ring

    @property
    def robot(self) -> RobotConfig:
        return self.method.robot(self.body)

    @property
    def train(self) -> TrainParams:
        return train_params(self.method, self.symmetric, self.init_velocity_mps)

    def world_map(self) -> WorldMap:
        return world_of(self.world)

    @property
    def world_name(self) -> str:
        return self.world.name if isinstance(self.world, WorldMap) else self.world.stem


@dataclass(frozen=True, slots=True)
class LearnResult:
    request: LearnRequest
    session: str  # the log session written
    method: dict[str, Any]  # the method learnt by, as the log records it
    summary: LearnSummary
    wall_s: float
    status: str
    minute_coverage: list[float]  # at the end of each of summary.minutes
    coverage: float  # after every episode of the session

    def document(self) -> dict[str, Any]:
        r = self.request
        inputs = {
            "world": world_input(r.world),
            "seed": r.seed,
            **config_input(r.config),
            **r.learn.to_dict(),
            "training": r.train.settings(),
            "from_fam": optional_file(r.from_fam),
            "method": self.method,
            "robot": profile_name(r.body),
        }
        outputs = {"log": str(r.log), "fam": output_path(r.fam_out)}
        return document("learn", inputs, outputs=outputs, **self.session_record())

    def session_record(self) -> dict[str, Any]:
        """What the session did (`tvl learn`'s document, and `tvl demo`'s learning)."""
        s = self.summary
        return {
            "session": self.session,
            "status": self.status,
            "episodes": s.episodes,
            "collisions": s.collisions,
            "exemplars": s.exemplars,
            "sim_minutes": s.sim_s / 60.0,
            "coverage": self.coverage,
            "wall_s": self.wall_s,
            "minutes": [
                {"session": self.session, **asdict(m), "minute": m.minute + 1, "coverage": c}
                for m, c in zip(s.minutes, self.minute_coverage, strict=True)
            ],
        }


def learn_to_log(
    request: LearnRequest,
    on_minute: Callable[[MinuteStats], None] = lambda m: None,
    on_progress: Callable[[float], None] = lambda sim_s: None,
    watch: StepSink | None = None,
) -> LearnResult:
    """Explore the world, appending each whole episode to a new session of the log; each
    step shown to `watch` if given (a live view)."""
    world = request.world_map()
    method = request.method
    robot = request.robot
    check_init_velocity(request.train, robot)
    config = resolve_fam_config(request.config, robot)
    if request.fam_out is not None:  # refused now, not once the log has been learnt
        check_storable(config, request.config)
        check_writable(request.fam_out)
    log = read_log(request.log, empty_allowed=True) if request.log.exists() else None
    earlier = log.sessions if log is not None else []
    fam, started_from = _fam_to_learn_into(request, config, robot, log)
    learner = Learner(
        world,
        robot,
        fam,
        request.learn,
        method,
        request.seed,
        seed_stream=len(earlier),
        symmetric=request.symmetric,
    )
    started = time.perf_counter()
    with (
        _open_session(request, world, robot, config, len(earlier), started_from) as writer,
        catching_signals() as interrupted,
    ):
        if writer.session != f"{len(earlier):04d}":
            raise BadInput(f"{request.log}: another process added a session meanwhile")
        recording = _SessionRecording(
            writer, CoverageTracker(world_floor(world, robot)), on_minute, on_progress
        )
        summary = learner.run(recording.episode, recording.minute, interrupted.reason, watch)
        status = ended_status(summary.stopped_by)
        session = writer.session
        writer.close(status)
    if request.fam_out is not None:
        _write_online_fam(request, fam, config, summary, session, started_from)
    return LearnResult(
        request,
        session,
        method_record(method),
        summary,
        time.perf_counter() - started,
        status,
        recording.minute_coverage,
        recording.coverage.fraction,
    )


def _fam_to_learn_into(
    request: LearnRequest, config: FamConfig, robot: RobotConfig, log: LearningLog | None
) -> tuple[Fam, dict[str, Any]]:
    """The FAM the session learns into, and the file it started from as the log records it
    (empty for none): --from-fam's trained FAM, or a new one trained on the log's sessions."""
    if request.from_fam is not None:
        if log is not None and log.sessions:
            raise BadInput(
                f"{request.log}: already holds sessions; --from-fam starts a new log "
                "(a log goes on from its own sessions)"
            )
        fam = _fam_to_start_from(request.from_fam, config, robot, request.method.memory)
        return fam, {"path": str(request.from_fam), "sha256": file_sha256(request.from_fam)}
    fam = Fam(config, [t.name for t in robot.trajectories], request.train.init_velocity_mps)
    if log is not None:
        # A log goes on from what its sessions learnt, trained as `tvl train` would.
        sessions, _ = distinct_sessions([log])
        earlier_episodes = [
            SessionEpisodes(
                perceived_episodes(s.episodes(), request.method.memory, robot),
                ended=True,
                behaving=s.kind != KIND_LEARNING,
            )
            for s in sessions
        ]
        train_sessions(fam, earlier_episodes, robot, request.train)
    return fam, {}


def _open_session(
    request: LearnRequest,
    world: WorldMap,
    robot: RobotConfig,
    config: FamConfig,
    seed_stream: int,
    started_from: dict[str, Any],
) -> LogWriter:
    """The log's new learning session, its parameters recorded."""
    parameters = {
        "config": config.name,
        **request.learn.to_dict(),
        **request.train.settings(),
        "seed_stream": seed_stream,
        "from_fam": started_from or None,
    }
    return LogWriter.open(
        request.log,
        world_name=world.name,
        world_text=world.text,
        seed=request.seed,
        parameters=parameters,
        robot_config=robot.to_dict(),
        fam_config=config.to_dict(),
        write_every_s=LOG_WRITE_EVERY_S,
        method=request.method,
    )


@dataclass
class _SessionRecording:
    """Where the session's finished episodes and minutes go: the log, the floor they cover,
    and the caller's progress."""

    writer: LogWriter
    coverage: CoverageTracker
    on_minute: Callable[[MinuteStats], None]
    on_progress: Callable[[float], None]
    minute_coverage: list[float] = field(default_factory=list)  # at the end of each minute

    def episode(self, episode: Episode) -> None:
        self.writer.append_episode(episode)
        self.coverage.add(episode.pose)
        self.on_progress(episode.end_time_s)

    def minute(self, stats: MinuteStats) -> None:
        self.writer.append_minute(
            minute=stats.minute,
            episodes=stats.episodes,
            collisions=stats.collisions,
            exemplars=stats.exemplars,
            delta_v=stats.delta_v,
        )
        self.minute_coverage.append(self.coverage.fraction)
        self.on_minute(stats)


def _write_online_fam(
    request: LearnRequest,
    fam: Fam,
    config: FamConfig,
    summary: LearnSummary,
    session: str,
    started_from: dict[str, Any],
) -> None:
    """Write the FAM the session learnt into to --fam, once the log's writer has closed: its
    provenance hashes the finished log."""
    assert request.fam_out is not None
    if summary.episodes == 0:
        raise BadInput(
            f"{request.fam_out}: not written: no episode finished in "
            f"{request.learn.minutes:g} simulated minutes, so nothing was learnt "
            f"(the log {request.log} keeps the session; learn for longer)"
        )
    write_fam(
        request.fam_out,
        fam,
        robot_config=request.robot,
        method=request.method,
        provenance={
            **provenance([read_log(request.log)], request.train, config),
            "online_session": session,
            "from_fam": started_from or None,
        },
    )


def _fam_to_start_from(
    path: Path, config: FamConfig, robot: RobotConfig, memory: MemoryConfig
) -> Fam:
    """A trained FAM to go on learning into: of this robot and of the configuration asked for."""
    found = read_fam(path)
    theirs = found.robot_config
    if body_of(theirs) != body_of(robot):
        raise BadInput(
            f"{path}: FAM was learnt on {robot_name(theirs)}, not on {robot_name(robot)}; "
            "give --robot to match it"
        )
    if theirs != robot:
        raise BadInput(
            f"{path}: FAM was learnt hearing by the {sonar_model_name(theirs.sonar) or 'unnamed'} "
            f"sonar model, not the {sonar_model_name(robot.sonar)}; give --sonar to match it"
        )
    if found.fam.config != config:
        raise BadInput(
            f"{path}: FAM has configuration {found.fam.config.name!r}, not {config.name!r} "
            "(give --config to match it)"
        )
    if found.method.memory != memory:
        raise BadInput(
            f"{path}: FAM reads through another echo memory ({found.method.memory.kind}) than "
            f"this session's ({memory.kind}); give --memory to match it"
        )
    return found.fam
