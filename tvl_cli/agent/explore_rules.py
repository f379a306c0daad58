"""How exploratory learning chooses the next (rotation, trajectory) pair to follow, by a
method's `exploration`: the paper's least experienced pair (Fig. 14), and the rules beyond
it, each an entry of core.additions.ADDITIONS or the paper's own alternative.

A rule sees every step's odometry (`visit`) and, when an episode is to start, the experience
of the 112 pairs as the FAM perceives the ring now (`choose`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from tvl_cli.agent.novelty import Places
from tvl_cli.agent.policy import Pose
from tvl_cli.core.method import LEAST_EXPERIENCE, NOVELTY, RANDOM, Method
from tvl_cli.core.robot_config import RobotConfig


def least_experienced(experience: np.ndarray, rng: np.random.Generator) -> tuple[int, int]:
    """(rotation, trajectory) of the least experienced pair; ties drawn by the generator."""
    flat = experience.ravel()
    candidates = np.flatnonzero(flat == flat.min())
    pick = int(candidates[rng.integers(len(candidates))])
    rotation, trajectory = divmod(pick, experience.shape[1])
    return rotation, trajectory


def random_pair(shape: tuple[int, int], rng: np.random.Generator) -> tuple[int, int]:
    """A (rotation, trajectory) pair drawn uniformly from the generator."""
    rotation, trajectory = divmod(int(rng.integers(shape[0] * shape[1])), shape[1])
    return rotation, trajectory


class ExplorationRule(Protocol):
    def visit(self, odometry: Pose) -> None: ...

    def choose(
        self, experience: np.ndarray, ring_m: np.ndarray, odometry: Pose, rng: np.random.Generator
    ) -> tuple[int, int]:
        """The pair to set off along, from `experience` (count, 7), seeing `ring_m` (16,)
        metres at `odometry`."""
        ...


class LeastExperience:
    """The paper's rule (Fig. 14): the least experienced pair."""

    def visit(self, odometry: Pose) -> None:
        pass

    def choose(
        self, experience: np.ndarray, ring_m: np.ndarray, odometry: Pose, rng: np.random.Generator
    ) -> tuple[int, int]:
        return least_experienced(experience, rng)


class RandomPair(LeastExperience):
    """The paper's "simplest way" (§4): a uniformly random pair."""

    def choose(
        self, experience: np.ndarray, ring_m: np.ndarray, odometry: Pose, rng: np.random.Generator
    ) -> tuple[int, int]:
        shape = experience.shape
        return random_pair((shape[0], shape[1]), rng)


class Novelty:
    """The least experienced of the pairs leading somewhere the odometry has not been, or of
    all when none does (agent.novelty)."""

    def __init__(self, robot: RobotConfig, method: Method) -> None:
        self.places = Places(robot, method.near_m)

    def visit(self, odometry: Pose) -> None:
        self.places.visit(odometry)

    def choose(
        self, experience: np.ndarray, ring_m: np.ndarray, odometry: Pose, rng: np.random.Generator
    ) -> tuple[int, int]:
        new = self.places.leading_to_new(ring_m, odometry)
        if new.any():  # else nothing new is in reach, and experience alone decides
            experience = np.where(new, experience, np.inf)
        rotation, trajectory = least_experienced(experience, rng)
        self.places.aim(rotation, trajectory)
        return rotation, trajectory


EXPLORATION_RULES: dict[str, Callable[[RobotConfig, Method], ExplorationRule]] = {
    LEAST_EXPERIENCE: lambda robot, method: LeastExperience(),
    NOVELTY: Novelty,
    RANDOM: lambda robot, method: RandomPair(),
}
