"""Kernels compile once: the real `tvl` keeps every kernel it ran in numba's cache, in the
directory NUMBA_CACHE_DIR names, and the next process loads them from there."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from conftest import TVL

# Every test here starts the real `tvl` and waits on it.
pytestmark = pytest.mark.slow

SQUARE = Path(__file__).resolve().parents[2] / "worlds" / "square.txt"
# Learning through the default echo memory keeps echoes and casts them, too.
KERNELS = {
    "ring_ranges", "clearances", "infer_views", "train_table", "remember_echoes", "_patches_met"
}  # fmt: skip


def cached(directory: Path) -> dict[str, float]:
    """Each cached kernel's name and when its index was written."""
    return {p.name.split(".")[1].split("-")[0]: p.stat().st_mtime for p in directory.rglob("*.nbi")}


def test_a_chosen_cache_holds_every_kernel_and_the_next_run_compiles_none(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    fam, log = tmp_path / "fam.h5", tmp_path / "log.h5"

    def tvl(*args: str | Path) -> None:
        subprocess.run([TVL, *map(str, args)], env=env, check=True, capture_output=True)

    tvl("learn", SQUARE, "--log", log, "--minutes", "1", "--fam", fam)
    tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.2")
    first = cached(cache)
    assert set(first) >= KERNELS
    tvl("run", fam, SQUARE, "--behaviour", "wall", "--minutes", "0.2")
    assert cached(cache) == first
