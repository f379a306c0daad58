"""`tvl world` through the real command: generated files, JSON, PNG, and every bad world file."""

from __future__ import annotations

import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest
from json_schemas import valid

from tvl_cli.sim import world_budget
from tvl_cli.sim.worldgen import generate_world

ROOT = Path(__file__).resolve().parents[2]
ROOM = "#######\n#.....#\n#..>..#\n#.....#\n#######\n"
RunTvl = Callable[..., subprocess.CompletedProcess[str]]  # the run_tvl and invoke_tvl fixtures
BODY = "(the robot is a disc of radius 0.2 m)"
WALL_USAGE = (
    "(expected x1 y1 x2 y2 [thickness] in metres, ends at least 0.01 m apart, thickness >= 0)"
)

BAD_WORLDS = {  # name -> (file bytes, the error after the file name)
    "unknown character": (
        ROOM.replace("#.....#\n####", "#...x.#\n####").encode(),
        ":4:5: unknown character 'x' (expected one of # . > < ^ v G o)",
    ),
    "unknown header key": (
        ("colour: red\n" + ROOM).encode(),
        ":1:1: unknown header key 'colour' "
        "(expected one of version name cell origin start roughness rough disc ring goal wall)",
    ),
    "bad header value": (
        ("cell: big\n" + ROOM).encode(),
        ":1:7: bad value for 'cell': 'big' (expected a size in metres from 0.01 to 10)",
    ),
    "roughness above 1": (
        ("roughness: 1.5\n" + ROOM).encode(),
        ":1:12: bad value for 'roughness': '1.5' (expected a fraction from 0 (smooth) to 1)",
    ),
    "roughness given twice": (
        ("roughness: 0.1\nroughness: 0.2\n" + ROOM).encode(),
        ":2:1: 'roughness' given twice (first on line 1)",
    ),
    "unsupported version": (
        ("version: 2\n" + ROOM).encode(),
        ":1:10: unsupported version '2' (this tvl reads version 1)",
    ),
    "no start": (
        ROOM.replace(">", ".").encode(),
        ": no start (put one of > < ^ v in the map, or a start: line)",
    ),
    "two starts": (
        ROOM.replace("#.....#\n####", "#.<...#\n####").encode(),
        ":4:3: two starts, at 3:4 and 4:3 (a world has exactly one)",
    ),
    "start inside a wall": (
        ROOM.replace(">", ".").replace("#######\n#..", "###>###\n#..", 1).encode(),
        f":1:4: the start touches the wall at 1:3 {BODY}",
    ),
    "start inside a disc": (
        ("disc: 0.875 0.625 0.3\n" + ROOM).encode(),
        f":4:4: the start overlaps the disc at x 0.875 y 0.625 r 0.3 {BODY}",
    ),
    "start touching a wall": (
        ROOM.replace("#..>..#", "#>....#").encode(),
        f":3:2: the start touches the wall at 3:1 {BODY}",
    ),
    "open boundary": (
        (ROOM[:-8] + "###.###\n").encode(),
        ":5:4: open boundary: the robot can leave the world here (walls must enclose the start)",
    ),
    "cell too small to make a map of": (
        ("cell: 1e-6\n" + ROOM).encode(),
        ":1:7: bad value for 'cell': '1e-6' (expected a size in metres from 0.01 to 10)",
    ),
    "cell of infinite metres": (
        ("cell: 1e309\n" + ROOM).encode(),
        ":1:7: bad value for 'cell': '1e309' (expected a size in metres from 0.01 to 10)",
    ),
    "disc outside the world": (
        ("disc: 50 50 0.2\n" + ROOM).encode(),
        ":1:7: disc at x 50 y 50 r 0.2 is outside the world (the map is 0..1.75 x 0..1.25 m)",
    ),
    "ring wider than the world": (
        ("ring: 1 1 1e300\n" + ROOM).encode(),
        ":1:7: ring at x 1 y 1 r 1e+300 reaches outside the world (the map is 0..1.75 x 0..1.25 m)",
    ),
    "ring outside the world": (
        ("ring: 50 50 2\n" + ROOM).encode(),
        ":1:7: ring at x 50 y 50 r 2 reaches outside the world (the map is 0..1.75 x 0..1.25 m)",
    ),
    "ring of no size": (
        ("ring: 1 1 1e-300\n" + ROOM).encode(),
        ":1:7: bad value for 'ring': '1 1 1e-300' (expected x y r in metres, r >= 0.01)",
    ),
    "wall with three numbers": (
        ("wall: 0.3 0.3 1\n" + ROOM).encode(),
        f":1:7: bad value for 'wall': '0.3 0.3 1' {WALL_USAGE}",
    ),
    "wall with a word for a number": (
        ("; a table edge\nwall:  0.3 0.3 one 0.3\n" + ROOM).encode(),
        f":2:8: bad value for 'wall': '0.3 0.3 one 0.3' {WALL_USAGE}",
    ),
    "wall of no length": (
        ("wall: 0.3 0.3 0.3 0.3\n" + ROOM).encode(),
        f":1:7: bad value for 'wall': '0.3 0.3 0.3 0.3' {WALL_USAGE}",
    ),
    "wall of a millimetre": (
        ("wall: 0.3 0.3 0.301 0.3\n" + ROOM).encode(),
        f":1:7: bad value for 'wall': '0.3 0.3 0.301 0.3' {WALL_USAGE}",
    ),
    "wall of negative thickness": (
        ("wall: 0.3 0.3 1 0.3 -0.1\n" + ROOM).encode(),
        f":1:7: bad value for 'wall': '0.3 0.3 1 0.3 -0.1' {WALL_USAGE}",
    ),
    "wall of infinite thickness": (
        ("wall: 0.3 0.3 1 0.3 inf\n" + ROOM).encode(),
        f":1:7: bad value for 'wall': '0.3 0.3 1 0.3 inf' {WALL_USAGE}",
    ),
    "wall end not a number": (
        ("wall: 0.3 0.3 nan 0.3\n" + ROOM).encode(),
        f":1:7: bad value for 'wall': '0.3 0.3 nan 0.3' {WALL_USAGE}",
    ),
    "wall leaving the world": (
        ("wall: 0.3 0.3 9 0.3\n" + ROOM).encode(),
        ":1:7: wall reaches outside the world (the map is 0..1.75 x 0..1.25 m)",
    ),
    "thick wall whose side pokes out of the world": (
        ("cell: 0.25\nwall: 0.3 0.1 1.4 0.1 0.4\n" + ROOM).encode(),
        ":2:7: wall reaches outside the world (the map is 0..1.75 x 0..1.25 m)",
    ),
    "start touching a header wall": (
        ("wall: 0.5 0.5 1.2 0.5 0.1\n" + ROOM).encode(),
        f":4:4: the start touches the wall at 1:7 {BODY}",
    ),
    "goal inside a thick header wall": (
        ("wall: 0.3 1 1.4 1 0.2\ngoal: 0.5 1\n" + ROOM).encode(),
        ":2:7: goal x 0.5 y 1 is inside a wall or pillar",
    ),
    "empty file": (b"", ": file is empty (a world needs a map of # walls and a start)"),
    "non-UTF-8 file": (
        ROOM.encode().replace(b"#..>", b"#.\xff>"),
        ":3:3: not a text file (byte 0xff is not UTF-8: a binary file, or text in another "
        "encoding)",
    ),
}
# A machine of 1 MiB, of which a world may take half: 4,369 bytes at 120 bytes a cell.
SMALL_MACHINE_BYTES = 1 << 20


def test_a_world_file_longer_than_this_machine_can_simulate_is_refused_unread(
    invoke_tvl: RunTvl, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(world_budget, "machine_bytes", lambda: SMALL_MACHINE_BYTES)
    path = tmp_path / "long.txt"
    path.write_text(ROOM + ";" * 5000)
    done = invoke_tvl("world", "check", path)
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr == (
        f"tvl: error: {path}: file is over 4,369 bytes, more cells than this machine can "
        "simulate (a world may take half its memory, 120 bytes a cell)\n"
    )


def test_a_world_too_large_for_this_machine_is_refused_naming_what_it_needs(
    invoke_tvl: RunTvl, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Short enough to read, but a checkerboard of walls, thousands of segments."""
    monkeypatch.setattr(world_budget, "machine_bytes", lambda: SMALL_MACHINE_BYTES)
    board = ["#" * 52, *("#" + ("#." * 25)[i % 2 : i % 2 + 50] + "#" for i in range(50)), "#" * 52]
    board[1] = "#>" + board[1][2:]
    path = tmp_path / "board.txt"
    path.write_text("\n".join(board))
    assert len(path.read_bytes()) < 4369
    done = invoke_tvl("world", "check", path)
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr.startswith(f"tvl: error: {path}: a world of 2,704 cells and ")
    assert done.stderr.endswith(
        "over the 512 KiB this machine gives a world (half its memory); "
        "use a coarser or smaller map\n"
    )


@pytest.mark.parametrize("case", BAD_WORLDS)
def test_bad_world_file_is_one_error_line_and_exit_2(
    case: str, invoke_tvl: RunTvl, tmp_path: Path
) -> None:
    data, error = BAD_WORLDS[case]
    path = tmp_path / "bad.txt"
    path.write_bytes(data)
    done = invoke_tvl("world", "check", path)
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr == f"tvl: error: {path}{error}\n"


def test_missing_world_file_is_one_error_line_and_exit_2(run_tvl: RunTvl, tmp_path: Path) -> None:
    missing = tmp_path / "none.txt"
    done = run_tvl("world", "show", missing)
    assert done.returncode == 2
    # Neither a file, nor a generated world, nor a bundled one: the three ways to name one.
    assert done.stderr.startswith(
        f"tvl: error: world '{missing}': no such world file {missing}, nor KIND:SEED, nor a "
        "bundled world (square, "
    )
    assert done.stderr.count("\n") == 1


def test_new_writes_the_generated_text_and_nothing_else(invoke_tvl: RunTvl, tmp_path: Path) -> None:
    done = invoke_tvl("world", "new", "corridor", "-o", tmp_path / "c.txt", "--size", "4", "4")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "c.txt").read_text(encoding="utf-8") == generate_world("corridor", 4, 4, 1)
    assert [p.name for p in tmp_path.iterdir()] == ["c.txt"]


def test_new_refuses_an_existing_file_unless_forced(invoke_tvl: RunTvl, tmp_path: Path) -> None:
    path = tmp_path / "lab.txt"
    path.write_text("keep me")
    refused = invoke_tvl("world", "new", "lab", "-o", path, "--seed", "3")
    assert (refused.returncode, path.read_text()) == (2, "keep me")
    assert invoke_tvl("world", "new", "lab", "-o", path, "--seed", "3", "--force").returncode == 0
    assert path.read_text(encoding="utf-8") == generate_world("lab", None, None, 3)


def test_check_reports_ok_with_the_counts(run_tvl: RunTvl) -> None:
    path = ROOT / "worlds" / "obstacles.txt"
    done = run_tvl("world", "check", path)
    assert (done.returncode, done.stdout) == (
        0,
        f"{path}: ok (4 segments, 7 discs, 0 rings, 4 goals)\n",
    )


def test_show_json_has_the_geometry_keys(invoke_tvl: RunTvl) -> None:
    done = invoke_tvl("world", "show", ROOT / "worlds" / "circle.txt", "--json")
    assert done.stdout.count("\n") == 1  # one line, for scripts that grep it
    geometry = valid("world show", done.stdout)["world"]
    assert list(geometry) == [
        "name", "cell_m", "origin_m", "size_m", "segments", "discs", "start", "goals", "rings"
    ]  # fmt: skip
    assert (geometry["origin_m"], geometry["size_m"]) == ([0.0, 0.0], [5.0, 5.0])
    assert geometry["segments"] == [
        [4.75, 0.25, 0.25, 0.25],
        [0.25, 4.75, 4.75, 4.75],
        [0.25, 0.25, 0.25, 4.75],
        [4.75, 4.75, 4.75, 0.25],
    ]
    assert geometry["rings"] == [[2.5, 2.5, 2.0]]


def test_show_prints_a_readable_summary(invoke_tvl: RunTvl) -> None:
    done = invoke_tvl("world", "show", ROOT / "worlds" / "narrow.txt")
    assert "size      6 x 4 m (cell 0.25 m)" in done.stdout.splitlines()
    assert "extent    x 0 to 6, y 0 to 4 m" in done.stdout.splitlines()


def test_show_gives_a_world_in_its_maps_frame(invoke_tvl: RunTvl, tmp_path: Path) -> None:
    path = tmp_path / "moved.txt"
    path.write_text("origin: -10.05 2.5\n" + ROOM)
    lines = invoke_tvl("world", "show", path).stdout.splitlines()
    assert "extent    x -10.05 to -8.3, y 2.5 to 3.75 m" in lines
    assert "start     x -9.175 y 3.125, heading 0°" in lines
    geometry = valid("world show", invoke_tvl("world", "show", path, "--json").stdout)["world"]
    assert geometry["origin_m"] == [-10.05, 2.5] and geometry["start"] == [-9.175, 3.125, 0.0]


def test_render_writes_a_png(invoke_tvl: RunTvl, tmp_path: Path) -> None:
    png = tmp_path / "lab.png"
    done = invoke_tvl("world", "render", ROOT / "worlds" / "lab.txt", "-o", png)
    assert done.returncode == 0, done.stderr
    assert png.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
    assert invoke_tvl("world", "render", ROOT / "worlds" / "lab.txt", "-o", png).returncode == 2


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, starts",
    [
        ("lab.svg", (b"<?xml", b"<svg")),
        ("lab.pdf", (b"%PDF",)),
        ("lab.jpg", (b"\xff\xd8\xff",)),
        ("LAB.JPEG", (b"\xff\xd8\xff",)),
    ],
)
def test_render_writes_the_format_the_extension_names(
    invoke_tvl: RunTvl, tmp_path: Path, name: str, starts: tuple[bytes, ...]
) -> None:
    picture = tmp_path / name
    done = invoke_tvl("world", "render", ROOT / "worlds" / "lab.txt", "-o", picture)
    assert done.returncode == 0, done.stderr
    assert picture.read_bytes().startswith(starts)


@pytest.mark.parametrize(
    "name, problem",
    [
        ("lab.bmp", ".bmp is no picture format tvl writes"),
        ("lab", "no extension names its picture format"),
    ],
)
def test_render_refuses_a_name_that_names_no_picture_format(
    invoke_tvl: RunTvl, tmp_path: Path, name: str, problem: str
) -> None:
    picture = tmp_path / name
    done = invoke_tvl("world", "render", ROOT / "worlds" / "lab.txt", "-o", picture)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert f"{picture}: {problem} (give .png, .svg, .pdf, .jpg, .jpeg)" in done.stderr
    assert not picture.exists()


def test_show_json_lists_header_walls_among_the_segments(
    invoke_tvl: RunTvl, tmp_path: Path
) -> None:
    path = tmp_path / "walls.txt"
    path.write_text("wall: 0.3 0.3 0.6 0.9\nwall: 1.2 0.3 1.2 0.9 0.1\n" + ROOM, encoding="utf-8")
    geometry = valid("world show", invoke_tvl("world", "show", path, "--json").stdout)["world"]
    assert len(geometry["segments"]) == 4 + 1 + 4  # the room, the thin wall, the thick one
    assert geometry["segments"][4] == [0.3, 0.3, 0.6, 0.9]
    thick_xs = {round(x, 9) for segment in geometry["segments"][5:] for x in segment[::2]}
    assert thick_xs == {1.15, 1.25}
    summary = invoke_tvl("world", "show", path).stdout.splitlines()
    assert "walls     9 segments, 0 rings" in summary


def test_new_rooms_writes_the_seeded_world_that_check_accepts(
    invoke_tvl: RunTvl, tmp_path: Path
) -> None:
    path = tmp_path / "rooms.txt"
    done = invoke_tvl("world", "new", "rooms", "--seed", "1003", "-o", path)
    assert done.returncode == 0, done.stderr
    assert path.read_text(encoding="utf-8") == generate_world("rooms", None, None, 1003)
    checked = invoke_tvl("world", "check", path)
    assert (checked.returncode, checked.stdout.startswith(f"{path}: ok (")) == (0, True)


@pytest.mark.parametrize("given", ["abc", "0", "-5", "1.5"])
def test_a_memory_given_that_is_no_whole_number_of_mib_is_one_line(
    invoke_tvl: RunTvl, monkeypatch: pytest.MonkeyPatch, given: str
) -> None:
    monkeypatch.setenv("TVL_MEMORY_MIB", given)
    done = invoke_tvl("world", "check", ROOT / "worlds" / "lab.txt")
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr == f"tvl: error: TVL_MEMORY_MIB={given!r}: expected a whole number of MiB\n"


def test_a_world_of_more_walls_than_its_physics_starts_from_in_seconds_is_refused(
    invoke_tvl: RunTvl, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(world_budget, "MAX_SEGMENTS", 100)
    board = ["#" * 52, *("#" + ("#." * 25)[i % 2 : i % 2 + 50] + "#" for i in range(50)), "#" * 52]
    board[1] = "#>" + board[1][2:]
    path = tmp_path / "board.txt"
    path.write_text("\n".join(board))
    done = invoke_tvl("world", "check", path)
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr.startswith(f"tvl: error: {path}: a world of ")
    assert done.stderr.endswith(
        " wall segments, over the 100 whose physics starts in seconds; use a coarser or "
        "smaller map\n"
    )
