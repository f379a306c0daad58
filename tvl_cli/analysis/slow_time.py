"""Why a run was slow: each step the policy drove slower than competence asks, told by the
simulator's truth and the run's FAM (analysis.autopsy.slow_cause judges it; the caller,
commands.contact_autopsy, gives the truth as the oracle velocities of a view).

A step is judged straight ahead (analysis.autopsy says why): which trajectories there were
truly fast (the oracle velocities, from the map and the true pose), which the FAM rated fast
on what it read (through the echo memory, where there is one), and which it would have rated
fast on the live ring alone.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from tvl_cli.analysis.autopsy import (
    FAST_DRIVE_MPS,
    SLOW_CAUSES,
    UNRATED,
    slow_cause,
)
from tvl_cli.core.fam import Fam
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig

# The true velocities (T,) m/s of the trajectories ahead of a true pose.
TrueAhead = Callable[[tuple[float, float, float]], np.ndarray]


def slow_time_by_cause(
    robot: RobotConfig,
    threshold: float,
    columns: Mapping[str, np.ndarray],
    poses_before: np.ndarray,
    true_ahead: TrueAhead,
    fam: Fam | None,
) -> dict[str, float]:
    """SLOW_CAUSES -> simulated seconds, over the steps (columns, as agent.trace names them;
    `poses_before` (N, 3) the true pose each reading was taken at) where the policy
    commanded less than FAST_DRIVE_MPS. A trajectory is fast, truly or as rated, at
    `threshold` x its maximum velocity, as the run's choices had it."""
    fast_from_mps = threshold * np.array([t.v_max_mps for t in robot.trajectories])  # (T,)
    read = np.asarray(columns["ring_mm"].any(axis=1))
    slow = (columns["reflex"] < 0) & (columns["speed_mps"] < FAST_DRIVE_MPS)
    live_m = mm_to_ring(columns["ring_mm"])  # (N, 16) metres
    read_m = mm_to_ring(columns.get("perceived_mm", columns["ring_mm"]))
    seconds = dict.fromkeys(SLOW_CAUSES, 0.0)
    cause = UNRATED
    for step in np.flatnonzero(slow):
        # A step that read no ring carries out the choice of the last one that did (the
        # rest of a spin to face another view): that choice's cause is its cause.
        if read[step]:
            x, y, theta = poses_before[step]
            truly_fast = true_ahead((float(x), float(y), float(theta))) >= fast_from_mps
            if fam is None:
                # The fast set the choice recorded is of the view it chose, which is the one
                # ahead unless it turned, and it turns only when it finds nothing fast ahead.
                ahead = columns["rotation"][step] == 0
                read_fast = np.asarray(columns["fast"][step], dtype=bool) & ahead
                live_fast = None
            else:
                read_fast = fam.velocities(read_m[step]) >= fast_from_mps  # rotation 0: ahead
                live_fast = fam.velocities(live_m[step]) >= fast_from_mps
            cause = slow_cause(truly_fast, read_fast, live_fast)
        seconds[cause] += robot.control_period_s
    return seconds
