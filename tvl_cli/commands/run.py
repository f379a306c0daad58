"""`tvl run` end to end: a FAM file and a world in, metrics (and a trace and a picture) out."""

from __future__ import annotations

import math
from collections.abc import Callable
from contextlib import AbstractContextManager, ExitStack
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from tvl_cli.agent.drive import Step, StepSink
from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.online import ECHO_AFTER_S, ECHO_BEFORE_S, OnlineLearner, OnlineSummary
from tvl_cli.agent.trace import ColumnSink, PathRecorder, TraceRecorder
from tvl_cli.analysis.robotdiff import robot_differences
from tvl_cli.core.behaviours import BEHAVIOUR_NAMES, is_threshold
from tvl_cli.core.errors import BadInput, check_run_minutes
from tvl_cli.core.fam_config import DEFAULT_INIT_VELOCITY_MPS
from tvl_cli.core.method import (
    BEHAVING_FIELDS,
    DEFAULT,
    NOT_GIVEN,
    Method,
    MethodChoice,
    as_choice,
    method_record,
)
from tvl_cli.core.metrics import MinuteContacts, MinuteTally, RunMetrics
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import body_of, profile_name, robot_name
from tvl_cli.core.training import TrainParams, train_params
from tvl_cli.io.famfile import FamFile, read_fam
from tvl_cli.io.json_documents import document, input_file, output_path, world_input
from tvl_cli.io.logfile import LogWriter
from tvl_cli.io.loglayout import KIND_BEHAVING, ended_status
from tvl_cli.io.logreader import file_sha256
from tvl_cli.io.runfile import RunTraceWriter, path_beside, run_trace_output
from tvl_cli.sim.worldmap import WorldMap, resolve_goal, world_of


@dataclass(frozen=True, slots=True)
class OnlineLearning:
    """`tvl run --learn`: train the FAM on what the run meets, in memory only; with a `log`
    (`--learn-log LOG`), appending each episode to a `behaving` session of it."""

    log: Path | None = None


@dataclass(frozen=True, slots=True)
class RunRequest:
    fam: Path
    world: Path | WorldMap  # a world file, or a world made here (`KIND:SEED`)
    behaviour: str
    threshold: float
    minutes: float
    seed: int
    goal: tuple[float, float] | None = None
    png: Path | None = None
    trace: Path | None = None
    # The run's choices (reflexes, wall rule, echo memory) and settings (a sonar model); not
    # given, ours, reading through the memory the FAM was trained through with the sonar it
    # was learnt with. The rest of the method is the FAM's.
    method: Method | MethodChoice = NOT_GIVEN
    learn: OnlineLearning | None = None  # learn while behaving (`--learn`)
    robot: RobotConfig | None = None  # the robot asked for (`--robot`); the FAM's if None


@dataclass(frozen=True, slots=True)
class RunResult:
    request: RunRequest
    metrics: RunMetrics
    minutes: list[MinuteContacts]
    learnt: OnlineSummary | None = None  # with --learn
    session: str | None = None  # the session appended to the log, with --learn-log LOG
    method: dict[str, Any] | None = None  # the run's method_record
    # The options the run was made with, as resolved (the FAM's sonar and memory, the
    # world's goal): the run's inputs beside its FAM and world files
    options: dict[str, Any] = field(default_factory=dict)
    stopped_by: str | None = None  # the signal that ended the run early ("SIGINT"), if one did

    def to_dict(self) -> dict[str, Any]:
        """What `tvl run --json` found: the metrics, the contacts of each simulated minute,
        and with --learn what the run learnt and the log session it went to (the method and
        the options are among its inputs)."""
        printed = {**asdict(self.metrics), "minutes": [asdict(m) for m in self.minutes]}
        if self.learnt is not None:
            # Not "learning": results files mark the ablation's runs with that key.
            printed["learnt"] = {**asdict(self.learnt), "session": self.session}
        return printed

    def document(self) -> dict[str, Any]:
        """The run's metrics at the top (as results files gather them), its inputs beside."""
        request = self.request
        inputs = {
            "fam": input_file(request.fam),
            "world": world_input(request.world),
            **self.options,
            "learn": request.learn is not None,
            "method": self.method,
        }
        outputs = {
            "png": output_path(request.png),
            "trace": output_path(request.trace),
            "log": output_path(request.learn.log if request.learn else None),
        }
        status = ended_status(self.stopped_by)
        return document("run", inputs, outputs=outputs, status=status, **self.to_dict())


def check_threshold(threshold: float) -> None:
    if not is_threshold(threshold):
        raise BadInput(f"--threshold {threshold:g} is outside (0, 1]")


def parse_goal(text: str) -> tuple[float, float]:
    """'X,Y' in metres (as `--goal` and a grid's goals write a goal)."""
    try:
        x, y = (float(part) for part in text.split(","))
    except ValueError:
        x = y = math.nan
    if not (math.isfinite(x) and math.isfinite(y)):
        raise BadInput(f"{text!r} is not X,Y in metres, e.g. 3.5,2.0")
    return x, y


def run_robot(
    learnt_by: RobotConfig, sonar: str | None, fam_path: Path, asked: RobotConfig | None = None
) -> RobotConfig:
    """The robot a FAM drives: the one it was learnt on, its ring heard by the sonar model
    asked for (or as it was learnt). A FAM's velocities are what its robot could drive, so
    a robot asked for (`--robot`) that differs from it in anything but the sonar model is
    refused, naming how they differ."""
    robot = learnt_by if sonar is None else learnt_by.heard_by(sonar)
    if asked is not None:
        differences = robot_differences(body_of(learnt_by), body_of(asked))
        if differences:
            shown = "; ".join(d.text() for d in differences[:3])
            more = f"; and {len(differences) - 3} more" if len(differences) > 3 else ""
            raise BadInput(
                f"{fam_path}: FAM was learnt on {robot_name(learnt_by)}, not on "
                f"{robot_name(asked)} ({shown}{more}); learn one with that --robot"
            )
    return robot


def request_robot(request: RunRequest, fam_file: FamFile | None = None) -> RobotConfig:
    """The robot the run drives: its FAM's (`fam_file`, else read from `request.fam`), with
    the sonar model asked for (`--sonar`), refused if it is not the robot asked for."""
    if fam_file is None:
        fam_file = read_fam(request.fam)
    sonar = dict(as_choice(request.method).settings).get("sonar")
    return run_robot(fam_file.robot_config, sonar, request.fam, request.robot)


def run_method(fam_file: FamFile, choice: MethodChoice) -> Method:
    """The method a run is made by: the FAM's (its labels, and the memory it reads through),
    with ours or the chosen reflexes, wall rule and memory, and the settings given."""
    # A run's own choices are ours unless chosen, whatever the FAM's learner would have run.
    inherited = replace(fam_file.method, reflexes=DEFAULT.reflexes, wall_rule=DEFAULT.wall_rule)
    return choice.over(inherited, BEHAVING_FIELDS)


def run_record(method: Method, fam_file: FamFile) -> dict[str, Any]:
    """What the run records of its method: every field, with those the FAM did not record or
    its sessions chose otherwise named, as the FAM names them."""
    made_by = fam_file.made_by
    return method_record(method, unrecorded=made_by.unrecorded, mixed=made_by.mixed)


def run_fam(request: RunRequest, watch: StepSink | None = None) -> RunMetrics:
    """The metrics of `run_behaviour`."""
    return run_behaviour(request, watch).metrics


def run_behaviour(
    request: RunRequest,
    watch: StepSink | None = None,
    stop: Callable[[], str | None] = lambda: None,
) -> RunResult:
    """Run one behaviour with a learnt FAM; write the trace and picture if asked, show each
    step to `watch` (a progress bar, a live view) as the run goes, and with `request.learn`
    train the FAM on what the run meets. A run that `stop()` names a reason for (a signal)
    ends at that step, and its trace and picture keep what it did."""
    _check_request(request)
    fam_file = read_fam(request.fam)
    world = world_of(request.world)
    method = run_method(fam_file, as_choice(request.method))
    recorded = run_record(method, fam_file)
    robot = request_robot(request, fam_file)
    goal = resolve_goal(request.world, world, request.behaviour, request.goal)
    path = PathRecorder()
    tally = MinuteTally(robot.control_period_s)
    with ExitStack() as outputs:
        learner, session = _online_learner(request, fam_file, world, robot, method, goal, outputs)
        sinks: list[ColumnSink] = [path] if request.png is not None else []
        trace = None
        if request.trace is not None:
            trace = outputs.enter_context(
                _trace_output(request, world, robot, method, recorded, fam_file, goal)
            )
            sinks.append(trace)
        recorder = TraceRecorder(method.reflexes, robot.sonar.count, sinks)
        on_step = _fan_out(
            recorder if sinks else None, watch, lambda step: tally.record(step.events), learner
        )
        metrics = behave(
            world,
            robot,
            fam_file.fam,
            request.behaviour,
            minutes=request.minutes,
            seed=request.seed,
            threshold=request.threshold,
            goal_xy=goal,
            on_step=on_step,
            method=method,
            stop=lambda: stop() is not None,
        )
        if learner is not None:
            learner.finish(metrics.sim_s)
        recorder.close()
        stopped_by = stop()
        if trace is not None:
            trace.metrics = asdict(metrics)
            trace.stopped_by = stopped_by
    if request.png is not None:
        _draw_path(request, world, robot, goal, path)
    learnt = learner.summary() if learner is not None else None
    options = {**run_options(request, goal), "robot": profile_name(robot)}
    return RunResult(
        request, metrics, tally.minutes(metrics), learnt, session, recorded, options, stopped_by
    )


def _check_request(request: RunRequest) -> None:
    """Refuse a behaviour, threshold or length no run has, before any file is read."""
    if request.behaviour not in BEHAVIOUR_NAMES:
        raise BadInput(f"unknown behaviour {request.behaviour!r}")
    check_threshold(request.threshold)
    check_run_minutes(request.minutes, RobotConfig().control_period_s)


def _draw_path(
    request: RunRequest,
    world: WorldMap,
    robot: RobotConfig,
    goal: tuple[float, float] | None,
    path: PathRecorder,
) -> None:
    """The --png picture of the path the run drove."""
    from tvl_cli.render.plot import render_recorded_path  # matplotlib only for a picture

    assert request.png is not None
    title = f"{request.behaviour} in {world.name}, threshold {request.threshold:g}"
    render_recorded_path(world, path.column, request.png, title, goal, robot)


def training_params(fam_file: FamFile, fam_path: Path) -> TrainParams:
    """How the episodes a run learns are labelled and trained: as the FAM's own were (its
    method's labels, its provenance's settings), so that the log replays into it."""
    training = fam_file.provenance.get("training")
    settings = training if isinstance(training, dict) else {}
    try:
        return train_params(
            fam_file.method,
            bool(settings.get("symmetric", True)),
            float(settings.get("init_velocity_mps", DEFAULT_INIT_VELOCITY_MPS)),
        )
    except (TypeError, ValueError, BadInput) as error:
        raise BadInput(
            f"{fam_path}: unreadable training settings in its provenance ({error})"
        ) from None


def run_options(request: RunRequest, goal: tuple[float, float] | None) -> dict[str, Any]:
    """What a run was asked to do beside its method, as it was done: the goal it sought where
    the request left it to the world."""
    return {
        "behaviour": request.behaviour,
        "threshold": request.threshold,
        "minutes": request.minutes,
        "goal": list(goal) if goal else None,
        "seed": request.seed,
    }


def _run_parameters(
    request: RunRequest, goal: tuple[float, float] | None, recorded_in: Path
) -> dict[str, Any]:
    """The run's parameters beside its method, as its trace and a behaving log session (the
    file `recorded_in`) keep them: the FAM by its path from that file's folder."""
    return {
        **run_options(request, goal),
        "fam": path_beside(request.fam, recorded_in),
        "fam_sha256": file_sha256(request.fam),
    }


def _online_learner(
    request: RunRequest,
    fam_file: FamFile,
    world: WorldMap,
    robot: RobotConfig,
    method: Method,
    goal: tuple[float, float] | None,
    outputs: ExitStack,
) -> tuple[OnlineLearner | None, str | None]:
    """The learner of a --learn run (None: the run does not learn), and the `behaving`
    session of the log it appends to (None: learning in memory, or not at all). The session
    is opened before any other output, so that a log refused (locked, not a log, another
    robot's) stops the run before it starts."""
    if request.learn is None:
        return None, None
    params = training_params(fam_file, request.fam)
    memory = method.memory
    if request.learn.log is None:
        return OnlineLearner(fam_file.fam, robot, params, world.start, memory=memory), None
    writer = outputs.enter_context(
        LogWriter.open(
            request.learn.log,
            world_name=world.name,
            world_text=world.text,
            seed=request.seed,
            parameters={
                **_run_parameters(request, goal, request.learn.log),
                "config": fam_file.fam.config.name,
                **params.settings(),
                "echo_before_s": ECHO_BEFORE_S,
                "echo_after_s": ECHO_AFTER_S,
            },
            robot_config=robot.to_dict(),
            fam_config=fam_file.fam.config.to_dict(),
            kind=KIND_BEHAVING,
            method=method,
        )
    )
    learner = OnlineLearner(
        fam_file.fam, robot, params, world.start, writer.append_episode, memory=memory
    )
    return learner, writer.session


def _trace_output(
    request: RunRequest,
    world: WorldMap,
    robot: RobotConfig,
    method: Method,
    recorded: dict[str, Any],
    fam_file: FamFile,
    goal: tuple[float, float] | None,
) -> AbstractContextManager[RunTraceWriter]:
    """The run trace file, with the run's parameters; the steps follow as the run goes."""
    assert request.trace is not None
    learning = request.learn
    return run_trace_output(
        request.trace,
        world_name=world.name,
        world_text=world.text,
        parameters={
            **_run_parameters(request, goal, request.trace),
            # Which sonars each trajectory's table reads, for the contact autopsy.
            "sonars_read": fam_file.fam.config.sonars_read(),
            # A run that learns drives with a FAM that changes: the file is where it started.
            "learn": None if learning is None else str(learning.log or ""),
        },
        robot_config=robot.to_dict(),
        reflex_names=method.reflexes,
        method=recorded,
    )


def _fan_out(*sinks: StepSink | None) -> StepSink | None:
    """One step sink feeding each of those given, in order; None if none is."""
    given = tuple(sink for sink in sinks if sink is not None)
    if not given:
        return None

    def each(step: Step) -> None:
        for sink in given:
            sink(step)

    return each
