"""How a learning log's sessions are stored (io.logfile lays them out): a session's datasets
chunked and uncompressed while it is written, so that a kill leaves every chunk where it was
(see io.logfile), and the whole log rewritten compressed once the session closes."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import h5py

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.hdf5_header import hdf5_output
from tvl_cli.io.loglayout import (
    EPISODE_DTYPE,
    EXEMPLAR_DATASETS,
    MINUTE_COLUMNS,
    MINUTE_UNITS,
    SESSIONS,
)

# Rows per chunk: about 32 KiB of sonar readings, enough for gzip to work with.
EXEMPLAR_CHUNK_ROWS = 1024
EPISODE_CHUNK_ROWS = 256
MINUTE_CHUNK_ROWS = 64
COMPRESSION: dict[str, Any] = {"compression": "gzip", "compression_opts": 4, "shuffle": True}


def new_session(f: h5py.File, robot: RobotConfig) -> h5py.Group:
    """The next session group, '0000', '0001', ..., with its empty growable datasets,
    uncompressed until the session closes (see io.logfile's docstring)."""
    sessions = f.require_group(SESSIONS)
    group = sessions.create_group(f"{len(sessions):04d}")
    row_shapes = {"ring_mm": (robot.sonar.count,), "pose": (3,), "odometry": (3,)}
    for name, (dtype, units, description) in EXEMPLAR_DATASETS.items():
        row = row_shapes.get(name, ())
        dataset = group.create_dataset(
            name,
            shape=(0, *row),
            maxshape=(None, *row),
            dtype=dtype,
            chunks=(EXEMPLAR_CHUNK_ROWS, *row),
        )
        dataset.attrs.update(units=units, description=description)
    group["trajectory"].attrs["names"] = [t.name for t in robot.trajectories]
    episodes = group.create_dataset(
        "episodes",
        shape=(0,),
        maxshape=(None,),
        dtype=EPISODE_DTYPE,
        chunks=(EPISODE_CHUNK_ROWS,),
    )
    episodes.attrs["description"] = (
        "one row per episode: exemplars first..first+count-1, how and where it ended"
    )
    minutes = group.create_dataset(
        "minutes",
        shape=(0, len(MINUTE_COLUMNS)),
        maxshape=(None, len(MINUTE_COLUMNS)),
        dtype="<f8",
        chunks=(MINUTE_CHUNK_ROWS, len(MINUTE_COLUMNS)),
    )
    minutes.attrs.update(
        columns=list(MINUTE_COLUMNS),
        units=list(MINUTE_UNITS),
        description="learning progress per simulated minute (delta_v: paper eq. 4)",
    )
    return group


def compress(path: Path) -> None:
    """Rewrite the log with every session's datasets gzip-compressed, then rename it into
    place; sessions already compressed are copied chunk for chunk, not recompressed."""
    with h5py.File(path, "r") as source, hdf5_output(path) as target:
        target.attrs.update(source.attrs)
        sessions = target.create_group(SESSIONS)
        for name, group in source[SESSIONS].items():
            if group["ring_mm"].compression is not None:
                source.copy(group, sessions, name)
                continue
            copy = sessions.create_group(name)
            copy.attrs.update(group.attrs)
            for dataset in group.values():
                compressed = copy.create_dataset(
                    dataset.name.rsplit("/", 1)[-1],
                    data=dataset[()],
                    maxshape=dataset.maxshape,
                    chunks=dataset.chunks,
                    **COMPRESSION,
                )
                compressed.attrs.update(dataset.attrs)
