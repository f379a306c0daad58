"""How a learning log and a run trace look summed up in a terminal (`tvl replay`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tvl_cli.cli.console import out
from tvl_cli.cli.tables import (
    GOAL_METRICS,
    NOTHING,
    cell,
    facts,
    label,
    labelled,
    percent,
    table,
)
from tvl_cli.core.method import describe_record
from tvl_cli.core.words import counted

if TYPE_CHECKING:
    # Named for their types only: a command's `--help` imports this module.
    from tvl_cli.commands.replay import LogReplay, Replay, RunReplay


def replay(summary: Replay) -> None:
    from tvl_cli.commands.replay import RunReplay  # loaded already: it made the summary

    if isinstance(summary, RunReplay):
        _run_replay(summary)
    else:
        _log_replay(summary)
    if summary.animation_frames is not None:
        out.print(f"animation: {counted(summary.animation_frames, 'frame')}")


LEARNT_COLUMNS = (
    "session",
    "episodes",
    "collisions",
    "exemplars",
    "simulated minutes",
    "coverage",
)


def _log_replay(summary: LogReplay) -> None:
    # Two tables of a row a session, each narrow enough for 80 columns.
    sessions = table(
        "session",
        "kind",
        "world",
        "seed",
        "explore",
        "status",
        title=f"learning log: {counted(len(summary.sessions), 'session')}, "
        f"{counted(summary.exemplars, 'exemplar')}",
        right=("seed",),
    )
    learnt = table(*LEARNT_COLUMNS, title="what each session learnt", right=LEARNT_COLUMNS[1:])
    for s in summary.sessions:
        sessions.add_row(s.session, s.kind, s.world, str(s.seed), cell(s.explore), s.status)
        learnt.add_row(
            s.session,
            str(s.episodes),
            str(s.collisions),
            str(s.exemplars),
            f"{s.sim_minutes:.1f}",
            percent(s.coverage),
        )
    out.print(sessions)
    out.print(learnt)
    for s in summary.sessions:
        out.print(f"session {s.session} method: {describe_record(s.method)}")
    if summary.sessions_drawn is not None:
        out.print(f"sessions drawn: {', '.join(summary.sessions_drawn)}")


# A run's events table lists when each event began, the first few of them: a run of spins
# has hundreds, and a row must stay one line.
LISTED_TIMES = 5


def _first_times(at_s: list[float]) -> str:
    """When an event began, the first LISTED_TIMES times and how many more."""
    if not at_s:
        return NOTHING
    shown = ", ".join(f"{t:.1f}" for t in at_s[:LISTED_TIMES])
    more = len(at_s) - LISTED_TIMES
    return f"{shown} … +{more}" if more > 0 else shown


def _run_replay(summary: RunReplay) -> None:
    parameters = {**summary.parameters}
    fam = parameters.pop("fam", None)
    shown = [
        ("world", summary.world),
        ("method", describe_record(summary.method)),
        ("steps", summary.steps),
        ("ended", summary.status),
    ]
    if fam is not None:
        shown.append(("FAM", fam["path"]))
    out.print(facts([*shown, *((label(k), v) for k, v in parameters.items())], title="run trace"))
    metrics = dict(summary.metrics)
    if summary.parameters.get("goal") is None:  # a run that sought no goal
        for key in GOAL_METRICS:
            metrics.pop(key, None)
    out.print(labelled(metrics, title="metrics"))
    if summary.events is None:
        out.print("decisions: not recorded (a format_version 1 trace)")
        return
    events = table("event", "times", "began at (s)", title="events", right=("times",))
    for e in summary.events:
        events.add_row(e.name, str(e.steps), _first_times(e.at_s or []))
    out.print(events)
    steps = table("taken by", "steps", title="steps", right=("steps",))
    for r in summary.reflexes or []:
        steps.add_row(f"reflex {r.name}", str(r.steps))
    for t in summary.trajectories or []:
        steps.add_row(f"driving {t.name}", str(t.steps))
    out.print(steps)
