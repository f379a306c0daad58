"""Training by each rule of labels: the paper's trains bit for bit as it always did, and the
heard rule labels every trajectory, from any log."""

from __future__ import annotations

import hashlib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tvl_cli.commands.train import ORACLE_LABELS, train_each_from_logs, train_from_logs
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DESIGNED, MULTI, SINGLE, FamConfig
from tvl_cli.core.labels import HEARD_LABELS
from tvl_cli.core.method import PAPER

ROOT = Path(__file__).resolve().parents[2]
LAB = ROOT / "logs" / "lab-s1.h5"


def digest(fam: Fam, config: FamConfig) -> str:
    h = hashlib.sha256()
    for t in range(len(config.tables)):
        h.update(fam.velocity_table(t).tobytes())
        h.update(fam.experience_table(t).tobytes())
    return h.hexdigest()[:16]


# The example lab log as it was learnt before there were heard labels (the paper's labels,
# 15 minutes, seed 1), kept so that the paper's FAMs of it stay comparable with what the
# training before the heard labels made of it.
BEFORE = ROOT / "tests" / "data" / "lab-s1-before-heard-labels.h5"
PAPER_DIGESTS = {"single": "36c74f77bd91dbb6", "multi": "7de4a8251478f749"}


@pytest.mark.slow  # over a second
@pytest.mark.parametrize("config", [SINGLE, MULTI], ids=lambda c: c.name)
def test_the_papers_method_trains_bit_for_bit_as_before(config: FamConfig) -> None:
    fam = train_from_logs([BEFORE], config, PAPER).fam
    assert digest(fam, config) == PAPER_DIGESTS[config.name]


@pytest.mark.slow  # over a second
def test_heard_labels_train_every_trajectory_from_a_log_learnt_by_the_papers_rule() -> None:
    # The example log was learnt labelling the driven trajectory alone; heard, its points
    # label the others too, and give every trajectory's rules far more experience.
    driven = train_from_logs([LAB], SINGLE, PAPER).fam
    heard = train_from_logs([LAB], SINGLE, replace(PAPER, labels=HEARD_LABELS)).fam
    assert heard.experience_table(0).sum() > 4 * driven.experience_table(0).sum()
    touched = (heard.experience_table(0) > 0).sum(axis=0)  # (7,) rules per trajectory
    assert (touched >= (driven.experience_table(0) > 0).sum(axis=0)).all()
    assert not np.array_equal(heard.velocity_table(0), driven.velocity_table(0))


@pytest.mark.slow  # over a second
def test_the_oracle_labels_label_every_trajectory_of_every_point_from_the_map() -> None:
    square = ROOT / "logs" / "square-s1.h5"
    driven = train_from_logs([square], SINGLE, PAPER)
    oracle = train_from_logs([square], SINGLE, PAPER, true_labels=True)
    # Every point trains all seven trajectories where the paper's trains one: seven times the
    # experience, from the same rings.
    total = oracle.fam.experience_table(0).sum()
    assert total == pytest.approx(7 * driven.fam.experience_table(0).sum(), rel=1e-9)
    assert oracle.provenance["labels_from"] == ORACLE_LABELS
    assert "labels_from" not in driven.provenance


@pytest.mark.slow  # over a second
@pytest.mark.parametrize("true_labels", [False, True], ids=["heard", "oracle"])
def test_configurations_trained_together_are_each_as_trained_alone(true_labels: bool) -> None:
    # One reading, perceiving and labelling of the log for all three: each FAM is bit for bit
    # the one `tvl train` makes alone, with its own provenance.
    square = ROOT / "logs" / "square-s1.h5"
    configs = [SINGLE, MULTI, DESIGNED]
    together = train_each_from_logs([square], configs, true_labels=true_labels)
    for config, summary in zip(configs, together, strict=True):
        alone = train_from_logs([square], config, true_labels=true_labels)
        assert digest(summary.fam, config) == digest(alone.fam, config)
        assert summary.provenance == alone.provenance
        assert summary.exemplars == alone.exemplars > 0
    assert len({digest(s.fam, c) for s, c in zip(together, configs, strict=True)}) == 3
