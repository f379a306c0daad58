"""`tvl world export` over an existing map writes its YAML and its image as one: stopped at
any moment (a failure between any two of its writes, a kill at random), the map on disk is
the old one whole or the new one whole, never a new image beside an old YAML."""

from __future__ import annotations

import errno
import random
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import TVL

from tvl_cli.io import occupancy_map
from tvl_cli.sim.worldmap import load_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
MAX_PIXELS = 1 << 24


def new_world(directory: Path) -> Path:
    """A world that differs from the square in everything a map records: its cell, its
    origin and its cells."""
    rows = ["#" * 40, *(["#" + "." * 38 + "#"] * 28), "#" * 40]
    rows[5] = "#...>" + "." * 34 + "#"
    path = directory / "new.txt"
    path.write_text("cell: 0.1\norigin: 3.5 -2\n" + "\n".join(rows) + "\n")
    return path


def read_back(map_yaml: Path) -> tuple[float, float, float, bytes]:
    """What a reader finds: the YAML's resolution and origin, and its image's pixels."""
    read = occupancy_map.read_occupancy_map(map_yaml, MAX_PIXELS)
    meta = read.meta
    return (meta.resolution_m, meta.origin_x_m, meta.origin_y_m, np.packbits(read.free).tobytes())


def export(invoke_tvl, world: Path, map_yaml: Path) -> None:
    done = invoke_tvl("world", "export", world, "-o", map_yaml, "--force")
    assert done.returncode == 0, done.stderr


@pytest.fixture
def versions(invoke_tvl, tmp_path: Path) -> tuple[Path, Path, tuple, tuple]:
    """The square exported as the old map, and what the old and the new maps read as."""
    new = new_world(tmp_path)
    for world, name in ((new, "expected-new"), (WORLDS / "square.txt", "map")):
        export(invoke_tvl, world, tmp_path / f"{name}.yaml")
    old, fresh = read_back(tmp_path / "map.yaml"), read_back(tmp_path / "expected-new.yaml")
    assert old != fresh and fresh[:3] == (0.1, 3.5, -2.0)
    return new, tmp_path / "map.yaml", old, fresh


def test_the_exported_map_keeps_the_worlds_frame(invoke_tvl, tmp_path: Path) -> None:
    new = new_world(tmp_path)
    export(invoke_tvl, new, tmp_path / "m.yaml")
    assert read_back(tmp_path / "m.yaml")[:3] == (0.1, 3.5, -2.0)
    back = tmp_path / "back.txt"
    done = invoke_tvl("world", "import", tmp_path / "m.yaml", "-o", back, "--start", "4,-1,0")
    assert done.returncode == 0, done.stderr
    assert load_world(back).origin_m == load_world(new).origin_m == (3.5, -2.0)
    # The map is its two files, under map_saver's names, and nothing else.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["back.txt", "m.pgm", "m.yaml", "new.txt"]


@pytest.mark.parametrize("failing_write", [1, 2, 3, 4])
def test_a_failure_between_any_two_writes_leaves_one_whole_map(
    invoke_tvl, versions, monkeypatch: pytest.MonkeyPatch, failing_write: int
) -> None:
    """The export makes four writes (its own image, the YAML naming it, the image under its
    usual name, the YAML naming that): a failing disk at each leaves the old map or the new.
    (An I/O error, not a full disk: on a full disk tvl leaves the process at once, which
    would end the test's too.)"""
    new, map_yaml, old, fresh = versions
    real = occupancy_map.atomic_output
    writes = []

    def failing(path: Path, overwrite: bool = True):
        writes.append(path)
        if len(writes) == failing_write:
            raise OSError(errno.EIO, "Input/output error")
        return real(path, overwrite)

    monkeypatch.setattr(occupancy_map, "atomic_output", failing)
    done = invoke_tvl("world", "export", new, "-o", map_yaml, "--force")
    assert done.returncode == 1 and done.stderr.count("\n") == 1
    assert read_back(map_yaml) in (old, fresh)
    if failing_write <= 2:  # before the YAML named anything new
        assert read_back(map_yaml) == old
        assert sorted(p.name for p in map_yaml.parent.glob("map*")) == ["map.pgm", "map.yaml"]


@pytest.mark.slow
def test_a_kill_at_any_moment_leaves_the_old_map_whole_or_the_new_one(
    versions, invoke_tvl, tmp_path: Path
) -> None:
    new, map_yaml, old, fresh = versions
    rng = random.Random(11)
    seen = set()
    for _ in range(24):
        before = set(tmp_path.iterdir())
        process = subprocess.Popen(
            [TVL, "world", "export", str(new), "-o", str(map_yaml), "--force"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        # Once the export's first file appears, a kill some milliseconds later falls among
        # its writes.
        deadline = time.monotonic() + 60
        while set(tmp_path.iterdir()) == before and process.poll() is None:
            assert time.monotonic() < deadline
            time.sleep(0.0002)
        time.sleep(rng.uniform(0.0, 0.012))
        process.send_signal(signal.SIGKILL)
        process.wait()
        found = read_back(map_yaml)
        assert found in (old, fresh)
        seen.add(found == fresh)
        export(invoke_tvl, WORLDS / "square.txt", map_yaml)  # the old map again
        assert read_back(map_yaml) == old
    assert seen == {False, True}  # kills fell both before and after the switch
