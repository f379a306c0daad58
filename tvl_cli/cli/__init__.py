"""The `tvl` command line: click only."""

from tvl_cli.cli.main import main

# `main` names the command group, which hides its module of the same name.
__all__ = [
    "baselines",
    "bench",
    "bench_view",
    "console",
    "documents",
    "examples",
    "explain",
    "export",
    "fam_commands",
    "fam_views",
    "figure",
    "grid_documents",
    "groups",
    "input_design",
    "learning",
    "live",
    "main",
    "memory_options",
    "options",
    "params",
    "replay_views",
    "runs",
    "schema",
    "sweep",
    "sweep_view",
    "tables",
    "views",
    "world",
]
