"""TOML files the user writes (a sweep's grid, a method): read whole, every fault one line."""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Any

from tvl_cli.core.errors import BadInput
from tvl_cli.core.text import decoded

if sys.version_info >= (3, 11):
    import tomllib
else:  # the same parser, before it joined the standard library
    import tomli as tomllib

# Where tomllib places a syntax error, at the end of its message.
_AT = re.compile(r"(?P<what>.*) \(at line (?P<line>\d+), column (?P<column>\d+)\)")


def read_toml(path: Path, what: str) -> dict[str, Any]:
    """The table of a TOML file; BadInput naming the file (and the line of a syntax error).
    `what` names the kind of file for a missing one ("grid")."""
    try:
        text = decoded(path.read_bytes(), str(path))
    except FileNotFoundError:
        raise BadInput(f"{path}: no such {what} file") from None
    except IsADirectoryError:
        raise BadInput(f"{path}: is a directory, not a {what} file") from None
    except OSError as error:
        raise BadInput(f"{path}: cannot read ({error.strerror})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        found = _AT.fullmatch(str(error))
        if found is None:
            raise BadInput(f"{path}: not TOML ({error})") from None
        raise BadInput(f"{path}:{found['line']}:{found['column']}: {found['what']}") from None
