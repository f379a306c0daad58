"""Write the golden files of each format version that tests/io/test_golden.py reads back.

    python tests/data/make_golden.py

They stand for the files users of each format version have on disk, so they are made once
and kept: a later tvl must still read them. The script writes those of the current versions
that are missing; the older ones were written by the tvl of their version. The expected
contents live here, as constants, and the test checks what the reader returns against them,
never against what the current writer would write. Refuses to overwrite existing golden files
unless given --force.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from tvl_cli.core.episode import Episode
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import SINGLE, FamConfig, FamInput, FamTable, Partition
from tvl_cli.core.memory import MemoryConfig
from tvl_cli.core.method import PAPER
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.logfile import LogWriter

HERE = Path(__file__).parent
GOLDEN_LOG = HERE / "golden-log-v1.h5"
GOLDEN_FAM = HERE / "golden-fam-v1.h5"
# Version 2 of the FAM file adds the echo memory it reads through.
GOLDEN_FAM_V2 = HERE / "golden-fam-v2.h5"
MEMORY = {"kind": "patches", "window_s": 12.5, "range_m": 1.75, "patch_m": 0.4}
# The files were written before clearing was a choice: read back, their memory never clears.
READ_MEMORY = MemoryConfig(**MEMORY, clearing="never")
# Log version 2 and FAM version 3 keep their method whole, once: one of no preset's.
GOLDEN_LOG_V2 = HERE / "golden-log-v2.h5"
GOLDEN_FAM_V3 = HERE / "golden-fam-v3.h5"
METHOD = replace(PAPER, near_m=0.2, reflexes=("bump", "tie"), memory=READ_MEMORY)
PROVENANCE_V3 = {
    "logs": [{"path": "golden-log-v2.h5", "sha256": "1" * 64, "sessions": ["0000", "0001"]}],
    "sessions_differ_in": [],
    "training": {"config": "tiny", "symmetric": False, "init_velocity_mps": 0.1},
}

ROBOT = RobotConfig()
NAMES = tuple(t.name for t in ROBOT.trajectories)
WORLD_TEXT = "version: 1\nname: golden\ncell: 0.25\n\n######\n#.>..#\n#....#\n######\n"
PARAMETERS = {"minutes": 0.5, "learn_speed_mps": 0.2, "decel_mps2": 0.5, "config": "single"}
# A session of log version 2 keeps only the settings that are not the method's.
PARAMETERS_V2 = {"minutes": 0.5, "learn_speed_mps": 0.2, "config": "single"}
SEEDS = (11, 12)
MINUTES = ((1.0, 2.0, 1.0, 5.0, 0.0125),)

# Two inputs of two sets: 4 rules x 7 trajectories.
_SETS = Partition(("N", "F"), (0.3, 1.0))
TINY = FamConfig(
    "tiny",
    (
        FamTable(
            "all", (FamInput("left", (3, 4), _SETS), FamInput("right", (12, 13), _SETS)), NAMES
        ),
    ),
)
INIT_VELOCITY_MPS = 0.1
PROVENANCE = {
    "logs": [{"path": "golden-log-v1.h5", "sha256": "0" * 64, "sessions": ["0000", "0001"]}],
    "decel_mps2": 0.5,
    "margin_m": 0.05,
    "symmetric": True,
    "init_velocity_mps": INIT_VELOCITY_MPS,
}


def golden_episodes() -> tuple[tuple[Episode, ...], ...]:
    """The episodes of each session: hand-picked values, nothing random."""
    first = Episode(
        index=0,
        ring_mm=np.array([[150 + 10 * i + s for s in range(16)] for i in range(3)], np.uint16),
        pose=np.array([[1.0, 1.0, 0.0], [1.02, 1.0, 0.0], [1.04, 1.0, 0.0]]),
        odometry=np.array([[1.0, 1.0, 0.0], [1.021, 1.0, 0.001], [1.042, 1.0, 0.002]]),
        arc_m=np.array([0.0, 0.02, 0.04]),
        trajectory=3,
        rotation=0,
        collided=True,
        bumped=True,
        end_arc_m=0.05,
        end_time_s=0.3,
    )
    second = Episode(
        index=1,
        ring_mm=np.full((2, 16), 4000, np.uint16),
        pose=np.array([[1.0, 1.5, 1.5], [1.0, 1.52, 1.55]]),
        odometry=np.array([[1.0, 1.5, 1.5], [1.0, 1.52, 1.55]]),
        arc_m=np.array([0.0, 0.02]),
        trajectory=2,
        rotation=4,
        collided=False,
        bumped=False,
        end_arc_m=12.566,
        end_time_s=63.2,
    )
    third = Episode(
        index=0,
        ring_mm=np.array([[1000] * 8 + [2000] * 8], np.uint16),
        pose=np.array([[2.0, 1.0, -1.0]]),
        odometry=np.array([[2.0, 1.0, -1.0]]),
        arc_m=np.array([0.0]),
        trajectory=6,
        rotation=15,
        collided=True,
        bumped=False,
        end_arc_m=0.01,
        end_time_s=0.2,
    )
    return ((first, second), (third,))


def golden_tables() -> tuple[np.ndarray, np.ndarray]:
    """Velocities (4, 7) m/s and experience (4, 7) of the one table: rule r, trajectory j."""
    rules, trajectories = np.meshgrid(np.arange(4), np.arange(7), indexing="ij")
    velocity = 0.05 * (rules + 1) + 0.01 * trajectories
    experience = (rules * 7 + trajectories) * 0.5
    return velocity, experience


def write_log(path: Path) -> None:
    """The log of the current version: the golden episodes, learnt by METHOD."""
    for seed, episodes in zip(SEEDS, golden_episodes(), strict=True):
        with LogWriter.open(
            path,
            world_name="golden",
            world_text=WORLD_TEXT,
            seed=seed,
            parameters=PARAMETERS_V2,
            robot_config=ROBOT.to_dict(),
            fam_config=SINGLE.to_dict(),
            method=METHOD,
        ) as writer:
            for episode in episodes:
                writer.append_episode(episode)
            if seed == SEEDS[0]:
                for minute, episodes_n, collisions, exemplars, delta_v in MINUTES:
                    writer.append_minute(
                        minute=int(minute),
                        episodes=int(episodes_n),
                        collisions=int(collisions),
                        exemplars=int(exemplars),
                        delta_v=delta_v,
                    )


def write_golden_fam(path: Path) -> None:
    """The FAM of the current version: the golden tables, made by METHOD."""
    velocity, experience = golden_tables()
    fam = Fam.from_tables(TINY, NAMES, [velocity], [experience], INIT_VELOCITY_MPS)
    write_fam(path, fam, robot_config=ROBOT, method=METHOD, provenance=PROVENANCE_V3)


def main(argv: list[str]) -> int:
    """Write the golden files that are missing: those of the current format versions. The
    older ones were written by the tvl of their version and are kept as they are."""
    force = "--force" in argv
    writers = {GOLDEN_LOG_V2: write_log, GOLDEN_FAM_V3: write_golden_fam}
    for path, write in writers.items():
        if path.exists() and not force:
            print(f"{path}: already exists (golden files are kept; use --force)", file=sys.stderr)
            return 2
        path.unlink(missing_ok=True)
        write(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
