"""`tvl diff`: where two FAM files of one configuration disagree, rule by rule."""

from __future__ import annotations

from pathlib import Path

from tvl_cli.analysis.famdiff import DEFAULT_TOLERANCE_MPS, FamDifference, diff_fams
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import file_sha256, refuse_repeated


def diff_files(
    first: Path, second: Path, tolerance_mps: float = DEFAULT_TOLERANCE_MPS, top: int = 20
) -> FamDifference:
    """Compare two FAM files rule by rule; the `top` rules that differ most named (0: all)."""
    fams = read_fam(first).fam, read_fam(second).fam
    # As train refuses one log given twice: a FAM compared with itself tells nothing.
    refuse_repeated([(path, file_sha256(path)) for path in (first, second)], "FAM")
    return diff_fams(*fams, tolerance_mps, top)
