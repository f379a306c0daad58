"""How results look in a terminal: rich tables and progress bars, all on one console each."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tvl_cli.cli.console import err, folded, out, say
from tvl_cli.cli.fam_views import explanation
from tvl_cli.cli.tables import GOAL_METRICS, NOTHING, cell, facts, label, labelled, percent, table
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.method import describe_record
from tvl_cli.core.words import counted

if TYPE_CHECKING:
    # What is shown, named for its type only: a command's `--help` imports this module, and
    # importing these would load every command's machinery.
    from rich.progress import Progress

    from tvl_cli.agent.drive import Step, StepSink
    from tvl_cli.agent.explore import MinuteStats
    from tvl_cli.analysis.autopsy import Autopsy
    from tvl_cli.commands.demo import DemoResult
    from tvl_cli.commands.explain import StepExplanation
    from tvl_cli.commands.learn import LearnResult
    from tvl_cli.commands.run import RunResult
    from tvl_cli.core.metrics import RunMetrics
    from tvl_cli.sim.worldmap import WorldMap


def _bar(description: str) -> Progress:
    # Imported for a bar, not with the module: a command's `--help` imports this module.
    from rich.progress import (
        BarColumn,
        Progress,
        TaskProgressColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TaskProgressColumn(),
        TimeElapsedColumn(),
        TextColumn("elapsed,"),
        TimeRemainingColumn(),
        TextColumn("left"),
        console=err,
        transient=True,
        # A bar only for a person watching: scripts and pipes get clean stderr.
        disable=not err.is_terminal,
    )


@contextmanager
def progress(description: str, quiet: bool = False) -> Iterator[Callable[[int, int], None]]:
    """A progress bar fed with (done, total); none when `quiet`."""
    with _bar(description) as bar:
        task = bar.add_task(description, total=None, visible=not quiet)
        yield lambda done, total: bar.update(task, completed=done, total=total)


# Steps between updates of a run's bar: a few a second of wall time.
PROGRESS_EVERY_STEPS = 60


@contextmanager
def run_progress(minutes: float) -> Iterator[StepSink]:
    """A bar over a run's simulated time, fed with its steps."""
    with _bar("running") as bar:
        task = bar.add_task("running", total=minutes * 60.0)
        steps = 0

        def on_step(step: Step) -> None:
            nonlocal steps
            steps += 1
            if steps % PROGRESS_EVERY_STEPS == 0:
                bar.update(task, completed=step.time_s)

        yield on_step


@contextmanager
def learning_progress(
    minutes: float, quiet: bool
) -> Iterator[tuple[Callable[[MinuteStats], None], Callable[[float], None]]]:
    """A bar over simulated time with the last minute's episodes, collisions and ΔV."""
    with _bar("learning") as bar:
        task = bar.add_task("learning", total=minutes * 60.0, visible=not quiet)

        def on_minute(stats: MinuteStats) -> None:
            bar.update(
                task,
                description=(
                    f"minute {stats.minute + 1}: {counted(stats.episodes, 'episode')}, "
                    f"{counted(stats.collisions, 'collision')}, ΔV {stats.delta_v:.2e}"
                ),
            )

        def on_progress(sim_s: float) -> None:
            bar.update(task, completed=sim_s)

        yield on_minute, on_progress


def learn_summary(result: LearnResult, log: Path) -> None:
    s = result.summary
    minutes = table(
        "minute",
        "episodes",
        "collisions",
        "exemplars",
        label("delta_v"),
        "coverage",
        title=f"learning → {log} ({result.status})",
        right=("minute", "episodes", "collisions", "exemplars", label("delta_v"), "coverage"),
    )
    for m, coverage in zip(s.minutes, result.minute_coverage, strict=True):
        minutes.add_row(
            str(m.minute + 1),
            str(m.episodes),
            str(m.collisions),
            str(m.exemplars),
            f"{m.delta_v:.2e}",
            percent(coverage),
        )
    out.print(minutes)
    out.print(
        f"{counted(s.episodes, 'episode')}, {counted(s.collisions, 'collision')}, "
        f"{counted(s.exemplars, 'exemplar')} in "
        f"{s.sim_s / 60:.1f} simulated minutes, coverage {percent(result.coverage)} "
        f"({result.wall_s:.1f} s), session {result.session}"
    )
    out.print(f"method: {describe_record(result.method)}")


def step_explanation(e: StepExplanation) -> None:
    ring = " ".join(f"{r:.2f}" for r in e.ring_m) if e.ring_m else "not read"
    velocities = " ".join(NOTHING if v is None else f"{v:.2f}" for v in e.velocities_mps)
    remembered = (
        [("virtual ring (m), S0..S15", " ".join(f"{r:.2f}" for r in e.perceived_m))]
        if e.perceived_m
        else []
    )
    rows = [
        ("ring (m), S0..S15", ring),
        *remembered,
        ("view (rotation)", str(e.rotation)),
        ("perceived (m/s), T3L..T3R", velocities),
        ("fast set", ", ".join(e.fast) or "none"),
        ("policy's choice", e.choice or "none"),
        ("driven", e.driven or "none (spin, back-off or trapped)"),
        ("reflex", e.reflex or "none"),
        ("events", ", ".join(e.events) or "none"),
    ]
    out.print(facts(rows, title=f"step {e.step}, ending at {e.time_s:.1f} s"))
    if e.why is not None:
        out.print(f"why, for {' and '.join(e.focus) or 'every trajectory'}:")
        explanation(e.why)


def autopsy(a: Autopsy) -> None:
    """The contact autopsy: each contact, the causes counted, the time by class, and the
    slow time by cause."""
    contacts = table(
        "time (s)",
        "event",
        "cause",
        "obstacle",
        "driven",
        "reflex",
        title=counted(len(a.contacts), "contact"),
    )
    for c in a.contacts:
        f = c.facts
        contacts.add_row(
            f"{f.time_s:.1f}", f.event, c.cause, f.obstacle, cell(f.trajectory), cell(f.reflex)
        )
    out.print(contacts)
    causes = table("cause", "contacts", title="causes", right=("contacts",))
    for cause, count in a.causes.items():
        if count:
            causes.add_row(cause, str(count))
    out.print(causes)
    total = sum(a.time_s.values()) or 1.0
    time = table(
        "class", "time (s)", "share", title="where the time went", right=("time (s)", "share")
    )
    for name, seconds in a.time_s.items():
        time.add_row(name, f"{seconds:.1f}", percent(seconds / total))
    out.print(time)
    slow = table(
        "cause", "time (s)", "share", title="why it drove slowly", right=("time (s)", "share")
    )
    for cause, seconds in a.slow_time_s.items():
        if seconds:
            slow.add_row(cause, f"{seconds:.1f}", percent(seconds / total))
    out.print(slow)
    if a.goal_failure is not None:
        out.print(
            f"goal missed: {a.goal_failure} (came within {a.goal_closest_m:.2f} m of it)",
            highlight=False,
        )


def run_metrics(metrics: RunMetrics, method: dict[str, Any] | None = None) -> None:
    """The metrics of a run (what --json prints, in words; a goal's only if it sought one),
    and the method it ran by (its record)."""
    shown = asdict(metrics)
    if metrics.goal_reached is None:
        for key in GOAL_METRICS:
            del shown[key]
    out.print(labelled(shown))
    if method is not None:
        out.print(f"reflexes: {', '.join(method.get('reflexes') or []) or 'none'}")
        out.print(f"method: {describe_record(method)}")


def warn_of_other_worlds(log: Path, world: Path | WorldMap, given: str) -> None:
    """One line on stderr when a session of `world` (a file, or a world made here, as the
    user named it: `given`) goes into a log whose sessions learnt in another world: a FAM
    trained from the log learns from both, which may be meant (a general FAM) or a log named
    by mistake."""
    from tvl_cli.core.errors import BadInput
    from tvl_cli.io.logreader import session_worlds
    from tvl_cli.sim.worldmap import world_of

    if not log.exists():
        return
    try:
        earlier = session_worlds(log)
        adding = world_of(world)
    except BadInput:
        return  # the command refuses it in its own words, in one line
    others = sorted({name for text, name in earlier.items() if text != adding.text})
    if others:
        say(
            f"tvl: warning: {log}: adding a session in {adding.name} ({given}) to sessions "
            f"in {', '.join(others)}: a FAM trained from this log learns from every world in it"
        )


def stopped(signal_name: str, sim_s: float, trace: Path | None) -> None:
    """Why a run ended before its time, and what it kept."""
    kept = f"; {trace} keeps it" if trace is not None else ""
    say(f"stopped by {signal_name} after {sim_s:.1f} simulated seconds{kept}")


def run_learning(result: RunResult, log: Path | None) -> None:
    """What a --learn run learnt, and where it went."""
    learnt = result.learnt
    if learnt is None:
        return
    endings = ", ".join(f"{count} {how}" for how, count in learnt.endings.items())
    where = f"{log} session {result.session}" if log is not None else "the FAM in memory only"
    out.print(
        f"learnt while behaving: {learnt.episodes} episodes (collision points: {endings}), "
        f"{learnt.exemplars} exemplars → {where}"
    )


def demo(result: DemoResult) -> None:
    learn_summary(result.learning, result.directory / "learn.h5")
    columns = (
        "FAM",
        "behaviour",
        "contacts (/min)",
        "near misses",
        "speed (m/s)",
        "clearance (m)",
    )
    runs = table(
        *columns,
        title=f"behaviours after learning (threshold {DEFAULT_THRESHOLD:g})",
        right=columns[2:],
    )
    for row in result.rows:
        m = row.metrics
        runs.add_row(
            row.config,
            row.behaviour,
            f"{m.contacts_per_min:.2f}",
            str(m.near_misses),
            f"{m.mean_speed_mps:.2f}",
            f"{m.mean_wall_clearance_m or m.mean_clearance_m:.2f}",
        )
    out.print(runs)
    # A line a picture, whole: in a table's column a path folds into pieces.
    out.print("pictures:", *(f"  {row.png}" for row in result.rows), sep="\n", soft_wrap=True)


def markdown_summary(text: str) -> None:
    """A figure's summary (markdown: `### title`, pipe tables and notes) laid out for the
    terminal: each table as a table of the terminal's, each note folded at its width."""
    title: str | None = None
    rows: list[list[str]] = []
    for line in [*text.splitlines(), ""]:
        if line.startswith("|"):
            cells = [c.strip().replace("`", "") for c in line.strip().strip("|").split("|")]
            if not all(set(c) <= {"-", ":"} for c in cells):  # not the header's rule
                rows.append(cells)
            continue
        if rows:
            shown = table(*rows[0], title=title, right=rows[0][2:])
            for cells in rows[1:]:
                shown.add_row(*cells)
            out.print(shown)
            rows, title = [], None
        if line.startswith("### "):
            title = line.removeprefix("### ")
        elif line.strip():
            out.print(folded(line.replace("`", "")), soft_wrap=True, markup=False)
