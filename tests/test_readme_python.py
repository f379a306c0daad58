"""The documentation's Python examples run as printed, from the repository's top folder."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from doc_pages import ROOT, code_blocks, every_page, page

from tvl_cli.core.method import DEFAULT

# The pages with a Python example, each run by a test below.
EXAMPLES = ("guide/python-api.md", "guide/gym.md", "guide/engine.md")


def _run_example(name: str, tmp_path: Path) -> list[str]:
    """Run the one Python block of a documentation page in a copy of the top folder's
    example inputs; its output lines."""
    (example,) = code_blocks(page(name), "python")
    for folder in ("worlds", "logs"):
        (tmp_path / folder).symlink_to(ROOT / folder)
    done = subprocess.run(
        [sys.executable, "-c", example], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()


def test_every_python_block_of_the_documentation_is_run_here() -> None:
    blocks = {name: len(code_blocks(text, "python")) for name, text in every_page().items()}
    assert {name: n for name, n in blocks.items() if n} == dict.fromkeys(EXAMPLES, 1)


@pytest.mark.slow  # over a second
def test_the_python_api_example_runs(tmp_path: Path) -> None:
    episodes, fam_memory, velocities, metrics = _run_example("guide/python-api.md", tmp_path)
    assert int(episodes.split()[0]) > 0
    # Learnt through our echo memory, the FAM reads through it, and so does its run.
    assert fam_memory == DEFAULT.memory.kind == "patches"
    assert len(velocities.strip("[]").split()) == 7
    run_memory, *measured = metrics.split()
    assert run_memory == "patches"
    contacts_per_min, speed = map(float, measured)
    assert contacts_per_min >= 0 and speed > 0
    assert (tmp_path / "api.h5").exists() and (tmp_path / "multi.h5").exists()


@pytest.mark.slow  # over a second
def test_the_gymnasium_example_runs(tmp_path: Path) -> None:
    episode, learning = _run_example("guide/gym.md", tmp_path)
    # TVL drove the whole 5-minute episode without a bump, forward most of the time.
    assert episode.startswith("300 s, bumped False, return ")
    assert float(episode.split()[-1]) > 60.0  # metres forward: 0.2 m/s or more on average
    bumps, *_, first_action = learning.split()
    assert int(bumps) > 0 and 0 <= int(first_action) <= 6


@pytest.mark.slow  # over a second
def test_the_step_engine_example_runs(tmp_path: Path) -> None:
    start, *events, end = _run_example("guide/engine.md", tmp_path)
    assert start.startswith("0.0 s, ring ahead ")
    # Straight on at 0.5 m/s for 3 s from the square's start meets the wall ahead once.
    assert len(events) == 1 and events[0].split(": ")[1].startswith("bump at x ")
    assert end.startswith("clearance 0.00 m") and end.endswith("bumped True")
