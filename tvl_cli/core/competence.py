"""Competence, defined once: what an `avoid` run must achieve for learning to count as done."""

from __future__ import annotations

from tvl_cli.core.metrics import RunMetrics

COMPETENCE_RUN_MINUTES = 5.0  # length of the avoid run that judges it
MAX_CONTACTS_PER_MIN = 0.2  # collisions and near misses together
MIN_MEAN_SPEED_MPS = 0.3


def is_competent(avoid_run: RunMetrics) -> bool:
    """At most 0.2 contacts per minute at a mean speed of at least 0.3 m/s."""
    return (
        avoid_run.contacts_per_min <= MAX_CONTACTS_PER_MIN
        and avoid_run.mean_speed_mps >= MIN_MEAN_SPEED_MPS
    )


def is_competent_run(run: RunMetrics, behaviour: str) -> bool:
    """A run of any behaviour judged as an avoid run is, and a goal run must also reach its
    goal: how the generalization benchmark counts its runs competent."""
    return is_competent(run) and (behaviour != "goal" or bool(run.goal_reached))
