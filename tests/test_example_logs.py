"""The example logs in logs/ are what `tvl learn` writes today, by their own script."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import h5py
import pytest
from conftest import TVL
from hdf5_contents import datasets

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ("square-s1.h5", "lab-s1.h5")
# Attributes that say when and by which version a file was written, not what it holds.
WHEN = {"created", "started", "ended", "tvl_version"}

pytestmark = pytest.mark.slow  # every test here starts a real `tvl` process


def _attributes(path: Path) -> dict[str, dict[str, object]]:
    found: dict[str, dict[str, object]] = {}

    def visit(name: str, obj: h5py.HLObject) -> None:
        found[name] = {k: str(v) for k, v in obj.attrs.items() if k not in WHEN}

    with h5py.File(path, "r") as f:
        visit("/", f)
        f.visititems(visit)
    return found


@pytest.fixture(scope="module")
def written_today(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The examples written again by logs/make_examples.sh, in a copy of its folder."""
    top = tmp_path_factory.mktemp("examples")
    (top / "logs").mkdir()
    shutil.copy(ROOT / "logs" / "make_examples.sh", top / "logs")
    (top / "worlds").symlink_to(ROOT / "worlds")
    subprocess.run(
        [top / "logs" / "make_examples.sh"],
        check=True,
        capture_output=True,
        env={**os.environ, "TVL": TVL},
        timeout=300,
    )
    return top / "logs"


@pytest.mark.parametrize("name", EXAMPLES)
def test_an_example_log_is_what_learning_writes_today(written_today: Path, name: str) -> None:
    shipped, today = ROOT / "logs" / name, written_today / name
    assert datasets(shipped) == datasets(today), f"run logs/make_examples.sh ({name})"
    assert _attributes(shipped) == _attributes(today), f"run logs/make_examples.sh ({name})"
