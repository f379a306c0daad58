"""A run's steps as columns: what a run trace (io.runfile) stores, one row per control step.

Steps are turned into columns a chunk at a time and handed to sinks (a trace file being
written, the path of a picture), so a run of any length holds at most one chunk of steps.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from tvl_cli.agent.drive import Step
from tvl_cli.core.contacts import EVENTS
from tvl_cli.core.ring import ring_to_mm
from tvl_cli.core.robot_config import DEFAULT_TRAJECTORIES

# A view's columns: the robot's trajectories, one velocity and one fast flag each.
TRAJECTORIES = len(DEFAULT_TRAJECTORIES)
NOT_READ_MM = 0  # ring_mm of a step where no one read the sonars: below any real range
NO_REFLEX = -1
# Steps turned into columns at once: about a simulated minute, a few hundred kB of Python
# objects; large enough that a trace file gets few, well-compressed writes.
CHUNK_STEPS = 1024

Columns = dict[str, np.ndarray]
ColumnSink = Callable[[Columns], None]


def before_each_step(after_each_step: np.ndarray, start: Sequence[float]) -> np.ndarray:
    """(N, 3) the pose (or odometry) each step began from, and so read its ring at, from the
    (N, 3) `pose` (or `odometry`) column, the pose after each step, of a run from `start`."""
    return np.vstack([np.asarray(start, dtype=np.float64)[None, :], after_each_step[:-1]])


class TraceRecorder:
    """Collects steps (a drive loop's on_step) and hands them to `sinks` as columns, a chunk
    at a time; `close()` hands over the last, partial chunk (possibly empty)."""

    def __init__(
        self, reflex_names: tuple[str, ...], sonar_count: int, sinks: Sequence[ColumnSink]
    ) -> None:
        self.reflex_names = reflex_names
        self._sonars = sonar_count
        self._sinks = tuple(sinks)
        self._rows: list[Step] = []

    def __call__(self, step: Step) -> None:
        self._rows.append(step)
        if len(self._rows) == CHUNK_STEPS:
            self._hand_over()

    def close(self) -> None:
        self._hand_over()

    def _hand_over(self) -> None:
        columns = step_columns(self._rows, self.reflex_names, self._sonars)
        self._rows = []
        for sink in self._sinks:
            sink(columns)


class PathRecorder:
    """A column sink keeping only what a picture of the run needs: pose, speed, events."""

    def __init__(self) -> None:
        self._chunks: list[Columns] = []

    def __call__(self, columns: Columns) -> None:
        self._chunks.append({k: columns[k] for k in ("pose", "speed_mps", "events")})

    def column(self, name: str) -> np.ndarray:
        return np.concatenate([chunk[name] for chunk in self._chunks])


def step_columns(rows: list[Step], reflex_names: tuple[str, ...], sonars: int) -> Columns:
    """The steps as columns, named as io.runfile stores them."""
    n = len(rows)
    not_read = np.full(sonars, np.nan)
    rings = np.array([s.ring_m if s.ring_m is not None else not_read for s in rows])
    ring_mm = ring_to_mm(np.nan_to_num(rings.reshape(n, sonars), nan=NOT_READ_MM))
    # What the choice read: the echo memory's virtual ring where it made one, else the ring.
    perceived = np.array(
        [
            s.decision.perceived_m if s.decision.perceived_m is not None else rings[i]
            for i, s in enumerate(rows)
        ]
    ).reshape(n, sonars)
    no_view = np.full(TRAJECTORIES, np.nan)
    no_fast = np.zeros(TRAJECTORIES, dtype=bool)
    reflex_index = {name: i for i, name in enumerate(reflex_names)}
    bits = {name: 1 << i for i, name in enumerate(EVENTS)}
    decisions = [s.decision for s in rows]
    return {
        "pose": np.array([s.pose for s in rows], dtype=np.float64).reshape(n, 3),
        "odometry": np.array([s.odometry for s in rows], dtype=np.float64).reshape(n, 3),
        "ring_mm": ring_mm,
        "perceived_mm": ring_to_mm(np.nan_to_num(perceived, nan=NOT_READ_MM)),
        "velocities": np.array(
            [d.velocities if d.velocities is not None else no_view for d in decisions]
        ).reshape(n, TRAJECTORIES),
        "fast": np.array(
            [d.fast if d.fast is not None else no_fast for d in decisions], dtype=bool
        ).reshape(n, TRAJECTORIES),
        "rotation": np.array([d.rotation for d in decisions], dtype=np.int8),
        "choice": np.array([d.choice for d in decisions], dtype=np.int8),
        "trajectory": np.array([d.trajectory for d in decisions], dtype=np.int8),
        "speed_mps": np.array([d.command.linear_mps for d in decisions], dtype=np.float64),
        "turn_radps": np.array([d.command.angular_radps for d in decisions], dtype=np.float64),
        "reflex": np.array(
            [reflex_index.get(d.reflex, NO_REFLEX) for d in decisions], dtype=np.int8
        ),
        "events": np.array([sum(bits[e] for e in s.events) for s in rows], dtype=np.uint8),
        "bumped": np.array([s.bumped for s in rows], dtype=bool),
    }
