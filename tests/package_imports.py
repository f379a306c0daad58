"""What each module of tvl_cli imports, read from its source without importing it: the one
reading of import statements that the import rules (tests/test_import_direction.py), the
packages' faces (tests/test_room_faces.py) and the map of rooms (benchmarks/room_links.py)
share."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "tvl_cli"


def imports(path: Path) -> list[str]:
    """Every module name an import statement in the file names, at any depth."""
    names: list[str] = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            base = node.module
            names += [base] + [f"{base}.{alias.name}" for alias in node.names]
    return names


def room_modules() -> list[tuple[str, Path]]:
    """Every module in a room (a folder of tvl_cli, at any depth below it), with its room."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).parts
        if len(parts) > 1:
            found.append((parts[0], path))
    return found


def room_imported(name: str) -> str | None:
    """The room of tvl_cli a module name an import gives (`imports`) lies in, if it lies in
    one: `tvl_cli.core.fam` and `tvl_cli.core.fam.Fam` lie in core, `tvl_cli` in none."""
    parts = name.split(".")
    return parts[1] if parts[0] == "tvl_cli" and len(parts) > 2 else None
