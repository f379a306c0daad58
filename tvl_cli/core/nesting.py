"""How deep the lists and tables of a file a user gives (TOML or JSON) may nest.

Python's parsers recurse once a level, so a file nested some thousands deep stops them with a
RecursionError, and one a few hundred deep passes them to stop whatever walks the value next.
tvl's own files nest a few levels (a FAM configuration, the deepest, six: its tables, their
inputs, a partition's names); a cap far above that and far below any recursion limit refuses
the rest, the same way wherever they are read, before anything acts on them.
"""

from __future__ import annotations

from typing import Any

from tvl_cli.core.errors import BadInput

MAX_NESTING = 32  # lists and tables (JSON objects) within one another


def too_deep(where: str) -> BadInput:
    """The refusal of a file nested beyond MAX_NESTING, or beyond what its parser could read."""
    return BadInput(
        f"{where}: nested too deeply (more than {MAX_NESTING} lists or tables within one another)"
    )


def nesting_depth(value: Any) -> int:
    """How many lists and dicts `value` holds one within another (0 for a number or text),
    walked without recursion, so that any depth is measured."""
    deepest = 0
    stack: list[tuple[Any, int]] = [(value, 0)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, dict):
            children: Any = item.values()
        elif isinstance(item, list | tuple):
            children = item
        else:
            continue
        depth += 1
        deepest = max(deepest, depth)
        if depth > MAX_NESTING:  # deep enough to refuse: no need to walk the rest
            return depth
        stack.extend((child, depth) for child in children)
    return deepest


def check_nesting(value: Any, where: str) -> None:
    """BadInput naming `where` if `value` nests deeper than MAX_NESTING."""
    if nesting_depth(value) > MAX_NESTING:
        raise too_deep(where)
