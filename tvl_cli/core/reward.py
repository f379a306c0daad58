"""The reward of a control step, in metres: the progress the wheels report, less a penalty for
a bump. The Q-learning baseline learns by it, and the Gymnasium task's rewards are made of it.
"""

from __future__ import annotations

import math

from tvl_cli.core.arcs import Pose

# A bump costs as much as 100 control periods of driving at top speed: no progress is worth one.
COLLISION_PENALTY_M = 6.0


def forward_travel_m(before: Pose, after: Pose) -> float:
    """Metres moved along the mean heading between two poses (negative going backwards)."""
    mid = 0.5 * (before[2] + after[2])
    return (after[0] - before[0]) * math.cos(mid) + (after[1] - before[1]) * math.sin(mid)


def bump_penalty_m(bumped: bool, collision_penalty_m: float = COLLISION_PENALTY_M) -> float:
    """What a step costs for bumping: the penalty if it bumped, else nothing."""
    return collision_penalty_m if bumped else 0.0


def step_reward(
    before: Pose, after: Pose, bumped: bool, collision_penalty_m: float = COLLISION_PENALTY_M
) -> float:
    """The reward of one step: metres moved forward by odometry, less the collision penalty if
    it bumped."""
    return forward_travel_m(before, after) - bump_penalty_m(bumped, collision_penalty_m)
