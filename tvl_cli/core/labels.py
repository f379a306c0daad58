"""Training labels: the speed at each recorded point that stops just short of the collision.

Braking at a constant deceleration a from speed v takes v^2 / (2 a) metres, so a point
d metres along the arc from the collision point may be passed at sqrt(2 a (d - margin)),
never more than the trajectory's maximum; after a full circle every point gets v_max
(paper §4.1).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from tvl_cli.core.errors import check_in_range
from tvl_cli.core.robot_config import SonarConfig

if TYPE_CHECKING:
    # The functions below import numpy when they run: core.method reads this module's
    # constants, and a command's `--help` imports core.method.
    import numpy as np

# A trajectory is "fast" at threshold t while the collision point is at least
# margin + (t * v_max)^2 / (2 a) away along it. A gentle deceleration makes that horizon long
# enough to turn away within it (at 0.85: 1.6 m for T0, 0.64 m for T3, whose sharpest turn
# needs about 0.8 m of arc to come parallel to a wall met head on); with 0.5 m/s² T3 stayed
# fast until 0.14 m from a wall, inside what the ring can resolve, and the robot grazed walls.
# 0.09 rather than 0.1: read at the paper's threshold of 0.85, these labels rate a way as
# those braking at 0.1 read at 0.9 would (the factor (0.85 / 0.9)^2), a little farther out,
# which, with the tight arcs' headroom below, kept the robot competent in more of the tuning
# worlds at as few contacts (docs/method.md, *Ours: the tight arcs lifted*).
DEFAULT_DECEL_MPS2 = 0.09
# Stop this far short of the collision point, the sonar's minimum range: no speed is learnt
# for the last stretch that the ring cannot tell from touching.
DEFAULT_MARGIN_M = 0.15
# Labels run no faster than this many times the trajectory's top speed: the paper's stop at
# the top speed, and so do ours on the arcs left unlifted (below).
TOP_SPEED_CEILING = 1.0
# Ours run past it, up to this multiple, where a way is clear far beyond its stopping
# distance: a way clear far beyond it is otherwise labelled as one just clear. Above 1, a
# label keeps saying how much farther the way is clear, up to where the braking speed is this
# multiple of the top, so that the average a FAM rule learns of a mixed place (some ways clear
# far, some blocked) can still reach the fast threshold; the robot never drives faster than
# the top speed (core.trajectory_choice). 1.2 is 1.25 scaled with the deceleration above
# (by 0.85 / 0.9), the ceiling measured best at 0.9.
DEFAULT_LABEL_CEILING = 1.2
MAX_LABEL_CEILING = 3.0
# The ceiling lifts the arcs alone that turn no wider than a radius (None: every trajectory).
# The tight arcs' labels stop changing nearest (0.83 m along T3 at its top speed, 2.15 m
# along T0), so those are the rules whose averages the cap holds under the threshold;
# lifting the long ways too makes the robot meet things more, not more competent
# (docs/method.md). Ours: 1 m, T2 and T3 each way. Any radius up to the largest: a wider arc
# is straight to the ring.
DEFAULT_CEILING_RADIUS_M = 1.0
MAX_CEILING_RADIUS_M = 100.0
# How a file or a flag names no radius, every trajectory lifted: a radius without bound.
EVERY_TRAJECTORY = "inf"
# What labels can be given: a deceleration of at most about 1 g, as hard as tyres grip (and
# beyond it every label past the margin is the trajectory's top speed); a margin of at most
# the ring's reach, beyond which every label of an episode that bumped is 0.
MAX_DECEL_MPS2 = 10.0
MAX_MARGIN_M = SonarConfig().max_range_m

# How much farther label_reach_m reaches than where the labels stop changing, relatively and
# absolutely: at the reach sqrt(2 a (reach - margin)) then rounds to at least v_max, so that a
# collision point left out beyond it gives the very label it would have given, bit for bit.
# Far wider than the rounding, far narrower than any distance that matters.
_REACH_SLACK = 1e-9
_REACH_SLACK_M = 1e-9

# What a recorded point labels (core.method.Method.labels): the trajectory it was driven
# along, from where that met its collision point (a bump, a sonar's collision point, or
# none after a full circle: the paper's, §4.1); or every trajectory, each from the echoes
# heard around it as well (core.heard).
BUMP_LABELS = "bump"
HEARD_LABELS = "heard"
LABEL_RULES = (BUMP_LABELS, HEARD_LABELS)


def velocity_labels(
    distance_to_collision_m: np.ndarray,
    v_max_mps: np.ndarray | float,
    decel_mps2: float = DEFAULT_DECEL_MPS2,
    margin_m: float = DEFAULT_MARGIN_M,
    ceiling: np.ndarray | float = TOP_SPEED_CEILING,
) -> np.ndarray:
    """Labels (N,) m/s for distances (N,) metres along the arc (inf: no collision ahead), no
    faster than `ceiling` (one, or one a label) times the top speed."""
    import numpy as np  # when labels are made, not when the constants are read

    check_in_range(decel_mps2, "deceleration", 0.0, MAX_DECEL_MPS2, "m/s²", low_allowed=False)
    check_in_range(margin_m, "margin", 0.0, MAX_MARGIN_M, "m")
    ceilings = np.asarray(ceiling, dtype=np.float64)
    for bound in (ceilings.min(initial=1.0), ceilings.max(initial=1.0)):
        check_in_range(float(bound), "label ceiling", 1.0, MAX_LABEL_CEILING, "times the top speed")
    distance = np.asarray(distance_to_collision_m, dtype=np.float64)
    braking_m = np.maximum(distance - margin_m, 0.0)
    top = np.asarray(v_max_mps, dtype=np.float64)
    return np.minimum(ceilings * top, np.sqrt(2.0 * decel_mps2 * braking_m))


def ceiling_radius(value: float) -> float | None:
    """The radius a method holds for one given: None (every trajectory) for an infinite one."""
    return None if value == math.inf else value


def trajectory_ceilings(
    radii_m: Sequence[float], ceiling: float, radius_m: float | None
) -> np.ndarray:
    """(T,) each trajectory's labels' ceiling, as a multiple of its top speed: `ceiling` for
    the trajectories of radius (m; inf: straight) at most `radius_m`, or every one if that is
    None; 1, the top speed, for the rest."""
    import numpy as np  # when labels are made, not when the constants are read

    radii = np.asarray(radii_m, dtype=np.float64)
    lifted = np.ones(radii.shape, dtype=bool) if radius_m is None else radii <= radius_m
    return np.where(lifted, ceiling, TOP_SPEED_CEILING)


def label_reach_m(
    top_speed_mps: float,
    decel_mps2: float,
    margin_m: float,
    ceiling: float = TOP_SPEED_CEILING,
) -> float:
    """How far (m) along a trajectory no faster than `top_speed_mps` a collision point can
    change its label: from margin + (c v_max)^2 / (2 a) on every label is c v_max
    (velocity_labels, c the ceiling), and the reach lies a hair beyond that."""
    saturation_m = margin_m + (ceiling * top_speed_mps) ** 2 / (2.0 * decel_mps2)
    return saturation_m * (1.0 + _REACH_SLACK) + _REACH_SLACK_M


def distances_to_collision(
    arc_m: np.ndarray, collided: bool, end_arc_m: float | None = None
) -> np.ndarray:
    """Distance (N,) metres from each recorded point to the episode's end, inf without a bump.

    `arc_m` (N,) is the arc length travelled at each point; the collision point is at
    `end_arc_m`, by default the last recorded point.
    """
    import numpy as np  # when labels are made, not when the constants are read

    arc = np.asarray(arc_m, dtype=np.float64)
    if not collided:
        return np.full(arc.shape, np.inf)
    if end_arc_m is None:
        end_arc_m = float(arc[-1]) if len(arc) else 0.0
    return end_arc_m - arc
