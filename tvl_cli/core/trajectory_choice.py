"""Behaviours as choices among fast trajectories (paper §2.1–2.2, §4.5).

A trajectory is *fast* when its perceived velocity reaches threshold × its maximum. Each
behaviour is a rule for which fast trajectory to take; when none is fast straight ahead,
the robot rotates its perception around the ring (±1, ±2, … ±8 sonar positions) and takes
the best fitting fast trajectory it finds there, to be faced by spinning on the spot.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.angles import wrap_rad
from tvl_cli.core.behaviours import LEFT_SONARS, RIGHT_SONARS

# How far along an arc its heading is judged: far enough that arcs of different radius
# point in clearly different directions, near enough to stay inside a few-metre arena.
LOOKAHEAD_M = 0.5


@dataclass(frozen=True, slots=True)
class Context:
    """What a behaviour knows besides the perceived velocities."""

    ring_m: np.ndarray  # (16,) metres, S0 forward, CCW
    # +1 left, -1 right: the side a tie goes to. The paper is silent on ties; 0 takes the
    # first in trajectory order (T3L to T3R) and looks left first when rotating perception.
    tie_side: int = 0
    goal_bearing_rad: float = 0.0  # goal direction relative to the heading (goal only)
    wall_side: int = 0  # +1 left, -1 right, 0 none found yet (wall following only)


@dataclass(frozen=True, slots=True)
class Choice:
    """Face sonar `rotation` (0: as now), then follow `trajectory` at `speed_mps`."""

    rotation: int  # -7..8 sonar positions, positive counter-clockwise
    trajectory: int
    speed_mps: float


def trajectory_headings(
    curvatures_per_m: np.ndarray, sonar_count: int, lookahead_m: float = LOOKAHEAD_M
) -> np.ndarray:
    """(sonar_count, 7) heading of each rotated trajectory after lookahead_m of it, radians."""
    sonar_angles = np.arange(sonar_count) * (2 * math.pi / sonar_count)
    return wrap_rad(sonar_angles[:, None] + curvatures_per_m[None, :] * lookahead_m)


def _wall_bearing(ring_m: np.ndarray, side: int) -> float:
    sonars = LEFT_SONARS if side > 0 else RIGHT_SONARS
    nearest = sonars[int(np.argmin(ring_m[list(sonars)]))]
    return float(wrap_rad(nearest * 2 * math.pi / len(ring_m)))


# A score per candidate (lower is better) from one rotation's trajectory headings.
Scorer = Callable[[np.ndarray, Context], np.ndarray]


def _avoid_score(headings: np.ndarray, ctx: Context) -> np.ndarray:
    # Nearest the forward direction; a tie goes to the one heading to the tie side.
    return np.abs(headings) - 1e-6 * np.sign(headings) * ctx.tie_side


def _wall_score(side: int) -> Scorer:
    def score(headings: np.ndarray, ctx: Context) -> np.ndarray:
        if ctx.wall_side != side:
            return _avoid_score(headings, ctx)
        # Paper §2.1: the fast trajectory nearest the nearest object on the wall's side, without
        # passing it (for a wall on the left, the nearest to its right), measured from the
        # object's bearing away from it. The outermost arc qualifies only while it heads short
        # of the wall: with the wall a metre off, a T3 arc is fast all the way round, and
        # taking it there circles beside the wall instead of closing in on it.
        away = (_wall_bearing(ctx.ring_m, side) - headings) * side
        return np.mod(away, 2 * math.pi)

    return score


def _goal_score(headings: np.ndarray, ctx: Context) -> np.ndarray:
    return np.abs(wrap_rad(headings - ctx.goal_bearing_rad))


BEHAVIOURS: dict[str, Scorer] = {
    "avoid": _avoid_score,
    "wall-left": _wall_score(1),
    "wall-right": _wall_score(-1),
    "goal": _goal_score,
}


def fast_set(velocities: np.ndarray, v_max: np.ndarray, threshold: float) -> np.ndarray:
    """(16, 7) bool: the trajectories perceived at threshold x their maximum or faster."""
    return velocities >= threshold * v_max[None, :]


def choose(
    velocities: np.ndarray,
    fast: np.ndarray,
    v_max: np.ndarray,
    headings: np.ndarray,
    behaviour: str,
    ctx: Context,
) -> Choice | None:
    """Pick a fast trajectory for `behaviour`, or None when no direction has one (trapped).

    velocities: (16, 7) perceived m/s, row k as if facing sonar k; fast: (16, 7) bool, the
    candidates (fast_set, less any the caller leaves out); v_max: (7,); headings: (16, 7)
    from trajectory_headings, how behaviours judge where a trajectory goes. The other views
    are read only when the view ahead has no candidate, so a caller whose view ahead has one
    may give that row alone, (1, 7).
    """
    n_sonars = headings.shape[0]
    scorer = _wall_score(ctx.wall_side or 1) if behaviour == "wall" else BEHAVIOURS[behaviour]
    # (16,) whether each view has a fast trajectory, found at once rather than view by view
    has_fast: list[bool] = fast.any(axis=1).tolist()  # type: ignore[assignment]
    if has_fast[0]:
        scores = np.where(fast[0], scorer(headings[0], ctx), np.inf)
        pick = int(np.argmin(scores))
        return Choice(0, pick, float(min(velocities[0, pick], v_max[pick])))
    side = -1 if ctx.tie_side < 0 else 1
    for step in range(1, n_sonars // 2 + 1):
        # Equally good views either side: the one on the tie side (left first) wins.
        rotations = [side * step, -side * step] if step < n_sonars // 2 else [step]
        best: tuple[float, int, int] | None = None
        for k in rotations:
            row = k % n_sonars
            if not has_fast[row]:
                continue
            scores = np.where(fast[row], scorer(headings[row], ctx), np.inf)
            j = int(np.argmin(scores))
            if best is None or scores[j] < best[0]:
                best = (float(scores[j]), k, j)
        if best is not None:
            _, k, j = best
            return Choice(k, j, float(min(velocities[k % n_sonars, j], v_max[j])))
    return None
