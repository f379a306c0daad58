"""The steps of one trajectory being followed, recorded as they are driven, for exploring
and for learning while behaving alike: each becomes an Episode once its ending is known."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from tvl_cli.agent.policy import Pose
from tvl_cli.core.episode import Episode


@dataclass(slots=True)
class EpisodeRecord:
    """A trajectory followed from a rotation, step by step."""

    trajectory: int
    rotation: int
    arc_m: float = 0.0  # commanded so far: odometry-free and exact (paper §4.1)
    rings: list[np.ndarray] = field(default_factory=list)  # uint16 mm
    poses: list[Pose] = field(default_factory=list)  # true, for people to draw
    odometry: list[Pose] = field(default_factory=list)
    arcs: list[float] = field(default_factory=list)  # arc_m at each ring
    perceived: list[np.ndarray] = field(default_factory=list)  # virtual rings, metres

    def record(
        self, ring_mm: np.ndarray, pose: Pose, odometry: Pose, perceived: np.ndarray | None = None
    ) -> None:
        """One step's reading, taken where the arc so far has brought the robot, and the
        virtual ring the FAM read there if an echo memory made one."""
        self.rings.append(ring_mm)
        self.poses.append(pose)
        self.odometry.append(odometry)
        self.arcs.append(self.arc_m)
        if perceived is not None:
            self.perceived.append(perceived)

    def episode(
        self,
        index: int,
        sonars: int,
        *,
        collided: bool,
        bumped: bool,
        end_arc_m: float,
        end_time_s: float,
    ) -> Episode:
        return Episode(
            index=index,
            ring_mm=np.array(self.rings, dtype=np.uint16).reshape(-1, sonars),
            pose=np.array(self.poses, dtype=np.float64).reshape(-1, 3),
            odometry=np.array(self.odometry, dtype=np.float64).reshape(-1, 3),
            arc_m=np.array(self.arcs, dtype=np.float64),
            trajectory=self.trajectory,
            rotation=self.rotation,
            collided=collided,
            bumped=bumped,
            end_arc_m=end_arc_m,
            end_time_s=end_time_s,
            fam_ring_m=(
                np.array(self.perceived, dtype=np.float64).reshape(-1, sonars)
                if self.perceived
                else None
            ),
        )
