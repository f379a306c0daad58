"""Competence, defined once: what an `avoid` run must achieve for learning to count as done."""

from __future__ import annotations

from tvl_cli.core.metrics import RunMetrics
from tvl_cli.core.robot_config import FASTEST_MPS

COMPETENCE_RUN_MINUTES = 5.0  # length of the avoid run that judges it
MAX_CONTACTS_PER_MIN = 0.2  # collisions and near misses together
# The mean speed asked for, as a share of the robot's fastest trajectory's top speed, so that
# a smaller, slower robot is judged by what it can drive.
MIN_SPEED_SHARE = 0.5
MIN_MEAN_SPEED_MPS = MIN_SPEED_SHARE * FASTEST_MPS  # the paper's robot's: 0.3 m/s


def is_competent(avoid_run: RunMetrics, fastest_mps: float = FASTEST_MPS) -> bool:
    """At most 0.2 contacts per minute at a mean speed of at least half the fastest
    trajectory's top speed (`fastest_mps`, by default the paper's robot's: 0.3 m/s)."""
    return (
        avoid_run.contacts_per_min <= MAX_CONTACTS_PER_MIN
        and avoid_run.mean_speed_mps >= MIN_SPEED_SHARE * fastest_mps
    )


def is_competent_run(run: RunMetrics, behaviour: str) -> bool:
    """A run of any behaviour judged as an avoid run is, and a goal run must also reach its
    goal: how the generalization benchmark counts its runs competent."""
    return is_competent(run) and (behaviour != "goal" or bool(run.goal_reached))
