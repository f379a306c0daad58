"""`tvl run` end to end: a FAM file and a world in, metrics (and a trace and a picture) out."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from tvl_cli.core.behaviours import BEHAVIOUR_NAMES
from tvl_cli.core.config import RobotConfig
from tvl_cli.core.errors import BadInput, check_minutes
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logfile import file_sha256
from tvl_cli.io.runfile import write_run
from tvl_cli.run import Runner, RunParams, RunResult, StepRecord
from tvl_cli.sim.worldmap import WorldMap, check_goal, load_world


@dataclass(frozen=True, slots=True)
class RunRequest:
    fam: Path
    world: Path
    behaviour: str
    threshold: float
    minutes: float
    seed: int
    goal: tuple[float, float] | None = None
    png: Path | None = None
    trace: Path | None = None
    near_miss_backoff: bool = True


def check_threshold(threshold: float) -> None:
    if not (math.isfinite(threshold) and 0 < threshold <= 1):
        raise BadInput(f"--threshold {threshold:g} is outside (0, 1]")


def parse_goal(text: str) -> tuple[float, float]:
    """'X,Y' in metres."""
    try:
        x, y = (float(part) for part in text.split(","))
    except ValueError:
        raise BadInput(f"--goal {text!r}: expected X,Y in metres, e.g. 3.5,2.0") from None
    return x, y


def resolve_goal(
    world_path: Path, world: WorldMap, behaviour: str, goal: tuple[float, float] | None
) -> tuple[float, float] | None:
    """The goal a run seeks: --goal checked against the world, else the world's first goal;
    None for other behaviours, which take no goal."""
    if behaviour != "goal":
        if goal is not None:
            raise BadInput("--goal is for --behaviour goal only")
        return None
    if goal is not None:
        check_goal(world, *goal, where=f"--goal {goal[0]:g},{goal[1]:g}")
        return goal
    if not world.goals:
        raise BadInput(f"{world_path}: world has no goal; give one with --goal X,Y")
    return world.goals[0]


def _robot_differences(theirs: RobotConfig, ours: RobotConfig) -> list[str]:
    mine, other = ours.to_dict(), theirs.to_dict()
    return sorted(key for key in mine if mine[key] != other.get(key))


def run_fam(request: RunRequest) -> RunResult:
    """Run one behaviour with a learnt FAM; write the trace and picture if asked."""
    if request.behaviour not in BEHAVIOUR_NAMES:
        raise BadInput(f"unknown behaviour {request.behaviour!r}")
    check_threshold(request.threshold)
    check_minutes(request.minutes)
    fam_file = read_fam(request.fam)
    world = load_world(request.world)
    robot = RobotConfig()
    differences = _robot_differences(fam_file.robot_config, robot)
    if differences:
        # Different sonars or trajectories mean different rules: refuse rather than mislead.
        raise BadInput(
            f"{request.fam}: FAM was learnt by another robot configuration than this "
            f"simulator's (differs in {', '.join(differences)})"
        )
    goal = resolve_goal(request.world, world, request.behaviour, request.goal)
    params = RunParams(
        request.behaviour, request.threshold, request.minutes, goal, request.near_miss_backoff
    )
    runner = Runner(world, robot, fam_file.fam, params, request.seed)
    steps: dict[str, list[Any]] = {f.name: [] for f in fields(StepRecord)}

    def record(step: StepRecord) -> None:
        for name, values in steps.items():
            values.append(getattr(step, name))

    result = runner.run(record)
    metrics = result.metrics
    if request.trace is not None:
        write_run(
            request.trace,
            world_name=world.name,
            world_text=world.text,
            parameters={
                "behaviour": request.behaviour,
                "threshold": request.threshold,
                "minutes": request.minutes,
                "goal": list(goal) if goal else None,
                "seed": request.seed,
                "near_miss_backoff": request.near_miss_backoff,
                "fam": str(request.fam),
                "fam_sha256": file_sha256(request.fam),
            },
            robot_config=robot.to_dict(),
            metrics=asdict(metrics),
            steps=steps,
        )
    if request.png is not None:
        from tvl_cli.plot import render_path  # matplotlib only when a picture is wanted

        render_path(
            world,
            steps["pose"],
            steps["speed_mps"],
            steps["bumped"],
            request.png,
            title=f"{request.behaviour} in {world.name}, threshold {request.threshold:g}",
            goal=goal,
        )
    return result
