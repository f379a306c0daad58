"""Trained FAMs and rings for comparing the FAM kernels with their references: each shipped
configuration, one of tables storing different numbers of trajectories and one of tables
of one and two inputs, trained on the example log of the lab."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DESIGNED, MULTI, SINGLE, FamConfig
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import SessionEpisodes, TrainParams, train_sessions
from tvl_cli.io.logreader import read_log

LOG = Path(__file__).resolve().parents[1] / "logs" / "lab-s1.h5"
ROBOT = RobotConfig()
NAMES = [t.name for t in ROBOT.trajectories]
# The single FAM's one table split in two: three trajectories in one, four in the other.
SPLIT = FamConfig(
    "split",
    (
        dataclasses.replace(SINGLE.tables[0], name="left", trajectories=tuple(NAMES[:3])),
        dataclasses.replace(SINGLE.tables[0], name="right", trajectories=tuple(NAMES[3:])),
    ),
)
# Tables of one and two inputs, the fewest a table's corners can be split between.
FEW = FamConfig(
    "few",
    (
        dataclasses.replace(
            SINGLE.tables[0], name="one", inputs=SINGLE.tables[0].inputs[:1],
            trajectories=tuple(NAMES[:3]),
        ),
        dataclasses.replace(
            SINGLE.tables[0], name="two", inputs=SINGLE.tables[0].inputs[:2],
            trajectories=tuple(NAMES[3:]),
        ),
    ),
)  # fmt: skip
CONFIGS = {c.name: c for c in (SINGLE, MULTI, DESIGNED, SPLIT, FEW)}


def learnt_fam(name: str, minutes: float = 5.0) -> Fam:
    """A FAM of the configuration trained on the first minutes of the example log."""
    fam = Fam(CONFIGS[name], NAMES)
    (session,) = read_log(LOG).sessions
    episodes = [e for e in session.episodes() if e.end_time_s <= 60.0 * minutes]
    train_sessions(fam, [SessionEpisodes(episodes, ended=True)], ROBOT, TrainParams())
    return fam


def logged_rings(count: int) -> np.ndarray:
    """(count, 16) metres: rings the robot read in the lab, spread over the log."""
    (session,) = read_log(LOG).sessions
    rings = mm_to_ring(np.concatenate([e.ring_mm for e in session.episodes()]))
    return rings[np.linspace(0, len(rings) - 1, count).astype(int)]


def odd_rings(count: int, seed: int) -> np.ndarray:
    """(count, 16) metres: uniform over the range, with readings exactly at the range's ends
    and on the fuzzy sets' centres, where a set's degree is exactly 0 or 1."""
    rng = np.random.default_rng(seed)
    rings = rng.uniform(ROBOT.sonar.min_range_m, ROBOT.sonar.max_range_m, (count, 16))
    centres = np.unique([c for t in SINGLE.tables for i in t.inputs for c in i.partition.centres_m])
    special = np.concatenate([centres, [ROBOT.sonar.min_range_m, ROBOT.sonar.max_range_m]])
    at = rng.random((count, 16)) < 0.3
    rings[at] = rng.choice(special, at.sum())
    return rings
