"""`tvl diff`: where two FAM files of one configuration disagree, rule by rule."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from tvl_cli.analysis.famdiff import DEFAULT_TOLERANCE_MPS, FamDifference, diff_fams
from tvl_cli.analysis.robotdiff import robot_differences
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import file_sha256, refuse_repeated


def diff_files(
    first: Path, second: Path, tolerance_mps: float = DEFAULT_TOLERANCE_MPS, top: int = 20
) -> FamDifference:
    """Compare two FAM files rule by rule, the `top` rules that differ most named (0: all),
    and the robots they were learnt on."""
    files = read_fam(first), read_fam(second)
    # As train refuses one log given twice: a FAM compared with itself tells nothing.
    refuse_repeated([(path, file_sha256(path)) for path in (first, second)], "FAM")
    found = diff_fams(files[0].fam, files[1].fam, tolerance_mps, top)
    return replace(found, robots=robot_differences(*(f.robot_config for f in files)))
