"""The learning log (`tvl-log`): every exemplar a learner recorded, grouped in sessions.

Layout (format_version 2; all lengths grow as whole episodes are appended):

    /                       format, format_version, tvl_version, created
    /sessions/0000          kind ('learning' or 'behaving'), world_name, world_text, seed,
                            method (JSON, core.method.method_record: every choice of the
                            method the session was learnt by), parameters (JSON: the
                            settings that are not the method's: minutes, speeds, seed
                            stream, ...), robot_config, fam_config (JSON), status, started,
                            ended, tvl_version, episodes_written, minutes_written
        ring_mm     (N, 16) uint16  sonar ranges in millimetres, S0 forward, CCW
        pose        (N, 3)  float64 true x, y (m), theta (rad)
        odometry    (N, 3)  float64 odometry x, y (m), theta (rad)
        arc_m       (N,)    float64 distance along the arc from the episode start
        trajectory  (N,)    int8    trajectory index (robot_config order)
        rotation    (N,)    int8    foveal rotation chosen, in sonar positions CCW
        episode     (N,)    int32   episode index in the session
        episodes    (E,)    one row per episode (EPISODE_DTYPE)
        minutes     (M, 5)  float64 per simulated minute: MINUTE_COLUMNS

Sessions of version 1 kept the method's pieces in their parameters (labels, collision
points, exploration rule, memory), some with a `method` of the learning fields beside them;
io.method_records reads them. A version 1 log that a session is added to becomes version 2:
its earlier sessions read as before.

Surviving a killed learner: a session starts in a copy of the log put in its place whole, so
a kill then leaves the log as it was or with the session, empty. A session being written
keeps its datasets chunked but uncompressed, so every chunk stays where it was first written
and HDF5 never frees and reuses file space. (A gzip chunk moves whenever an episode makes it
grow, and a kill between the reuse of its old place and the next flush leaves the last
flushed metadata pointing at another chunk's bytes: a whole log lost.) Episodes are written
a few at a time (those that ended within `write_every_s` simulated seconds of each other,
and every one held when a minute's row is written or the session closes); after every write
the file is flushed, and only then are the session's `episodes_written` and
`minutes_written` attributes raised to count the new rows; a reader trusts those counts. A
kill loses at most the episodes held since the last write. Closing the session rewrites the
log with gzip and shuffle into a temporary file renamed into place, so a finished log is
compressed, and a killed one is whole, and compressed when the next session on it closes.

The online FAM must train on mm_to_ring(ring_to_mm(ring)), the values kept here, so that
`tvl train` rebuilds it exactly from the log.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path
from types import TracebackType
from typing import Any

import h5py
import numpy as np

from tvl_cli import __version__
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.method import Method, method_record
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.atomic import refuse_missing_directory
from tvl_cli.io.hdf5_header import (
    FORMAT_VERSIONS,
    LOG_FORMAT,
    hdf5_output,
    open_for_appending,
    open_for_reading,
    read_json_attr,
    to_json,
    utc_now,
    write_header,
)
from tvl_cli.io.lock import WriterLock
from tvl_cli.io.log_storage import compress, new_session
from tvl_cli.io.loglayout import (
    COMMITTED_EPISODES,
    COMMITTED_MINUTES,
    EPISODE_DTYPE,
    EXEMPLAR_DATASETS,
    KIND_LEARNING,
    SESSION_KINDS,
    SESSIONS,
    STATUS_FINISHED,
    STATUS_RUNNING,
    check_log_structure,
)


class LogWriter:
    """Appends one session to a learning log, holding the log's writer lock until close."""

    def __init__(
        self, path: Path, lock: WriterLock, f: h5py.File, group: h5py.Group, write_every_s: float
    ) -> None:
        self.path = path
        self._lock = lock
        self._file: h5py.File | None = f
        self._group = group
        # Handles looked up once: a lookup by name costs about as much as a small write.
        self._datasets = {name: group[name] for name in (*EXEMPLAR_DATASETS, "episodes")}
        self._minutes_dataset = group["minutes"]
        self._episodes = 0  # written
        self._exemplars = 0  # written
        self._minutes = 0
        self._write_every_s = write_every_s
        self._held: list[Episode] = []  # appended, not yet written
        self._written_until_s = 0.0  # simulated time when the last episode written ended

    @classmethod
    def open(
        cls,
        path: Path | str,
        *,
        world_name: str,
        world_text: str,
        seed: int,
        parameters: dict[str, Any],
        robot_config: dict[str, Any],
        fam_config: dict[str, Any],
        method: Method,
        kind: str = KIND_LEARNING,
        write_every_s: float = 0.0,
    ) -> LogWriter:
        """Create the log, or add a new session of `kind` (SESSION_KINDS) to an existing one
        (which must be a tvl-log of the same robot). BadInput if another process is writing
        it. Episodes are written once those held span `write_every_s` simulated seconds
        since the last write (0: each as it is appended)."""
        if kind not in SESSION_KINDS:
            raise ValueError(f"session kind {kind!r} is none of {', '.join(SESSION_KINDS)}")
        path = Path(path)
        refuse_missing_directory(path)
        lock = WriterLock.acquire(path)
        made = False  # whether this opening put a new log at `path`
        f: h5py.File | None = None
        attrs = {
            "kind": kind,
            "world_name": world_name,
            "world_text": world_text,
            "seed": np.int64(seed),
            "method": to_json(method_record(method)),
            "parameters": to_json(parameters),
            "robot_config": to_json(robot_config),
            "fam_config": to_json(fam_config),
            "status": STATUS_RUNNING,
            "started": utc_now(),
            "tvl_version": __version__,
            COMMITTED_EPISODES: np.int64(0),
            COMMITTED_MINUTES: np.int64(0),
        }
        try:
            if path.exists():
                session = _add_session(path, robot_config, attrs)
            else:
                session = _create_with_session(path, robot_config, attrs)
                made = True
            f = open_for_appending(path, LOG_FORMAT)
            group = f[SESSIONS][session]
        except BaseException:
            _abandon(path, made, lock, f)
            raise
        return cls(path, lock, f, group, write_every_s)

    @property
    def session(self) -> str:
        """The session's group name, e.g. '0001'."""
        return self._group.name.rsplit("/", 1)[-1]

    def append_episode(self, episode: Episode) -> None:
        """Take one whole episode; write it with those held since the last write once it
        ended `write_every_s` simulated seconds or more after the last one written."""
        _check_episode(episode, self._episodes + len(self._held))
        self._held.append(episode)
        if episode.end_time_s - self._written_until_s >= self._write_every_s:
            self._write_held()
            self._commit()

    def append_minute(
        self, *, minute: int, episodes: int, collisions: int, exemplars: int, delta_v: float
    ) -> None:
        """Append one row of per-minute learning statistics, with every episode held."""
        self._write_held()
        row = np.array([[minute, episodes, collisions, exemplars, delta_v]], dtype=np.float64)
        _append(self._minutes_dataset, row, self._minutes)
        self._minutes += 1
        self._commit()

    def close(self, status: str = STATUS_FINISHED) -> None:
        """Record how the session ended ('finished', 'interrupted: SIGINT', ...), compress
        the log and release the lock. Closing twice does nothing."""
        if self._file is None:
            return
        try:
            if self._held:
                self._write_held()
                self._commit()
            self._group.attrs.update(status=status, ended=utc_now())
            self._file.close()
            self._file = None
            compress(self.path)
        finally:
            self._file = None
            self._lock.release()

    def _write_held(self) -> None:
        """Write the episodes held, one write per dataset for all of them."""
        held, self._held = self._held, []
        if not held:
            return
        columns = {
            "ring_mm": [e.ring_mm for e in held],
            "pose": [e.pose for e in held],
            "odometry": [e.odometry for e in held],
            "arc_m": [e.arc_m for e in held],
            "trajectory": [np.full(e.exemplar_count, e.trajectory, np.int8) for e in held],
            "rotation": [np.full(e.exemplar_count, e.rotation, np.int8) for e in held],
            "episode": [np.full(e.exemplar_count, e.index, np.int32) for e in held],
        }
        for name, values in columns.items():
            _append(self._datasets[name], np.concatenate(values), self._exemplars)
        firsts = self._exemplars + np.cumsum([0] + [e.exemplar_count for e in held[:-1]])
        rows = np.array(
            [
                (
                    first,
                    e.exemplar_count,
                    e.trajectory,
                    e.rotation,
                    e.collided,
                    e.bumped,
                    e.end_time_s,
                    e.end_arc_m,
                )
                for first, e in zip(firsts.tolist(), held, strict=True)
            ],
            dtype=EPISODE_DTYPE,
        )
        _append(self._datasets["episodes"], rows, self._episodes)
        self._exemplars += sum(e.exemplar_count for e in held)
        self._episodes += len(held)
        self._written_until_s = held[-1].end_time_s

    def _commit(self) -> None:
        """Make the rows written so far durable, then count them in the session's attributes.

        Two flushes: the counts reach the file only after the rows they count, so a reader
        trusts the counts whatever moment a kill cut the writer short.
        """
        assert self._file is not None, "the log writer is closed"
        self._file.flush()
        # modify() rewrites the attribute in place, where update() would delete and add it.
        self._group.attrs.modify(COMMITTED_EPISODES, np.int64(self._episodes))
        self._group.attrs.modify(COMMITTED_MINUTES, np.int64(self._minutes))
        self._file.flush()

    def __enter__(self) -> LogWriter:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        if kind is None:
            self.close()
        elif issubclass(kind, KeyboardInterrupt):
            self.close("interrupted: SIGINT")
        else:
            self.close(f"failed: {kind.__name__}")


def _check_episode(episode: Episode, expected_index: int) -> None:
    """Refuse what h5py would silently convert or half write (programming errors)."""
    if episode.index != expected_index:
        raise ValueError(f"episode {episode.index} appended as number {expected_index}")
    if episode.ring_mm.dtype != np.uint16:
        raise ValueError(
            f"ring_mm must be uint16 millimetres (ring_to_mm), not {episode.ring_mm.dtype}"
        )
    n = episode.exemplar_count
    shapes = {
        "ring_mm": (episode.ring_mm.shape, (n, episode.ring_mm.shape[-1])),
        "pose": (episode.pose.shape, (n, 3)),
        "odometry": (episode.odometry.shape, (n, 3)),
        "arc_m": (episode.arc_m.shape, (n,)),
    }
    for name, (shape, expected) in shapes.items():
        if shape != expected:
            raise ValueError(f"episode {episode.index}: {name} has shape {shape}, not {expected}")


# A session is started in a copy of the log, never in the log itself: HDF5 writes the blocks a
# new group changes in no set order, and a kill between two of them leaves a file whose root
# it cannot open, with every session before lost.


def _create_with_session(path: Path, robot_config: dict[str, Any], attrs: dict[str, Any]) -> str:
    """A new log at `path` holding its first session, linked into place; the session's name."""
    with hdf5_output(path, overwrite=False, appendable=True) as log:
        write_header(log, LOG_FORMAT)
        return _start_session(log, robot_config, attrs)


def _add_session(path: Path, robot_config: dict[str, Any], attrs: dict[str, Any]) -> str:
    """The log at `path` with a new session added, once it is known to take one; its name."""
    with open_for_reading(path, LOG_FORMAT) as log:
        check_log_structure(log, path)
        _refuse_other_robot(log, path, robot_config)
    with hdf5_output(path, based_on=path.read_bytes(), appendable=True) as log:
        # Its new session keeps the method as this version does: a tvl that reads only
        # version 1 must refuse the log rather than misread that session.
        log.attrs["format_version"] = FORMAT_VERSIONS[LOG_FORMAT]
        return _start_session(log, robot_config, attrs)


def _start_session(log: h5py.File, robot_config: dict[str, Any], attrs: dict[str, Any]) -> str:
    group = new_session(log, RobotConfig.from_dict(robot_config))
    group.attrs.update(attrs)
    return str(group.name).rsplit("/", 1)[-1]


def _abandon(path: Path, made: bool, lock: WriterLock, f: h5py.File | None) -> None:
    """Undo a session's opening that failed: the log, if this opening put it in place (never
    one another program put there meanwhile), the lock, and the file as far as HDF5 can
    close it."""
    # Cleared first: HDF5 may fail again closing a file it could not write (a full disk), and
    # a log this opening made holds nothing yet.
    if made:
        path.unlink(missing_ok=True)
    lock.release()
    if f is not None:
        with contextlib.suppress(OSError, RuntimeError):
            f.close()


def _refuse_other_robot(f: h5py.File, path: Path, robot_config: dict[str, Any]) -> None:
    """One log, one robot: `tvl train` refuses logs of different robots, so say it now."""
    for name, group in f.get(SESSIONS, {}).items():
        if read_json_attr(group, "robot_config", path) != _round_trip(robot_config):
            raise BadInput(
                f"{path}: session {name} was recorded with another robot configuration; "
                "log this robot to a new file"
            )


def _round_trip(value: dict[str, Any]) -> Any:
    """The value as it reads back from JSON (tuples become lists)."""
    return json.loads(to_json(value))


def _append(dataset: h5py.Dataset, values: np.ndarray, start: int) -> None:
    """Write rows at `start` with one resize and one write: per-row appends cost ~0.2 ms."""
    if len(values) == 0:
        return
    dataset.resize(start + len(values), axis=0)
    dataset[start:] = values
