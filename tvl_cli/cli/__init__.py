"""The `tvl` command line: click only."""

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
