"""The run trace (`tvl-run`): every control step of one behaviour run, why it was taken,
and the run's metrics.

Layout (format_version 4; version 3 kept the method's reflexes and memory in its parameters
and some or none of it in `method` (io.method_records reads them), version 2 had no
perceived_mm, version 1 only pose, odometry, ring_mm, velocities, trajectory, speed_mps and
bumped, with velocities facing forward; all are still read):

    /             format, format_version, tvl_version, created, world_name, world_text,
                  method (JSON, core.method.method_record: every choice of the method the run
                  was made by: its reflexes, its sonar, its echo memory, ...), parameters
                  (JSON: behaviour, threshold, minutes, goal, seed, FAM file (its path from
                  the trace's folder) and its SHA-256, the sonars each trajectory's table
                  reads), robot_config (JSON), metrics (JSON: what `tvl run --json` prints),
                  status ("finished", or "interrupted: SIGINT" for a run Ctrl-C ended early)
    pose          (N, 3) float64  true x, y (m), theta (rad) after each step
    odometry      (N, 3) float64  odometry x, y (m), theta (rad) after each step
    ring_mm       (N, 16) uint16  sonar ranges read before the step, mm; 0 if not read
    perceived_mm  (N, 16) uint16  what the choice read of them: the echo memory's virtual ring
                                  where it made one, else ring_mm
    velocities    (N, 7) float64  perceived m/s of the 7 trajectories in the view used; NaN
    fast          (N, 7) bool     the fast set of that view
    rotation      (N,) int8       the view: sonar positions CCW the choice was made facing
    choice        (N,) int8       the policy's choice of trajectory, -1 none this step
    trajectory    (N,) int8       trajectory driven, -1 spinning, reversing or trapped
    speed_mps     (N,) float64    commanded forward speed (negative when reversing)
    turn_radps    (N,) float64    commanded turn rate
    reflex        (N,) int8       the reflex that overrode the policy (attribute `names`), -1
    events        (N,) uint8      events the step began, one bit each (attribute `bits`)
    bumped        (N,) bool       bump sensor after the step

`status` came without a new format version: how the run ended changes how nothing else is
read. A trace without it finished.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from tvl_cli.core.contacts import EVENTS, steps_beginning
from tvl_cli.core.errors import BadInput
from tvl_cli.core.method import Method
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.hdf5_header import (
    LIBVER,
    METHOD_RECORDED_SINCE,
    RUN_FORMAT,
    FormatError,
    open_for_reading,
    read_json_attr,
    read_str_attr,
    to_json,
    write_header,
)
from tvl_cli.io.loglayout import STATUS_FINISHED, ended_status
from tvl_cli.io.method_records import ReadMethod, current, trace_method

_COMPRESSION: dict[str, Any] = {"compression": "gzip", "compression_opts": 4, "shuffle": True}
_CHUNK_ROWS = 1024  # steps per HDF5 chunk
# name -> (units, description)
_DATASETS: dict[str, tuple[str, str]] = {
    "pose": ("m, m, rad", "true pose x, y, theta after each control step"),
    "odometry": ("m, m, rad", "odometry pose x, y, theta after each control step"),
    "ring_mm": ("mm", "sonar ranges S0..S15 read before the step, S0 forward, CCW; 0 unread"),
    "velocities": ("m/s", "perceived velocity of each trajectory in the view used; NaN none"),
    "trajectory": ("", "trajectory driven (robot_config order); -1 spinning or reversing"),
    "speed_mps": ("m/s", "commanded forward speed, negative when reversing"),
    "bumped": ("", "bump sensor after the step"),
}
# The decision record, added in format_version 2.
_DECISION_DATASETS: dict[str, tuple[str, str]] = {
    "fast": ("", "the fast set of the view used"),
    "rotation": ("sonar positions", "the view the choice was made in, counter-clockwise"),
    "choice": ("", "the policy's choice of trajectory before any reflex; -1 none"),
    "turn_radps": ("rad/s", "commanded turn rate, counter-clockwise"),
    "reflex": ("", "the reflex that overrode the policy (index into `names`); -1 none"),
    "events": ("", "events the step began, one bit each (bit i is `bits`[i])"),
}
# What the choice read of the ring, added in format_version 3.
_PERCEPTION_DATASETS: dict[str, tuple[str, str]] = {
    "perceived_mm": ("mm", "what the choice read of the ring: the echo memory's virtual ring"),
}
_OPTIONAL_DATASETS = {**_DECISION_DATASETS, **_PERCEPTION_DATASETS}
# The format_version that added each of those groups: a trace of that version or later
# holds every dataset of it.
_ADDED_IN_VERSION = {2: _DECISION_DATASETS, 3: _PERCEPTION_DATASETS}


@dataclass(frozen=True, slots=True, eq=False)
class RunTrace:
    """A run as recorded step by step."""

    world_name: str
    world_text: str
    parameters: dict[str, Any]
    metrics: dict[str, Any]
    arrays: dict[str, np.ndarray]  # the datasets above, by name
    made_by: ReadMethod  # the method the run was made by
    reflex_names: tuple[str, ...] = ()
    robot_config: dict[str, Any] = field(default_factory=dict)  # RobotConfig.to_dict()
    status: str = STATUS_FINISHED  # or "interrupted: SIGINT": a run stopped early

    @property
    def method(self) -> Method:
        return self.made_by.method

    @property
    def steps(self) -> int:
        return len(self.arrays["pose"])

    @property
    def period_s(self) -> float:
        """Simulated seconds a step: the run's simulated time over its steps (0 for none).
        Step i ends at (i + 1) * period_s, the time its events are given at."""
        return float(self.metrics["sim_s"]) / self.steps if self.steps else 0.0

    @property
    def has_decisions(self) -> bool:
        """Whether the trace records why each step was taken (format_version 2)."""
        return "events" in self.arrays

    def event_steps(self, event: str) -> np.ndarray:
        """The indices of the steps that began `event` (one of core.contacts.EVENTS)."""
        if not self.has_decisions:
            return np.array([], dtype=np.int64)
        return steps_beginning(self.arrays["events"], event)


class RunTraceWriter:
    """Appends a run's steps to a trace file as they come, a chunk of columns at a time."""

    def __init__(self, f: h5py.File, reflex_names: tuple[str, ...]) -> None:
        self._file = f
        self._reflex_names = reflex_names
        self._steps = 0
        # Held open to the end: a dataset closed mid-run would flush its chunks in h5py's
        # deallocator, where a failed write can only be printed, not raised.
        self._datasets: dict[str, h5py.Dataset] = {}
        self.metrics: dict[str, Any] = {}  # what `tvl run --json` prints, set when the run ends
        self.stopped_by: str | None = None  # the signal that ended the run early, if one did

    def __call__(self, columns: dict[str, np.ndarray]) -> None:
        """Append the columns (every dataset above, by name, one row per step)."""
        if not self._datasets:
            self._create(columns)
        n = len(columns["pose"])
        if n:
            for name, dataset in self._datasets.items():
                dataset.resize(self._steps + n, axis=0)
                dataset[self._steps :] = columns[name]
            self._steps += n

    def _create(self, columns: dict[str, np.ndarray]) -> None:
        """Resizable datasets shaped and typed like the first columns."""
        for name, (units, description) in {**_DATASETS, **_OPTIONAL_DATASETS}.items():
            values = columns[name]
            dataset = self._datasets[name] = self._file.create_dataset(
                name,
                shape=(0, *values.shape[1:]),
                maxshape=(None, *values.shape[1:]),
                dtype=values.dtype,
                chunks=(_CHUNK_ROWS, *values.shape[1:]),
                **_COMPRESSION,
            )
            dataset.attrs.update(units=units, description=description)
        self._file["reflex"].attrs["names"] = list(self._reflex_names)
        self._file["events"].attrs["bits"] = list(EVENTS)


@contextmanager
def run_trace_output(
    path: Path | str,
    *,
    world_name: str,
    world_text: str,
    parameters: dict[str, Any],
    robot_config: dict[str, Any],
    reflex_names: tuple[str, ...],
    method: dict[str, Any],
) -> Iterator[RunTraceWriter]:
    """A run trace written while the run goes: yields the writer (a column sink, whose
    `metrics` the caller sets); the file appears at `path` only when the block ends well.
    `method` is the run's method as core.method.method_record gives it.

    Written straight to a temporary file beside `path`, so a run of any length needs no more
    memory than a chunk. HDF5 cannot close a file it failed to write and crashes trying, so
    after a failed write the file is left open: the temporary file is removed, the error
    goes on, and the command line ends the process (cli.main).
    """
    with atomic_output(path) as temporary:
        f = h5py.File(temporary, "w", libver=LIBVER)
        try:
            write_header(
                f, RUN_FORMAT, method=method, parameters=parameters, robot_config=robot_config
            )
            f.attrs.update(world_name=world_name, world_text=world_text)
            writer = RunTraceWriter(f, reflex_names)
            yield writer
            f.attrs["metrics"] = to_json(writer.metrics)
            f.attrs["status"] = ended_status(writer.stopped_by)
            f.flush()
        except (OSError, RuntimeError):
            raise  # possibly a failed write: closing could crash
        except BaseException:
            f.close()
            raise
        f.close()


def path_beside(file: Path, recorded_in: Path) -> str:
    """`file`'s path as a file written at `recorded_in` records it: relative to that file's
    folder, so that the two moved or shared together still find each other."""
    return os.path.relpath(os.path.abspath(file), os.path.abspath(recorded_in.parent))


def recorded_paths(recorded: str, recorded_in: Path) -> list[Path]:
    """Where a file a trace (or a log) names may be from here, likeliest first: relative to
    that file's folder, as tvl records it; else as written, relative to where the run was
    made, as traces written before recorded it. An absolute path is itself."""
    named = Path(recorded)
    if named.is_absolute():
        return [named]
    beside = Path(os.path.normpath(recorded_in.parent / named))
    return [beside] if beside == named else [beside, named]


def read_run(path: Path | str) -> RunTrace:
    """Read a run trace; FormatError if it is not a readable tvl-run file."""
    with open_for_reading(path, RUN_FORMAT) as f:
        version = int(f.attrs["format_version"])  # checked on opening
        names = _datasets_of_version(version)
        # Found missing here, not as a KeyError in whatever reads the trace.
        missing = [name for name in names if name not in f]
        if missing:
            plural = "s" if len(missing) > 1 else ""
            raise FormatError(f"{path}: run trace has no {', '.join(missing)} dataset{plural}")
        try:
            arrays = {name: f[name][()] for name in names}
            reflex_names = (
                tuple(str(n) for n in f["reflex"].attrs.get("names", ())) if "reflex" in f else ()
            )
        except OSError as error:
            raise FormatError(f"{path}: run trace is corrupt ({error})") from None
        _check_shapes(arrays, path)
        _check_finite(arrays, path)
        parameters, metrics = (read_json_attr(f, name, path) for name in ("parameters", "metrics"))
        _check_records(parameters, metrics, len(arrays["pose"]), path)
        robot_config = read_json_attr(f, "robot_config", path)
        recorded = read_json_attr(f, "method", path) if "method" in f.attrs else None
        return RunTrace(
            world_name=read_str_attr(f, "world_name", path),
            world_text=read_str_attr(f, "world_text", path),
            parameters=parameters,
            metrics=metrics,
            arrays=arrays,
            made_by=_method(recorded, version, parameters, robot_config, path),
            reflex_names=reflex_names,
            robot_config=robot_config,
            status=read_str_attr(f, "status", path) if "status" in f.attrs else STATUS_FINISHED,
        )


def _method(
    recorded: Any, version: int, parameters: dict[str, Any], robot_config: Any, path: Path | str
) -> ReadMethod:
    """The run's method, from its record or, in a trace of version 3 or older, its pieces."""
    where = f"{path}: run trace"
    if version >= METHOD_RECORDED_SINCE[RUN_FORMAT]:
        return current(recorded, where)
    try:
        robot = RobotConfig.from_dict(robot_config)
    except (BadInput, KeyError, TypeError, ValueError) as error:
        raise FormatError(f"{where}'s robot_config is malformed ({error})") from None
    return trace_method(recorded, parameters, robot, where)


def _datasets_of_version(version: int) -> list[str]:
    """The datasets a trace of this format_version holds."""
    added = (list(group) for since, group in _ADDED_IN_VERSION.items() if version >= since)
    return [*_DATASETS, *(name for group in added for name in group)]


# Datasets with a row per step rather than a value: their rows' shapes, when fixed.
_ROWS = {
    "pose": (3,),
    "odometry": (3,),
    "ring_mm": None,
    "perceived_mm": None,
    "velocities": None,
    "fast": None,
}


def _check_shapes(arrays: dict[str, np.ndarray], path: Path | str) -> None:
    """Every dataset has one entry per step, each of the shape its meaning needs."""
    steps = len(arrays["pose"]) if arrays["pose"].ndim else 0
    for name, values in arrays.items():
        row = _ROWS.get(name, ())
        wanted = 2 if name in _ROWS else 1
        if values.ndim != wanted or len(values) != steps or (row and values.shape[1:] != row):
            shape = "x".join(map(str, values.shape)) or "a scalar"
            raise FormatError(f"{path}: run trace is corrupt ({name} is {shape}, {steps} steps)")


# Measurements every step has; velocities may be NaN where no view was perceived.
_MEASURED = ("pose", "odometry", "speed_mps", "turn_radps")


def _check_finite(arrays: dict[str, np.ndarray], path: Path | str) -> None:
    """A NaN or infinite pose would be drawn as a path cut short or through a wall."""
    for name in _MEASURED:
        if name in arrays and not np.isfinite(arrays[name]).all():
            raise FormatError(f"{path}: run trace's {name} holds a value that is not finite")


def _check_records(parameters: Any, metrics: Any, steps: int, path: Path | str) -> None:
    """The run's parameters and metrics are JSON objects, the metrics' numbers finite (so
    that `tvl replay --json` can print them), and a run of any steps gives its simulated
    time (which times its steps)."""
    for name, record in (("parameters", parameters), ("metrics", metrics)):
        if not isinstance(record, dict):
            raise FormatError(f"{path}: run trace's {name} is not a JSON object")
    for key, value in metrics.items():
        if isinstance(value, float) and not np.isfinite(value):
            raise FormatError(f"{path}: run trace's metric {key} is {value}, not a finite number")
    sim_s = metrics.get("sim_s")
    timed = isinstance(sim_s, (int, float)) and not isinstance(sim_s, bool) and sim_s > 0
    if steps and not timed:
        raise FormatError(f"{path}: run trace's metrics give no simulated time (sim_s)")
