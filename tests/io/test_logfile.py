"""The learning log: round trips, sessions, the writer lock and surviving a killed writer."""

from __future__ import annotations

import dataclasses
import hashlib
import os
import signal
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from log_samples import (
    PARAMETERS,
    ROBOT,
    WORLD_TEXT,
    assert_same_episode,
    open_sample_writer,
    sample_episode,
)
from method_samples import LIVE_RING

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.ring import mm_to_ring, ring_to_mm
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io import logfile
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.hdf5_header import FormatError
from tvl_cli.io.loglayout import MINUTE_COLUMNS
from tvl_cli.io.logreader import read_log

HERE = Path(__file__).parent

# A child process that opens a sample log, appends `count` episodes (writing them once they
# span `write_every_s` simulated seconds, 0 by default), says so, then waits for a line on
# stdin before it closes the log (or is killed while it waits).
CHILD = """
import sys
sys.path.insert(0, sys.argv[1])
from log_samples import open_sample_writer, sample_episode
writer = open_sample_writer(sys.argv[2], write_every_s=float(sys.argv[4]))
for index in range(int(sys.argv[3])):
    writer.append_episode(sample_episode(index))
print("written", flush=True)
sys.stdin.readline()
writer.close()
"""


# A child that appends sample episodes without end, printing each index once it is written.
ENDLESS_CHILD = """
import sys
sys.path.insert(0, sys.argv[1])
from log_samples import open_sample_writer, sample_episode
writer = open_sample_writer(sys.argv[2])
index = 0
while True:
    writer.append_episode(sample_episode(index))
    print(index, flush=True)
    index += 1
"""

# A child that appends 3 episodes, held (writes every 1000 simulated seconds), then a
# minute's row, says so and waits to be killed.
MINUTE_CHILD = """
import sys
sys.path.insert(0, sys.argv[1])
from log_samples import open_sample_writer, sample_episode
writer = open_sample_writer(sys.argv[2], write_every_s=1000.0)
for index in range(3):
    writer.append_episode(sample_episode(index))
writer.append_minute(minute=0, episodes=3, collisions=1, exemplars=12, delta_v=0.01)
print("written", flush=True)
sys.stdin.readline()
"""

# A child that holds a file open read-write with plain h5py, as another HDF5 program would.
H5PY_CHILD = """
import sys, h5py
f = h5py.File(sys.argv[1], "r+")
print("open", flush=True)
sys.stdin.readline()
"""


def write_sample_log(path: Path, episodes: int = 4) -> None:
    with open_sample_writer(path) as writer:
        for index in range(episodes):
            writer.append_episode(sample_episode(index))


def start_child(path: Path, episodes: int, write_every_s: float = 0.0) -> subprocess.Popen[str]:
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(HERE), str(path), str(episodes), str(write_every_s)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert child.stdout is not None
    assert child.stdout.readline() == "written\n"
    return child


def finish_child(child: subprocess.Popen[str]) -> None:
    child.communicate("\n", timeout=30)
    assert child.returncode == 0


def kill_child(child: subprocess.Popen[str]) -> None:
    os.kill(child.pid, signal.SIGKILL)
    child.communicate(timeout=30)
    assert child.returncode == -signal.SIGKILL


def test_episodes_read_back_equal_to_those_written(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    written = [sample_episode(i) for i in range(6)]
    with open_sample_writer(path) as writer:
        for episode in written:
            writer.append_episode(episode)
    (session,) = read_log(path).sessions
    read = session.episodes()
    assert len(read) == len(written)
    for r, w in zip(read, written, strict=True):
        assert_same_episode(r, w)


def test_session_attributes_read_back(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    write_sample_log(path)
    (session,) = read_log(path).sessions
    assert session.name == "0000"
    assert session.world_name == "box"
    assert session.world_text == WORLD_TEXT
    assert session.seed == 7
    assert session.parameters == PARAMETERS
    assert session.robot_config == ROBOT
    assert session.fam_config == SINGLE
    assert session.status == "finished"
    assert session.started <= (session.ended or "")


def test_exemplar_columns_repeat_the_episode_trajectory_rotation_and_index(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    write_sample_log(path, episodes=3)
    (session,) = read_log(path).sessions
    expected = [sample_episode(i) for i in range(3)]
    counts = [e.exemplar_count for e in expected]
    np.testing.assert_array_equal(session.episode, np.repeat([0, 1, 2], counts))
    np.testing.assert_array_equal(
        session.trajectory, np.repeat([e.trajectory for e in expected], counts)
    )
    np.testing.assert_array_equal(
        session.rotation, np.repeat([e.rotation for e in expected], counts)
    )
    np.testing.assert_array_equal(session.episode_table["first"], np.cumsum([0, *counts[:-1]]))


def test_source_names_the_file_its_digest_and_sessions(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    write_sample_log(path, episodes=2)
    source = read_log(path).source()
    assert source["path"] == str(path)
    assert source["sha256"] == hashlib.sha256(path.read_bytes()).hexdigest()
    (session,) = source["sessions"]
    assert session["name"] == "0000" and session["seed"] == 7 and session["episodes"] == 2
    assert session["exemplars"] == sum(sample_episode(i).exemplar_count for i in (0, 1))


def test_minutes_read_back_in_order(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    with open_sample_writer(path) as writer:
        writer.append_episode(sample_episode(0))
        writer.append_minute(minute=1, episodes=12, collisions=5, exemplars=900, delta_v=0.25)
        writer.append_minute(minute=2, episodes=9, collisions=2, exemplars=850, delta_v=0.125)
    (session,) = read_log(path).sessions
    np.testing.assert_array_equal(session.minutes, [[1, 12, 5, 900, 0.25], [2, 9, 2, 850, 0.125]])
    with h5py.File(path) as f:
        assert list(f["sessions/0000/minutes"].attrs["columns"]) == list(MINUTE_COLUMNS)


def test_second_writer_appends_a_new_session(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    write_sample_log(path, episodes=2)
    with open_sample_writer(path, seed=8) as writer:
        assert writer.session == "0001"
        writer.append_episode(sample_episode(0))
    log = read_log(path)
    assert [s.name for s in log.sessions] == ["0000", "0001"]
    assert [s.seed for s in log.sessions] == [7, 8]
    assert [len(s.episode_table) for s in log.sessions] == [2, 1]
    assert log.exemplar_count == sum(sample_episode(i).exemplar_count for i in (0, 1, 0))


def test_appending_another_robot_is_refused_and_the_log_left_alone(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    write_sample_log(path)
    before = path.read_bytes()
    with pytest.raises(BadInput, match=r"a\.h5: session 0000 was recorded with another robot"):
        open_sample_writer(path, robot=RobotConfig(radius_m=0.25))
    assert path.read_bytes() == before


def test_appending_to_a_fam_file_is_refused_and_the_file_left_alone(tmp_path: Path) -> None:
    from tvl_cli.core.fam import Fam

    path = tmp_path / "f.h5"
    write_fam(
        path,
        Fam(SINGLE, [t.name for t in ROBOT.trajectories]),
        robot_config=ROBOT,
        method=LIVE_RING,
        provenance={},
    )
    before = path.read_bytes()
    with pytest.raises(FormatError, match=r"f\.h5: is a tvl-fam file, expected a tvl-log"):
        open_sample_writer(path)
    assert path.read_bytes() == before


def test_a_file_another_program_puts_at_a_new_logs_name_meanwhile_is_kept(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "a.h5"
    made_header = logfile.write_header

    def another_program_writes_first(f: h5py.File, file_format: str) -> None:
        path.write_bytes(b"theirs")  # while the new log is being made beside it
        made_header(f, file_format)

    monkeypatch.setattr(logfile, "write_header", another_program_writes_first)
    with pytest.raises(BadInput, match=r"a\.h5: another process wrote it meanwhile"):
        open_sample_writer(path)
    assert path.read_bytes() == b"theirs"
    assert [p.name for p in tmp_path.iterdir()] == ["a.h5"]  # no temporary file, no lock


def test_new_log_in_a_missing_directory_is_refused(tmp_path: Path) -> None:
    with pytest.raises(BadInput, match=r"directory .*nowhere does not exist"):
        open_sample_writer(tmp_path / "nowhere" / "a.h5")


def test_log_without_exemplars_is_refused_naming_the_file(tmp_path: Path) -> None:
    path = tmp_path / "empty.h5"
    open_sample_writer(path).close()
    with pytest.raises(BadInput, match=r"empty\.h5: has no exemplars"):
        read_log(path)


def test_episode_index_out_of_sequence_is_rejected(tmp_path: Path) -> None:
    with open_sample_writer(tmp_path / "a.h5") as writer, pytest.raises(ValueError):
        writer.append_episode(sample_episode(1))


def test_ring_in_metres_is_rejected_not_truncated(tmp_path: Path) -> None:
    episode = sample_episode(0)
    in_metres = dataclasses.replace(episode, ring_mm=mm_to_ring(episode.ring_mm))
    with open_sample_writer(tmp_path / "a.h5") as writer, pytest.raises(ValueError, match="uint16"):
        writer.append_episode(in_metres)


def test_episode_with_a_short_column_is_rejected_before_anything_is_written(tmp_path: Path) -> None:
    episode = sample_episode(0)
    short = dataclasses.replace(episode, pose=episode.pose[:-1])
    path = tmp_path / "a.h5"
    with open_sample_writer(path) as writer:
        with pytest.raises(ValueError, match="pose has shape"):
            writer.append_episode(short)
        writer.append_episode(episode)
    (read,) = read_log(path).sessions[0].episodes()
    assert_same_episode(read, episode)


def test_keyboard_interrupt_marks_the_session_interrupted(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    with pytest.raises(KeyboardInterrupt), open_sample_writer(path) as writer:
        writer.append_episode(sample_episode(0))
        raise KeyboardInterrupt
    (session,) = read_log(path).sessions
    assert session.status == "interrupted: SIGINT"
    assert len(session.episode_table) == 1


def test_close_records_the_status_given(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    writer = open_sample_writer(path)
    writer.append_episode(sample_episode(0))
    writer.close("interrupted: SIGTERM")
    assert read_log(path).sessions[0].status == "interrupted: SIGTERM"


def test_exemplar_datasets_are_chunked_gzip_shuffled_and_resizable(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    write_sample_log(path)
    with h5py.File(path) as f:
        session = f["sessions/0000"]
        for name in ("ring_mm", "pose", "odometry", "arc_m", "trajectory", "rotation", "episode"):
            dataset = session[name]
            assert dataset.compression == "gzip" and dataset.shuffle, name
            assert dataset.chunks is not None and dataset.maxshape[0] is None, name
            assert "units" in dataset.attrs, name
        assert session["ring_mm"].dtype == np.uint16
        assert session["ring_mm"].attrs["units"] == "mm"
        assert list(session["trajectory"].attrs["names"]) == [t.name for t in ROBOT.trajectories]


def test_ring_to_mm_keeps_the_nearest_millimetre_and_is_stable() -> None:
    ring_m = np.array([0.15, 0.1234, 0.1236, 3.9999, 4.0, 70.0])
    mm = ring_to_mm(ring_m)
    np.testing.assert_array_equal(mm, [150, 123, 124, 4000, 4000, 65535])
    assert mm.dtype == np.uint16
    kept = mm_to_ring(mm)
    np.testing.assert_array_equal(mm_to_ring(ring_to_mm(kept)), kept)


def test_collided_episode_measures_distance_to_the_end_and_a_free_one_infinity() -> None:
    collided, free = sample_episode(0), sample_episode(1)
    np.testing.assert_allclose(collided.distances_m(), collided.end_arc_m - collided.arc_m)
    assert np.isinf(free.distances_m()).all()


def test_second_writer_in_another_process_is_refused_with_its_pid(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    child = start_child(path, episodes=1)
    try:
        with pytest.raises(
            BadInput,
            match=rf"x\.h5: locked by another tvl learn or run --learn \(pid {child.pid}\)",
        ):
            open_sample_writer(path)
    finally:
        finish_child(child)
    assert len(read_log(path).sessions) == 1


def test_reading_a_log_being_written_says_who_writes_it(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    child = start_child(path, episodes=1)
    try:
        with pytest.raises(
            BadInput,
            match=rf"x\.h5: locked by another tvl learn or run --learn \(pid {child.pid}\)",
        ):
            read_log(path)
    finally:
        finish_child(child)


def test_closing_releases_the_lock_and_removes_the_lock_file(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    write_sample_log(path)
    assert not (tmp_path / "x.h5.lock").exists()
    open_sample_writer(path).close()
    assert len(read_log(path).sessions) == 2


def test_writer_killed_after_n_episodes_leaves_n_whole_episodes(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    child = start_child(path, episodes=5)
    kill_child(child)
    (session,) = read_log(path).sessions
    read = session.episodes()
    assert len(read) == 5
    for index, episode in enumerate(read):
        assert_same_episode(episode, sample_episode(index))
    assert session.status == "interrupted: not closed"


def test_a_killed_writer_loses_at_most_the_episodes_held_since_its_last_write(
    tmp_path: Path,
) -> None:
    # Sample episode i ends at 10 (i + 1) simulated seconds: with writes every 30 s, the
    # episodes ending at 30 and 60 s wrote those before them, and the one ending at 70 s
    # was still held when the writer was killed.
    path = tmp_path / "x.h5"
    every_s, appended = 30.0, 7
    kill_child(start_child(path, episodes=appended, write_every_s=every_s))
    (session,) = read_log(path).sessions
    read = session.episodes()
    for index, episode in enumerate(read):
        assert_same_episode(episode, sample_episode(index))
    last_end_s = sample_episode(appended - 1).end_time_s
    bound = sum(sample_episode(i).end_time_s <= last_end_s - every_s for i in range(appended))
    assert bound <= len(read) == appended - 1  # the one held was lost, as the bound allows


def test_closing_writes_every_episode_held(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    with pytest.raises(KeyboardInterrupt), open_sample_writer(path, write_every_s=1e9) as writer:
        for index in range(5):
            writer.append_episode(sample_episode(index))
        raise KeyboardInterrupt
    (session,) = read_log(path).sessions
    assert session.status == "interrupted: SIGINT"
    for index, episode in enumerate(session.episodes()):
        assert_same_episode(episode, sample_episode(index))
    assert len(session.episodes()) == 5


def test_a_minutes_row_is_written_with_every_episode_held(tmp_path: Path) -> None:
    path = tmp_path / "a.h5"
    child = subprocess.Popen(
        [sys.executable, "-c", MINUTE_CHILD, str(HERE), str(path)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert child.stdout is not None
    assert child.stdout.readline() == "written\n"
    kill_child(child)
    (session,) = read_log(path).sessions
    assert len(session.episodes()) == 3
    assert len(session.minutes) == 1


def test_new_writer_after_a_killed_one_takes_the_lock(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    child = start_child(path, episodes=2)
    kill_child(child)
    with open_sample_writer(path) as writer:
        writer.append_episode(sample_episode(0))
    assert [len(s.episode_table) for s in read_log(path).sessions] == [2, 1]


@pytest.mark.slow  # over a second
@pytest.mark.parametrize("written", [1, 30, 150])
def test_writer_killed_mid_write_leaves_only_whole_episodes(tmp_path: Path, written: int) -> None:
    path = tmp_path / "x.h5"
    child = subprocess.Popen(
        [sys.executable, "-c", ENDLESS_CHILD, str(HERE), str(path)],
        stdout=subprocess.PIPE,
        text=True,
    )
    assert child.stdout is not None
    for _ in range(written):
        child.stdout.readline()
    kill_child(child)  # most likely while it writes the next episode
    (session,) = read_log(path).sessions
    read = session.episodes()
    assert len(read) >= written
    for index, episode in enumerate(read):
        assert_same_episode(episode, sample_episode(index))


@pytest.mark.slow
def test_killed_session_is_compressed_when_the_next_session_closes(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    kill_child(start_child(path, episodes=2))
    with h5py.File(path) as f:
        assert f["sessions/0000/ring_mm"].compression is None
    open_sample_writer(path).close()
    with h5py.File(path) as f:
        assert f["sessions/0000/ring_mm"].compression == "gzip"
    (killed, _) = read_log(path).sessions
    for index, episode in enumerate(killed.episodes()):
        assert_same_episode(episode, sample_episode(index))


def test_log_held_open_by_another_hdf5_program_is_refused_clearly(tmp_path: Path) -> None:
    path = tmp_path / "x.h5"
    write_sample_log(path)
    child = subprocess.Popen(
        [sys.executable, "-c", H5PY_CHILD, str(path)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert child.stdout is not None and child.stdout.readline() == "open\n"
    try:
        with pytest.raises(BadInput, match=r"x\.h5: in use by another program"):
            open_sample_writer(path)
    finally:
        finish_child(child)
    assert not (tmp_path / "x.h5.lock").exists()
