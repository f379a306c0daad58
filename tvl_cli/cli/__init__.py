"""The `tvl` command line: click only."""

from tvl_cli.cli.main import main

__all__ = ["main"]
