"""`tvl run` end to end: a FAM file and a world in, metrics (and a trace and a picture) out."""

from __future__ import annotations

from contextlib import AbstractContextManager, ExitStack
from dataclasses import asdict, dataclass, replace
from pathlib import Path

from tvl_cli.agent.behave import behave
from tvl_cli.agent.drive import Step, StepSink
from tvl_cli.agent.reflexes import STACK_ORDER
from tvl_cli.agent.trace import ColumnSink, PathRecorder, TraceRecorder
from tvl_cli.core.behaviours import BEHAVIOUR_NAMES, is_threshold
from tvl_cli.core.config import RobotConfig, SonarConfig
from tvl_cli.core.errors import BadInput, check_run_minutes
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import file_sha256
from tvl_cli.io.runfile import RunTraceWriter, run_trace_output
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
    reflexes: tuple[str, ...] = STACK_ORDER
    sonar: str | None = None  # "real" or "ideal"; None: the sonar the FAM was learnt with


def check_threshold(threshold: float) -> None:
    if not is_threshold(threshold):
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


def run_robot(learnt_by: RobotConfig, sonar: str | None, fam_path: Path) -> RobotConfig:
    """The robot a FAM drives: this simulator's, with the sonar model the FAM was learnt with
    (or the one asked for). Refused if the FAM's robot differs in anything else: other
    sonars or trajectories mean other rules."""
    ideal = learnt_by.sonar.ideal if sonar is None else sonar == "ideal"
    robot = RobotConfig(sonar=SonarConfig(ideal=ideal))
    ours, theirs = robot.to_dict(), replace(learnt_by, sonar=robot.sonar).to_dict()
    differences = sorted(key for key in ours if ours[key] != theirs.get(key))
    if differences:
        raise BadInput(
            f"{fam_path}: FAM was learnt by another robot configuration than this "
            f"simulator's (differs in {', '.join(differences)})"
        )
    return robot


def run_fam(request: RunRequest, watch: StepSink | None = None) -> RunMetrics:
    """Run one behaviour with a learnt FAM; write the trace and picture if asked, and show
    each step to `watch` (a progress bar, a live view) as the run goes."""
    if request.behaviour not in BEHAVIOUR_NAMES:
        raise BadInput(f"unknown behaviour {request.behaviour!r}")
    check_threshold(request.threshold)
    check_run_minutes(request.minutes, RobotConfig().control_period_s)
    fam_file = read_fam(request.fam)
    world = load_world(request.world)
    robot = run_robot(fam_file.robot_config, request.sonar, request.fam)
    goal = resolve_goal(request.world, world, request.behaviour, request.goal)
    path = PathRecorder()
    with ExitStack() as outputs:
        sinks: list[ColumnSink] = [path] if request.png is not None else []
        trace = None
        if request.trace is not None:
            trace = outputs.enter_context(_trace_output(request, world, robot, goal))
            sinks.append(trace)
        recorder = TraceRecorder(request.reflexes, robot.sonar.count, sinks)
        on_step = _both(recorder if sinks else None, watch)
        metrics = behave(
            world,
            robot,
            fam_file.fam,
            request.behaviour,
            minutes=request.minutes,
            seed=request.seed,
            threshold=request.threshold,
            goal_xy=goal,
            reflexes=request.reflexes,
            on_step=on_step,
        )
        recorder.close()
        if trace is not None:
            trace.metrics = asdict(metrics)
    if request.png is not None:
        # matplotlib only when a picture is wanted
        from tvl_cli.render.plot import path_marks, render_path

        render_path(
            world,
            path.column("pose"),
            path.column("speed_mps"),
            path_marks(path.column("events")),
            request.png,
            title=f"{request.behaviour} in {world.name}, threshold {request.threshold:g}",
            goal=goal,
        )
    return metrics


def _trace_output(
    request: RunRequest, world: WorldMap, robot: RobotConfig, goal: tuple[float, float] | None
) -> AbstractContextManager[RunTraceWriter]:
    """The run trace file, with the run's parameters; the steps follow as the run goes."""
    assert request.trace is not None
    return run_trace_output(
        request.trace,
        world_name=world.name,
        world_text=world.text,
        parameters={
            "behaviour": request.behaviour,
            "threshold": request.threshold,
            "minutes": request.minutes,
            "goal": list(goal) if goal else None,
            "seed": request.seed,
            "reflexes": list(request.reflexes),
            "sonar": "ideal" if robot.sonar.ideal else "real",
            "fam": str(request.fam),
            "fam_sha256": file_sha256(request.fam),
        },
        robot_config=robot.to_dict(),
        reflex_names=request.reflexes,
    )


def _both(first: StepSink | None, second: StepSink | None) -> StepSink | None:
    """One step sink feeding both, or whichever there is."""
    if first is None or second is None:
        return first or second
    both = (first, second)

    def each(step: Step) -> None:
        for sink in both:
            sink(step)

    return each
