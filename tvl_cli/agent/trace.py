"""A run's steps as columns: what a run trace (io.runfile) stores, one row per control step."""

from __future__ import annotations

import numpy as np

from tvl_cli.agent.drive import Step
from tvl_cli.core.contacts import EVENTS
from tvl_cli.core.ring import ring_to_mm

NOT_READ_MM = 0  # ring_mm of a step where no one read the sonars: below any real range
NO_REFLEX = -1


class TraceRecorder:
    """Collects steps (a drive loop's on_step) and hands them over as arrays."""

    def __init__(self, reflex_names: tuple[str, ...], sonar_count: int) -> None:
        self.reflex_names = reflex_names
        self._sonars = sonar_count
        self._rows: list[Step] = []

    def __call__(self, step: Step) -> None:
        self._rows.append(step)

    def arrays(self) -> dict[str, np.ndarray]:
        """The columns, named as io.runfile stores them."""
        rows = self._rows
        n = len(rows)
        not_read = np.full(self._sonars, np.nan)
        rings = np.array([s.ring_m if s.ring_m is not None else not_read for s in rows])
        ring_mm = ring_to_mm(np.nan_to_num(rings.reshape(n, self._sonars), nan=NOT_READ_MM))
        no_view = np.full(7, np.nan)
        no_fast = np.zeros(7, dtype=bool)
        reflex_index = {name: i for i, name in enumerate(self.reflex_names)}
        bits = {name: 1 << i for i, name in enumerate(EVENTS)}
        return {
            "pose": np.array([s.pose for s in rows], dtype=np.float64).reshape(n, 3),
            "odometry": np.array([s.odometry for s in rows], dtype=np.float64).reshape(n, 3),
            "ring_mm": ring_mm,
            "velocities": np.array(
                [d.velocities if d.velocities is not None else no_view for d in _decisions(rows)]
            ).reshape(n, 7),
            "fast": np.array(
                [d.fast if d.fast is not None else no_fast for d in _decisions(rows)], dtype=bool
            ).reshape(n, 7),
            "rotation": np.array([s.decision.rotation for s in rows], dtype=np.int8),
            "choice": np.array([s.decision.choice for s in rows], dtype=np.int8),
            "trajectory": np.array([s.decision.trajectory for s in rows], dtype=np.int8),
            "speed_mps": np.array([s.decision.command.linear_mps for s in rows]),
            "turn_radps": np.array([s.decision.command.angular_radps for s in rows]),
            "reflex": np.array(
                [reflex_index.get(s.decision.reflex, NO_REFLEX) for s in rows], dtype=np.int8
            ),
            "events": np.array([sum(bits[e] for e in s.events) for s in rows], dtype=np.uint8),
            "bumped": np.array([s.bumped for s in rows], dtype=bool),
        }


def _decisions(rows: list[Step]) -> list:
    return [s.decision for s in rows]
