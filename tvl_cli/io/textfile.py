"""Settings files a user writes (a method, a sweep's grid, a FAM configuration): read whole,
every fault one line naming the file."""

from __future__ import annotations

from pathlib import Path

from tvl_cli.core.errors import BadInput
from tvl_cli.core.text import decoded

# A settings file is a few kilobytes (a designed FAM configuration, the largest, about 20):
# a megabyte is far beyond any written by hand or by tvl, and small enough to read at once.
MAX_SETTINGS_BYTES = 1 << 20


def read_settings_text(path: Path, what: str) -> str:
    """The text of a settings file; BadInput naming the file if it is missing, a directory,
    unreadable, over MAX_SETTINGS_BYTES or not UTF-8. `what` names the kind of file
    ("grid")."""
    try:
        with path.open("rb") as stream:
            data = stream.read(MAX_SETTINGS_BYTES + 1)
    except FileNotFoundError:
        raise BadInput(f"{path}: no such {what} file") from None
    except IsADirectoryError:
        raise BadInput(f"{path}: is a directory, not a {what} file") from None
    except OSError as error:
        raise BadInput(f"{path}: cannot read ({error.strerror})") from None
    if len(data) > MAX_SETTINGS_BYTES:
        raise BadInput(
            f"{path}: over {MAX_SETTINGS_BYTES // (1 << 20)} MiB; not a {what} file written "
            "by hand or by tvl"
        )
    return decoded(data, str(path))
