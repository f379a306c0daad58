"""The terminal's two consoles (results on stdout, progress and messages on stderr) and how
plain text is folded to fit them."""

from __future__ import annotations

import textwrap

from rich.console import Console

# The widest a line of plain text (not a table) is printed, on a terminal of any width: a
# rule of a FAM of many inputs folds under its first line, indented by CONTINUED.
TEXT_WIDTH = 100
CONTINUED = "    "

out = Console(highlight=False)
err = Console(stderr=True, highlight=False)


def say(message: str) -> None:
    """A message on stderr, on one line however long (a script reads it whole)."""
    err.print(message, soft_wrap=True, markup=False)


def folded(text: str) -> str:
    """Plain text folded between words at the terminal's width, at most TEXT_WIDTH, its
    lines after the first indented: a long sentence stays readable in any terminal."""
    return textwrap.fill(
        text,
        width=min(out.width, TEXT_WIDTH),
        subsequent_indent=CONTINUED,
        break_long_words=False,
        break_on_hyphens=False,
    )
