"""`tvl bench`'s room: the shipped suites, as cells run on the sweep's engine.

The suites (generalization, claims) are each a list of cells (cells) planned from its options
(options, generalization, claims, references, controllers), done by the verbs' own work (work)
on the sweep's engine with a journal to go on from (runner).
"""

__all__ = [
    "cells",
    "claims",
    "controllers",
    "generalization",
    "options",
    "references",
    "runner",
    "work",
]
