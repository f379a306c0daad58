"""How wall following finds its wall: our reading where the paper is silent.

The paper follows "fast trajectories closest to the nearest object", and for the left wall
closest to its right (§2.1, Fig. 4(b)). It does not say from how far an object counts as the
wall, nor whether the side, once found, is kept. A wall rule answers both: given the
behaviour, what the ring reads and the side found so far (+1 left, -1 right, 0 none), the side
to follow now. Until it finds one the robot goes on as when avoiding.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from tvl_cli.core.behaviours import LEFT_SONARS, RIGHT_SONARS

if TYPE_CHECKING:
    # For the types alone: the rules index arrays without calling numpy, and core.method,
    # which a command's `--help` imports, names this module's rules.
    import numpy as np

# A reading this short on one side means a wall to follow on that side.
WALL_SEEN_M = 1.0


def wall_seen(ring_m: np.ndarray, side: int) -> bool:
    """Whether a reading within WALL_SEEN_M shows an object on `side` (+1 left, -1 right)."""
    sonars = LEFT_SONARS if side > 0 else RIGHT_SONARS
    return bool(ring_m[list(sonars)].min() <= WALL_SEEN_M)


def nearest_side(ring_m: np.ndarray) -> int:
    """+1 if the nearest object within WALL_SEEN_M is on the left, -1 right, 0 none."""
    left = float(ring_m[list(LEFT_SONARS)].min())
    right = float(ring_m[list(RIGHT_SONARS)].min())
    if min(left, right) > WALL_SEEN_M:
        return 0
    return 1 if left <= right else -1


def first_seen(behaviour: str, ring_m: np.ndarray, found: int) -> int:
    """The side of the first object within WALL_SEEN_M (on the behaviour's side, or either
    for `wall`), kept from then on."""
    if found or not behaviour.startswith("wall"):
        return found
    if behaviour == "wall":
        return nearest_side(ring_m)
    side = 1 if behaviour == "wall-left" else -1
    return side if wall_seen(ring_m, side) else 0


# (behaviour, ring (16,) metres, side found so far) -> the side to follow, 0 none yet.
WallRule = Callable[[str, "np.ndarray", int], int]
FIRST_SEEN = "first-seen"
WALL_RULES: dict[str, WallRule] = {FIRST_SEEN: first_seen}
