"""`tvl diff`: where two FAM files of one configuration disagree, rule by rule."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from tvl_cli.analysis.famdiff import DEFAULT_TOLERANCE_MPS, FamDifference, diff_fams
from tvl_cli.analysis.robotdiff import robot_differences
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.json_documents import document, input_file
from tvl_cli.io.logreader import file_sha256, refuse_repeated


@dataclass(frozen=True, slots=True)
class FilesDiffered:
    """Two FAM files compared, and how they differ."""

    first: Path
    second: Path
    top: int
    difference: FamDifference

    def document(self) -> dict[str, Any]:
        inputs = {
            "first": input_file(self.first),
            "second": input_file(self.second),
            "tolerance_mps": self.difference.tolerance_mps,
            "top": self.top,
        }
        return document("diff", inputs, **self.difference.to_dict())


def diff_files(
    first: Path, second: Path, tolerance_mps: float = DEFAULT_TOLERANCE_MPS, top: int = 20
) -> FilesDiffered:
    """Compare two FAM files rule by rule, the `top` rules that differ most named (0: all),
    and the robots they were learnt on."""
    files = read_fam(first), read_fam(second)
    # As train refuses one log given twice: a FAM compared with itself tells nothing.
    refuse_repeated([(path, file_sha256(path)) for path in (first, second)], "FAM")
    found = diff_fams(files[0].fam, files[1].fam, tolerance_mps, top)
    robots = robot_differences(*(f.robot_config for f in files))
    return FilesDiffered(first, second, top, replace(found, robots=robots))
