"""An exclusive lock held by the one process that writes a file, so a second writer is refused
(a log's learner; a sweep, on its directory's journal).

The lock is a sidecar file `NAME.lock` next to the file, locked with flock and holding the
writer's pid for the error message. It is a sidecar, not a lock on the HDF5 file itself,
because HDF5 flocks the file too and two flocks from one process on one file conflict.
The kernel drops the lock when the writer dies, so a killed writer never blocks the next.
"""

from __future__ import annotations

import fcntl
import os
from pathlib import Path

from tvl_cli.core.errors import BadInput


def lock_path(path: Path) -> Path:
    return path.with_name(path.name + ".lock")


class WriterLock:
    """Holds the lock from acquire() to release(); BadInput names the holder's pid."""

    def __init__(self, path: Path, fd: int) -> None:
        self._path = path
        self._fd: int | None = fd

    @classmethod
    def acquire(cls, path: Path, holder: str = "another tvl learn or run --learn") -> WriterLock:
        """The lock on `path`; BadInput saying `holder` (and its pid) has it. A lock file left
        by a process that died is taken over: its flock died with it."""
        sidecar = lock_path(path)
        while True:
            try:
                fd = os.open(sidecar, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as error:
                raise BadInput(
                    f"{path}: cannot create lock file {sidecar} ({error.strerror})"
                ) from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                pid = writer_pid(path)
                pid_text = f" (pid {pid})" if pid is not None else ""
                raise BadInput(f"{path}: locked by {holder}{pid_text}") from None
            # A previous holder may have unlinked the sidecar between our open and our
            # flock; then we hold a lock nobody else can see, so start again.
            if _same_file(fd, sidecar):
                break
            os.close(fd)
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        return cls(path, fd)

    def release(self) -> None:
        """Remove the sidecar while still holding the lock, then drop the lock."""
        if self._fd is None:
            return
        lock_path(self._path).unlink(missing_ok=True)
        os.close(self._fd)
        self._fd = None


def _same_file(fd: int, path: Path) -> bool:
    try:
        on_disk = os.stat(path)
    except FileNotFoundError:
        return False
    held = os.fstat(fd)
    return (held.st_dev, held.st_ino) == (on_disk.st_dev, on_disk.st_ino)


def writer_pid(path: Path) -> int | None:
    """The pid of another live process writing `path`, or None when no other process holds
    the lock (this process's own lock does not count)."""
    sidecar = lock_path(path)
    try:
        fd = os.open(sidecar, os.O_RDONLY)
    except OSError:
        return None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            text = os.read(fd, 32).decode("ascii", errors="replace").strip()
            pid = int(text) if text.isdigit() else None
            return None if pid == os.getpid() else pid
        fcntl.flock(fd, fcntl.LOCK_UN)
        return None
    finally:
        os.close(fd)
