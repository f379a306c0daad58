"""The layout of a learning log, in one place: what its writer makes and its reader expects,
and the check that a file holds it before anything reads or appends."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from tvl_cli.io.hdf5_header import FormatError

SESSIONS = "sessions"

EPISODE_DTYPE = np.dtype(
    [
        ("first", "<i8"),  # index of the episode's first exemplar in the session
        ("count", "<i4"),  # exemplars in the episode
        ("trajectory", "i1"),
        ("rotation", "i1"),
        ("collided", "?"),  # ended at a collision point: labels brake to it
        ("bumped", "?"),  # that point was a bump, not one the sonars found too near
        ("end_time_s", "<f8"),  # simulated time at the end, from the session start
        ("end_arc_m", "<f8"),  # arc length at the end: the collision point if collided
    ]
)
MINUTE_COLUMNS = ("minute", "episodes", "collisions", "exemplars", "delta_v")
MINUTE_UNITS = ("min", "", "", "", "m/s per control step")

# Session attributes counting the rows known to be whole in the file: rows past them may be
# half written by a killed writer and are ignored.
COMMITTED_EPISODES = "episodes_written"
COMMITTED_MINUTES = "minutes_written"

# What a session recorded: exploration (`tvl learn`) or a behaviour learning as it went
# (`tvl run --learn`). Both keep the same exemplars; sessions written before kinds were
# recorded are learning sessions.
KIND_LEARNING = "learning"
KIND_BEHAVING = "behaving"
SESSION_KINDS = (KIND_LEARNING, KIND_BEHAVING)

STATUS_RUNNING = "running"
STATUS_FINISHED = "finished"
STATUS_NOT_CLOSED = "interrupted: not closed"  # the writer died without closing the session


def ended_status(stopped_by: str | None) -> str:
    """How a session or a run ended: finished, or stopped early by a signal ("SIGINT")."""
    return STATUS_FINISHED if stopped_by is None else f"interrupted: {stopped_by}"


# name -> (dtype, units, description) of the per-exemplar datasets, in writing order.
EXEMPLAR_DATASETS: dict[str, tuple[str, str, str]] = {
    "ring_mm": ("<u2", "mm", "sonar ranges S0..S15, S0 forward, numbered counter-clockwise"),
    "pose": ("<f8", "m, m, rad", "true pose x, y, theta"),
    "odometry": ("<f8", "m, m, rad", "odometry pose x, y, theta"),
    "arc_m": ("<f8", "m", "distance along the arc from the episode start"),
    "trajectory": ("i1", "", "trajectory index, in the order of robot_config trajectories"),
    "rotation": ("i1", "sonar positions", "foveal rotation chosen, counter-clockwise"),
    "episode": ("<i4", "", "episode index in this session"),
}


def check_log_structure(f: h5py.File, path: Path | str) -> None:
    """FormatError naming the first part of the layout a log lacks or holds in another form:
    caught on opening, not after a whole session was learnt."""
    if SESSIONS not in f:
        return
    sessions = f[SESSIONS]
    if not isinstance(sessions, h5py.Group):
        raise FormatError(f"{path}: corrupt tvl-log (/{SESSIONS} is not a group)")
    for name, group in sessions.items():
        where = f"{path}: session {name}"
        if not isinstance(group, h5py.Group):
            raise FormatError(f"{where}: corrupt (not a group)")
        expected: dict[str, np.dtype] = {
            **{column: np.dtype(spec[0]) for column, spec in EXEMPLAR_DATASETS.items()},
            "episodes": EPISODE_DTYPE,
            "minutes": np.dtype("<f8"),
        }
        for dataset, dtype in expected.items():
            found = group.get(dataset)
            if not isinstance(found, h5py.Dataset):
                raise FormatError(f"{where}: corrupt (no {dataset} dataset)")
            if found.dtype != dtype:
                raise FormatError(f"{where}: corrupt ({dataset} holds {found.dtype}, not {dtype})")
        _check_committed(group, where)


def _check_committed(group: h5py.Group, where: str) -> None:
    """The committed counts and the episode table must describe rows that exist, in order."""
    episodes = group.attrs.get(COMMITTED_EPISODES)
    minutes = group.attrs.get(COMMITTED_MINUTES)
    for attribute, value, rows in (
        (COMMITTED_EPISODES, episodes, len(group["episodes"])),
        (COMMITTED_MINUTES, minutes, len(group["minutes"])),
    ):
        if not isinstance(value, np.integer | int) or not 0 <= int(value) <= rows:
            raise FormatError(f"{where}: corrupt ({attribute} is {value!r}, {rows} rows stored)")
    table = group["episodes"][: int(episodes)]
    expected_first = np.concatenate([[0], np.cumsum(table["count"][:-1], dtype=np.int64)])
    if len(table) and ((table["count"] < 0).any() or (table["first"] != expected_first).any()):
        raise FormatError(f"{where}: corrupt (episode table out of order or negative counts)")
