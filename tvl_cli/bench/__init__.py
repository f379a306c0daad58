"""`tvl bench`'s room: the shipped suites, as cells run on the sweep's engine.

The suites (generalization, claims) are each a list of cells (suite_cells) planned from its
options (suite_options, generalization_suite, claims_suite, references, controllers), done by
the verbs' own work (suite_work) on the sweep's engine with a journal to go on from
(suite_runner).
"""

__all__ = [
    "claims_suite",
    "controllers",
    "generalization_suite",
    "references",
    "suite_cells",
    "suite_options",
    "suite_runner",
    "suite_work",
]
