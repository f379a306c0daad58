"""Rewrites the table of additions in docs/method.md, between its markers, from
tvl_cli.core.additions.ADDITIONS: `python docs/additions_table.py` (or `--check`: exit 1 when
the page's table is not the registry's)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from tvl_cli.core.additions import additions_table

PAGE = Path(__file__).resolve().parent / "method.md"
START, END = "<!-- additions:start -->", "<!-- additions:end -->"


def with_table(text: str) -> str:
    """The page's text with the registry's table between its markers."""
    before, start, rest = text.partition(START)
    _, end, after = rest.partition(END)
    if not start or not end:
        raise SystemExit(f"{PAGE}: no {START} ... {END} block")
    return f"{before}{START}\n{additions_table()}{END}{after}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only say whether it is current")
    args = parser.parse_args()
    text = PAGE.read_text(encoding="utf-8")
    current = with_table(text)
    if args.check:
        if current != text:
            print(f"{PAGE}: the table of additions is not ADDITIONS'; run {sys.argv[0]}")
            sys.exit(1)
        return
    PAGE.write_text(current, encoding="utf-8")
    print(f"wrote the table of additions into {PAGE}")


if __name__ == "__main__":
    main()
