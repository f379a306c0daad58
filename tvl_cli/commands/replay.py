"""`tvl replay`: what a learning log or a run trace holds, as numbers and pictures."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tvl_cli.agent.novelty import explore_rule
from tvl_cli.analysis.coverage import coverage_by_minute, coverage_of
from tvl_cli.commands.learn import world_floor
from tvl_cli.core.contacts import BUMP, EVENTS, NEAR_MISS, TRAPPED
from tvl_cli.core.errors import BadInput
from tvl_cli.io.loglayout import KIND_LEARNING, MINUTE_COLUMNS
from tvl_cli.io.logreader import LearningLog, Session, read_log
from tvl_cli.io.runfile import RunTrace, read_run
from tvl_cli.io.schema import LOG_FORMAT, RUN_FORMAT, file_format
from tvl_cli.sim.worldmap import parse_world


@dataclass(frozen=True, slots=True)
class Replay:
    """A summary: a title, rows of (label, value), and per-minute rows for a learning log."""

    kind: str  # the file format
    facts: list[tuple[str, Any]]
    minutes: list[dict[str, str | float]] | None = None  # a learning log's; None for a run

    def to_dict(self) -> dict[str, Any]:
        """The facts by label; a learning log's per-minute rows under `minutes` (a run's
        `minutes` is its length, one of its parameters)."""
        rows = {} if self.minutes is None else {"minutes": self.minutes}
        return {"format": self.kind, **dict(self.facts), **rows}


def _learning(
    log: LearningLog, png: Path | None, curves: Path | None, session: str | None
) -> Replay:
    facts: list[tuple[str, Any]] = [("sessions", len(log.sessions))]
    minutes: list[dict[str, str | float]] = []
    coverage: dict[str, list[float]] = {}  # by session: at the end of each whole minute
    for s in log.sessions:
        collisions = int(s.episode_table["bumped"].sum())
        sim_s = float(s.episode_table["end_time_s"][-1]) if len(s.episode_table) else 0.0
        floor = world_floor(
            parse_world(s.world_text, f"{log.path} session {s.name}"), s.robot_config
        )
        exemplars = s.minutes[:, MINUTE_COLUMNS.index("exemplars")]
        coverage[s.name] = coverage_by_minute(floor, s.pose, exemplars)
        whole = coverage_of(floor, s.pose)
        explore = f"explore {explore_rule(s.parameters)}, " if s.kind == KIND_LEARNING else ""
        facts.append(
            (
                f"session {s.name}",
                f"{s.world_name}, seed {s.seed}, {explore}{s.status}: "
                f"{len(s.episode_table)} episodes, {collisions} collisions, "
                f"{s.exemplar_count} exemplars, {sim_s / 60:.1f} simulated min, "
                f"coverage {whole:.0%}",
            )
        )
        minutes += [
            {
                "session": s.name,
                **dict(zip(MINUTE_COLUMNS, map(float, row), strict=True)),
                "coverage": fraction,
            }
            for row, fraction in zip(s.minutes, coverage[s.name], strict=True)
        ]
    facts.append(("exemplars", log.exemplar_count))
    chosen = _session(log, session)
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
            names = ", ".join(s.name for s in drawn)
            facts.append(("sessions drawn", names))
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
    return Replay(LOG_FORMAT, facts, minutes)


def _session(log: LearningLog, name: str | None) -> Session:
    """The session named (as '0001' or 1), or the last."""
    if name is None:
        return log.sessions[-1]
    for found in log.sessions:
        if found.name == name or (name.isdigit() and int(found.name) == int(name)):
            return found
    names = ", ".join(s.name for s in log.sessions)
    raise BadInput(f"{log.path}: no session {name!r} (it has {names})")


# Events a person looks for first, each listed with the times the steps began them.
LISTED_EVENTS = (BUMP, NEAR_MISS, TRAPPED)


def _events(trace: RunTrace) -> list[tuple[str, Any]]:
    """How many steps began each event, and when the contacts and traps happened."""
    if not trace.has_decisions:
        return [("decisions", "not recorded (a format_version 1 trace)")]
    period_s = trace.period_s
    facts: list[tuple[str, Any]] = []
    for event in EVENTS:
        steps = trace.event_steps(event)
        facts.append((f"events: {event}", len(steps)))
        if event in LISTED_EVENTS and len(steps):
            # The time an event began: the end of the step that began it.
            facts.append((f"{event} at (s)", [round(float(i + 1) * period_s, 1) for i in steps]))
    overridden = trace.arrays["reflex"]
    for index, name in enumerate(trace.reflex_names):
        facts.append((f"steps taken by reflex {name}", int((overridden == index).sum())))
    # Which trajectories carried the run: a robot that keeps to the sharp arcs is slow
    # however few things it meets.
    driven = trace.arrays["trajectory"]
    for index, trajectory in enumerate(trace.robot_config.get("trajectories", ())):
        facts.append((f"steps driving {trajectory['name']}", int((driven == index).sum())))
    return facts


def _run(trace: RunTrace, png: Path | None) -> Replay:
    facts: list[tuple[str, Any]] = [
        ("world", trace.world_name),
        *trace.parameters.items(),
        ("steps", trace.steps),
        *trace.metrics.items(),
        *_events(trace),
    ]
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
        )
    return Replay(RUN_FORMAT, facts)


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
        summary = _run(trace, png)
        if animation is not None:
            from tvl_cli.render.animate import Window, animate_run  # matplotlib: only here

            window = Window(animation.from_s, animation.to_s, animation.every)
            frames = animate_run(
                trace, animation.out, window, animation.fps, animation.video, on_frame
            )
            summary.facts.append(("animation frames", frames))
        return summary

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
            summary.facts.append(("animation frames", frames))
        return summary
    raise BadInput(f"{path}: is a {kind} file; replay reads tvl-log and tvl-run files")
