"""`tvl replay`: what a learning log or a run trace holds, as numbers and pictures."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.analysis.coverage import coverage_by_minute, coverage_of, world_floor
from tvl_cli.core.contacts import EVENTS
from tvl_cli.core.errors import BadInput
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.hdf5_header import LOG_FORMAT, RUN_FORMAT, file_format
from tvl_cli.io.json_documents import document, input_file, output_path
from tvl_cli.io.loglayout import KIND_LEARNING, MINUTE_COLUMNS, STATUS_FINISHED
from tvl_cli.io.logreader import LearningLog, Session, read_log
from tvl_cli.io.runfile import RunTrace, read_run, recorded_paths
from tvl_cli.sim.worldmap import parse_world


@dataclass(frozen=True, slots=True)
class SessionSummary:
    """One session of a learning log, as `tvl replay` sums it up."""

    session: str
    kind: str  # KIND_LEARNING or KIND_BEHAVING
    world: str
    seed: int
    explore: str | None  # the exploration rule of a learning session; None for behaving
    status: str
    episodes: int
    collisions: int
    exemplars: int
    sim_minutes: float
    coverage: float  # share of the reachable floor the session's paths visited
    method: dict[str, Any] | None  # core.method.method_record; None: unrecorded


@dataclass(frozen=True, slots=True)
class LogReplay:
    """A learning log summed up: each session, and each whole minute of each."""

    sessions: list[SessionSummary]
    exemplars: int
    minutes: list[dict[str, str | int | float]]  # one per whole minute, learn's rows
    sessions_drawn: list[str] | None = None  # with --png
    animation_frames: int | None = None  # with --gif or --mp4

    kind = LOG_FORMAT

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": self.kind,
            "sessions": [asdict(s) for s in self.sessions],
            "exemplars": self.exemplars,
            "minutes": self.minutes,
            "sessions_drawn": self.sessions_drawn,
            "animation_frames": self.animation_frames,
        }


@dataclass(frozen=True, slots=True)
class StepCount:
    """How many steps of a run something took: an event began, a reflex drove, a
    trajectory was driven."""

    name: str
    steps: int
    at_s: list[float] | None = None  # an event's: when each began (the end of its step)


@dataclass(frozen=True, slots=True)
class RunReplay:
    """A run trace summed up: what the run was asked, what it measured, how its steps went.
    The counts by step are None for a trace that records no decisions (format_version 1)."""

    world: str
    parameters: dict[str, Any]
    steps: int
    metrics: dict[str, Any]
    events: list[StepCount] | None
    reflexes: list[StepCount] | None
    trajectories: list[StepCount] | None
    method: dict[str, Any] | None  # core.method.method_record; None: unrecorded
    status: str = STATUS_FINISHED  # or "interrupted: SIGINT": the run was stopped early
    animation_frames: int | None = None

    kind = RUN_FORMAT

    def to_dict(self) -> dict[str, Any]:
        def counts(found: list[StepCount] | None, what: str) -> list[dict[str, Any]] | None:
            if found is None:
                return None
            rows = [{what: c.name, "steps": c.steps} for c in found]
            if what == "event":
                rows = [{**row, "at_s": c.at_s} for row, c in zip(rows, found, strict=True)]
            return rows

        return {
            "format": self.kind,
            "world": self.world,
            "status": self.status,
            "parameters": self.parameters,
            "method": self.method,
            "steps": self.steps,
            "metrics": self.metrics,
            "events": counts(self.events, "event"),
            "reflexes": counts(self.reflexes, "reflex"),
            "trajectories": counts(self.trajectories, "trajectory"),
            "animation_frames": self.animation_frames,
        }


Replay = LogReplay | RunReplay


@dataclass(frozen=True, slots=True)
class Replayed:
    """A file replayed as asked: the file, the session chosen, the pictures drawn (None:
    not asked for) and its summary."""

    file: Path
    session: str | None
    pictures: dict[str, Path | None]  # png, curves, animation
    summary: Replay

    def document(self) -> dict[str, Any]:
        inputs = {"file": input_file(self.file), "session": self.session}
        outputs = {name: output_path(path) for name, path in self.pictures.items()}
        return document("replay", inputs, outputs=outputs, **self.summary.to_dict())


def _learning(
    log: LearningLog, png: Path | None, curves: Path | None, session: str | None
) -> LogReplay:
    sessions: list[SessionSummary] = []
    minutes: list[dict[str, str | int | float]] = []
    coverage: dict[str, list[float]] = {}  # by session: at the end of each whole minute
    for s in log.sessions:
        floor = world_floor(
            parse_world(s.world_text, f"{log.path} session {s.name}"), s.robot_config
        )
        exemplars = s.minutes[:, MINUTE_COLUMNS.index("exemplars")]
        coverage[s.name] = coverage_by_minute(floor, s.pose, exemplars)
        sessions.append(
            SessionSummary(
                session=s.name,
                kind=s.kind,
                world=s.world_name,
                seed=s.seed,
                explore=s.method.exploration if s.kind == KIND_LEARNING else None,
                status=s.status,
                episodes=len(s.episode_table),
                collisions=int(s.episode_table["bumped"].sum()),
                exemplars=s.exemplar_count,
                sim_minutes=_simulated_minutes(s),
                coverage=coverage_of(floor, s.pose),
                method=s.made_by.record(),
            )
        )
        minutes += [
            {"session": s.name, **_minute_row(row), "coverage": fraction}
            for row, fraction in zip(s.minutes, coverage[s.name], strict=True)
        ]
    chosen = _session(log, session)
    drawn_names = None
    if png is not None or curves is not None:
        from tvl_cli.render import plot  # matplotlib only when a picture is wanted

        if png is not None:
            # Every session in the chosen one's world, unless one was asked for.
            drawn = (
                [chosen]
                if session
                else [s for s in log.sessions if s.world_text == chosen.world_text]
            )
            world = parse_world(chosen.world_text, f"{log.path} session {chosen.name}")
            paths = [e.pose for s in drawn for e in s.episodes()]
            drawn_names = [s.name for s in drawn]
            names = ", ".join(drawn_names)
            plot.render_paths(world, paths, png, f"learning episodes, session {names}")
        if curves is not None:
            if not len(chosen.minutes):
                raise BadInput(f"{log.path}: session {chosen.name} has no whole learning minute")
            plot.render_learning_curves(
                chosen.minutes,
                MINUTE_COLUMNS,
                coverage[chosen.name],
                curves,
                f"learning in {chosen.world_name}, session {chosen.name}",
            )
    return LogReplay(sessions, log.exemplar_count, minutes, drawn_names)


def _simulated_minutes(session: Session) -> float:
    """How long a session learnt: a learning session that finished, the minutes it was asked
    for (it drove them all; the episode under way when time ran out is not kept); any other,
    to the end of its last episode kept."""
    asked = session.parameters.get("minutes")
    if session.kind == KIND_LEARNING and session.status == STATUS_FINISHED and asked:
        return float(asked)
    table = session.episode_table
    return float(table["end_time_s"][-1]) / 60.0 if len(table) else 0.0


def _minute_row(row: np.ndarray) -> dict[str, int | float]:
    """A log's minute row (stored as floats, the minute as its start, 0 for the first) as
    `tvl learn` gives it: counts as whole numbers, the minute counted from 1, ΔV a float."""
    values = {
        name: float(value) if name == "delta_v" else int(value)
        for name, value in zip(MINUTE_COLUMNS, row, strict=True)
    }
    return {**values, "minute": int(values["minute"]) + 1}


def _session(log: LearningLog, name: str | None) -> Session:
    """The session named (as '0001' or 1), or the last."""
    if name is None:
        return log.sessions[-1]
    for found in log.sessions:
        if found.name == name or (name.isdigit() and int(found.name) == int(name)):
            return found
    names = ", ".join(s.name for s in log.sessions)
    raise BadInput(f"{log.path}: no session {name!r} (it has {names})")


def _step_counts(
    trace: RunTrace,
) -> tuple[list[StepCount], list[StepCount], list[StepCount]] | tuple[None, None, None]:
    """How many steps began each event (and when), were taken by each reflex, and drove
    each trajectory: a robot that keeps to the sharp arcs is slow however few things it
    meets."""
    if not trace.has_decisions:
        return None, None, None
    period_s = trace.period_s
    events = []
    for event in EVENTS:
        steps = trace.event_steps(event)
        # The time an event began: the end of the step that began it.
        at_s = [float(i + 1) * period_s for i in steps]
        events.append(StepCount(event, len(steps), at_s))
    overridden = trace.arrays["reflex"]
    reflexes = [
        StepCount(name, int((overridden == index).sum()))
        for index, name in enumerate(trace.reflex_names)
    ]
    driven = trace.arrays["trajectory"]
    trajectories = [
        StepCount(t["name"], int((driven == index).sum()))
        for index, t in enumerate(trace.robot_config.get("trajectories", ()))
    ]
    return events, reflexes, trajectories


def _run(trace: RunTrace, path: Path, png: Path | None) -> RunReplay:
    if png is not None:
        from tvl_cli.render import plot

        world = parse_world(trace.world_text, trace.world_name)
        goal = trace.parameters.get("goal")
        plot.render_path(
            world,
            trace.arrays["pose"],
            trace.arrays["speed_mps"],
            plot.path_marks(trace.arrays["events"])
            if trace.has_decisions
            else plot.bump_marks(trace.arrays["bumped"]),
            png,
            title=f"{trace.parameters.get('behaviour')} in {trace.world_name}",
            goal=tuple(goal) if goal else None,
            robot=RobotConfig.from_dict(trace.robot_config),
        )
    events, reflexes, trajectories = _step_counts(trace)
    return RunReplay(
        trace.world_name,
        _parameters(trace, path),
        trace.steps,
        trace.metrics,
        events,
        reflexes,
        trajectories,
        trace.made_by.record(),
        trace.status,
    )


def _parameters(trace: RunTrace, path: Path) -> dict[str, Any]:
    """The run's parameters as its trace keeps them, the FAM as a file (its path from here:
    where it is, else where the trace says it was; and its SHA-256); the sonars each table
    reads, which only the autopsy needs, left out."""
    parameters = {
        key: value
        for key, value in trace.parameters.items()
        if key not in ("sonars_read", "fam", "fam_sha256")
    }
    if "fam" in trace.parameters:
        places = recorded_paths(str(trace.parameters["fam"]), path)
        parameters["fam"] = {
            "path": str(next((p for p in places if p.is_file()), places[0])),
            "sha256": trace.parameters.get("fam_sha256"),
        }
    return parameters


@dataclass(frozen=True, slots=True)
class Animation:
    """An animation to write (a GIF, or an MP4 by its suffix): where, which window, how fast."""

    out: Path
    from_s: float | None = None
    to_s: float | None = None
    every: int | None = None
    fps: int = 10
    video: bool = False  # an MP4 rather than a GIF


def replay(
    path: Path,
    png: Path | None = None,
    curves: Path | None = None,
    session: str | None = None,
    animation: Animation | None = None,
    on_frame: Callable[[int, int], None] | None = None,
) -> Replay:
    """Summarise a learning log or a run trace; draw its paths (and learning curves): a
    log's sessions in one world, or the one named by `session`; animate a run, telling
    `on_frame` (frames drawn, frames in all) after each frame."""
    kind = file_format(path)
    if kind == RUN_FORMAT:
        if curves is not None:
            raise BadInput(f"{path}: a run trace has no learning curves (--curves is for logs)")
        if session is not None:
            raise BadInput(f"{path}: a run trace has no sessions (--session is for logs)")
        trace = read_run(path)
        run = _run(trace, path, png)
        if animation is not None:
            from tvl_cli.render.animate import Window, animate_run  # matplotlib: only here

            window = Window(animation.from_s, animation.to_s, animation.every)
            frames = animate_run(
                trace, animation.out, window, animation.fps, animation.video, on_frame
            )
            return replace(run, animation_frames=frames)
        return run

    if kind == LOG_FORMAT:
        log = read_log(path)
        summary = _learning(log, png, curves, session)
        if animation is not None:
            from tvl_cli.render.animate import Window, animate_session  # matplotlib: only here

            window = Window(animation.from_s, animation.to_s, animation.every)
            chosen = _session(log, session)
            frames = animate_session(
                chosen, animation.out, window, animation.fps, animation.video, on_frame
            )
            return replace(summary, animation_frames=frames)
        return summary
    raise BadInput(f"{path}: is a {kind} file; replay reads tvl-log and tvl-run files")
