"""Training a FAM from recorded episodes: the one path shared by `tvl learn` (online) and
`tvl train` (log replay), so that replaying a log rebuilds the online FAM bit for bit.

A session's episodes are trained in the order they ended, each once its labels are known:
at once by the paper's rule (the driven trajectory, from its own collision point), or once
the echoes around it have been heard by the heard rule (core.heard), the rest when the
session ends. Sessions learnt while behaving are labelled by the same rule as those learnt
exploring."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DEFAULT_INIT_VELOCITY_MPS
from tvl_cli.core.heard import HeardEpisode, HeardLabeller, heard_episodes
from tvl_cli.core.labels import (
    DEFAULT_CEILING_RADIUS_M,
    DEFAULT_DECEL_MPS2,
    DEFAULT_LABEL_CEILING,
    DEFAULT_MARGIN_M,
    HEARD_LABELS,
    label_reach_m,
    trajectory_ceilings,
    velocity_labels,
)
from tvl_cli.core.method import Method
from tvl_cli.core.robot_config import SLOWEST_TOP_MPS, RobotConfig
from tvl_cli.core.robot_profiles import robot_name


@dataclass(frozen=True, slots=True)
class TrainParams:
    """How exemplars become FAM entries: the method's labels, and the settings beyond it."""

    decel_mps2: float = DEFAULT_DECEL_MPS2
    margin_m: float = DEFAULT_MARGIN_M
    symmetric: bool = True
    init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS
    labels: str = HEARD_LABELS  # which trajectories a recorded point labels (LABEL_RULES)
    label_ceiling: float = DEFAULT_LABEL_CEILING  # labels no faster than this x the top speed
    # on the arcs turning no wider than this (m); None: on every trajectory
    label_ceiling_radius_m: float | None = DEFAULT_CEILING_RADIUS_M

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

    def reach_m(self, robot: RobotConfig) -> float:
        """How far (m) along any of the robot's trajectories a collision point can change one
        of these labels (core.labels.label_reach_m)."""
        return label_reach_m(
            max(robot.v_max_mps), self.decel_mps2, self.margin_m, self.label_ceiling
        )

    def ceilings(self, robot: RobotConfig) -> np.ndarray:
        """(T,) each of the robot's trajectories' labels' ceiling (core.labels)."""
        return trajectory_ceilings(robot.radii_m, self.label_ceiling, self.label_ceiling_radius_m)

    def settings(self) -> dict[str, float | bool]:
        """What a FAM's provenance records of its training: the settings that are not the
        method's (whose labels the FAM's method records)."""
        return {"symmetric": self.symmetric, "init_velocity_mps": self.init_velocity_mps}


def check_init_velocity(params: TrainParams, robot: RobotConfig) -> None:
    """An entry never trained must read slower than every trajectory of the robot trained
    for (paper §3.1), whose slowest top speed may be below the paper's robot's."""
    slowest = min(robot.v_max_mps)
    if params.init_velocity_mps >= slowest:
        raise BadInput(
            f"--init-velocity {params.init_velocity_mps:g} must be below the slowest "
            f"trajectory's maximum of {robot_name(robot)} ({slowest:g} m/s)"
        )


def train_params(
    method: Method, symmetric: bool = True, init_velocity_mps: float = DEFAULT_INIT_VELOCITY_MPS
) -> TrainParams:
    """How a FAM is trained by `method`'s labels, with the settings beyond the method."""
    return TrainParams(
        method.decel_mps2,
        method.margin_m,
        symmetric,
        init_velocity_mps,
        method.labels,
        method.label_ceiling,
        method.label_ceiling_radius_m,
    )


def episode_labels(episode: Episode, robot: RobotConfig, params: TrainParams) -> np.ndarray:
    """(n,) m/s: at each point, the speed on the driven trajectory that stops just short of
    its collision point."""
    v_max = robot.trajectories[episode.trajectory].v_max_mps
    ceiling = params.ceilings(robot)[episode.trajectory]
    return velocity_labels(
        episode.distances_m(), v_max, params.decel_mps2, params.margin_m, ceiling
    )


def train_episode(fam: Fam, episode: Episode, robot: RobotConfig, params: TrainParams) -> float:
    """Train on one whole episode's driven trajectory, on exactly the ring values the log keeps
    (or the virtual rings the echo memory made of them); the summed absolute change of the
    FAM's velocity entries, m/s (Fam.train)."""
    labels = episode_labels(episode, robot, params)
    trajectories = np.full(len(labels), episode.trajectory)
    return fam.train(episode.fam_rings(), trajectories, labels, symmetric=params.symmetric)


def heard_labels(heard: HeardEpisode, robot: RobotConfig, params: TrainParams) -> np.ndarray:
    """(n, T) m/s: the label of every trajectory at each of an episode's points; NaN where
    the point labels none."""
    distances = heard.distances_m  # (n, T) metres; NaN: no label
    labelled = ~np.isnan(distances)
    labels = np.full(distances.shape, np.nan)
    v_max = np.broadcast_to(np.array(robot.v_max_mps), distances.shape)  # (n, T) m/s
    ceilings = np.broadcast_to(params.ceilings(robot), distances.shape)
    labels[labelled] = velocity_labels(
        distances[labelled],
        v_max[labelled],
        params.decel_mps2,
        params.margin_m,
        ceilings[labelled],
    )
    return labels


def train_heard(fam: Fam, heard: HeardEpisode, robot: RobotConfig, params: TrainParams) -> float:
    """Train on every trajectory each of an episode's points labels (core.heard), point by
    point in trajectory order; the summed absolute change, as train_episode."""
    labels = heard_labels(heard, robot, params)
    points, trajectories = np.nonzero(~np.isnan(labels))  # row-major: point by point
    rings = heard.episode.fam_rings()[points]
    return fam.train(rings, trajectories, labels[points, trajectories], symmetric=params.symmetric)


Trained = tuple[Episode, float]  # an episode, and the change its training made


class SessionTrainer:
    """Trains a FAM with one session's episodes, handed in the order they ended, by the
    labels' rule: each at once (the paper's), or once its labels are heard."""

    def __init__(
        self, fam: Fam, robot: RobotConfig, params: TrainParams, behaving: bool = False
    ) -> None:
        """`behaving`: the episodes are stretches driven while behaving (agent.online)."""
        self._fam = fam
        self._robot = robot
        self._params = params
        heard = params.labels == HEARD_LABELS
        self._heard = (
            HeardLabeller(robot, params.reach_m(robot), behaving=behaving) if heard else None
        )

    def add(self, episode: Episode) -> list[Trained]:
        """Take an episode; those trained now, with the change each made."""
        if self._heard is None:
            return [(episode, train_episode(self._fam, episode, self._robot, self._params))]
        return [self._train(h) for h in self._heard.add(episode)]

    def finish(self) -> list[Trained]:
        """The session has ended: the episodes still waiting, trained."""
        return [] if self._heard is None else [self._train(h) for h in self._heard.finish()]

    def _train(self, heard: HeardEpisode) -> Trained:
        return heard.episode, train_heard(self._fam, heard, self._robot, self._params)


@dataclass(frozen=True, slots=True)
class SessionEpisodes:
    """A session's episodes to train on, from its first, as its learner trained them."""

    episodes: Sequence[Episode]
    ended: bool  # the session ended with them (else it went on, its last labels unheard)
    # Learnt while behaving: the episodes are the stretches a behaviour drove (agent.online).
    behaving: bool = False


def labelled_episodes(
    session: SessionEpisodes, robot: RobotConfig, params: TrainParams
) -> list[HeardEpisode]:
    """The session's episodes that train_sessions trains on, each with the collision point
    of every trajectory its points label: all of them by the heard rule (those whose labels
    were heard), the driven one alone by the paper's rule."""
    if params.labels == HEARD_LABELS:
        reach_m = params.reach_m(robot)
        return heard_episodes(
            session.episodes, robot, session.ended, reach_m, behaving=session.behaving
        )
    return [driven_labels(episode, len(robot.trajectories)) for episode in session.episodes]


def driven_labels(episode: Episode, trajectories: int) -> HeardEpisode:
    """The episode's labels by the paper's rule: its driven trajectory's alone."""
    distances = np.full((episode.exemplar_count, trajectories), np.nan)
    distances[:, episode.trajectory] = episode.distances_m()
    return HeardEpisode(episode, distances)


def train_sessions(
    fam: Fam,
    sessions: Sequence[SessionEpisodes],
    robot: RobotConfig,
    params: TrainParams,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
) -> int:
    """Train the FAM on the sessions in order, each as its learner did; the exemplars read."""
    return train_sessions_each([fam], sessions, robot, params, on_progress)


def train_sessions_each(
    fams: Sequence[Fam],
    sessions: Sequence[SessionEpisodes],
    robot: RobotConfig,
    params: TrainParams,
    on_progress: Callable[[int, int], None] = lambda done, total: None,
) -> int:
    """train_sessions for each of several FAMs, every session labelled once for them all
    (labelled_episodes: the episodes in the order a SessionTrainer trains them); the
    exemplars read."""
    total = sum(e.exemplar_count for s in sessions for e in s.episodes)
    done = 0
    for session in sessions:
        for labelled in labelled_episodes(session, robot, params):
            for fam in fams:
                if params.labels == HEARD_LABELS:
                    train_heard(fam, labelled, robot, params)
                else:
                    train_episode(fam, labelled.episode, robot, params)
            done += labelled.episode.exemplar_count
            on_progress(done, total)
    return total
