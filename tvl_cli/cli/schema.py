"""`tvl schema`: the JSON Schema each command's `--json` document follows."""

from __future__ import annotations

import click

from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import print_json
from tvl_cli.cli.params import complete_schema_command
from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.io.json_documents import (
    SCHEMA_COMMANDS,
    command_schema,
    document,
    load_schema,
    schema_name,
    schema_version,
)


@click.command(epilog=examples("schema"))
@click.argument("command", nargs=-1, metavar="[COMMAND]", shell_complete=complete_schema_command)
@click.option("--json", "as_json", is_flag=True, help="Print the list (or the schema) as JSON.")
def schema(command: tuple[str, ...], as_json: bool) -> None:
    """Print the JSON Schema of COMMAND's --json output; with no COMMAND, list them.

    COMMAND is as typed, `run` or `world new` (or `world-new`). The schema printed needs no
    other file: the definitions it shares with the others are embedded in it."""
    if not command:
        if as_json:
            print_json(document("schema", {"command": None}, schemas=_listing()))
        else:
            width = max(map(len, SCHEMA_COMMANDS)) + 2
            for row in _listing():
                command_name = str(row["command"])
                click.echo(f"{command_name:<{width}}{row['id']}  (version {row['schema_version']})")
        return
    name = _known(" ".join(command))
    if as_json:
        print_json(
            document(
                "schema",
                {"command": name},
                schemas=[row for row in _listing() if row["command"] == name],
                json_schema=command_schema(name),
            )
        )
    else:
        print_json(command_schema(name))


def _known(given: str) -> str:
    """The command named, as SCHEMA_COMMANDS spells it; BadInput with the nearest name."""
    words = " ".join(given.replace("-", " ").split())
    if words in SCHEMA_COMMANDS:
        return words
    raise BadInput(f"no command {given!r} prints JSON ({did_you_mean(words, SCHEMA_COMMANDS)})")


def _listing() -> list[dict[str, object]]:
    return [
        {
            "command": command,
            "id": load_schema(schema_name(command))["$id"],
            "schema_version": schema_version(command),
        }
        for command in SCHEMA_COMMANDS
    ]
