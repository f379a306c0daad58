"""`tvl world import`: ROS map_server occupancy grids, written as map_saver writes them, become
worlds that `tvl world check` accepts and a robot learns in; every bad map is one line."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from json_schemas import valid
from map_samples import (
    BLOCK_LEFT,
    BLOCK_SIZE,
    BLOCK_TOP,
    FREE,
    OCCUPIED,
    ROOM_COLUMNS,
    ROOM_LEFT,
    ROOM_ROWS,
    ROOM_TOP,
    ROS1_FREE_THRESH,
    UNKNOWN,
    map_frame_of_pixel,
    pgm_bytes,
    room_pixels,
    write_map,
)

from tvl_cli.cli.main import main
from tvl_cli.io import occupancy_map
from tvl_cli.io.logreader import read_log
from tvl_cli.sim import world_budget
from tvl_cli.sim.worldmap import layout, load_world

START_PIXEL = (12, 12)  # row, column: 0.275 m and more from every wall
MAX_PIXELS = 1 << 24
START = "{:g},{:g},90".format(*map_frame_of_pixel(*START_PIXEL))


def read_map(path: Path) -> occupancy_map.OccupancyMap:
    return occupancy_map.read_occupancy_map(path, MAX_PIXELS)


def tvl(*args: object) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, [str(a) for a in args])
    return done.exit_code, done.stdout, done.stderr


def imported(yaml_path: Path, *options: object) -> Path:
    """Import the map into world.txt beside it; the world's path."""
    world = yaml_path.parent / "world.txt"
    code, _, stderr = tvl("world", "import", yaml_path, "-o", world, "--start", START, *options)
    assert code == 0, stderr
    return world


def expected_room_grid() -> list[str]:
    """The room's world, its walls' outer box: walls, free floor and the block."""
    grid = np.full((ROOM_ROWS, ROOM_COLUMNS), ".")
    grid[[0, -1], :] = "#"
    grid[:, [0, -1]] = "#"
    top, left = BLOCK_TOP - ROOM_TOP, BLOCK_LEFT - ROOM_LEFT
    grid[top : top + BLOCK_SIZE, left : left + BLOCK_SIZE] = "#"
    return ["".join(row) for row in grid]


# The room's walls' outer box in the map's frame: its bottom-left corner.
ROOM_ORIGIN = (-0.7, -1.75)


def test_a_map_saver_map_becomes_its_walls_free_floor_and_start(tmp_path: Path) -> None:
    world = load_world(imported(write_map(tmp_path, free_thresh=ROS1_FREE_THRESH)))
    assert list(layout(world)[0]) == expected_room_grid()
    assert (world.width_m, world.height_m, world.cell_m) == (2.0, 1.5, 0.05)
    assert (
        world.origin_m
        == ROOM_ORIGIN
        == (
            -1.0 + ROOM_LEFT * 0.05,
            -2.0 + (40 - ROOM_TOP - ROOM_ROWS) * 0.05,
        )
    )
    # The start is where it was asked for, in the map's frame, which is the world's.
    assert world.start == (*map_frame_of_pixel(*START_PIXEL), math.pi / 2)
    # The room's outline and the block's: four walls each, on the map's pixel edges.
    assert len(world.segments) == 8
    assert (1.25, -1.7, -0.65, -1.7) in world.segments  # the floor's bottom edge


def test_json_gives_the_extent_the_free_cells_and_the_map_frame(tmp_path: Path) -> None:
    map_yaml = write_map(tmp_path, free_thresh=ROS1_FREE_THRESH)
    world = tmp_path / "world.txt"
    code, stdout, _ = tvl("world", "import", map_yaml, "-o", world, "--start", START, "--json")
    assert code == 0
    found = valid("world import", stdout)
    assert found["inputs"]["start"] == [float(v) for v in START.split(",")]
    assert found["inputs"]["image"]["path"] == str(map_yaml.with_suffix(".pgm"))
    assert found["outputs"] == {"world": str(world)}
    assert (found["columns"], found["rows"], found["cell_m"]) == (40, 30, 0.05)
    assert found["free_cells"] == int((room_pixels() == FREE).sum()) == 38 * 28 - 16
    assert found["origin_m"] == list(ROOM_ORIGIN)
    assert found["start"] == [-0.375, -0.625, 90.0]  # the map's frame, as given
    assert found["start_chosen"] is False and found["narrow_passages"] == []
    assert "origin: -0.7 -1.75\nstart: -0.375 -0.625 90.0\n" in world.read_text()


def test_the_world_passes_world_check(tmp_path: Path) -> None:
    world = imported(write_map(tmp_path, free_thresh=ROS1_FREE_THRESH))
    code, stdout, _ = tvl("world", "check", world)
    assert code == 0 and "ok (8 segments, 0 discs, 0 rings, 0 goals)" in stdout


def test_nav2s_free_thresh_reads_unknown_grey_as_free_as_map_server_does(tmp_path: Path) -> None:
    """(255 - 205) / 255 = 0.196 < 0.25: map_server serves map_saver's unknown as free, and
    so does the import, saying so. The floor then reaches the image's edge, walled past it."""
    world_path = tmp_path / "world.txt"
    code, _, stderr = tvl(
        "world", "import", write_map(tmp_path), "-o", world_path, "--start", START
    )
    assert code == 0
    assert stderr.splitlines() == [
        f"tvl: warning: {tmp_path / 'room.yaml'}: 800 cells of grey 205 (map_saver's "
        "unknown) are free under free_thresh 0.25, as map_server reads them; "
        "free_thresh 0.196 keeps them unknown"
    ]
    world = load_world(world_path)
    rows = layout(world)[0]
    assert (len(rows), len(rows[0])) == (40 + 2, 50 + 2)
    assert set(rows[0]) == set(rows[-1]) == {"#"} and rows[1] == "#" + "." * 50 + "#"


def test_negate_reads_dark_as_free(tmp_path: Path) -> None:
    plain = load_world(imported(write_map(tmp_path, free_thresh=ROS1_FREE_THRESH)))
    negated_dir = tmp_path / "negated"
    negated_dir.mkdir()
    inverted = 255 - room_pixels()
    negated = write_map(negated_dir, inverted, free_thresh=ROS1_FREE_THRESH, negate=1)
    assert layout(load_world(imported(negated)))[0] == layout(plain)[0]


def test_a_png_map_reads_as_its_pgm(tmp_path: Path) -> None:
    from PIL import Image

    plain = load_world(imported(write_map(tmp_path, free_thresh=ROS1_FREE_THRESH)))
    png_dir = tmp_path / "png"
    png_dir.mkdir()
    Image.fromarray(room_pixels(), mode="L").save(png_dir / "room.png")
    png_yaml = write_map(png_dir, free_thresh=ROS1_FREE_THRESH, image="room.png")
    assert layout(load_world(imported(png_yaml)))[0] == layout(plain)[0]


def test_a_png_with_alpha_averages_its_opacity_in_as_map_server_does(tmp_path: Path) -> None:
    """Trinary mode: an opaque grey 205 pixel reads (3 * 205 + 255) / 4 = 217.5, p = 0.147, free
    under 0.196; scale mode leaves opacity out and reads every transparent pixel unknown."""
    from PIL import Image

    grey = room_pixels()
    rgba = np.dstack([grey, grey, grey, np.full_like(grey, 255)])
    rgba[0, 0, 3] = 0  # one transparent corner pixel
    Image.fromarray(rgba, mode="RGBA").save(tmp_path / "room.png")
    trinary = read_map(write_map(tmp_path, free_thresh=ROS1_FREE_THRESH, image="room.png"))
    opaque_grey = (grey == UNKNOWN) & (rgba[..., 3] == 255)
    assert trinary.free[opaque_grey].all() and trinary.occupied[grey == OCCUPIED].all()
    assert trinary.unknown[0, 0]  # (3 * 205 + 0) / 4: p = 0.397, between the thresholds
    scale = read_map(
        write_map(tmp_path, free_thresh=ROS1_FREE_THRESH, image="room.png", mode="scale")
    )
    assert not scale.free[grey == UNKNOWN].any() and scale.unknown[0, 0]
    assert scale.free[grey == FREE].all()


def test_raw_mode_reads_pixel_values_as_percent_occupancy(tmp_path: Path) -> None:
    pixels = np.array([[0, 10, 50, 70, 100, 101, 255]], dtype=np.uint8)
    read = read_map(write_map(tmp_path, pixels, mode="raw"))
    assert read.free.tolist() == [[True, True, False, False, False, False, False]]
    assert read.occupied.tolist() == [[False, False, False, True, True, False, False]]


def test_a_sixteen_bit_pgm_is_read_at_its_maxval(tmp_path: Path) -> None:
    pixels = room_pixels().astype(">u2") * 257  # the same shades, on 0..65535
    image = tmp_path / "room.pgm"
    write_map(tmp_path, free_thresh=ROS1_FREE_THRESH)
    image.write_bytes(b"P5 50 40 65535\n" + pixels.tobytes())
    read = read_map(tmp_path / "room.yaml")
    assert np.array_equal(read.free, room_pixels() == FREE)


def test_the_same_map_imports_to_the_same_bytes(tmp_path: Path) -> None:
    map_yaml = write_map(tmp_path)
    first, second = tmp_path / "a.txt", tmp_path / "b.txt"
    for out in (first, second):
        assert tvl("world", "import", map_yaml, "-o", out, "--start", START)[0] == 0
    assert first.read_bytes() == second.read_bytes()


def test_name_names_the_world(tmp_path: Path) -> None:
    world = imported(write_map(tmp_path), "--name", "lab floor 2")
    assert load_world(world).name == "lab floor 2"


def test_a_robot_learns_in_the_imported_world(tmp_path: Path) -> None:
    world_path = imported(write_map(tmp_path, free_thresh=ROS1_FREE_THRESH))
    log = tmp_path / "log.h5"
    code, _, stderr = tvl("learn", world_path, "--log", log, "--minutes", "0.5")
    assert code == 0, stderr
    (session,) = read_log(log).sessions
    assert session.exemplar_count > 0 and session.world_name == "room"
    # Every pose on the room's floor, clear of its outer walls, in the map's frame.
    world = load_world(world_path)
    x, y = session.pose[:, 0] - ROOM_ORIGIN[0], session.pose[:, 1] - ROOM_ORIGIN[1]
    assert (x > 0.05).all() and (x < world.width_m - 0.05).all()
    assert (y > 0.05).all() and (y < world.height_m - 0.05).all()


def _bad_yaml(tmp_path: Path, **changes: object) -> Path:
    return write_map(tmp_path, **changes)


def _yaml_text(tmp_path: Path, text: str) -> Path:
    write_map(tmp_path)
    (tmp_path / "room.yaml").write_text(text)
    return tmp_path / "room.yaml"


def _image_bytes(tmp_path: Path, data: bytes) -> Path:
    path = write_map(tmp_path)
    (tmp_path / "room.pgm").write_bytes(data)
    return path


BAD_MAPS = {  # name -> (make the map in a directory, what the one line says)
    "no resolution": (
        lambda d: _bad_yaml(d, resolution=None),
        "room.yaml: no 'resolution' (a map_server map gives image, resolution, origin, "
        "negate, occupied_thresh, free_thresh)",
    ),
    "resolution not a number": (
        lambda d: _bad_yaml(d, resolution="abc"),
        "room.yaml: 'resolution' holds 'abc', not a number",
    ),
    "threshold not a number": (
        lambda d: _bad_yaml(d, occupied_thresh="true"),
        "room.yaml: 'occupied_thresh' holds True, not a number",
    ),
    "resolution too large to be a number": (
        lambda d: _bad_yaml(d, resolution="1" + "0" * 400),
        "room.yaml: 'resolution' holds 1000",
    ),
    "infinite origin": (
        lambda d: _bad_yaml(d, origin="[.inf, 0, 0]"),
        "room.yaml: 'origin' holds inf, not a finite number",
    ),
    "origin of two numbers": (
        lambda d: _bad_yaml(d, origin="[0, 0]"),
        "room.yaml: 'origin' is [0, 0], not [x, y, yaw]",
    ),
    "origin turned": (
        lambda d: _bad_yaml(d, origin="[0, 0, 0.5]"),
        "room.yaml: origin yaw is 0.5 rad; a world's walls run along its axes, so only a "
        "map with yaw 0 can be imported",
    ),
    "thresholds out of order": (
        lambda d: _bad_yaml(d, free_thresh=0.7),
        "room.yaml: free_thresh 0.7 and occupied_thresh 0.65 are not in order "
        "(0 <= free_thresh < occupied_thresh <= 1)",
    ),
    "threshold above 1": (
        lambda d: _bad_yaml(d, occupied_thresh=1.5),
        "room.yaml: free_thresh 0.25 and occupied_thresh 1.5 are not in order",
    ),
    "negate 2": (lambda d: _bad_yaml(d, negate=2), "room.yaml: 'negate' is 2, not 0 or 1"),
    "unknown mode": (
        lambda d: _bad_yaml(d, mode="fancy"),
        "room.yaml: 'mode' is 'fancy', not one of trinary, scale, raw",
    ),
    "resolution finer than a world's cell": (
        lambda d: _bad_yaml(d, resolution=0.005),
        "room.yaml: resolution 0.005 m is outside a world's cell sizes (0.01 to 10 m)",
    ),
    "zero resolution": (
        lambda d: _bad_yaml(d, resolution=0),
        "room.yaml: 'resolution' is 0, not a size in metres above 0",
    ),
    "not YAML": (
        lambda d: _yaml_text(d, "image: room.pgm\nresolution: [0.05\n"),
        "room.yaml:3:1: not valid YAML",
    ),
    "a list, not keys": (
        lambda d: _yaml_text(d, "- image\n- resolution\n"),
        "room.yaml: not a map_server map (expected image, resolution, origin, negate, "
        "occupied_thresh, free_thresh)",
    ),
    "yaml too big": (
        lambda d: _yaml_text(d, "# " + "x" * 70_000 + "\n"),
        "room.yaml: file is over 65,536 bytes (a map's YAML is a few lines)",
    ),
    "image missing": (
        lambda d: _bad_yaml(d, image="gone.pgm"),
        "gone.pgm: no such file",
    ),
    "image corrupt": (
        lambda d: _image_bytes(d, b"hello, not an image"),
        "room.pgm: not a PGM image (it does not start with P5 or P2)",
    ),
    "image smaller than it says": (
        lambda d: _image_bytes(d, pgm_bytes(room_pixels())[:-50]),
        "room.pgm: holds 1,950 bytes of pixels, not the 2,000 its header's 50 x 40 needs",
    ),
    "image larger than it says": (
        lambda d: _image_bytes(d, pgm_bytes(room_pixels()) + b"\0" * 10),
        "room.pgm: holds 2,010 bytes of pixels, not the 2,000 its header's 50 x 40 needs",
    ),
    "image of too many pixels": (
        lambda d: _image_bytes(d, b"P5\n100000 100000\n255\n" + b"\0" * 100),
        "room.pgm: image is 100000 x 100000 pixels, over the ",
    ),
    "plain image with a word": (
        lambda d: _image_bytes(d, b"P2\n2 1\n255\n254 free\n"),
        "room.pgm: P2 pixels hold something that is not a whole number",
    ),
    "pixel above maxval": (
        lambda d: _image_bytes(d, b"P2\n2 1\n100\n99 101\n"),
        "room.pgm: a pixel is 101, above the maxval 100",
    ),
    "truncated png": (
        lambda d: _truncated_png(d),
        "room.png: not a readable PNG image",
    ),
    "no free cell": (
        lambda d: write_map(d, np.full((4, 4), OCCUPIED, dtype=np.uint8)),
        "room.yaml: the map has no free cell (under its free_thresh)",
    ),
}


def _truncated_png(directory: Path) -> Path:
    from PIL import Image

    Image.fromarray(np.random.default_rng(1).integers(0, 255, (40, 50), dtype=np.uint8)).save(
        directory / "room.png"
    )
    data = (directory / "room.png").read_bytes()
    (directory / "room.png").write_bytes(data[: len(data) // 2])
    return write_map(directory, image="room.png")


@pytest.mark.parametrize("case", sorted(BAD_MAPS))
def test_a_bad_map_is_one_line_naming_the_file_and_nothing_is_written(
    case: str, tmp_path: Path
) -> None:
    make, message = BAD_MAPS[case]
    map_yaml = make(tmp_path)
    world = tmp_path / "world.txt"
    code, stdout, stderr = tvl("world", "import", map_yaml, "-o", world, "--start", START)
    assert code == 2 and stdout == ""
    (line,) = stderr.splitlines()
    assert line.startswith("tvl: error: ") and message in line, line
    assert not world.exists()


def test_an_image_file_over_what_the_machine_can_read_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Half of 128 KiB at 64 bytes a pixel: 1,024 pixels, and 4 bytes each of file.
    monkeypatch.setattr(world_budget, "machine_bytes", lambda: 128 * 1024)
    code, _, stderr = tvl(
        "world", "import", write_map(tmp_path), "-o", tmp_path / "w.txt", "--start", START
    )
    assert code == 2
    assert "room.pgm: image is 50 x 40 pixels, over the 1,024 this machine can read" in stderr
    assert not (tmp_path / "w.txt").exists()


BAD_STARTS = {  # --start -> what the one line says
    "1,2": "--start '1,2': expected X,Y,HEADING_DEG, e.g. 1.5,2.0,90",
    "a,b,c": "--start 'a,b,c': expected X,Y,HEADING_DEG",
    "nan,0,0": "--start 'nan,0,0': expected X,Y,HEADING_DEG",
    "5,5,0": "--start 5,5,0: x 5 y 5 is not on the map's free floor",
    "-0.65,-0.5,0": "--start -0.65,-0.5,0: x -0.65 y -0.5 is not on the map's free floor",
    "-0.6,-0.5,0": "--start -0.6,-0.5,0: the robot (a disc of radius 0.2 m) would touch the "
    "wall cell at x -0.675 y -0.475; the widest free place is x -0.075 y -0.875 "
    "(--start -0.075,-0.875,0)",
    "1e308,1e308,0": "--start 1e+308,1e+308,0: x 1e+308 y 1e+308 is not on the map's free "
    "floor; the widest free place is x -0.075 y -0.875",
    "0,0,400": "--start '0,0,400': heading 400° is beyond a turn (from -360 to 360)",
}


@pytest.mark.parametrize("start", sorted(BAD_STARTS))
def test_a_start_off_the_floor_is_one_line(start: str, tmp_path: Path) -> None:
    world = tmp_path / "world.txt"
    map_yaml = write_map(tmp_path, free_thresh=ROS1_FREE_THRESH)
    code, _, stderr = tvl("world", "import", map_yaml, "-o", world, "--start", start)
    assert code == 2
    (line,) = stderr.splitlines()
    assert BAD_STARTS[start] in line, line
    assert not world.exists()


def test_an_existing_world_is_kept_unless_force(tmp_path: Path) -> None:
    map_yaml = write_map(tmp_path)
    world = tmp_path / "world.txt"
    world.write_text("keep me")
    code, _, stderr = tvl("world", "import", map_yaml, "-o", world, "--start", START)
    assert code == 2 and "world.txt: already exists (use --force to overwrite)" in stderr
    assert world.read_text() == "keep me"
    assert tvl("world", "import", map_yaml, "-o", world, "--start", START, "--force")[0] == 0
    assert load_world(world).name == "room"


def test_a_name_of_two_lines_is_refused(tmp_path: Path) -> None:
    code, _, stderr = tvl(
        "world", "import", write_map(tmp_path), "-o", tmp_path / "w.txt", "--start", START,
        "--name", "a\nb",
    )  # fmt: skip
    assert code == 2 and "--name 'a\\nb': a world's name is one line of text" in stderr
