"""The behaviours by name, and when a trajectory is fast (paper §2.1–2.2, §4.5).

What the commands' options offer and check, apart from the choice among fast trajectories
that performs each behaviour (core.trajectory_choice), so that a command's `--help` loads no
numpy.
"""

from __future__ import annotations

import math

# The paper's default: fast means at least 85 % of a trajectory's maximum velocity.
DEFAULT_THRESHOLD = 0.85
GOAL_RADIUS_M = 0.3  # a goal counts as reached this near (goal seeking stops there)


def is_threshold(value: float) -> bool:
    """A threshold is a fraction of each trajectory's maximum velocity, in (0, 1]."""
    return math.isfinite(value) and 0 < value <= 1


# `wall` follows the side of the nearest object (Fig. 4(b)), so it scores like wall-left or
# wall-right once the wall rule (core.wall_rules) has found that side.
BEHAVIOUR_NAMES = ("avoid", "wall-left", "wall-right", "wall", "goal")

# Each side front to back, mirror images, so that equal readings pick the same sonar on both.
LEFT_SONARS = (2, 3, 4, 5, 6)
RIGHT_SONARS = (14, 13, 12, 11, 10)
