"""The JSON documents `--json` prints: the schema of each (shipped in tvl_cli/schemas/), the
stamp every document carries, and how a file it read is recorded.

Each schema is the one home of its document's `schema_version`: the stamp reads it from the
schema file, so the version a document claims is always the one its schema describes.
"""

from __future__ import annotations

import json
from functools import cache
from importlib.resources import files
from pathlib import Path
from typing import Any

from tvl_cli import __version__

# Every command that prints a JSON document, by the words a user types; its schema is
# tvl_cli/schemas/NAME.schema.json, NAME the words joined by "-".
SCHEMA_COMMANDS = (
    "world new",
    "world show",
    "world check",
    "world render",
    "world import",
    "world export",
    "learn",
    "train",
    "inspect",
    "diff",
    "design",
    "run",
    "replay",
    "explain",
    "demo",
    "baseline dwa",
    "baseline qlearn",
    "sweep",
    "export",
    "figure",
    "schema",
)
# The definitions the commands' schemas share, referred to by its $id.
COMMON = "common"


def schema_name(command: str) -> str:
    """The file name's stem of a command's schema: `world new` -> `world-new`."""
    return "-".join(command.split())


@cache
def load_schema(name: str) -> dict[str, Any]:
    """A schema of the package by its name (a command's, or COMMON)."""
    text = (files("tvl_cli") / "schemas" / f"{name}.schema.json").read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema


def command_schema(command: str) -> dict[str, Any]:
    """A command's schema, whole: the shared definitions it refers to embedded under its
    `$defs` by their `$id` (a JSON Schema 2020-12 bundle), so that it needs no other file."""
    schema = load_schema(schema_name(command))
    common = load_schema(COMMON)
    return {**schema, "$defs": {**schema.get("$defs", {}), common["$id"]: common}}


def schema_version(command: str) -> int:
    """The version of a command's document: the one its schema fixes."""
    version: int = load_schema(schema_name(command))["properties"]["schema_version"]["const"]
    return version


def document(command: str, inputs: dict[str, Any], **body: Any) -> dict[str, Any]:
    """A command's JSON document: which schema (and version of it) it follows, the tvl that
    wrote it, what it was given (`inputs`), then what it found."""
    return {
        "schema": load_schema(schema_name(command))["$id"],
        "schema_version": schema_version(command),
        "tvl_version": __version__,
        "inputs": inputs,
        **body,
    }


def input_file(path: Path | str) -> dict[str, str]:
    """A file a command read, as a document records it: where, and its bytes' SHA-256, so
    that a saved result can be traced to the very file it came from."""
    from tvl_cli.io.logreader import file_sha256  # loads h5py, which `tvl schema` needs not

    return {"path": str(path), "sha256": file_sha256(path)}


def optional_file(path: Path | str | None) -> dict[str, str] | None:
    return None if path is None else input_file(path)


def output_path(path: Path | str | None) -> str | None:
    """A file a command wrote (None: not asked for)."""
    return None if path is None else str(path)
