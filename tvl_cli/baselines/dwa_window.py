"""The Dynamic Window Approach (Fox, Burgard and Thrun 1997): velocity search for a unicycle.

Each control period the robot may only reach the velocities (v, w) its accelerations allow
from the current ones (the dynamic window); of those it keeps the admissible ones, from which
it can still stop before the first obstacle on their arc, and drives the one maximising

    score = heading_weight * heading + clearance_weight * clearance + velocity_weight * velocity

with each term scaled to [0, 1]: heading is the alignment, judged where the robot would stop,
with the goal (or, without one, with the direction `avoid` wanders); clearance is the free
distance along the arc, at most what the candidate covers within the horizon; velocity is
v / v_max. The obstacle distances come from the caller, which knows the world: this module
builds the candidate arcs and rays and scores them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tvl_cli.core.angles import wrap_rad

# Far above the rounding of a clearance, far below any distance the window tells apart.
_CLEARANCE_ROUNDING_M = 1e-6


@dataclass(frozen=True, slots=True)
class DwaParams:
    """Limits and weights; defaults are ours (the paper fixes none for this robot)."""

    # A firm brake, a real robot of this size's limit (not a label's rate: TVL's labels, the
    # paper's as read off its Figure 21 and ours, brake more gently). 2 rad/s² reaches the
    # full turn rate in 0.5 s.
    accel_mps2: float = 0.5
    angular_accel_radps2: float = 2.0
    v_max_mps: float = 0.6  # T0's maximum: no faster than a TVL trajectory
    w_max_radps: float = 1.0  # the spin rate, beyond every trajectory's (T3 at 0.35 m/s: 0.7)
    v_samples: int = 5
    w_samples: int = 11
    # Arcs are judged over this many seconds: obstacles beyond do not change the choice.
    horizon_s: float = 2.0
    arc_step_m: float = 0.025  # well under the thinnest obstacle (a quarter-metre cell)
    wander_rays: int = 24  # directions around the robot `avoid` judges for room to go
    # Keep this far from obstacles: a few centimetres to spare, the DWA's own (Fox et al. fix
    # none), not tied to any TVL method's labels, so that changing those leaves it as it is.
    margin_m: float = 0.05
    heading_weight: float = 0.3
    clearance_weight: float = 0.4
    velocity_weight: float = 0.3


@dataclass(frozen=True, slots=True, eq=False)
class Candidates:
    """The sampled dynamic window, one entry per (v, w) pair."""

    v_mps: np.ndarray  # (N,) forward speed
    w_radps: np.ndarray  # (N,) turn rate, positive counter-clockwise


def dynamic_window(v_mps: float, w_radps: float, period_s: float, p: DwaParams) -> Candidates:
    """The grid of velocities reachable within one control period from (v, w)."""
    dv = p.accel_mps2 * period_s
    dw = p.angular_accel_radps2 * period_s
    v = np.linspace(max(0.0, v_mps - dv), min(p.v_max_mps, v_mps + dv), p.v_samples)
    w = np.linspace(
        max(-p.w_max_radps, w_radps - dw), min(p.w_max_radps, w_radps + dw), p.w_samples
    )
    v_grid, w_grid = np.meshgrid(v, w, indexing="ij")  # (V, W) each
    return Candidates(v_grid.ravel(), w_grid.ravel())


def lookahead_m(p: DwaParams) -> float:
    """How far the fastest candidate goes within the horizon: the arcs are checked that far."""
    return p.v_max_mps * p.horizon_s


def arc_lengths(p: DwaParams) -> np.ndarray:
    """(K,) metres along each arc where the body is checked: one step on, up to the lookahead."""
    far = lookahead_m(p)
    count = math.ceil(far / p.arc_step_m)
    return np.linspace(far / count, far, count)


def _arc_offsets(curvature: np.ndarray, s_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Forward and leftward displacement after s metres on arcs of the given curvatures.

    sin(ks)/k and (1 - cos ks)/k written with sinc, so a straight line (k = 0) needs no case.
    """
    turn = curvature * s_m
    forward = s_m * np.sinc(turn / math.pi)
    left = s_m * np.sin(0.5 * turn) * np.sinc(turn / (2.0 * math.pi))
    return forward, left


def arc_points(
    pose: tuple[float, float, float], candidates: Candidates, s_m: np.ndarray
) -> np.ndarray:
    """(N, K, 2) world positions of the body centre s_m (K,) metres along each candidate's arc.

    A candidate that does not move forward (v = 0) spins in place: all its points are the start.
    """
    x, y, theta = pose
    moving = candidates.v_mps > 0.0
    curvature = np.divide(
        candidates.w_radps, candidates.v_mps, out=np.zeros_like(candidates.w_radps), where=moving
    )[:, None]  # (N, 1) per metre
    s = np.where(moving[:, None], s_m[None, :], 0.0)  # (N, K) metres
    forward, left = _arc_offsets(curvature, s)
    cos, sin = math.cos(theta), math.sin(theta)
    return np.stack([x + forward * cos - left * sin, y + forward * sin + left * cos], axis=-1)


def clearance_read_m(s_m: np.ndarray, p: DwaParams) -> float:
    """Metres of body-edge clearance beyond which a free distance (baselines.dwa_kernel) reads
    no difference: there a point's spare clearance exceeds the longest step to the next point
    (or from the start to the first), so the point after it bounds the free distance, and a
    clearance given as inf gives the same free distances bit for bit. Callers ask for no
    farther obstacle than this (a hair beyond, for the rounding of a clearance)."""
    longest_step_m = float(np.max(np.diff(s_m, prepend=0.0)))
    return p.margin_m + longest_step_m + _CLEARANCE_ROUNDING_M


def admissible(v_mps: np.ndarray, free_m: np.ndarray, p: DwaParams) -> np.ndarray:
    """(N,) bool: braking at accel_mps2 stops the body within the free distance."""
    return v_mps <= np.sqrt(2.0 * p.accel_mps2 * free_m)


def predicted_poses(
    pose: tuple[float, float, float], candidates: Candidates, period_s: float, p: DwaParams
) -> np.ndarray:
    """(N, 3) x, y, heading where each candidate leaves the robot: one period at (v, w), then
    braking both at full deceleration (the paper's heading is judged there). The position is
    taken on the candidate's arc, exact when both reach zero together."""
    v, w = candidates.v_mps, candidates.w_radps
    travel = v * period_s + v**2 / (2.0 * p.accel_mps2)  # (N,) metres
    turn = w * period_s + w * np.abs(w) / (2.0 * p.angular_accel_radps2)  # (N,) radians
    curvature = np.divide(w, v, out=np.zeros_like(w), where=v > 0.0)
    forward, left = _arc_offsets(curvature, travel)
    x, y, theta = pose
    cos, sin = math.cos(theta), math.sin(theta)
    return np.stack(
        [x + forward * cos - left * sin, y + forward * sin + left * cos, theta + turn], 1
    )


def ray_points(
    pose: tuple[float, float, float], offsets_rad: np.ndarray, s_m: np.ndarray
) -> np.ndarray:
    """(D, K, 2) world positions s_m (K,) metres along straight rays at offsets (D,) from the
    heading."""
    x, y, theta = pose
    angles = theta + offsets_rad[:, None]  # (D, 1) radians
    return np.stack([x + s_m * np.cos(angles), y + s_m * np.sin(angles)], axis=-1)


def wander_heading(
    heading_rad: float, offsets_rad: np.ndarray, free_m: np.ndarray, p: DwaParams, side: int
) -> float:
    """Where `avoid` heads: straight on while that is free to the lookahead, else the freest
    ray (free_m (D,) along offsets (D,)), the one nearest straight on among rays within an arc
    step of the freest, on the `side` (+1 left, -1 right) it last turned if still tied.

    Without it a goal-less DWA aims where it already faces, and drives up to every wall and
    stops there before turning; with it, it turns away as soon as the way ahead is short.
    """
    ahead = np.flatnonzero(offsets_rad == 0.0)
    if len(ahead) and free_m[ahead[0]] >= lookahead_m(p) - p.arc_step_m:
        return heading_rad
    tied = free_m >= free_m.max() - p.arc_step_m
    # Nearest straight on first; on the preferred side first at equal offsets.
    rank = np.abs(offsets_rad) - 1e-6 * side * np.sign(offsets_rad)
    return heading_rad + float(offsets_rad[tied][np.argmin(rank[tied])])


def goal_headings(predicted: np.ndarray, goal_xy: tuple[float, float]) -> np.ndarray:
    """(N,) direction from each predicted position (N, 3) to the goal, radians."""
    return np.arctan2(goal_xy[1] - predicted[:, 1], goal_xy[0] - predicted[:, 0])


def heading_scores(predicted: np.ndarray, wanted_rad: np.ndarray | float) -> np.ndarray:
    """(N,) 1 where the predicted heading (column 2 of (N, 3)) is the wanted one, 0 opposite."""
    error = wrap_rad(wanted_rad - predicted[:, 2])  # (N,) radians
    return 1.0 - np.abs(error) / math.pi


def best_candidate(
    candidates: Candidates, free_m: np.ndarray, heading: np.ndarray, p: DwaParams
) -> int:
    """Index of the admissible candidate with the highest score.

    When none is admissible (the robot is already too fast for what is ahead) it brakes as
    hard as it can, turning the way with the most room.
    """
    ok = admissible(candidates.v_mps, free_m, p)
    if not ok.any():
        slowest = candidates.v_mps == candidates.v_mps.min()
        return int(np.argmax(np.where(slowest, free_m, -np.inf)))
    # dist(v, w), capped at what the candidate covers within the horizon: a slow circle
    # that never meets anything is not worth a fast free run.
    reach = np.minimum(free_m, candidates.v_mps * p.horizon_s)
    score = (
        p.heading_weight * heading
        + p.clearance_weight * reach / lookahead_m(p)
        + p.velocity_weight * candidates.v_mps / p.v_max_mps
    )
    return int(np.argmax(np.where(ok, score, -np.inf)))


def recovery_spin(candidates: Candidates, side: int) -> int:
    """Index of the stopped candidate turning fastest towards `side` (+1 left, -1 right).

    A stopped robot whose best choice is to stay stopped is stuck: nothing in the score
    rewards turning on the spot towards room to move (the known trap of a goal-less DWA), so it
    turns until a moving candidate wins.
    """
    stopped = candidates.v_mps == 0.0
    return int(np.argmax(np.where(stopped, side * candidates.w_radps, -np.inf)))
