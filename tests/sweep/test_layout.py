"""Where a sweep or a bench keeps its logs and FAMs: named for the learning they hold."""

from __future__ import annotations

from dataclasses import replace

from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT, PAPER
from tvl_cli.sweep.layout import learning_tag


def test_a_log_is_named_for_every_learning_choice_of_its_method_ours_too() -> None:
    # Ours as it was before its labels changed is not ours now: a directory's log and FAMs
    # learnt then must not be taken for ours now.
    ours_before = replace(DEFAULT, decel_mps2=0.1, label_ceiling=1.0)
    tags = {learning_tag(m) for m in (DEFAULT, ours_before, PAPER)}
    assert len(tags) == 3
    assert learning_tag(DEFAULT).startswith("-default-")
    assert learning_tag(PAPER).startswith("-paper-")
    assert learning_tag(ours_before).startswith("-method-")


def test_choices_made_when_behaving_share_the_log() -> None:
    # The reflexes are a run's: one log serves ours with any of them.
    assert learning_tag(replace(DEFAULT, reflexes=())) == learning_tag(DEFAULT)
    # The memory is learning's too: the log's episodes were perceived through it.
    assert learning_tag(replace(DEFAULT, memory=NO_MEMORY)) != learning_tag(DEFAULT)
