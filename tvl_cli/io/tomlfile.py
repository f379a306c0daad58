"""TOML files the user writes (a sweep's grid, a method): read whole, every fault one line."""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Any

from tvl_cli.core.errors import BadInput
from tvl_cli.core.nesting import MAX_NESTING, check_nesting, too_deep
from tvl_cli.io.textfile import read_settings_text

if sys.version_info >= (3, 11):
    import tomllib
else:  # the same parser, before it joined the standard library
    import tomli as tomllib

# Where tomllib places a syntax error, at the end of its message.
_AT = re.compile(r"(?P<what>.*) \(at line (?P<line>\d+), column (?P<column>\d+)\)")
# What nests in TOML, found without parsing: strings and comments (each skipped whole, so
# that what they hold counts for nothing), brackets and braces, the dots of dotted keys, and
# what ends a key.
_NESTING_TOKENS = re.compile(
    r'"""(?:[^\\]|\\.)*?"""'  # a multi-line basic string
    r"|'''.*?'''"  # a multi-line literal string
    r'|"(?:[^"\\\n]|\\.)*"'  # a basic string
    r"|'[^'\n]*'"  # a literal string
    r"|#[^\n]*"  # a comment
    r"|[][{}.=,\n]",
    re.DOTALL,
)


def read_toml(path: Path, what: str) -> dict[str, Any]:
    """The table of a TOML file; BadInput naming the file (and the line of a syntax error).
    `what` names the kind of file for a missing one ("grid")."""
    return loads_toml(read_settings_text(path, what), str(path))


def loads_toml(text: str, where: str) -> dict[str, Any]:
    """The table of TOML text; BadInput naming `where` (and the line of a syntax error), or
    saying the text nests deeper than core.nesting allows."""
    _check_text_nesting(text, where)
    try:
        table = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        found = _AT.fullmatch(str(error))
        if found is None:
            raise BadInput(f"{where}: not TOML ({error})") from None
        raise BadInput(f"{where}:{found['line']}:{found['column']}: {found['what']}") from None
    check_nesting(table, where)  # what the text's count may miss (a table named twice over)
    return table


def _check_text_nesting(text: str, where: str) -> None:
    """BadInput naming the line where the text nests deeper than MAX_NESTING, found before
    tomllib parses it: tomllib recurses once a bracket, and takes time quadratic in the parts
    of a dotted key (`a.a.a…`, each a table within the last), so that a file of a megabyte
    nested either way would take it minutes or all the memory. Each part of a dotted key,
    bracket and brace counts a level (a header's bracket and a number's point too: a level or
    two more than the value holds, far within the cap)."""
    depth = parts = 0
    for token in _NESTING_TOKENS.finditer(text):
        mark = token.group()
        if mark == ".":
            parts += 1
        elif mark in ("[", "{"):
            depth, parts = depth + 1, 0
        elif mark in ("]", "}"):
            depth, parts = max(depth - 1, 0), 0
        elif mark in ("=", ",", "\n"):
            parts = 0
        if depth + parts > MAX_NESTING:
            line = text.count("\n", 0, token.start()) + 1
            raise too_deep(f"{where}:{line}")
