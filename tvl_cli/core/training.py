"""Training a FAM from recorded episodes: the one path shared by `tvl learn` (online) and
`tvl train` (log replay), so that replaying a log rebuilds the online FAM bit for bit."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import DEFAULT_INIT_VELOCITY_MPS, Fam
from tvl_cli.core.labels import DEFAULT_DECEL_MPS2, DEFAULT_MARGIN_M, velocity_labels
from tvl_cli.core.method import Method
from tvl_cli.core.robot_config import SLOWEST_TOP_MPS, RobotConfig


@dataclass(frozen=True, slots=True)
class TrainParams:
    """How exemplars become FAM entries: the method's labels, and the settings beyond it."""

    decel_mps2: float = DEFAULT_DECEL_MPS2
    margin_m: float = DEFAULT_MARGIN_M
    symmetric: bool = True
    init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS

    def __post_init__(self) -> None:
        # Checked here, before any file is touched, rather than at the first label.
        if not (math.isfinite(self.decel_mps2) and self.decel_mps2 > 0):
            raise BadInput(f"--decel {self.decel_mps2:g} must be > 0 m/s²")
        if not (math.isfinite(self.margin_m) and self.margin_m >= 0):
            raise BadInput(f"--margin {self.margin_m:g} must be >= 0 m")
        slowest = SLOWEST_TOP_MPS
        if not (math.isfinite(self.init_velocity_mps) and 0 <= self.init_velocity_mps < slowest):
            # An input never met must be perceived as slow (paper §3.1), never as fast.
            raise BadInput(
                f"--init-velocity {self.init_velocity_mps:g} must be >= 0 m/s and below the "
                f"slowest trajectory's maximum ({slowest:g} m/s)"
            )

    def settings(self) -> dict[str, float | bool]:
        """What a FAM's provenance records of its training: the settings that are not the
        method's (whose labels the FAM's method records)."""
        return {"symmetric": self.symmetric, "init_velocity_mps": self.init_velocity_mps}


def train_params(
    method: Method, symmetric: bool = True, init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS
) -> TrainParams:
    """How a FAM is trained by `method`'s labels, with the settings beyond the method."""
    return TrainParams(method.decel_mps2, method.margin_m, symmetric, init_velocity_mps)


def episode_labels(episode: Episode, robot: RobotConfig, params: TrainParams) -> np.ndarray:
    """(n,) m/s: at each point, the speed that stops just short of the collision point."""
    v_max = robot.trajectories[episode.trajectory].v_max_mps
    return velocity_labels(episode.distances_m(), v_max, params.decel_mps2, params.margin_m)


def train_episode(fam: Fam, episode: Episode, robot: RobotConfig, params: TrainParams) -> float:
    """Train on one whole episode, on exactly the ring values the log keeps (or the virtual
    rings the echo memory made of them); the summed absolute change of the FAM's velocity
    entries, m/s (Fam.train)."""
    labels = episode_labels(episode, robot, params)
    trajectories = np.full(len(labels), episode.trajectory)
    return fam.train(episode.fam_rings(), trajectories, labels, symmetric=params.symmetric)


def train_episodes(
    fam: Fam,
    episodes: Sequence[Episode],
    robot: RobotConfig,
    params: TrainParams,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
) -> int:
    """Train the FAM on the episodes in order, as the online learner did; the exemplars used."""
    total = sum(e.exemplar_count for e in episodes)
    done = 0
    for episode in episodes:
        train_episode(fam, episode, robot, params)
        done += episode.exemplar_count
        on_progress(done, total)
    return total
