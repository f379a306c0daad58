"""What the benchmarks that study ours' runs read from a `tvl bench generalization` directory:
its worlds and the FAMs its ours rows (or a method controller's rows) trained from each
world's first-trial log, and their runs there traced step by step, as the benchmark's first
trial drives them."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.trace import Columns, TraceRecorder
from tvl_cli.commands.run import run_robot
from tvl_cli.core.method import DEFAULT, Method
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.io.famfile import FamFile, read_fam
from tvl_cli.sim.worldmap import WorldMap
from tvl_cli.sweep.layout import learning_tag

CONFIGS = ("single", "multi", "designed")  # the shipped configurations ours rows train
SEED = 1  # the benchmark's first trial
MINUTES = 5.0  # a run of the benchmark


def seeds(span: str) -> range:
    """The rooms seeds of a --worlds A-B."""
    first, last = (int(n) for n in span.split("-"))
    return range(first, last + 1)


def world_path(bench: Path, seed: int) -> Path:
    return bench / "worlds" / f"rooms-s{seed}.txt"


def ours_fam_path(bench: Path, seed: int, config: str, method: Method = DEFAULT) -> Path:
    """The FAM of `config` the bench's ours rows (or the rows of a controller learning by
    `method`) trained from the world's first-trial log."""
    return bench / "fams" / f"rooms-s{seed}-s1-m15.0-single{learning_tag(method)}-{config}.h5"


def ours_fam(
    bench: Path, seed: int, config: str, method: Method = DEFAULT
) -> tuple[FamFile, RobotConfig]:
    """That FAM, and the robot a run of it drives (`tvl run`'s)."""
    path = ours_fam_path(bench, seed, config, method)
    fam_file = read_fam(path)
    return fam_file, run_robot(fam_file.robot_config, None, path, DEFAULT_ROBOT)


def traced(run: Callable[..., object]) -> dict[str, np.ndarray]:
    """The columns of every step of a run, `run(on_step=...)` driving it with our reflexes."""
    chunks: list[Columns] = []
    trace = TraceRecorder(DEFAULT.reflexes, DEFAULT_ROBOT.sonar.count, [chunks.append])
    run(on_step=trace)
    trace.close()
    return {name: np.concatenate([c[name] for c in chunks]) for name in chunks[0]}


def ours_avoid(
    world: WorldMap, fam_file: FamFile, robot: RobotConfig, method: Method = DEFAULT
) -> dict[str, np.ndarray]:
    """The columns of an avoid run of a FAM (ours_fam) in the world, as the bench drives it
    by `method`."""
    return traced(
        partial(
            behave, world, robot, fam_file.fam, "avoid", minutes=MINUTES, seed=SEED, method=method
        )
    )
