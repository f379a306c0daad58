"""The `tvl` command line runs numpy's and SciPy's BLAS on the calling thread, unless the user
chose a number of threads."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(
    not Path("/proc/self/task").is_dir(), reason="threads are counted in /proc"
)

# What a new interpreter that loads the command line, then numpy and SciPy's linear algebra
# (each with an OpenBLAS of its own), holds: the setting, and how many threads it runs.
PROBE = (
    "import os, tvl_cli.cli, numpy, scipy.linalg\n"
    "print(os.environ['OPENBLAS_NUM_THREADS'], len(os.listdir('/proc/self/task')))"
)


def probe(env: dict[str, str]) -> list[str]:
    result = subprocess.run(
        [sys.executable, "-c", PROBE],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    )
    return result.stdout.split()


def test_the_command_line_starts_no_blas_threads() -> None:
    unset = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    assert probe(unset) == ["1", "1"]


def test_a_users_own_setting_stands() -> None:
    setting, _ = probe({**os.environ, "OPENBLAS_NUM_THREADS": "2"})
    assert setting == "2"
