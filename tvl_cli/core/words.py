"""Counts in words, for people: `1 collision`, `2 collisions`, `1 near miss`."""

from __future__ import annotations

# Nouns whose plural is not the singular and an s.
_PLURALS = {"near miss": "near misses"}


def counted(n: int, noun: str) -> str:
    """`n` and `noun` in the number `n` takes: `1 disc`, `0 discs`, `3 near misses`."""
    return f"{n} {noun if n == 1 else plural(noun)}"


def plural(noun: str) -> str:
    return _PLURALS.get(noun, f"{noun}s")
