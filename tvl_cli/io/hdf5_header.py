"""Format names and versions shared by every tvl file, and the checks every reader makes.

Each file carries root attributes `format`, `format_version`, `tvl_version` and `created`,
so a reader can refuse another format or a newer version by name instead of misreading it.
"""

from __future__ import annotations

import errno
import io
import json
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import h5py

from tvl_cli import __version__
from tvl_cli.core import jsontext
from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.lock import writer_pid

LOG_FORMAT = "tvl-log"
FAM_FORMAT = "tvl-fam"
RUN_FORMAT = "tvl-run"

# The newest version of each format this tvl writes and reads.
# A FAM file of version 2 records the echo memory it reads through, which a reader of
# version 1 would silently run without; a run trace of version 3 records what the FAM read.
# Log 2, FAM 3 and run trace 4 keep the method once, whole, in their `method` attribute, and
# no longer the pieces older readers read it from (a session's labels, memory and
# exploration in its parameters, a FAM's labels in its provenance and memory in `memory`, a
# trace's reflexes and memory in its parameters): an older tvl would read those files as
# made without the memory. io.method_records reads every version's method.
FORMAT_VERSIONS: dict[str, int] = {LOG_FORMAT: 2, FAM_FORMAT: 3, RUN_FORMAT: 4}
# The first version of each format that records its method whole.
METHOD_RECORDED_SINCE: dict[str, int] = {LOG_FORMAT: 2, FAM_FORMAT: 3, RUN_FORMAT: 4}

# HDF5 1.8 object headers: readable by any HDF5 library since 2008, and they allow attributes
# over 64 KiB (a large world map's text) in dense storage.
LIBVER = ("v108", "v108")
# Appending rewrites HDF5's metadata in place, and a kill can cut a write short at a memory
# page boundary (Linux copies a write into the file a page at a time). With every block the
# appender allocates starting on a page, a block smaller than a page (a dataset's header, a
# group's attributes) is written whole or not at all, never torn.
PAGE_BYTES = 4096
# h5py.File's settings for a file appended to in place: each block allocated starts on a page.
APPENDABLE = {"alignment_threshold": 1, "alignment_interval": PAGE_BYTES}


class FormatError(BadInput):
    """A file that is not the tvl file a command expects: other format, newer, corrupt."""


def utc_now() -> str:
    """The current UTC time as ISO 8601 to the second, as stored in `created` attributes."""
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


def to_json(value: Any) -> str:
    """Canonical JSON for attributes: sorted keys (same input, same bytes), one key a line so
    that `h5dump -A` reads well, and lists of plain values kept on one line."""
    return _json_lines(value, 0)


def _json_lines(value: Any, depth: int) -> str:
    inner, outer = " " * (depth + 1), " " * depth
    if isinstance(value, dict) and value:
        items = (
            f"{inner}{json.dumps(str(key))}: {_json_lines(value[key], depth + 1)}"
            for key in sorted(value)
        )
        return "{\n" + ",\n".join(items) + f"\n{outer}}}"
    if isinstance(value, (list, tuple)) and any(isinstance(v, (dict, list, tuple)) for v in value):
        items = (inner + _json_lines(v, depth + 1) for v in value)
        return "[\n" + ",\n".join(items) + f"\n{outer}]"
    return json.dumps(value)


def write_header(f: h5py.File, file_format: str, **json_attrs: Any) -> None:
    """Root attributes that make a file describe itself; each extra keyword is stored as JSON."""
    f.attrs["format"] = file_format
    f.attrs["format_version"] = FORMAT_VERSIONS[file_format]
    f.attrs["tvl_version"] = __version__
    f.attrs["created"] = utc_now()
    for name, value in json_attrs.items():
        f.attrs[name] = to_json(value)


def read_json_attr(obj: h5py.HLObject, name: str, path: Path | str) -> Any:
    """Parse a JSON attribute; a missing or malformed one is a FormatError naming the file."""
    text = read_str_attr(obj, name, path)
    try:
        return jsontext.loads(text, f"{path}: {obj.name}@{name}")
    except json.JSONDecodeError as error:
        raise FormatError(f"{path}: {obj.name}@{name} is not valid JSON ({error})") from None
    except BadInput as error:  # nested beyond reason, or a number of a million digits
        raise FormatError(str(error)) from None


def read_str_attr(obj: h5py.HLObject, name: str, path: Path | str) -> str:
    """A string attribute, whether stored variable-length (h5py) or fixed-length (other tools)."""
    if name not in obj.attrs:
        raise FormatError(f"{path}: {obj.name} has no {name!r} attribute")
    value = obj.attrs[name]
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    if not isinstance(value, str):
        raise FormatError(f"{path}: attribute {obj.name}@{name} is not a string")
    return value


def open_for_reading(path: Path | str, expected_format: str) -> h5py.File:
    """Open a tvl file read-only after checking its format and version.

    Every failure (missing, not HDF5, truncated, corrupt, locked, another format, a newer
    version) is a one-line BadInput or FormatError naming the file.
    """
    return _open_checked(path, expected_format, "r")


def open_for_appending(path: Path | str, expected_format: str) -> h5py.File:
    """Open an existing tvl file read-write, with the same checks as open_for_reading; what
    is added to it starts on a page (PAGE_BYTES)."""
    return _open_checked(path, expected_format, "r+", LIBVER)


def _open_checked(
    path: Path | str, expected_format: str, mode: str, libver: tuple[str, str] | None = None
) -> h5py.File:
    f = _open_hdf5(Path(path), mode, libver)
    try:
        check_format(f, expected_format, path)
    except BaseException:
        f.close()
        raise
    return f


def _open_hdf5(path: Path, mode: str, libver: tuple[str, str] | None) -> h5py.File:
    if path.is_dir():
        raise BadInput(f"{path}: is a directory, not a file")
    if not path.exists():
        raise BadInput(f"{path}: no such file")
    try:
        if mode == "r":
            return h5py.File(path, mode, libver=libver)
        return h5py.File(path, mode, libver=libver, **APPENDABLE)
    except OSError as error:
        raise _open_error(path, error) from None


def _open_error(path: Path, error: OSError) -> BadInput:
    """Turn h5py's open failures, which differ only in their message, into one clear line."""
    message = str(error)
    if error.errno == errno.EACCES or "Permission denied" in message:
        return BadInput(f"{path}: permission denied")
    if "unable to lock file" in message:
        pid = writer_pid(path)
        if pid is not None:
            return BadInput(f"{path}: locked by another tvl learn or run --learn (pid {pid})")
        return BadInput(f"{path}: in use by another program (the HDF5 file is locked)")
    if "file signature not found" in message:
        if path.stat().st_size == 0:
            return FormatError(f"{path}: is empty, not an HDF5 file")
        return FormatError(f"{path}: not an HDF5 file")
    if "truncated file" in message:
        return FormatError(f"{path}: truncated (the file is shorter than HDF5 says it should be)")
    return FormatError(f"{path}: corrupt HDF5 file ({_detail(message)})")


def _detail(message: str) -> str:
    """The parenthesised reason of an h5py error, on one line."""
    start = message.find("(")
    detail = message[start + 1 : message.rfind(")")] if start >= 0 else message
    return " ".join(detail.split())


def check_format(f: h5py.File, expected_format: str, path: Path | str) -> None:
    """Refuse a file that is not `expected_format`, or is of a version newer than we read."""
    found = _format_of(f, path)
    if found != expected_format:
        if found in FORMAT_VERSIONS:
            raise FormatError(f"{path}: is a {found} file, expected a {expected_format}")
        raise FormatError(f"{path}: not a tvl file (its format is {found!r})")
    version = f.attrs.get("format_version")
    if version is None or not _is_integer(version):
        raise FormatError(f"{path}: {found} file without an integer 'format_version'")
    newest = FORMAT_VERSIONS[expected_format]
    if int(version) > newest:
        raise FormatError(
            f"{path}: format_version {int(version)} is newer than this tvl reads ({newest})"
        )
    if int(version) < 1:
        raise FormatError(f"{path}: unknown format_version {int(version)}")


def file_format(path: Path | str) -> str:
    """The `format` of a tvl file of any kind (for commands that read several kinds)."""
    with _open_hdf5(Path(path), "r", None) as f:
        return _format_of(f, path)


def _format_of(f: h5py.File, path: Path | str) -> str:
    """The root `format` attribute, whether stored variable- or fixed-length."""
    try:
        found = f.attrs.get("format")
    except (OSError, KeyError) as error:
        raise FormatError(f"{path}: corrupt HDF5 file ({_detail(str(error))})") from None
    if isinstance(found, bytes):
        found = found.decode("utf-8", errors="replace")
    if not isinstance(found, str):
        raise FormatError(f"{path}: not a tvl file (no 'format' attribute)")
    return found


def _is_integer(value: Any) -> bool:
    return hasattr(value, "__index__")


@contextmanager
def hdf5_output(
    path: Path | str, overwrite: bool = True, *, based_on: bytes = b"", appendable: bool = False
) -> Iterator[h5py.File]:
    """An HDF5 file built in memory, then written to `path` whole through `atomic_output`:
    a new one, or a copy of `based_on` (a whole file's bytes) changed. `appendable`: made to
    be appended to in place afterwards (open_for_appending), each block on a page.

    HDF5 cannot close a file it failed to write and crashes trying: a full disk must fail in
    a plain write instead, which raises OSError (ENOSPC) and leaves no temporary file.
    """
    image = io.BytesIO(based_on)
    settings = APPENDABLE if appendable else {}
    with h5py.File(image, "r+" if based_on else "w", libver=LIBVER, **settings) as f:
        yield f
    with atomic_output(path, overwrite) as temporary:
        try:
            temporary.write_bytes(image.getbuffer())
        except OSError as error:
            raise OSError(error.errno, error.strerror, str(path)) from None
