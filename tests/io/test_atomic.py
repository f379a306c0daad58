"""Outputs appear whole or not at all, and a failed write leaves the old file alone."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output


def test_success_replaces_the_file_with_what_was_written(tmp_path: Path) -> None:
    path = tmp_path / "out.h5"
    path.write_text("old")
    with atomic_output(path) as temporary:
        temporary.write_text("new")
    assert path.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["out.h5"]


def test_writes_go_to_a_temporary_file_in_the_same_directory(tmp_path: Path) -> None:
    path = tmp_path / "out.h5"
    with atomic_output(path) as temporary:
        assert temporary.parent == tmp_path
        assert temporary != path
        assert not path.exists()
        temporary.write_text("x")


def test_failure_removes_the_temporary_file_and_keeps_the_old_one(tmp_path: Path) -> None:
    path = tmp_path / "out.h5"
    path.write_text("old")
    with pytest.raises(RuntimeError), atomic_output(path) as temporary:
        temporary.write_text("half")
        raise RuntimeError("disk on fire")
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.h5"]


def test_interrupt_removes_the_temporary_file(tmp_path: Path) -> None:
    path = tmp_path / "out.h5"
    with pytest.raises(KeyboardInterrupt), atomic_output(path) as temporary:
        temporary.write_text("half")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def _finished_pid() -> int:
    """The process id of a process that has ended."""
    import subprocess
    import sys

    child = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], check=True,
                           capture_output=True, text=True)  # fmt: skip
    return int(child.stdout)


def test_temporary_files_of_killed_writers_are_removed_by_the_next_write(tmp_path: Path) -> None:
    path = tmp_path / "out.h5"
    with atomic_output(path) as temporary:  # learn how this host names its temporary files
        host = temporary.name.split(".")[3]
        temporary.write_text("x")
    gone = _finished_pid()
    abandoned = tmp_path / f".out.h5.{host}.{gone}.0a1b2c3d.tmp"
    kept = [
        tmp_path / f".out.h5.{host}.{os.getpid()}.4e5f6a7b.tmp",  # a writer still at work
        tmp_path / f".out.h5.elsewhere.{gone}.0a1b2c3d.tmp",  # another host's writer
        tmp_path / f".out.h5.7.{host}.{gone}.0a1b2c3d.tmp",  # the file out.h5.7's
        tmp_path / f".other.h5.{host}.{gone}.0a1b2c3d.tmp",
    ]
    for leftover in (abandoned, *kept):
        leftover.write_text("half")
    with atomic_output(path) as temporary:
        temporary.write_text("new")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["out.h5", *(k.name for k in kept)])


def test_replacing_keeps_the_permissions_of_the_old_file(tmp_path: Path) -> None:
    path = tmp_path / "out.h5"
    path.write_text("old")
    path.chmod(0o640)
    with atomic_output(path) as temporary:
        temporary.write_text("new")
    assert path.stat().st_mode & 0o777 == 0o640


def test_missing_directory_is_refused_naming_it(tmp_path: Path) -> None:
    path = tmp_path / "nowhere" / "out.h5"
    with pytest.raises(BadInput, match=r"directory .*nowhere does not exist"), atomic_output(path):
        pass


def test_directory_as_output_is_refused(tmp_path: Path) -> None:
    with pytest.raises(BadInput, match="is a directory"), atomic_output(tmp_path):
        pass


def test_unwritable_directory_is_refused(tmp_path: Path) -> None:
    locked = tmp_path / "ro"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if _can_write(locked):
            pytest.skip("running with permissions that ignore directory modes (root)")
        with pytest.raises(BadInput, match="cannot write"), atomic_output(locked / "out.h5"):
            pass
    finally:
        locked.chmod(0o700)


def _can_write(directory: Path) -> bool:
    try:
        (directory / "probe").write_text("")
    except PermissionError:
        return False
    (directory / "probe").unlink()
    return True


def test_without_overwrite_a_file_written_meanwhile_is_kept_and_ours_refused(
    tmp_path: Path,
) -> None:
    path = tmp_path / "fam.h5"
    with (
        pytest.raises(BadInput, match="another process wrote it meanwhile"),
        atomic_output(path, overwrite=False) as temporary,
    ):
        temporary.write_text("ours")
        path.write_text("theirs")  # a second `tvl train` to the same output finishes first
    assert path.read_text() == "theirs"
    assert [p.name for p in tmp_path.iterdir()] == ["fam.h5"]


def test_without_overwrite_a_new_file_is_put_in_place(tmp_path: Path) -> None:
    path = tmp_path / "fam.h5"
    with atomic_output(path, overwrite=False) as temporary:
        temporary.write_text("ours")
    assert path.read_text() == "ours"
    assert [p.name for p in tmp_path.iterdir()] == ["fam.h5"]
