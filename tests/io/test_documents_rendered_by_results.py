"""Each command's JSON document is rendered in one place: by its result type's `document()`
method, beside the work that made the result (tests/cli/test_schemas.py holds each document,
made for real, to its schema field by field). The one exception is `tvl schema`, whose
document is the listing of the others, made where it is printed."""

from __future__ import annotations

import ast
from pathlib import Path

from package_imports import PACKAGE

from tvl_cli.io.json_documents import SCHEMA_COMMANDS

# Printed by the command line itself, with no result type: the schemas' own listing.
MADE_BY_THE_COMMAND_LINE = {"schema": "cli/schema.py"}


def _documents_built() -> list[tuple[str, str, str | None]]:
    """Every call `document("COMMAND", ...)` in the package: the command, the module, and the
    class whose `document` method makes the call (None: anywhere else)."""
    found = []
    for path in sorted(PACKAGE.glob("**/*.py")):
        if path.name == "json_documents.py":
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        module = path.relative_to(PACKAGE).as_posix()
        for owner, method in _methods(tree):
            for node in ast.walk(method):
                command = _document_call(node)
                if command is not None:
                    found.append((command, module, owner))
    return found


def _methods(tree: ast.Module) -> list[tuple[str | None, ast.AST]]:
    """Each class's `document` method with its class; every other top-level statement with
    None, so that a document built anywhere else is found too."""
    pieces: list[tuple[str | None, ast.AST]] = []
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                is_document = isinstance(item, ast.FunctionDef) and item.name == "document"
                pieces.append((node.name if is_document else None, item))
        else:
            pieces.append((None, node))
    return pieces


def _document_call(node: ast.AST) -> str | None:
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)):
        return None
    if node.func.id != "document" or not node.args:
        return None
    first = node.args[0]
    return first.value if isinstance(first, ast.Constant) else None


def test_each_commands_document_is_rendered_by_a_result_type() -> None:
    built = _documents_built()
    assert {command for command, _, _ in built} == set(SCHEMA_COMMANDS)
    elsewhere = [
        (command, module)
        for command, module, owner in built
        if owner is None and MADE_BY_THE_COMMAND_LINE.get(command) != module
    ]
    assert not elsewhere, f"documents built outside a result type's document(): {elsewhere}"


def test_no_result_type_renders_two_commands() -> None:
    commands_of: dict[str, set[str]] = {}
    for command, module, owner in _documents_built():
        if owner is not None:
            commands_of.setdefault(f"{module}:{owner}", set()).add(command)
    assert all(len(commands) == 1 for commands in commands_of.values()), commands_of


def test_the_checks_see_the_package() -> None:
    assert Path(PACKAGE / "io" / "json_documents.py").is_file()
    assert len(_documents_built()) >= len(SCHEMA_COMMANDS)
