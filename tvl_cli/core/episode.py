"""One learning episode: the exemplars recorded along one followed trajectory."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tvl_cli.core.labels import distances_to_collision
from tvl_cli.core.ring import mm_to_ring


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
    # (n, sonars) metres the FAM read at each exemplar: the echo memory's virtual rings;
    # None when it read the logged ring itself (no memory).
    fam_ring_m: np.ndarray | None = None

    @property
    def exemplar_count(self) -> int:
        return len(self.arc_m)

    def steps(self, control_period_s: float) -> np.ndarray:
        """(n,) the control step each exemplar was read on, counted from the session start.

        An episode's exemplars are read on consecutive steps, the last one on the step before
        the episode ended (the step that ended it judged the reading after it), in learning
        and in learning while behaving alike.
        """
        last = round(self.end_time_s / control_period_s) - 1
        return np.arange(last - self.exemplar_count + 1, last + 1)

    def fam_rings(self) -> np.ndarray:
        """(n, sonars) metres: what the FAM is trained on at each exemplar."""
        return self.fam_ring_m if self.fam_ring_m is not None else mm_to_ring(self.ring_mm)

    def distances_m(self) -> np.ndarray:
        """(n,) metres along the arc from each exemplar to the collision point; inf if none."""
        return distances_to_collision(self.arc_m, self.collided, self.end_arc_m)
