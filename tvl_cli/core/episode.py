"""One learning episode: the exemplars recorded along one followed trajectory."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tvl_cli.core.labels import distances_to_collision


@dataclass(frozen=True, slots=True, eq=False)
class Episode:
    """One followed trajectory: its exemplars and how it ended."""

    index: int  # in the session, from 0
    ring_mm: np.ndarray  # (n, sonars) uint16 mm, S0 forward, CCW
    pose: np.ndarray  # (n, 3) true x m, y m, theta rad
    odometry: np.ndarray  # (n, 3) odometry x m, y m, theta rad
    arc_m: np.ndarray  # (n,) distance along the arc from the episode start
    trajectory: int  # index in the robot configuration's trajectories
    rotation: int  # foveal rotation chosen, sonar positions CCW
    collided: bool
    bumped: bool  # the collision point was a bump (else the sonars found it, or none)
    end_arc_m: float  # arc length at the end: the collision point if collided
    end_time_s: float  # simulated time at the end, from the session start

    @property
    def exemplar_count(self) -> int:
        return len(self.arc_m)

    def distances_m(self) -> np.ndarray:
        """(n,) metres along the arc from each exemplar to the collision point; inf if none."""
        return distances_to_collision(self.arc_m, self.collided, self.end_arc_m)
