"""Write an output file whole or not at all: a temporary file beside it, renamed into place."""

from __future__ import annotations

import glob
import os
import secrets
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from tvl_cli.core.errors import BadInput


@contextmanager
def atomic_output(path: Path | str) -> Iterator[Path]:
    """Yield a temporary path to write; on success it replaces `path`, on any failure
    (including Ctrl-C) it is removed and an existing `path` is left untouched.

    The temporary file sits in the same directory so the rename never crosses file systems.
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise BadInput(f"{path}: cannot write, directory {path.parent} does not exist")
    if path.is_dir():
        raise BadInput(f"{path}: is a directory, not a file")
    _remove_abandoned_temporaries(path)
    temporary = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        # Created here, not by the writer, so that a read-only directory is a clear error;
        # an ordinary open() gives the file the user's usual permissions (umask).
        with open(temporary, "xb"):
            pass
    except OSError as error:
        raise BadInput(f"{path}: cannot write ({error.strerror})") from None
    if path.exists():
        # A replaced file keeps the permissions its owner gave it.
        os.chmod(temporary, stat.S_IMODE(path.stat().st_mode))
    try:
        yield temporary
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def _remove_abandoned_temporaries(path: Path) -> None:
    """Delete temporary files for `path` left by writers that no longer run.

    Only a hard kill (SIGKILL, a power cut) gets past the cleanup above; the writer's process
    id in the name tells such leftovers from the temporary file of a writer still at work.
    """
    for leftover in path.parent.glob(f".{glob.escape(path.name)}.*.tmp"):
        pid = leftover.name[len(path.name) + 2 :].split(".")[0]
        if pid.isdigit() and not _running(int(pid)):
            leftover.unlink(missing_ok=True)


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)  # signal 0: only asks whether the process exists
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # it exists, under another user
    return True
