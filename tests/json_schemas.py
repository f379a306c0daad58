"""A command's `--json` document checked against the schema the package ships for it."""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator
from typing import Any

from jsonschema import Draft202012Validator, ValidationError, validators

from tvl_cli.io.json_documents import command_schema

# JSON Schema counts 1.0 an integer; tvl writes every count as a whole number (1), in every
# document alike, and these checks hold it to that.
_WHOLE = Draft202012Validator.TYPE_CHECKER.redefine(
    "integer", lambda checker, value: isinstance(value, int) and not isinstance(value, bool)
)
StrictValidator = validators.extend(Draft202012Validator, type_checker=_WHOLE)


def valid(command: str, printed: str | dict[str, Any]) -> dict[str, Any]:
    """The document (as printed, or parsed), once it is found to follow `command`'s schema;
    AssertionError listing where it does not."""
    document = json.loads(printed) if isinstance(printed, str) else printed
    errors = list(StrictValidator(command_schema(command)).iter_errors(document))
    assert not errors, "\n".join(
        f"{'/'.join(map(str, e.absolute_path)) or '(top)'}: {e.message[:300]}"
        for e in _leaves(errors)
    )
    return document  # type: ignore[no-any-return]


def _leaves(errors: Iterable[ValidationError]) -> Iterator[ValidationError]:
    """The errors that say where: those under a oneOf or anyOf, not the oneOf itself."""
    for error in errors:
        if error.context:
            yield from _leaves(error.context)
        else:
            yield error


# What every document opens with, before what the command found.
ENVELOPE = frozenset({"schema", "schema_version", "tvl_version", "inputs", "outputs"})
