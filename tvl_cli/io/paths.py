"""Outputs that are inputs: refused by what the file is, not by what it is called, so that a
symbolic link, a hard link or a path spelt another way cannot make a command overwrite a file
it is reading."""

from __future__ import annotations

import os
from pathlib import Path

from tvl_cli.core.errors import BadInput


def same_file(a: Path, b: Path) -> bool:
    """Whether two paths name one file (the same device and inode); False if either is
    missing or cannot be looked at."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def refuse_output_among_inputs(output: Path, inputs: dict[str, Path]) -> None:
    """BadInput if the output is one of the inputs (named by the keys, as "MAP.yaml")."""
    for what, path in inputs.items():
        if same_file(output, path):
            raise BadInput(
                f"{output}: is {what} ({path}), which this command reads; write to another file"
            )
