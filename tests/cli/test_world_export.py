"""`tvl world export`: a world drawn on its cells as map_saver writes a map, which `tvl world
import` reads back to the same grid."""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner
from json_schemas import ENVELOPE, valid

from tvl_cli.cli.main import main
from tvl_cli.io.pgm import decode_pgm
from tvl_cli.sim.worldmap import layout, load_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"


def tvl(*args: object) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, [str(a) for a in args])
    return done.exit_code, done.stdout, done.stderr


def exported(world: Path, map_yaml: Path) -> np.ndarray:
    """Export the world; the PGM's pixels."""
    code, _, stderr = tvl("world", "export", world, "-o", map_yaml)
    assert code == 0, stderr
    pixels, maxval = decode_pgm(map_yaml.with_suffix(".pgm").read_bytes(), 10**6)
    assert maxval == 255
    return pixels


def start_of(world: Path) -> str:
    x, y, heading = load_world(world).start
    return f"{x!r},{y!r},{math.degrees(heading):g}"


def test_the_yaml_is_map_savers_with_the_worlds_cell_and_origin(tmp_path: Path) -> None:
    exported(WORLDS / "square.txt", tmp_path / "square.yaml")
    assert yaml.safe_load((tmp_path / "square.yaml").read_text()) == {
        "image": "square.pgm",
        "mode": "trinary",
        "resolution": 0.25,
        "origin": [0.0, 0.0, 0.0],
        "negate": 0,
        "occupied_thresh": 0.65,
        # ROS 1's value: grey 205 stays unknown when the map is read again.
        "free_thresh": 0.196,
    }


def test_the_square_is_its_walls_in_black_and_its_floor_in_white(tmp_path: Path) -> None:
    pixels = exported(WORLDS / "square.txt", tmp_path / "square.yaml")
    assert pixels.shape == (16, 16)
    assert (pixels[[0, -1], :] == 0).all() and (pixels[:, [0, -1]] == 0).all()
    assert (pixels[1:-1, 1:-1] == 254).all()


@pytest.mark.parametrize("name", ["square", "lab", "circle", "obstacles"])
def test_import_reads_an_export_back_to_the_same_grid(name: str, tmp_path: Path) -> None:
    world = WORLDS / f"{name}.txt"
    first = exported(world, tmp_path / "first.yaml")
    back = tmp_path / "back.txt"
    code, _, stderr = tvl(
        "world", "import", tmp_path / "first.yaml", "-o", back, "--start", start_of(world)
    )
    assert code == 0, stderr
    assert load_world(back).start == pytest.approx(load_world(world).start)
    assert np.array_equal(exported(back, tmp_path / "second.yaml"), first)


def test_a_grid_world_comes_back_cell_for_cell(tmp_path: Path) -> None:
    world = WORLDS / "square.txt"
    exported(world, tmp_path / "square.yaml")
    back = tmp_path / "back.txt"
    code, _, _ = tvl(
        "world", "import", tmp_path / "square.yaml", "-o", back, "--start", start_of(world)
    )
    assert code == 0
    # The start comes back as a `start:` line rather than a character of the map.
    without_start = [row.replace(">", ".") for row in layout(load_world(world))[0]]
    assert list(layout(load_world(back))[0]) == without_start
    assert load_world(back).segments == load_world(world).segments


def test_pillars_and_thin_walls_are_drawn_on_their_cells(tmp_path: Path) -> None:
    lab = load_world(WORLDS / "lab.txt")
    pixels = exported(WORLDS / "lab.txt", tmp_path / "lab.yaml")
    rows = len(layout(lab)[0])
    for x, y, _ in lab.discs:
        assert pixels[rows - 1 - int(y / lab.cell_m), int(x / lab.cell_m)] == 0
    # More occupied than the map's hashes: the header's walls and discs are drawn too.
    hashes = sum(row.count("#") for row in layout(lab)[0])
    assert int((pixels == 0).sum()) > hashes


def test_json_gives_the_files_and_the_cells(tmp_path: Path) -> None:
    code, stdout, _ = tvl(
        "world", "export", WORLDS / "square.txt", "-o", tmp_path / "m.yaml", "--json"
    )
    assert code == 0
    printed = valid("world export", stdout)
    assert printed["inputs"]["world"] == {
        "path": str(WORLDS / "square.txt"),
        "sha256": hashlib.sha256((WORLDS / "square.txt").read_bytes()).hexdigest(),
    }
    assert printed["outputs"] == {
        "map_yaml": str(tmp_path / "m.yaml"),
        "image": str(tmp_path / "m.pgm"),
    }
    assert {k: v for k, v in printed.items() if k not in ENVELOPE} == {
        "cell_m": 0.25,
        "columns": 16,
        "rows": 16,
        "free_cells": 14 * 14,
        "occupied_cells": 16 * 16 - 14 * 14,
    }


def test_an_output_not_named_yaml_is_refused(tmp_path: Path) -> None:
    code, _, stderr = tvl("world", "export", WORLDS / "square.txt", "-o", tmp_path / "m.txt")
    assert code == 2
    assert stderr.strip().endswith(
        "m.txt: a map_server map is a .yaml file (its PGM goes beside it)"
    )
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("existing", ["m.yaml", "m.pgm"])
def test_an_existing_map_or_image_is_kept_unless_force(existing: str, tmp_path: Path) -> None:
    (tmp_path / existing).write_text("keep me")
    args = ("world", "export", WORLDS / "square.txt", "-o", tmp_path / "m.yaml")
    code, _, stderr = tvl(*args)
    assert code == 2 and f"{existing}: already exists (use --force to overwrite)" in stderr
    assert (tmp_path / existing).read_text() == "keep me"
    assert sorted(p.name for p in tmp_path.iterdir()) == [existing]
    assert tvl(*args, "--force")[0] == 0
    assert (tmp_path / "m.pgm").read_bytes().startswith(b"P5\n16 16\n255\n")


def test_a_bad_world_is_one_line_and_nothing_is_written(tmp_path: Path) -> None:
    bad = tmp_path / "bad.txt"
    bad.write_text("#####\n#...#\n#####\n")
    code, _, stderr = tvl("world", "export", bad, "-o", tmp_path / "m.yaml")
    assert code == 2 and stderr.splitlines() == [
        f"tvl: error: {bad}: no start (put one of > < ^ v in the map, or a start: line)"
    ]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.txt"]
