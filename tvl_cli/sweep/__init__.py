"""`tvl sweep`'s room: a grid of cells read from TOML (grid), learnt, trained and run on local
processes or a Dask cluster (runner, executors), and summarised over seeds (summary)."""
