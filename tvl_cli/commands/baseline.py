"""`tvl baseline dwa` and `tvl baseline qlearn` end to end: checked options and a world in,
the metrics of `tvl run` (and a picture) out."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from tvl_cli.agent.trace import PathRecorder, TraceRecorder
from tvl_cli.baselines.dwa import BEHAVIOURS, MAP, SENSORS, run_dwa
from tvl_cli.baselines.qlearning import QLearningResult, learn_and_evaluate
from tvl_cli.commands.run import resolve_goal
from tvl_cli.core.config import RobotConfig
from tvl_cli.core.errors import BadInput, check_minutes, check_run_minutes
from tvl_cli.core.memory import NO_MEMORY, NONE, NOT_CHOSEN, MemoryChoice
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.sim.worldmap import WorldMap, load_world


def _goal(
    world_path: Path, world: WorldMap, behaviour: str, goal: tuple[float, float] | None
) -> tuple[float, float] | None:
    if behaviour not in BEHAVIOURS:
        raise BadInput(f"unknown behaviour {behaviour!r} (choose from {', '.join(BEHAVIOURS)})")
    return resolve_goal(world_path, world, behaviour, goal)


def _draw(
    world: WorldMap,
    path: PathRecorder,
    png: Path,
    title: str,
    goal: tuple[float, float] | None,
) -> None:
    # matplotlib only when a picture is wanted
    from tvl_cli.render.plot import path_marks, render_path

    render_path(
        world,
        path.column("pose"),
        path.column("speed_mps"),
        path_marks(path.column("events")),
        png,
        title=title,
        goal=goal,
    )


def dwa_session(
    world_path: Path,
    behaviour: str,
    goal: tuple[float, float] | None,
    minutes: float,
    seed: int,
    png: Path | None = None,
    reflexes: tuple[str, ...] = (),
    sensor: str = MAP,
    memory: MemoryChoice = NOT_CHOSEN,
) -> RunMetrics:
    """One DWA run in a world file inside the named reflexes, knowing the obstacles by the
    map or by the sonar ring (through an echo memory if chosen); the path drawn to `png`."""
    check_run_minutes(minutes, RobotConfig().control_period_s)
    if sensor not in SENSORS:
        raise BadInput(f"--sensor {sensor}: choose {', '.join(SENSORS)}")
    if sensor == MAP and memory.given and memory.kind != NONE:
        raise BadInput("--memory is for --sensor ring: the map needs no memory")
    world = load_world(world_path)
    goal = _goal(world_path, world, behaviour, goal)
    robot = RobotConfig()
    path = PathRecorder()
    steps = TraceRecorder(reflexes, robot.sonar.count, [path])
    metrics = run_dwa(
        world,
        robot,
        minutes,
        seed,
        goal,
        reflexes=reflexes,
        on_step=steps if png else None,
        sensor=sensor,
        memory=memory.over(NO_MEMORY),
    )
    if png is not None:
        steps.close()
        _draw(world, path, png, f"DWA by the {sensor}, {behaviour} in {world.name}", goal)
    return metrics


@dataclass(frozen=True, slots=True)
class QLearnReport:
    result: QLearningResult
    checked_competence: bool

    def to_dict(self) -> dict[str, Any]:
        """The run metrics of the greedy run, then what learning cost (and achieved)."""
        result = self.result
        report = asdict(result.evaluation)
        report["learn_minutes"] = result.learn_minutes
        report["learn_collisions"] = result.learn_collisions
        if self.checked_competence:
            report["time_to_competence_min"] = result.time_to_competence_min
            report["competence_checks"] = [asdict(c) for c in result.checks]
        return report

    def summary(self) -> str:
        """What learning cost, and when it became competent if that was judged."""
        result = self.result
        text = (
            f"learnt {result.learn_minutes:g} simulated minutes "
            f"with {result.learn_collisions} collisions"
        )
        if self.checked_competence:
            reached = result.time_to_competence_min
            text += "; time to competence: " + (
                f"{reached:g} min"
                if reached is not None
                else f"not within {result.learn_minutes:g} min"
            )
        return text


def qlearn_session(
    world_path: Path,
    learn_minutes: float,
    minutes: float,
    seed: int,
    competence_every: float | None = None,
    png: Path | None = None,
    reflexes: tuple[str, ...] = (),
) -> QLearnReport:
    """Learn a Q-table in a world file, then run it greedily inside the named reflexes; its
    path drawn to `png`."""
    check_run_minutes(minutes, RobotConfig().control_period_s)
    check_minutes(learn_minutes, "--learn-minutes", zero_allowed=True)
    if competence_every is not None and not (
        math.isfinite(competence_every) and competence_every > 0
    ):
        raise BadInput(f"--competence-every {competence_every:g} must be a positive number")
    world = load_world(world_path)
    robot = RobotConfig()
    path = PathRecorder()
    steps = TraceRecorder(reflexes, robot.sonar.count, [path])
    result = learn_and_evaluate(
        world,
        robot,
        learn_minutes,
        minutes,
        seed,
        competence_every,
        reflexes=reflexes,
        on_step=steps if png else None,
    )
    if png is not None:
        steps.close()
        title = f"Q-learning after {learn_minutes:g} min, avoid in {world.name}"
        _draw(world, path, png, title, None)
    return QLearnReport(result, competence_every is not None)
