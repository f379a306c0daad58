"""The README's walk-through runs as printed, through the real `tvl`, and leaves nothing in
the checkout that git would list as new: what it writes goes to `scratch/`, which git
ignores, as it does the folders the set-up commands and the documentation build write."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from conftest import TVL
from doc_pages import ROOT, code_blocks, page, section

from tvl_cli.io.runfile import read_run

WALK_THROUGH = "The pipeline, on files that exist"


@pytest.mark.slow  # starts `tvl` a dozen times
def test_the_readme_pipeline_runs_and_writes_only_under_scratch(tmp_path: Path) -> None:
    (block,) = code_blocks(section(page("README.md"), WALK_THROUGH), "sh")
    for folder in ("worlds", "logs"):
        (tmp_path / folder).symlink_to(ROOT / folder)
    # `source .venv/bin/activate` puts the environment's `tvl` first on the path: so does this.
    path = f"{Path(TVL).parent}{os.pathsep}{os.environ['PATH']}"
    done = subprocess.run(
        ["bash", "-e", "-c", block],
        cwd=tmp_path,
        env={**os.environ, "PATH": path},
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["logs", "scratch", "worlds"]
    written = {p.name for p in (tmp_path / "scratch").iterdir()}
    # Every output the block names, and nothing it does not name.
    named = {word.split("/", 1)[1] for word in block.split() if word.startswith("scratch/")}
    assert written == named
    # The moment the README explains is the circle run's first bump, as its comment says and
    # as the events table of `tvl replay` shows it.
    trace = read_run(tmp_path / "scratch" / "circle.h5")
    first_bump_s = (trace.event_steps("bump")[0] + 1) * trace.period_s
    assert f"# events: its first bump at {first_bump_s:.1f} s" in block
    assert re.search(rf"│ bump +│ +\d+ │ {first_bump_s:.1f}[ ,]", done.stdout)
    assert f"tvl explain scratch/circle.h5 --at {first_bump_s:.1f} " in block


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_git_ignores_what_the_readme_commands_write() -> None:
    if not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    written = ["tvl-demo/single.h5", "scratch/wall.png", "scratch/single.h5", "site/index.html"]
    ignored = subprocess.run(
        ["git", "check-ignore", "--no-index", *written],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert ignored.stdout.split() == written
