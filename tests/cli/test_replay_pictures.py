"""What replay and run pictures show: every session of a log or a chosen one, and the
events of a run marked on its path."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import invoke as tvl
from json_schemas import valid
from test_bad_numbers import SQUARE

from tvl_cli.core.contacts import BACKOFF, BUMP, EVENTS, NEAR_MISS
from tvl_cli.render.plot import PATH_MARKS, bump_marks, path_marks

PNG_MAGIC = b"\x89PNG"


@pytest.fixture(scope="module")
def two_sessions(tmp_path_factory: pytest.TempPathFactory) -> Path:
    log = tmp_path_factory.mktemp("replay") / "log.h5"
    for _ in range(2):
        assert tvl("learn", SQUARE, "--log", log, "--minutes", "0.5").returncode == 0
    return log


def test_a_log_picture_draws_every_session_of_its_world(two_sessions: Path, tmp_path: Path):
    png = tmp_path / "all.png"
    printed = valid("replay", tvl("replay", two_sessions, "--png", png, "--json").stdout)
    assert printed["sessions_drawn"] == ["0000", "0001"] and printed["outputs"]["png"] == str(png)
    assert png.read_bytes().startswith(PNG_MAGIC)


@pytest.mark.slow
def test_a_log_picture_of_one_session(two_sessions: Path, tmp_path: Path) -> None:
    png, curves = tmp_path / "one.png", tmp_path / "curves.png"
    done = tvl("replay", two_sessions, "--png", png, "--session", "0", "--curves", curves, "--json")
    assert done.returncode == 0, done.stderr
    assert valid("replay", done.stdout)["sessions_drawn"] == ["0000"]
    missing = tvl("replay", two_sessions, "--png", tmp_path / "x.png", "--session", "9")
    assert missing.returncode == 2 and "no session '9' (it has 0000, 0001)" in missing.stderr


def test_a_path_marks_collisions_near_misses_and_back_offs() -> None:
    bit = {name: 1 << i for i, name in enumerate(EVENTS)}
    events = np.array([0, bit[BUMP] | bit[BACKOFF], 0, bit[NEAR_MISS], bit[BACKOFF], 0])
    marks = path_marks(events.astype(np.uint8))
    assert set(marks) == set(PATH_MARKS) == {BUMP, NEAR_MISS, BACKOFF}
    assert [marks[BUMP].tolist(), marks[NEAR_MISS].tolist(), marks[BACKOFF].tolist()] == [
        [1], [3], [1, 4]
    ]  # fmt: skip
    # A trace without events: the steps where the bump sensor closed.
    assert bump_marks(np.array([0, 1, 1, 0, 1], dtype=bool))[BUMP].tolist() == [1, 4]
