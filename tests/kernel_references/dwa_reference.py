"""The DWA's free distances in plain numpy, from every arc point's clearance: what
`baselines.dwa_kernel.walked_free_distances` computes, kept for the tests that compare the
two."""

from __future__ import annotations

import numpy as np


def free_distances_reference(
    clearance_m: np.ndarray, start_clearance_m: float, s_m: np.ndarray, margin_m: float
) -> np.ndarray:
    """(N,) metres each arc can be followed, from the body-edge clearance (N, K) at each of
    its points s_m (K,) along it and the start's (baselines.dwa_kernel documents the rule)."""
    allowed = min(margin_m, start_clearance_m)
    spare = clearance_m - allowed  # (N, K) metres
    count, samples = spare.shape
    near = spare < 0.0  # (N, K)
    first = np.where(near.any(axis=1), near.argmax(axis=1), samples)  # (N,)
    # Arc length and spare clearance of the last free point, the start standing in as point -1.
    s_before = np.concatenate([[0.0], s_m])  # (K + 1,)
    c_before = np.concatenate([np.full((count, 1), start_clearance_m - allowed), spare], axis=1)
    reach = s_before[first] + c_before[np.arange(count), first]
    bound = np.concatenate([s_m, [s_m[-1]]])[first]  # (N,) first point too near, or the end
    return np.minimum(reach, bound)
