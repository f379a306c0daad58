"""Reading a learning log (`tvl-log`, laid out as io.logfile describes): its sessions,
their episodes and per-minute tables, trusting only the rows a writer committed."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import FamConfig
from tvl_cli.core.method import Method
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.hdf5_header import (
    LOG_FORMAT,
    FormatError,
    open_for_reading,
    read_json_attr,
    read_str_attr,
)
from tvl_cli.io.lock import writer_pid
from tvl_cli.io.loglayout import (
    COMMITTED_EPISODES,
    COMMITTED_MINUTES,
    EXEMPLAR_DATASETS,
    KIND_LEARNING,
    MINUTE_COLUMNS,
    SESSION_KINDS,
    SESSIONS,
    STATUS_NOT_CLOSED,
    STATUS_RUNNING,
    check_log_structure,
)
from tvl_cli.io.method_records import ReadMethod, session_method


@dataclass(frozen=True, slots=True, eq=False)
class Session:
    """One learning session as read back: its settings and its whole episodes."""

    name: str  # the group name, e.g. '0000'
    kind: str  # 'learning' (`tvl learn`) or 'behaving' (`tvl run --learn`)
    world_name: str
    world_text: str
    seed: int
    parameters: dict[str, Any]
    robot_config: RobotConfig
    fam_config: FamConfig
    status: str  # 'finished', 'interrupted: SIGINT', 'interrupted: not closed', ...
    started: str  # UTC ISO 8601
    ended: str | None
    tvl_version: str
    ring_mm: np.ndarray  # (N, sonars) uint16 mm
    pose: np.ndarray  # (N, 3) true x m, y m, theta rad
    odometry: np.ndarray  # (N, 3)
    arc_m: np.ndarray  # (N,) m
    trajectory: np.ndarray  # (N,) int8
    rotation: np.ndarray  # (N,) int8
    episode: np.ndarray  # (N,) int32
    episode_table: np.ndarray  # (E,) EPISODE_DTYPE
    minutes: np.ndarray  # (M, 5) float64, MINUTE_COLUMNS
    made_by: ReadMethod  # the method it was learnt by

    @property
    def method(self) -> Method:
        return self.made_by.method

    @property
    def exemplar_count(self) -> int:
        return len(self.arc_m)

    def episodes(self) -> list[Episode]:
        """The session's episodes, whose arrays are views into the session's arrays."""
        episodes = []
        for index, row in enumerate(self.episode_table):
            rows = slice(int(row["first"]), int(row["first"]) + int(row["count"]))
            episodes.append(
                Episode(
                    index=index,
                    ring_mm=self.ring_mm[rows],
                    pose=self.pose[rows],
                    odometry=self.odometry[rows],
                    arc_m=self.arc_m[rows],
                    trajectory=int(row["trajectory"]),
                    rotation=int(row["rotation"]),
                    collided=bool(row["collided"]),
                    bumped=bool(row["bumped"]),
                    end_arc_m=float(row["end_arc_m"]),
                    end_time_s=float(row["end_time_s"]),
                )
            )
        return episodes


@dataclass(frozen=True, slots=True, eq=False)
class LearningLog:
    """A whole learning log as read back, with the SHA-256 of the file for provenance."""

    path: Path
    sha256: str
    tvl_version: str
    created: str
    sessions: tuple[Session, ...]

    @property
    def exemplar_count(self) -> int:
        return sum(s.exemplar_count for s in self.sessions)

    def source(self) -> dict[str, Any]:
        """This log as a FAM file's provenance names it: path, SHA-256 and sessions."""
        return {
            "path": str(self.path),
            "sha256": self.sha256,
            "sessions": [
                {
                    "name": s.name,
                    "world_name": s.world_name,
                    "seed": s.seed,
                    "status": s.status,
                    "episodes": len(s.episode_table),
                    "exemplars": s.exemplar_count,
                }
                for s in self.sessions
            ],
        }


def read_log(path: Path | str, empty_allowed: bool = False) -> LearningLog:
    """Read a learning log; FormatError if it is not a readable tvl-log, BadInput if it holds
    no exemplars (unless `empty_allowed`: a log to go on learning into may be one whose
    first learner was stopped before it finished an episode)."""
    path = Path(path)
    with open_for_reading(path, LOG_FORMAT) as f:
        check_log_structure(f, path)
        try:
            sessions = tuple(
                _read_session(group, name, path)
                for name, group in sorted(f.get(SESSIONS, {}).items())
            )
            log = LearningLog(
                path=path,
                sha256=file_sha256(path),
                tvl_version=read_str_attr(f, "tvl_version", path),
                created=read_str_attr(f, "created", path),
                sessions=sessions,
            )
        except (OSError, KeyError, ValueError, TypeError) as error:
            raise FormatError(f"{path}: corrupt tvl-log ({error})") from None
    if log.exemplar_count == 0 and not empty_allowed:
        raise BadInput(f"{path}: has no exemplars (no finished episode in any session)")
    return log


def session_worlds(path: Path | str) -> dict[str, str]:
    """The world each session of a log learnt in, by its text, with its name: read from the
    sessions' attributes alone, quick beside reading their exemplars."""
    path = Path(path)
    with open_for_reading(path, LOG_FORMAT) as f:
        check_log_structure(f, path)
        try:
            return {
                read_str_attr(group, "world_text", path): read_str_attr(group, "world_name", path)
                for _, group in sorted(f.get(SESSIONS, {}).items())
            }
        except (OSError, KeyError, ValueError, TypeError) as error:
            raise FormatError(f"{path}: corrupt tvl-log ({error})") from None


def _read_session(group: h5py.Group, name: str, path: Path) -> Session:
    where = f"{path}: session {name}"
    try:
        robot = RobotConfig.from_dict(read_json_attr(group, "robot_config", path))
        fam = FamConfig.from_dict(read_json_attr(group, "fam_config", path))
    except (KeyError, TypeError, ValueError) as error:
        raise FormatError(f"{where}: malformed configuration ({error})") from None
    table = group["episodes"][: int(group.attrs[COMMITTED_EPISODES])]
    end = int(table["first"][-1] + table["count"][-1]) if len(table) else 0
    columns = {column: group[column][:end] for column in EXEMPLAR_DATASETS}
    if any(len(values) < end for values in columns.values()):
        raise FormatError(f"{where}: fewer exemplars stored than its episodes list")
    minutes = group["minutes"][: int(group.attrs[COMMITTED_MINUTES])]
    _check_ranges(columns, robot, where)
    _check_values(columns, table, minutes, where)
    kind = read_str_attr(group, "kind", path) if "kind" in group.attrs else KIND_LEARNING
    if kind not in SESSION_KINDS:
        raise FormatError(f"{where}: unknown session kind {kind!r}")
    status = read_str_attr(group, "status", path)
    if status == STATUS_RUNNING and writer_pid(path) is None:
        status = STATUS_NOT_CLOSED
    parameters = read_json_attr(group, "parameters", path)
    if not isinstance(parameters, dict):
        raise FormatError(f"{where}: parameters are not a JSON object")
    recorded = read_json_attr(group, "method", path) if "method" in group.attrs else None
    return Session(
        name=name,
        kind=kind,
        world_name=read_str_attr(group, "world_name", path),
        world_text=read_str_attr(group, "world_text", path),
        seed=int(group.attrs["seed"]),
        parameters=parameters,
        robot_config=robot,
        fam_config=fam,
        status=status,
        started=read_str_attr(group, "started", path),
        ended=read_str_attr(group, "ended", path) if "ended" in group.attrs else None,
        tvl_version=read_str_attr(group, "tvl_version", path),
        episode_table=table,
        minutes=minutes,
        made_by=session_method(recorded, parameters, robot, where),
        **columns,
    )


def _check_ranges(columns: dict[str, np.ndarray], robot: RobotConfig, where: str) -> None:
    """Indices a trainer would use must be in range, or it would fail far from the cause."""
    sonars = robot.sonar.count
    if columns["ring_mm"].shape[1:] != (sonars,):
        raise FormatError(f"{where}: ring_mm has {columns['ring_mm'].shape[1:]} readings a row")
    trajectory = columns["trajectory"]
    if len(trajectory) and not 0 <= trajectory.min() <= trajectory.max() < len(robot.trajectories):
        raise FormatError(f"{where}: trajectory index out of range")
    rotation = columns["rotation"]
    if len(rotation) and not 0 <= rotation.min() <= rotation.max() < sonars:
        raise FormatError(f"{where}: rotation out of range")


# Rows of more than one number, and how many numbers each holds.
_ROW_WIDTHS = {"pose": 3, "odometry": 3}


def _check_values(
    columns: dict[str, np.ndarray], table: np.ndarray, minutes: np.ndarray, where: str
) -> None:
    """Every row the shape its meaning needs, and every measurement a finite number: a NaN
    would train into every rule it touched, and a picture would silently leave it out."""
    for name, width in _ROW_WIDTHS.items():
        if columns[name].ndim != 2 or columns[name].shape[1] != width:
            raise FormatError(f"{where}: {name} rows hold {columns[name].shape[1:]}, not {width}")
    if columns["arc_m"].ndim != 1:
        raise FormatError(f"{where}: arc_m holds rows, not one distance a step")
    if minutes.ndim != 2 or minutes.shape[1] != len(MINUTE_COLUMNS):
        raise FormatError(
            f"{where}: minutes rows hold {minutes.shape[1:]} values, not {len(MINUTE_COLUMNS)}"
        )
    measured = {
        "pose": columns["pose"],
        "odometry": columns["odometry"],
        "arc_m": columns["arc_m"],
        "episodes end_time_s": table["end_time_s"],
        "episodes end_arc_m": table["end_arc_m"],
        "minutes": minutes,
    }
    for name, values in measured.items():
        if not np.isfinite(values).all():
            raise FormatError(f"{where}: {name} holds a value that is not a finite number")


def file_sha256(path: Path | str) -> str:
    """Hex SHA-256 of a file's bytes, read in 1 MiB blocks."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def refuse_repeated(files: Sequence[tuple[Path, str]], what: str) -> None:
    """Refuse one file given twice, by content: (path, SHA-256) pairs, `what` naming the kind
    ("log"). The same log twice would train every exemplar twice; the same FAM twice would
    be compared with itself."""
    seen: dict[str, Path] = {}
    for path, sha256 in files:
        if sha256 in seen:
            raise BadInput(f"{path}: the same {what} as {seen[sha256]}, given twice")
        seen[sha256] = path
