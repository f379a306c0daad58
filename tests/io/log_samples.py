"""Deterministic learning-log content for the file tests, importable by child processes too."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from tvl_cli.core.episode import Episode
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.ring import ring_to_mm
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.logfile import LogWriter

ROBOT = RobotConfig()
WORLD_TEXT = "version: 1\nname: box\n\n#####\n#.>.#\n#####\n"
PARAMETERS = {"minutes": 1.0, "learn_speed_mps": 0.2, "config": "single"}


def sample_episode(index: int) -> Episode:
    """Episode `index`: its own seed, 3 to 9 exemplars, collided when the index is even."""
    rng = np.random.default_rng(index)
    n = 3 + index % 7
    step_m = 0.02
    return Episode(
        index=index,
        ring_mm=ring_to_mm(rng.uniform(0.15, 4.0, (n, 16))),  # (n, 16) mm
        pose=rng.normal(size=(n, 3)),  # (n, 3) m, m, rad
        odometry=rng.normal(size=(n, 3)),
        arc_m=np.arange(n) * step_m,  # (n,) m
        trajectory=index % 7,
        rotation=(3 * index) % 16,
        collided=index % 2 == 0,
        bumped=index % 4 == 0,
        end_arc_m=n * step_m,
        end_time_s=10.0 * (index + 1),
    )


def open_sample_writer(
    path: Path | str, seed: int = 7, robot: RobotConfig = ROBOT, write_every_s: float = 0.0
) -> LogWriter:
    return LogWriter.open(
        path,
        world_name="box",
        world_text=WORLD_TEXT,
        seed=seed,
        parameters=PARAMETERS,
        robot_config=robot.to_dict(),
        fam_config=SINGLE.to_dict(),
        # Its own, not tests/method_samples: child processes import this module alone.
        method=replace(DEFAULT, memory=NO_MEMORY),
        write_every_s=write_every_s,
    )


def assert_same_episode(read: Episode, written: Episode) -> None:
    for name in ("ring_mm", "pose", "odometry", "arc_m"):
        expected = getattr(written, name)
        actual = getattr(read, name)
        assert actual.dtype == expected.dtype, name
        np.testing.assert_array_equal(actual, expected, err_msg=name)
    for name in (
        "index",
        "trajectory",
        "rotation",
        "collided",
        "bumped",
        "end_arc_m",
        "end_time_s",
    ):
        assert getattr(read, name) == getattr(written, name), name
