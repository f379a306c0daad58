"""The JSON documents `--json` prints: the schema of each (shipped in tvl_cli/schemas/), the
stamp every document carries, and how a file it read is recorded.

Each schema is the one home of its document's `schema_version`: the stamp reads it from the
schema file, so the version a document claims is always the one its schema describes.
"""

from __future__ import annotations

import hashlib
import json
from functools import cache
from importlib.resources import files
from pathlib import Path
from typing import Any, Protocol

from tvl_cli import __version__
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS

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
    "bench generalization",
    "bench claims",
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
    """A command's schema, whole: the shared definitions it refers to, and those they refer
    to, embedded under its `$defs` by their `$id` (a JSON Schema 2020-12 bundle), so that it
    needs no other file and changes only with what its document may hold."""
    schema = load_schema(schema_name(command))
    common = load_schema(COMMON)
    shared = common["$defs"]
    wanted: set[str] = set()
    found = _shared_refs(schema, common["$id"])
    while found - wanted:
        wanted |= found
        found = wanted | {n for name in wanted for n in _shared_refs(shared[name], "")}
    used = {**common, "$defs": {name: shared[name] for name in sorted(wanted)}}
    return {**schema, "$defs": {**schema.get("$defs", {}), common["$id"]: used}}


def _shared_refs(schema: Any, common_id: str) -> set[str]:
    """The names of the shared definitions `schema` refers to: `COMMON_ID#/$defs/NAME` from a
    command's schema, `#/$defs/NAME` (common_id "") from within the shared file."""
    found: set[str] = set()
    if isinstance(schema, dict):
        ref = schema.get("$ref")
        prefix = f"{common_id}#/$defs/"
        if isinstance(ref, str) and ref.startswith(prefix):
            found.add(ref[len(prefix) :])
        for value in schema.values():
            found |= _shared_refs(value, common_id)
    elif isinstance(schema, list):
        for item in schema:
            found |= _shared_refs(item, common_id)
    return found


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


class MadeText(Protocol):
    """An input made rather than read, such as a generated world: its name and its text."""

    @property
    def name(self) -> str: ...

    @property
    def text(self) -> str: ...


def world_input(world: Path | MadeText) -> dict[str, str]:
    """A world file as read; a world made here (generated) by its name, and the digest of
    its text."""
    if isinstance(world, Path):
        return input_file(world)
    return {"path": world.name, "sha256": hashlib.sha256(world.text.encode()).hexdigest()}


def optional_file(path: Path | str | None) -> dict[str, str] | None:
    return None if path is None else input_file(path)


def output_path(path: Path | str | None) -> str | None:
    """A file a command wrote (None: not asked for)."""
    return None if path is None else str(path)


def config_input(spec: str) -> dict[str, Any]:
    """A FAM configuration as given: a shipped one's name, or a file read."""
    return {
        "config": spec,
        "config_file": None if spec in BUILTIN_FAM_CONFIGS else input_file(spec),
    }
