"""Compiled training changes a FAM, bit for bit, as the numpy reference does, and sums the
change of its velocities (ΔV) as numpy summed a copy of every entry."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_fams import CONFIGS, learnt_fam, logged_rings, odd_rings
from kernel_references.rule_updates_reference import train_table_reference

from tvl_cli.core.fam import Fam


def tables(fam: Fam) -> bytes:
    count = len(fam.config.tables)
    return b"".join(
        fam.velocity_table(t).tobytes() + fam.experience_table(t).tobytes() for t in range(count)
    )


def exemplars(count: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    rings = np.concatenate([logged_rings(count // 2), odd_rings(count - count // 2, seed)])
    return rings, rng.integers(0, 7, count), rng.uniform(0.0, 0.6, count)


@pytest.mark.slow
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


@pytest.mark.parametrize("name", ["single", "multi"])
def test_the_change_is_what_a_copy_of_every_velocity_before_and_after_gives(name: str) -> None:
    fam = learnt_fam(name, minutes=2.0)
    tables = range(len(fam.config.tables))
    for seed in (3, 4):  # a second batch too: the first leaves nothing behind
        before = np.concatenate([fam.velocity_table(t).ravel() for t in tables])
        rings, trajectories, labels = exemplars(40, seed)
        change = fam.train(rings, trajectories, labels) / fam.entry_count
        after = np.concatenate([fam.velocity_table(t).ravel() for t in tables])
        assert change == float(np.abs(after - before).mean()) > 0.0
    assert fam.entry_count == len(before)
