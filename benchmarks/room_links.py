"""How the rooms of tvl_cli (its top-level packages) hang together, and what has grown long.

How many pairs of rooms are linked by at least one import, either way, out of all the pairs,
and which; each room's modules (its packages' `__init__` too) and lines; and the modules and
functions grown past their size.

    python benchmarks/room_links.py [--json]

Imports are read from the source as tests/test_import_direction.py reads them
(tests/package_imports.py), function-level ones too. A module's lines are its file's lines; a
function's run from its `def` to its last line (ast: end_lineno - lineno + 1), methods and
nested functions each counted.
"""

from __future__ import annotations

import argparse
import ast
import json
import sys
from pathlib import Path

# The reading of imports the import rules' tests hold the package to.
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from package_imports import PACKAGE, imports, room_imported, room_modules

LONG_MODULE_LINES = 400
LONG_FUNCTION_LINES = 60


def rooms() -> list[str]:
    return sorted(path.parent.name for path in PACKAGE.glob("*/__init__.py"))


def linked_pairs() -> list[tuple[str, str]]:
    """Each pair of rooms (sorted) one of which imports from the other."""
    pairs = set()
    for room, path in room_modules():
        for name in imports(path):
            other = room_imported(name)
            if other is not None and other != room:
                pairs.add(tuple(sorted((room, other))))
    return sorted(pairs)


def function_lines(tree: ast.Module) -> list[tuple[str, int]]:
    """Every function's name and lines, methods and nested functions too."""
    return [
        (node.name, node.end_lineno - node.lineno + 1)
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.end_lineno
    ]


def survey() -> dict:
    """The figures, as --json prints them."""
    names = rooms()
    pairs = linked_pairs()
    per_room = {room: {"modules": 0, "lines": 0} for room in names}
    long_modules, long_functions = [], []
    for room, path in room_modules():
        text = path.read_text(encoding="utf-8")
        lines = len(text.splitlines())
        where = path.relative_to(PACKAGE.parent).as_posix()
        per_room[room]["modules"] += 1
        per_room[room]["lines"] += lines
        if lines > LONG_MODULE_LINES:
            long_modules.append({"module": where, "lines": lines})
        for function, length in function_lines(ast.parse(text)):
            if length > LONG_FUNCTION_LINES:
                long_functions.append({"module": where, "function": function, "lines": length})
    return {
        "rooms": len(names),
        "linked_pairs": len(pairs),
        "pairs": len(names) * (len(names) - 1) // 2,
        "links": [list(pair) for pair in pairs],
        "per_room": per_room,
        "long_modules": long_modules,
        "long_functions": long_functions,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print only the figures, as JSON")
    args = parser.parse_args()
    figures = survey()
    if args.json:
        print(json.dumps(figures))
        return
    print(
        f"{figures['linked_pairs']} of {figures['pairs']} pairs of {figures['rooms']} rooms "
        "linked by an import:"
    )
    for first, second in figures["links"]:
        print(f"  {first} - {second}")
    print(f"{'room':<12}{'modules':>9}{'lines':>7}")
    for room, counts in figures["per_room"].items():
        print(f"  {room:<10}{counts['modules']:>9}{counts['lines']:>7}")
    long_modules = [f"{each['module']}: {each['lines']}" for each in figures["long_modules"]]
    print(f"modules over {LONG_MODULE_LINES} lines: {len(long_modules)}")
    for line in long_modules:
        print(f"  {line}")
    long_functions = [
        f"{each['module']}::{each['function']}: {each['lines']}"
        for each in figures["long_functions"]
    ]
    print(f"functions over {LONG_FUNCTION_LINES} lines: {len(long_functions)}")
    for line in long_functions:
        print(f"  {line}")


if __name__ == "__main__":
    main()
