"""`tvl sweep`'s room: grids of cells run on local processes or Dask, summarised over seeds.

A grid of cells is read from TOML (grid), learnt, trained and run on local processes or a Dask
cluster (runner, executors), and summarised over seeds (summary).
"""

__all__ = [
    "cell",
    "executors",
    "grid",
    "grid_entries",
    "grid_keys",
    "layout",
    "queue",
    "runner",
    "summary",
    "work",
]
