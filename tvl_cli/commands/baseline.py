"""`tvl baseline dwa` and `tvl baseline qlearn` end to end: checked options and a world in,
the metrics of `tvl run` (and a picture) out."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

from tvl_cli.agent.trace import PathRecorder, TraceRecorder
from tvl_cli.baselines.dwa import BEHAVIOURS, MAP, SENSORS, run_dwa
from tvl_cli.baselines.qlearning import QLearningResult, learn_and_evaluate
from tvl_cli.core.errors import BadInput, check_minutes, check_run_minutes
from tvl_cli.core.memory import NO_MEMORY, NONE
from tvl_cli.core.method import (
    DEFAULT,
    NOT_GIVEN,
    Method,
    MethodChoice,
    as_choice,
    method_record,
)
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.words import counted
from tvl_cli.io.json_documents import document, output_path, world_input
from tvl_cli.sim.worldmap import WorldMap, resolve_goal, world_of

# What a baseline takes of a method: the reflexes around it, and the DWA by the ring its echo
# memory. Not given, a baseline runs alone on the live ring.
REFLEXES_ONLY = ("reflexes",)
DWA_FIELDS = ("reflexes", "memory")
ALONE = replace(DEFAULT, reflexes=(), memory=NO_MEMORY)


def _draw(
    world: WorldMap, path: PathRecorder, png: Path, title: str, goal: tuple[float, float] | None
) -> None:
    from tvl_cli.render.plot import render_recorded_path  # matplotlib only for a picture

    render_recorded_path(world, path.column, png, title, goal)


def _goal(
    given: Path | WorldMap, world: WorldMap, behaviour: str, goal: tuple[float, float] | None
) -> tuple[float, float] | None:
    if behaviour not in BEHAVIOURS:
        raise BadInput(f"unknown behaviour {behaviour!r} (choose from {', '.join(BEHAVIOURS)})")
    return resolve_goal(given, world, behaviour, goal)


def dwa_session(
    given: Path | WorldMap,
    behaviour: str,
    goal: tuple[float, float] | None,
    minutes: float,
    seed: int,
    png: Path | None = None,
    method: Method | MethodChoice = NOT_GIVEN,
    sensor: str = MAP,
) -> DwaReport:
    """One DWA run in a world (a file, or one made here) inside the method's reflexes,
    knowing the obstacles by the map or by the sonar ring (through the method's echo
    memory); the path drawn to `png`."""
    check_run_minutes(minutes, RobotConfig().control_period_s)
    if sensor not in SENSORS:
        raise BadInput(f"--sensor {sensor}: choose {', '.join(SENSORS)}")
    choice = as_choice(method)
    if sensor == MAP and choice.memory.given and choice.memory.kind != NONE:
        raise BadInput("--memory is for --sensor ring: the map needs no memory")
    chosen = choice.over(ALONE, DWA_FIELDS)
    reflexes = chosen.reflexes
    world = world_of(given)
    asked_goal = list(goal) if goal else None
    goal = _goal(given, world, behaviour, goal)
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
        # The map knows every obstacle: there is nothing to remember.
        memory=NO_MEMORY if sensor == MAP else chosen.memory,
    )
    if png is not None:
        steps.close()
        _draw(world, path, png, f"DWA by the {sensor}, {behaviour} in {world.name}", goal)
    fields = REFLEXES_ONLY if sensor == MAP else DWA_FIELDS
    options = {"behaviour": behaviour, "goal": asked_goal, "minutes": minutes, "sensor": sensor}
    asked = BaselineAsked(given, seed, options, png)
    return DwaReport(metrics, {**method_record(chosen, fields), "preset": None}, asked)


@dataclass(frozen=True, slots=True)
class BaselineAsked:
    """What a baseline command was asked: its world, seed, options and picture."""

    world: Path | WorldMap  # a world file, or a world made here (`KIND:SEED`)
    seed: int
    options: dict[str, Any]
    png: Path | None

    def inputs(self, method: dict[str, Any]) -> dict[str, Any]:
        """What a baseline document echoes: these, and what it took of a method."""
        return {
            "world": world_input(self.world),
            "seed": self.seed,
            "method": method,
            **self.options,
        }

    def outputs(self) -> dict[str, Any]:
        return {"png": output_path(self.png)}


@dataclass(frozen=True, slots=True)
class DwaReport:
    metrics: RunMetrics
    method: dict[str, Any]  # what the baseline took of a method (no preset: it is no TVL)
    asked: BaselineAsked

    def document(self) -> dict[str, Any]:
        inputs, outputs = self.asked.inputs(self.method), self.asked.outputs()
        return document("baseline dwa", inputs, outputs=outputs, **asdict(self.metrics))


@dataclass(frozen=True, slots=True)
class QLearnReport:
    result: QLearningResult
    checked_competence: bool
    method: dict[str, Any]  # what the baseline took of a method (no preset: it is no TVL)
    asked: BaselineAsked

    def document(self) -> dict[str, Any]:
        inputs, outputs = self.asked.inputs(self.method), self.asked.outputs()
        return document("baseline qlearn", inputs, outputs=outputs, **self.to_dict())

    def to_dict(self) -> dict[str, Any]:
        """The run metrics of the greedy run, then what learning cost (and achieved); the
        method is among a document's inputs."""
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
            f"with {counted(result.learn_collisions, 'collision')}"
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
    given: Path | WorldMap,
    learn_minutes: float,
    minutes: float,
    seed: int,
    competence_every: float | None = None,
    png: Path | None = None,
    method: Method | MethodChoice = NOT_GIVEN,
) -> QLearnReport:
    """Learn a Q-table in a world (a file, or one made here), then run it greedily inside
    the method's reflexes; its path drawn to `png`."""
    chosen = as_choice(method).over(ALONE, REFLEXES_ONLY)
    reflexes = chosen.reflexes
    check_run_minutes(minutes, RobotConfig().control_period_s)
    check_minutes(learn_minutes, "--learn-minutes", zero_allowed=True)
    if competence_every is not None and not (
        math.isfinite(competence_every) and competence_every > 0
    ):
        raise BadInput(f"--competence-every {competence_every:g} must be a positive number")
    world = world_of(given)
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
    recorded = {**method_record(chosen, REFLEXES_ONLY), "preset": None}
    options = {
        "learn_minutes": learn_minutes,
        "minutes": minutes,
        "competence_every": competence_every,
    }
    asked = BaselineAsked(given, seed, options, png)
    return QLearnReport(result, competence_every is not None, recorded, asked)
