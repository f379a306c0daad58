"""`tvl world import` with no option but the map: the start chosen, any heading, cells
coarsened and the map cropped, passages narrower than the robot named, the map's own files
never overwritten, and a world too large for the machine refused naming what makes it fit."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from json_schemas import valid
from map_samples import FREE, OCCUPIED, ROS1_FREE_THRESH, UNKNOWN, write_map

from tvl_cli.sim import world_budget
from tvl_cli.sim.worldmap import layout, load_world

# A map at 5 cm: a large room (3.0 x 2.0 m inside) left of a small one (0.8 x 1.0 m), one
# wall between them, with a doorway 0.25 m wide: narrower than the robot's 0.4 m.
ROWS, COLUMNS = 60, 100
ORIGIN = (-10.0, -10.0, 0.0)  # as Nav2's maps have it: the map's frame lies off the image


def two_rooms(door_pixels: int = 5) -> np.ndarray:
    pixels = np.full((ROWS, COLUMNS), UNKNOWN, dtype=np.uint8)
    pixels[10:52, 10:89] = OCCUPIED
    pixels[11:51, 11:71] = FREE  # the large room: 40 rows x 60 columns
    pixels[31:51, 72:88] = FREE  # the small one: 20 x 16, the wall column 71 between
    pixels[31 + 7 : 31 + 7 + door_pixels, 71] = FREE  # the doorway in it
    return pixels


def pixel_centre(row: int, column: int) -> tuple[float, float]:
    return ORIGIN[0] + (column + 0.5) * 0.05, ORIGIN[1] + (ROWS - row - 0.5) * 0.05


def rooms_map(directory: Path, pixels: np.ndarray | None = None) -> Path:
    origin = "[{:g}, {:g}, {:g}]".format(*ORIGIN)
    pixels = two_rooms() if pixels is None else pixels
    return write_map(directory, pixels, free_thresh=ROS1_FREE_THRESH, origin=origin)


def test_with_no_start_the_robot_starts_at_the_widest_place_of_the_largest_room(
    invoke_tvl, tmp_path: Path
) -> None:
    world_path = tmp_path / "w.txt"
    done = invoke_tvl("world", "import", rooms_map(tmp_path), "-o", world_path, "--json")
    assert done.returncode == 0, done.stderr
    found = valid("world import", done.stdout)
    # The large room spans rows 11..50 and columns 11..70 of the image: the places 1 m from
    # its top, bottom and left walls are equally wide along its middle; the first of them in
    # reading order is pixel (30, 30).
    x, y = pixel_centre(30, 30)
    assert found["start"] == [x, y, 0.0] and found["start_chosen"] is True
    world = load_world(world_path)
    assert world.start == (x, y, 0.0)
    assert found["inputs"]["start"] is None


def test_the_chosen_start_is_printed(invoke_tvl, tmp_path: Path) -> None:
    done = invoke_tvl("world", "import", rooms_map(tmp_path), "-o", tmp_path / "w.txt")
    assert done.returncode == 0
    assert "start x -8.475 y -8.525 heading 0° (the widest free place, 0.97 m clear)" in (
        done.stdout
    )
    assert "origin x -9.5 y -9.6 (the map's frame)" in done.stdout


def test_a_start_may_face_any_way(invoke_tvl, tmp_path: Path) -> None:
    world_path = tmp_path / "w.txt"
    done = invoke_tvl(
        "world", "import", rooms_map(tmp_path), "-o", world_path, "--start", "-8,-8.5,-30"
    )
    assert done.returncode == 0, done.stderr
    assert load_world(world_path).start == (-8.0, -8.5, math.radians(-30))


def test_a_passage_narrower_than_the_robot_is_named(invoke_tvl, tmp_path: Path) -> None:
    world_path = tmp_path / "w.txt"
    done = invoke_tvl("world", "import", rooms_map(tmp_path), "-o", world_path, "--json")
    assert done.returncode == 0
    (passage,) = valid("world import", done.stdout)["narrow_passages"]
    # The doorway: five pixels of the wall column 71, rows 38 to 42; its middle is narrowest.
    assert passage["width_m"] == 0.25
    assert (passage["x_m"], passage["y_m"]) == pixel_centre(40, 71)
    assert passage["beyond_m2"] > 0.1  # the small room, where the body fits
    (warning,) = done.stderr.splitlines()
    assert warning == (
        f"tvl: warning: {tmp_path / 'room.yaml'}: 1 passage narrower than the robot (0.4 m "
        f"across) leads to floor it fits on but cannot reach; the narrowest is 0.25 m wide at "
        f"x -6.425 y -9.025, with {passage['beyond_m2']:.3g} m² beyond it"
    )


def test_a_doorway_the_robot_fits_through_is_no_warning(invoke_tvl, tmp_path: Path) -> None:
    done = invoke_tvl(
        "world", "import", rooms_map(tmp_path, two_rooms(door_pixels=12)), "-o",
        tmp_path / "w.txt", "--json",
    )  # fmt: skip
    assert done.returncode == 0 and done.stderr == ""
    assert valid("world import", done.stdout)["narrow_passages"] == []


def test_coarser_cells_keep_every_wall(invoke_tvl, tmp_path: Path) -> None:
    """At 0.15 m a cell covers three pixels a side: the one-pixel wall between the rooms,
    and the doorway narrower than a cell, stay shut."""
    world_path = tmp_path / "w.txt"
    done = invoke_tvl(
        "world", "import", rooms_map(tmp_path), "-o", world_path, "--cell", "0.15", "--json"
    )
    assert done.returncode == 0, done.stderr
    world = load_world(world_path)
    assert world.cell_m == 0.15
    rows = layout(world)[0]
    # The grid starts at the image's bottom-left corner, whole cells of three pixels.
    assert world.origin_m[0] == pytest.approx(-10.0 + 3 * 0.15)
    assert all(row[0] == "#" and row[-1] == "#" for row in rows)
    assert valid("world import", done.stdout)["inputs"]["cell_m"] == 0.15
    # No free cell where the image has any pixel not free: the floor is within the rooms.
    assert sum(row.count(".") for row in rows) <= (40 // 3) * (60 // 3) + (20 // 3) * (11 // 3)


def test_cells_finer_than_the_map_are_refused(invoke_tvl, tmp_path: Path) -> None:
    done = invoke_tvl(
        "world", "import", rooms_map(tmp_path), "-o", tmp_path / "w", "--cell", "0.01"
    )
    assert done.returncode == 2
    assert done.stderr == (
        "tvl: error: --cell 0.01: cells are from the map's resolution, 0.05 m, to 10 m\n"
    )


def test_a_crop_keeps_the_rectangle_asked_for(invoke_tvl, tmp_path: Path) -> None:
    """The large room's left half alone."""
    world_path = tmp_path / "w.txt"
    done = invoke_tvl(
        "world", "import", rooms_map(tmp_path), "-o", world_path, "--crop", "-9.5,-9.5,-8,-7.5"
    )
    assert done.returncode == 0, done.stderr
    world = load_world(world_path)
    assert world.origin_m[0] >= -9.55 and world.origin_m[0] + world.width_m <= -7.95
    assert world.origin_m[1] + world.height_m <= -7.45


@pytest.mark.parametrize(
    ("crop", "error"),
    [
        ("1,2,3", "--crop '1,2,3': expected X0,Y0,X1,Y1 with X0 < X1, Y0 < Y1, metres"),
        ("2,0,1,1", "--crop '2,0,1,1': expected X0,Y0,X1,Y1"),
        ("50,50,60,60", "--crop 50,50,60,60: holds no cell of the map (the map is x -10..-5 "),
    ],
)
def test_a_bad_crop_is_one_line(invoke_tvl, tmp_path: Path, crop: str, error: str) -> None:
    done = invoke_tvl("world", "import", rooms_map(tmp_path), "-o", tmp_path / "w", "--crop", crop)
    assert done.returncode == 2 and done.stderr.startswith(f"tvl: error: {error}")


def test_a_map_of_no_room_wide_enough_is_refused_saying_how_wide(invoke_tvl, tmp_path) -> None:
    pixels = np.full((20, 20), OCCUPIED, dtype=np.uint8)
    pixels[5:15, 8:12] = FREE  # 0.2 m wide
    done = invoke_tvl("world", "import", rooms_map(tmp_path, pixels), "-o", tmp_path / "w")
    assert done.returncode == 2
    assert done.stderr == (
        f"tvl: error: {tmp_path / 'room.yaml'}: no free place is wide enough for the robot "
        "(a disc of radius 0.2 m); the widest clearance is 0.075 m\n"
    )


@pytest.mark.parametrize("which", ["room.pgm", "room.yaml"])
@pytest.mark.parametrize("how", ["same path", "hard link", "symbolic link"])
def test_an_output_that_is_one_of_the_maps_files_is_refused_and_left_whole(
    invoke_tvl, tmp_path: Path, which: str, how: str
) -> None:
    map_yaml = rooms_map(tmp_path)
    target = tmp_path / which
    before = target.read_bytes()
    output = target
    if how != "same path":
        output = tmp_path / "elsewhere" / "out.txt"
        output.parent.mkdir()
        (os.link if how == "hard link" else os.symlink)(target, output)
    done = invoke_tvl("world", "import", map_yaml, "-o", output, "--force")
    assert done.returncode == 2 and done.stdout == ""
    (line,) = done.stderr.splitlines()
    assert line.startswith(f"tvl: error: {output}: ")
    assert target.read_bytes() == before


def test_a_world_too_large_for_the_machine_is_refused_and_fits_coarser(
    invoke_tvl, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """On a machine of 2 MiB (1 MiB for a world), a hall of 100 x 100 cells at 5 cm (1.2 MB
    at 120 bytes a cell) is too large, though its image (640 kB at 64 bytes a pixel) is
    read; at 30 cm it fits."""
    monkeypatch.setattr(world_budget, "machine_bytes", lambda: 2 << 20)
    hall = np.full((100, 100), FREE, dtype=np.uint8)
    hall[[0, -1], :] = hall[:, [0, -1]] = OCCUPIED
    map_yaml = rooms_map(tmp_path, hall)
    done = invoke_tvl("world", "import", map_yaml, "-o", tmp_path / "w.txt")
    assert done.returncode == 2
    assert done.stderr.startswith(f"tvl: error: {map_yaml}: its free floor spans 100 x 100 cells: ")
    assert done.stderr.endswith("; coarsen it (--cell) or crop it (--crop)\n")
    assert not (tmp_path / "w.txt").exists()
    coarse = invoke_tvl("world", "import", map_yaml, "-o", tmp_path / "w.txt", "--cell", "0.3")
    assert coarse.returncode == 0, coarse.stderr
