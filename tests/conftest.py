"""Shared fixtures: the real `tvl` command as a subprocess."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

# The console script installed beside the interpreter running the tests.
TVL = str(Path(sys.executable).with_name("tvl"))


@pytest.fixture
def run_tvl() -> Callable[..., subprocess.CompletedProcess[str]]:
    """Run `tvl ARGS...` and return the finished process (text output, never raises)."""

    def run(*args: str | Path) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [TVL, *map(str, args)], capture_output=True, text=True, timeout=120, check=False
        )

    return run
