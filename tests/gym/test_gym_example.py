"""The documentation's example of training an agent on tvl/SonarRing-v0 runs as printed and
learns: the table it trains for a few thousand steps passes the baseline's competence run."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "docs" / "examples" / "gym_q_learning.py"
LINE = re.compile(
    r"(?P<label>\w+): (?P<steps>\d+) steps, \d+ episodes; greedy for 5 minutes: "
    r"(?P<contacts>[\d.]+) contacts a minute, (?P<speed>[\d.]+) m/s, (?P<verdict>.+)"
)


@pytest.mark.slow  # about two seconds
def test_the_gym_training_example_learns_to_avoid(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, str(EXAMPLE)],
        cwd=tmp_path,  # the example names bundled worlds, needing no files of the checkout
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    untrained, trained = (LINE.fullmatch(line) for line in done.stdout.splitlines())
    assert untrained is not None and trained is not None, done.stdout
    assert (untrained["steps"], trained["steps"]) == ("0", "5000")
    # An empty table drives straight into the wall and pushes there; a trained one drives on.
    assert untrained["verdict"] == "not competent" and float(untrained["speed"]) < 0.05
    assert trained["verdict"] == "competent" and float(trained["speed"]) > 0.3
