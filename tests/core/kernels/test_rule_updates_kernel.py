"""Compiled training changes a FAM, bit for bit, as the numpy reference does, and sums the
change of its velocities (ΔV) as numpy sums every entry."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_fams import CONFIGS, learnt_fam, logged_rings, odd_rings

from tvl_cli.core.fam import Fam
from tvl_cli.core.kernels.rule_updates import summed_change
from tvl_cli.core.kernels.rule_updates_reference import (
    summed_change_reference,
    train_table_reference,
)


def tables(fam: Fam) -> bytes:
    count = len(fam.config.tables)
    return b"".join(
        fam.velocity_table(t).tobytes() + fam.experience_table(t).tobytes() for t in range(count)
    )


def exemplars(count: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    rings = np.concatenate([logged_rings(count // 2), odd_rings(count - count // 2, seed)])
    return rings, rng.integers(0, 7, count), rng.uniform(0.0, 0.6, count)


@pytest.mark.parametrize("symmetric", [True, False])
@pytest.mark.parametrize("name", sorted(CONFIGS))
def test_a_batch_trains_the_fam_as_the_reference_does(name: str, symmetric: bool) -> None:
    compiled, reference = learnt_fam(name, minutes=2.0), learnt_fam(name, minutes=2.0)
    reference._train_table = train_table_reference
    # Big enough to be summed in several chunks by the multi FAM's widest tables.
    rings, trajectories, labels = exemplars(6000, seed=len(name))
    change = compiled.train(rings, trajectories, labels, symmetric)
    assert change == reference.train(rings, trajectories, labels, symmetric)
    assert tables(compiled) == tables(reference)
    assert change > 0.0


def test_the_change_is_what_a_copy_of_every_velocity_before_and_after_gives() -> None:
    fam = learnt_fam("multi", minutes=2.0)
    every = [fam.velocity_table(t).ravel() for t in range(len(fam.config.tables))]
    before = np.concatenate(every)
    rings, trajectories, labels = exemplars(40, seed=3)
    change = fam.train(rings, trajectories, labels) / fam.entry_count
    after = np.concatenate([fam.velocity_table(t).ravel() for t in range(len(every))])
    assert change == float(np.abs(after - before).mean())
    assert fam.entry_count == len(before)


@pytest.mark.parametrize("total", [1, 7, 8, 129, 5040, 31250, 123625])
def test_a_sparse_change_sums_as_numpy_sums_it(total: int) -> None:
    rng = np.random.default_rng(total)
    for touched in (1, 5, 60, 700):
        entries = np.unique(rng.integers(0, total, touched))
        change = rng.uniform(0.0, 0.1, len(entries)) * 10.0 ** rng.integers(-6, 1, len(entries))
        assert summed_change(entries, change, total) == summed_change_reference(
            entries, change, total
        )
