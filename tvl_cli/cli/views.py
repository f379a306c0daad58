"""How results look in a terminal: rich tables and progress bars, all on one console each."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.console import Console
from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn
from rich.table import Table

from tvl_cli.core.behaviours import DEFAULT_THRESHOLD

if TYPE_CHECKING:
    # What is shown, named for its type only: a command's `--help` imports this module, and
    # importing these would load every command's machinery.
    from tvl_cli.agent.drive import Step, StepSink
    from tvl_cli.agent.explore import MinuteStats
    from tvl_cli.analysis.autopsy import Autopsy
    from tvl_cli.analysis.famdiff import FamDifference
    from tvl_cli.commands.demo import DemoResult
    from tvl_cli.commands.explain import StepExplanation
    from tvl_cli.commands.learn import LearnResult
    from tvl_cli.commands.replay import Replay
    from tvl_cli.commands.run import RunResult
    from tvl_cli.commands.sweep import SweepResult
    from tvl_cli.commands.train import TrainSummary
    from tvl_cli.core.explain import Explanation
    from tvl_cli.core.metrics import RunMetrics

out = Console(highlight=False)
err = Console(stderr=True, highlight=False)


def say(message: str) -> None:
    err.print(message)


def _bar(description: str) -> Progress:
    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TaskProgressColumn(),
        TimeElapsedColumn(),
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
                    f"minute {stats.minute + 1}: {stats.episodes} episodes, "
                    f"{stats.collisions} collisions, ΔV {stats.delta_v:.2e}"
                ),
            )

        def on_progress(sim_s: float) -> None:
            bar.update(task, completed=sim_s)

        yield on_minute, on_progress


def learn_json(result: LearnResult) -> dict[str, Any]:
    s = result.summary
    return {
        "episodes": s.episodes,
        "collisions": s.collisions,
        "exemplars": s.exemplars,
        "sim_minutes": s.sim_s / 60.0,
        "coverage": result.coverage,
        "wall_s": result.wall_s,
        "status": result.status,
        "minutes": [
            {**asdict(m), "coverage": c}
            for m, c in zip(s.minutes, result.minute_coverage, strict=True)
        ],
    }


def learn_summary(result: LearnResult, log: Path) -> None:
    s = result.summary
    table = Table(title=f"learning → {log} ({result.status})", show_header=True)
    for column in (
        "minute",
        "episodes",
        "collisions",
        "exemplars",
        "ΔV (m/s per step)",
        "coverage",
    ):
        table.add_column(column, justify="right")
    for m, coverage in zip(s.minutes, result.minute_coverage, strict=True):
        table.add_row(
            str(m.minute + 1),
            str(m.episodes),
            str(m.collisions),
            str(m.exemplars),
            f"{m.delta_v:.2e}",
            f"{coverage:.0%}",
        )
    out.print(table)
    out.print(
        f"{s.episodes} episodes, {s.collisions} collisions, {s.exemplars} exemplars in "
        f"{s.sim_s / 60:.1f} simulated minutes, coverage {result.coverage:.0%} "
        f"({result.wall_s:.1f} s)"
    )


def train_json(summary: TrainSummary, output: Path) -> dict[str, Any]:
    return {
        "output": str(output),
        "config": summary.fam.config.name,
        "episodes": summary.episodes,
        "exemplars": summary.exemplars,
        "rules_touched": summary.rules_touched,
        "rules_total": summary.rules_total,
        "wall_s": summary.wall_s,
        "repeated_sessions": summary.repeated_sessions,
    }


def train_summary(summary: TrainSummary, output: Path) -> None:
    table = Table(title=f"trained → {output}", show_header=False)
    table.add_column()
    table.add_column(justify="right")
    table.add_row("configuration", summary.fam.config.name)
    table.add_row("episodes", str(summary.episodes))
    table.add_row("exemplars used", str(summary.exemplars))
    table.add_row("rules touched", f"{summary.rules_touched} of {summary.rules_total}")
    table.add_row("rules never touched", str(summary.rules_total - summary.rules_touched))
    table.add_row("time", f"{summary.wall_s:.2f} s")
    for repeat in summary.repeated_sessions:
        table.add_row("trained once", repeat)
    out.print(table)


def fam_difference(d: FamDifference, first: Path, second: Path) -> None:
    table = Table(title=f"{first} → {second} ({d.config}, tolerance {d.tolerance_mps:g} m/s)")
    for column in ("trajectory", "rules differing", "mean |change| m/s"):
        table.add_column(column, justify="right")
    for t in d.trajectories:
        table.add_row(t.trajectory, f"{t.differing} of {t.rules}", f"{t.mean_abs_change_mps:.3f}")
    out.print(table)
    for rule in d.largest:
        out.print(rule.sentence(), highlight=False, markup=False, soft_wrap=True)


def step_explanation(e: StepExplanation) -> None:
    facts = Table(title=f"step {e.step}, ending at {e.time_s:.1f} s", show_header=False)
    facts.add_column()
    facts.add_column()
    ring = " ".join(f"{r:.2f}" for r in e.ring_m) if e.ring_m else "not read"
    velocities = " ".join("-" if v is None else f"{v:.2f}" for v in e.velocities_mps)
    remembered = (
        [("virtual ring (m), S0..S15", " ".join(f"{r:.2f}" for r in e.perceived_m))]
        if e.perceived_m
        else []
    )
    for label, value in (
        ("ring (m), S0..S15", ring),
        *remembered,
        ("view (rotation)", str(e.rotation)),
        ("perceived (m/s), T3L..T3R", velocities),
        ("fast set", ", ".join(e.fast) or "none"),
        ("policy's choice", e.choice or "none"),
        ("driven", e.driven or "none (spin, back-off or trapped)"),
        ("reflex", e.reflex or "none"),
        ("events", ", ".join(e.events) or "none"),
    ):
        facts.add_row(label, value)
    out.print(facts)
    if e.why is not None:
        out.print(f"why, for {' and '.join(e.focus) or 'every trajectory'}:")
        explanation(e.why)


def autopsy(a: Autopsy) -> None:
    """The contact autopsy: each contact, the causes counted, the time by class."""
    contacts = Table(title=f"{len(a.contacts)} contacts")
    for column in ("time (s)", "event", "cause", "obstacle", "driven", "reflex"):
        contacts.add_column(column)
    for c in a.contacts:
        f = c.facts
        contacts.add_row(
            f"{f.time_s:.1f}", f.event, c.cause, f.obstacle, f.trajectory or "-", f.reflex or "-"
        )
    out.print(contacts)
    causes = Table(title="causes")
    causes.add_column("cause")
    causes.add_column("contacts", justify="right")
    for cause, count in a.causes.items():
        if count:
            causes.add_row(cause, str(count))
    out.print(causes)
    total = sum(a.time_s.values()) or 1.0
    time = Table(title="where the time went")
    for column in ("class", "seconds", "share"):
        time.add_column(column, justify="right" if column != "class" else "left")
    for name, seconds in a.time_s.items():
        time.add_row(name, f"{seconds:.1f}", f"{seconds / total:.0%}")
    out.print(time)
    if a.goal_failure is not None:
        out.print(
            f"goal missed: {a.goal_failure} (came within {a.goal_closest_m:.2f} m of it)",
            highlight=False,
        )


def explanation(e: Explanation) -> None:
    inputs = Table(title="inputs")
    for column in ("table", "input", "sonars", "range (m)", "memberships"):
        inputs.add_column(column)
    for i in e.inputs:
        fired = ", ".join(f"{s.name} {s.degree:.2f}" for s in i.fired)
        sonars = ",".join(f"S{s}" for s in i.sonars)
        inputs.add_row(i.table, i.name, sonars, f"{i.value_m:.3f}", fired)
    out.print(inputs)
    rules = Table(title="rules that fire")
    for column in ("table", "IF", "strength", "THEN (m/s, experience)"):
        rules.add_column(column)
    for r in e.rules:
        then = ", ".join(
            f"{t} = {v:.2f} ({x:.1f})"
            for t, v, x in zip(r.trajectories, r.velocities_mps, r.experience, strict=True)
        )
        rules.add_row(r.table, " AND ".join(r.set_names), f"{r.strength:.3f}", then)
    out.print(rules)
    perceived = Table(title="perceived")
    for name in e.trajectories:
        perceived.add_column(name, justify="right")
    perceived.add_row(*(f"{v:.2f} m/s" for v in e.velocities_mps))
    perceived.add_row(*(f"exp {x:.1f}" for x in e.experience))
    out.print(perceived)


def _metrics_rows(metrics: RunMetrics) -> list[tuple[str, str]]:
    def show(value: object) -> str:
        if value is None:
            return "—"
        return f"{value:.3f}" if isinstance(value, float) else str(value)

    return [(name, show(value)) for name, value in asdict(metrics).items()]


def run_metrics(metrics: RunMetrics, reflexes: tuple[str, ...] | None = None) -> None:
    """The metrics of a run (what --json prints), and the reflexes it ran with."""
    table = Table(show_header=False)
    table.add_column()
    table.add_column(justify="right")
    for name, value in _metrics_rows(metrics):
        table.add_row(name, value)
    out.print(table)
    if reflexes is not None:
        out.print(f"reflexes: {', '.join(reflexes) or 'none (the paper method)'}")


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


def replay(summary: Replay) -> None:
    table = Table(title=summary.kind, show_header=False)
    table.add_column()
    table.add_column()
    for name, value in summary.facts:
        table.add_row(str(name), str(value))
    out.print(table)


def demo_json(result: DemoResult) -> dict[str, Any]:
    """The learning summary, then each run's metrics as `tvl run --json` prints them."""
    return {
        "directory": str(result.directory),
        "learning": learn_json(result.learning),
        "runs": [
            {"config": r.config, "behaviour": r.behaviour, "png": str(r.png), **asdict(r.metrics)}
            for r in result.rows
        ],
    }


def demo(result: DemoResult) -> None:
    learn_summary(result.learning, result.directory / "learn.h5")
    table = Table(title=f"behaviours after learning (threshold {DEFAULT_THRESHOLD:g})")
    for column in (
        "FAM",
        "behaviour",
        "contacts/min",
        "near misses",
        "speed m/s",
        "clearance m",
        "picture",
    ):
        table.add_column(column)
    for row in result.rows:
        m = row.metrics
        table.add_row(
            row.config,
            row.behaviour,
            f"{m.contacts_per_min:.2f}",
            str(m.near_misses),
            f"{m.mean_speed_mps:.2f}",
            f"{m.mean_wall_clearance_m or m.mean_clearance_m:.2f}",
            str(row.png),
        )
    out.print(table)


def sweep_json(result: SweepResult) -> dict[str, Any]:
    return {
        "out": str(result.out),
        "cells": result.cells,
        "done": result.done,
        "skipped": result.skipped,
        "files": [str(path) for path in result.files],
        "plot": None if result.plot is None else str(result.plot),
    }
