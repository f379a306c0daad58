"""The heard labels seek echoes only as far along each trajectory as a collision point can
change a label (core.labels.label_reach_m): on a log learnt by `tvl learn`, the labels and the
FAM they train are bit for bit those of seeking every echo however far."""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
from conftest import TVL

from tvl_cli.commands.train import train_from_logs
from tvl_cli.core import training
from tvl_cli.core.heard import heard_episodes
from tvl_cli.core.labels import velocity_labels
from tvl_cli.core.training import TrainParams
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.log_sessions import common_robot, distinct_sessions
from tvl_cli.io.logreader import read_log

pytestmark = pytest.mark.slow  # starts a real `tvl learn`

LAB = Path(__file__).resolve().parents[2] / "worlds" / "lab.txt"


@pytest.fixture(scope="module")
def learnt(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """Three simulated minutes learnt in the lab by our method: the log and the FAM."""
    directory = tmp_path_factory.mktemp("lab")
    log, fam = directory / "lab.h5", directory / "fam.h5"
    done = subprocess.run(
        [TVL, "learn", LAB, "--log", log, "--minutes", "3", "--fam", fam],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return log, fam


def test_the_heard_labels_within_the_reach_are_those_of_every_echo(
    learnt: tuple[Path, Path],
) -> None:
    logs = [read_log(learnt[0])]
    robot, params = common_robot(logs), TrainParams()
    (session,), _ = distinct_sessions(logs)
    episodes = session.episodes()
    reach = params.reach_m(robot)
    within, every = (
        np.concatenate([h.distances_m for h in heard_episodes(episodes, robot, True, r)])
        for r in (reach, math.inf)
    )
    # The collision points up to the reach are those of every echo; some beyond it are not,
    # found farther along or not at all where the echoes that made them were left out.
    near = every <= reach
    np.testing.assert_array_equal(within[near], every[near])
    changed = (within != every) & ~np.isnan(every)
    assert changed.any() and (every[changed] > reach).all() and (within[changed] > reach).all()
    # None of them changes a label (NaN: none given, alike).
    v_max = np.array(robot.v_max_mps)
    labels = [
        velocity_labels(d, v_max, params.decel_mps2, params.margin_m) for d in (within, every)
    ]
    np.testing.assert_array_equal(*labels)
    assert (labels[1] < v_max).sum() > 1000  # far from all the top speed


def test_the_fam_trained_within_the_reach_is_that_of_every_echo(
    learnt: tuple[Path, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    log, fam_path = learnt
    online = read_fam(fam_path).fam  # learnt with the reach
    config = online.config
    within = train_from_logs([log], config).fam
    monkeypatch.setattr(training, "label_reach_m", lambda *_: math.inf)
    every = train_from_logs([log], config).fam
    for t in range(len(config.tables)):
        for fam in (within, online):
            np.testing.assert_array_equal(fam.velocity_table(t), every.velocity_table(t))
            np.testing.assert_array_equal(fam.experience_table(t), every.experience_table(t))
