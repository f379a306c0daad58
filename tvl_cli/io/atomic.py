"""Write an output file whole or not at all: a temporary file beside it, renamed into place."""

from __future__ import annotations

import glob
import os
import re
import secrets
import socket
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from tvl_cli.core.errors import BadInput

# This host's name as it appears in temporary file names (no dots, so names split cleanly).
_HOST = socket.gethostname().replace(".", "-").replace("/", "-") or "host"


@contextmanager
def atomic_output(path: Path | str, overwrite: bool = True) -> Iterator[Path]:
    """Yield a temporary path to write; on success it replaces `path`, on any failure
    (including Ctrl-C) it is removed and an existing `path` is left untouched.

    With `overwrite` False, a `path` that appeared while the temporary file was written (a
    second process writing the same output) is refused, not replaced: the file is put in
    place with a hard link, which fails if the name is taken.

    The temporary file sits in the same directory so the rename never crosses file systems.
    """
    path = Path(path)
    _remove_abandoned_temporaries(path)
    temporary = _temporary_beside(path)
    if path.exists():
        # A replaced file keeps the permissions its owner gave it.
        os.chmod(temporary, stat.S_IMODE(path.stat().st_mode))
    try:
        yield temporary
        if overwrite:
            os.replace(temporary, path)
        else:
            _link_new(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def check_writable(path: Path | str) -> None:
    """BadInput, as atomic_output would refuse it, unless a file can be written at `path`
    (tried, and taken back at once): for an output written only after long work."""
    _temporary_beside(Path(path)).unlink()


def _temporary_beside(path: Path) -> Path:
    """A new empty temporary file in `path`'s folder, named for `path` and this process;
    BadInput naming `path` if there is no such folder or it takes no new file."""
    refuse_missing_directory(path)
    refuse_non_file(path)
    temporary = path.with_name(f".{path.name}.{_HOST}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        # Created here, not by the writer, so that a read-only directory is a clear error;
        # an ordinary open() gives the file the user's usual permissions (umask).
        with open(temporary, "xb"):
            pass
    except OSError as error:
        raise BadInput(f"{path}: cannot write ({error.strerror})") from None
    return temporary


def refuse_missing_directory(path: Path) -> None:
    """BadInput unless the directory to write `path` in is there: one that does not exist,
    or a file named where a directory should be."""
    folder = path.parent
    if folder.is_dir():
        return
    if folder.exists():
        raise BadInput(f"{path}: cannot write, {folder} is a file, not a directory")
    raise BadInput(f"{path}: cannot write, directory {folder} does not exist")


def refuse_non_file(path: Path) -> None:
    """An output name taken by a directory or a device (/dev/full, a pipe) is refused, even
    with --force: replacing it would destroy what is there, not a file of ours."""
    if path.is_dir():
        raise BadInput(f"{path}: is a directory, not a file")
    if path.exists() and not path.is_file():
        raise BadInput(f"{path}: is a device or other special file, not a file to write")


def _link_new(temporary: Path, path: Path) -> None:
    """Give the finished file its name only if no other file has taken it."""
    try:
        os.link(temporary, path)
    except FileExistsError:
        raise BadInput(
            f"{path}: another process wrote it meanwhile (use --force to overwrite)"
        ) from None
    except OSError:  # a file system without hard links: check, then rename
        if path.exists():
            raise BadInput(f"{path}: already exists (use --force to overwrite)") from None
        os.replace(temporary, path)
        return
    temporary.unlink()


def _remove_abandoned_temporaries(path: Path) -> None:
    """Delete temporary files for `path` left by writers on this host that no longer run.

    Only a hard kill (SIGKILL, a power cut) gets past the cleanup above. The host and process
    id in the name tell such leftovers from the temporary file of a writer still at work,
    here or on another host sharing the directory (whose processes this host cannot see).
    """
    pattern = re.compile(
        rf"\.{re.escape(path.name)}\.{re.escape(_HOST)}\.(\d+)\.[0-9a-f]{{8}}\.tmp"
    )
    for leftover in path.parent.glob(f".{glob.escape(path.name)}.*.tmp"):
        found = pattern.fullmatch(leftover.name)
        if found and not _running(int(found.group(1))):
            leftover.unlink(missing_ok=True)


# A temporary file's name: "." + output name + "." + host + "." + pid + "." + 8 hex + ".tmp".
_TEMPORARY = re.compile(r"\.(?P<output>.+)\.[^./]+\.\d+\.[0-9a-f]{8}\.tmp")


def output_named_by(filename: str) -> str:
    """The output a temporary file of atomic_output is written for, so that an error met
    while writing names the file the user asked for; any other name unchanged."""
    path = Path(filename)
    found = _TEMPORARY.fullmatch(path.name)
    return str(path.with_name(found.group("output"))) if found else filename


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)  # signal 0: only asks whether the process exists
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # it exists, under another user
    return True
