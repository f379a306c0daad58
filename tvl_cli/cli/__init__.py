"""The `tvl` command line: click only."""

import os

# tvl's array work is small (a ring of 16, a 2 x 2 turn), so a BLAS thread pool buys nothing;
# OpenBLAS would start one a core in every process, numpy's and SciPy's each, and its threads
# spin: CPU spent for no work, and in a bench's worker processes one pool per core apiece.
# Set before numpy loads, which reads it then; a user's own setting stands.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from tvl_cli.cli.main import main

# `main` names the command group, which hides its module of the same name.
__all__ = [
    "baseline",
    "bench",
    "bench_view",
    "console",
    "demo",
    "design",
    "diff",
    "examples",
    "explain",
    "export",
    "fam_views",
    "figure",
    "groups",
    "inspect",
    "learn",
    "live",
    "main",
    "memory_options",
    "options",
    "params",
    "replay",
    "replay_views",
    "run",
    "schema",
    "sweep",
    "sweep_view",
    "tables",
    "train",
    "views",
    "world",
]
