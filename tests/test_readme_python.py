"""The README's Python example runs as printed, from the repository's top folder."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_the_readme_python_example_runs(tmp_path: Path) -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    (example,) = re.findall(r"```python\n(.*?)```", readme, flags=re.DOTALL)
    (tmp_path / "worlds").symlink_to(ROOT / "worlds")
    done = subprocess.run(
        [sys.executable, "-c", example], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    episodes, velocities, metrics = done.stdout.splitlines()
    assert int(episodes.split()[0]) > 0
    assert len(velocities.strip("[]").split()) == 7
    contacts_per_min, speed = map(float, metrics.split())
    assert contacts_per_min >= 0 and speed > 0
    assert (tmp_path / "api.h5").exists() and (tmp_path / "multi.h5").exists()
