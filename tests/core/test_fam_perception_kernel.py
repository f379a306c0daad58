"""Compiled FAM perception is, bit for bit, the numpy reference's: all 112 views of a ring,
and batches of rings, through FAMs of every shape trained on a real log."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_fams import CONFIGS, learnt_fam, logged_rings, odd_rings
from kernel_references.perception_reference import infer_views_reference

RINGS = np.concatenate([logged_rings(150), odd_rings(150, seed=4)])


@pytest.fixture(scope="module", params=sorted(CONFIGS))
def fam(request: pytest.FixtureRequest):
    return learnt_fam(request.param)


def test_all_views_of_a_ring_are_perceived_as_by_the_reference(fam) -> None:
    for ring in RINGS:
        views = fam.inference_inputs(ring[None], np.zeros(16, dtype=np.intp), np.arange(16))
        velocities, experience = fam.perceive(ring)
        expected_v, expected_e = np.empty((16, 7)), np.empty((16, 7))
        infer_views_reference(*views, expected_v, expected_e)
        assert velocities.tobytes() == expected_v.tobytes()
        assert experience.tobytes() == expected_e.tobytes()


@pytest.mark.parametrize("rotation", [0, 5, 13])
def test_a_batch_of_rings_is_perceived_as_by_the_reference(fam, rotation: int) -> None:
    views = np.arange(len(RINGS))
    inputs = fam.inference_inputs(RINGS, views, np.full(len(RINGS), rotation))
    expected_v, expected_e = np.empty((len(RINGS), 7)), np.empty((len(RINGS), 7))
    infer_views_reference(*inputs, expected_v, expected_e)
    assert fam.velocities(RINGS, rotation).tobytes() == expected_v.tobytes()
    assert fam.experience(RINGS, rotation).tobytes() == expected_e.tobytes()
    # The FAM was trained: perception is not the initial velocity everywhere.
    assert len(np.unique(expected_v)) > 100 and (expected_e > 0).any()
