"""Sonar ranges in the form logs and traces keep: uint16 millimetres.

The online FAM must train on mm_to_ring(ring_to_mm(ring)), the values a log keeps, so that
`tvl train` rebuilds it exactly from the log.
"""

from __future__ import annotations

import numpy as np

MM_PER_M = 1000.0
MM_MAX = np.iinfo(np.uint16).max


def ring_to_mm(ring_m: np.ndarray) -> np.ndarray:
    """Sonar ranges in metres -> uint16 millimetres (nearest), the form the log keeps."""
    mm = np.rint(np.asarray(ring_m, dtype=np.float64) * MM_PER_M)
    # np.clip would do, at a quarter more of the cost of a learning step's conversion.
    np.maximum(mm, 0, out=mm)
    np.minimum(mm, MM_MAX, out=mm)
    return mm.astype(np.uint16)


def mm_to_ring(ring_mm: np.ndarray) -> np.ndarray:
    """uint16 millimetres -> float64 metres: the exact values the FAM trains on."""
    return np.asarray(ring_mm, dtype=np.float64) / MM_PER_M


def beam_lines(
    ring_m: np.ndarray, pose: np.ndarray, body_radius_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """Each transducer's reading as a line from its place on the body's edge to its echo, in
    the frame of the pose: starts and ends (..., 16, 2) for ranges (..., 16) in metres and
    poses (..., 3) x, y, theta. Transducer i faces 2 pi i / 16 from the heading (S0 ahead,
    counter-clockwise)."""
    ring_m = np.asarray(ring_m, dtype=np.float64)
    pose = np.asarray(pose, dtype=np.float64)
    count = ring_m.shape[-1]
    angles = pose[..., 2:3] + 2.0 * np.pi * np.arange(count) / count  # (..., 16) rad
    unit = np.stack([np.cos(angles), np.sin(angles)], axis=-1)  # (..., 16, 2)
    start = pose[..., None, :2] + body_radius_m * unit
    return start, start + ring_m[..., None] * unit
