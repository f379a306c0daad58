"""Text map -> WorldMap: geometry, enclosure and the errors that name line and column."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from tvl_cli.sim.worldmap import WorldMapError, load_world, parse_world

ROOM = """\
######
#....#
#.>..#
#....#
######
"""

L_ROOM = """\
#######
#.....#
#.>...#
#.....####
#........#
#........#
##########
"""


def test_rectangular_room_compiles_to_four_segments() -> None:
    world = parse_world(ROOM, "room.txt")
    assert sorted(world.segments) == sorted(
        [
            (1.25, 0.25, 0.25, 0.25),  # bottom wall, running -x
            (0.25, 1.0, 1.25, 1.0),  # top wall, running +x
            (0.25, 0.25, 0.25, 1.0),  # left wall, running +y
            (1.25, 1.0, 1.25, 0.25),  # right wall, running -y
        ]
    )


def test_l_shaped_room_compiles_to_six_segments() -> None:
    assert len(parse_world(L_ROOM, "l.txt").segments) == 6


def test_free_standing_one_cell_wall_adds_its_outline() -> None:
    text = "#########\n#.......#\n#.>.....#\n#.......#\n#...###.#\n#.......#\n#########\n"
    segments = parse_world(text, "bar.txt").segments
    assert len(segments) == 4 + 4
    assert (1.0, 0.5, 1.75, 0.5) in segments  # underside of the bar, wall on its left (above)


def test_segments_keep_the_wall_on_their_left() -> None:
    world = parse_world(L_ROOM, "l.txt")
    rows = L_ROOM.splitlines()
    for x1, y1, x2, y2 in world.segments:
        length = math.hypot(x2 - x1, y2 - y1)
        # a point just left of the segment's middle
        px = (x1 + x2) / 2 - 0.01 * (y2 - y1) / length
        py = (y1 + y2) / 2 + 0.01 * (x2 - x1) / length
        row = rows[len(rows) - 1 - int(py / world.cell_m)]
        assert row[int(px / world.cell_m)] == "#"


def test_origin_is_bottom_left_with_the_last_line_at_y_zero() -> None:
    text = "#####\n#...#\n#...#\n#.>.#\n#...#\n#..G#\n#####\n"
    world = parse_world(text, "o.txt")
    assert world.start == (0.625, 0.875, 0.0)
    assert world.goals == ((0.875, 0.375),)
    assert (world.width_m, world.height_m) == (1.25, 1.75)


@pytest.mark.parametrize(
    ("char", "heading"), [(">", 0.0), ("<", math.pi), ("^", math.pi / 2), ("v", -math.pi / 2)]
)
def test_start_character_sets_the_heading(char: str, heading: float) -> None:
    assert parse_world(ROOM.replace(">", char), "h.txt").start[2] == heading


def test_header_sets_name_cell_and_goals() -> None:
    world = parse_world(
        "; a comment\nversion: 1\nname: tiny\ncell: 0.5\ngoal: 1.2 1.3\n" + ROOM, "r.txt"
    )
    assert (world.name, world.cell_m, world.width_m) == ("tiny", 0.5, 3.0)
    assert world.goals == ((1.2, 1.3),)


def test_walls_are_smooth_unless_the_header_gives_a_roughness() -> None:
    assert parse_world(ROOM, "r.txt").roughness == 0.0
    assert parse_world("roughness: 0.25\n" + ROOM, "r.txt").roughness == 0.25


def test_name_defaults_to_the_file_stem() -> None:
    assert parse_world(ROOM, "worlds/my-room.txt").name == "my-room"


def test_disc_directive_makes_one_disc() -> None:
    world = parse_world("disc: 1.0 0.6 0.15\n" + ROOM, "d.txt")
    assert world.discs == ((1.0, 0.6, 0.15),)


def test_pillar_character_is_a_disc_filling_its_cell() -> None:
    text = "########\n#......#\n#.>....#\n#......#\n#....o.#\n########\n"
    assert parse_world(text, "p.txt").discs == ((1.375, 0.375, 0.125),)


RING_ONLY = """\
ring: 1.5 1.5 1.2
............
............
............
............
............
.....>......
............
............
............
............
............
............
"""


def test_ring_encloses_a_start_inside_it_without_any_border() -> None:
    world = parse_world(RING_ONLY, "ring.txt")
    assert world.rings == ((1.5, 1.5, 1.2),)
    assert world.segments == ()


def test_start_outside_a_ring_with_no_border_is_an_open_boundary() -> None:
    outside = RING_ONLY.replace(".....>......", "............").replace(
        "............\n............\n", "............\n.>..........\n", 1
    )
    with pytest.raises(WorldMapError, match=r"ring\.txt:3:1: open boundary"):
        parse_world(outside, "ring.txt")


def test_gap_under_a_short_line_is_an_open_boundary() -> None:
    text = "######\n#....#\n#.>..#\n#....#\n#...\n######\n"
    with pytest.raises(WorldMapError, match=r"g\.txt:4:5: open boundary"):
        parse_world(text, "g.txt")


def test_two_starts_name_both_positions() -> None:
    with pytest.raises(WorldMapError, match=r"t\.txt:4:5: two starts, at 3:3 and 4:5"):
        parse_world(ROOM.replace("#....#\n######", "#...<#\n######"), "t.txt")


def test_start_touching_a_wall_diagonally_is_refused() -> None:
    text = "#######\n#.....#\n#.....#\n#..>..#\n#....##\n#.....#\n#######\n"
    parse_world(text.replace("#....##", "#.....#"), "ok.txt")
    with pytest.raises(WorldMapError, match=r"w\.txt:4:4: the start touches the wall at 5:5"):
        parse_world(text.replace("#....##", "#...#.#"), "w.txt")


def test_start_overlapping_a_disc_is_refused() -> None:
    with pytest.raises(
        WorldMapError, match=r"d\.txt:4:3: the start overlaps the disc at x 0.9 y 0.6 r 0.1"
    ):
        parse_world("disc: 0.9 0.6 0.1\n" + ROOM, "d.txt")


def test_start_touching_a_ring_is_refused() -> None:
    with pytest.raises(WorldMapError, match="the start touches the ring"):
        parse_world("ring: 0.625 0.625 0.15\n" + ROOM, "r.txt")


def test_goal_inside_a_wall_is_refused() -> None:
    with pytest.raises(WorldMapError, match=r"g\.txt:1:7: goal x 0.1 y 0.1 is inside a wall"):
        parse_world("goal: 0.1 0.1\n" + ROOM, "g.txt")


@pytest.mark.parametrize(
    ("header", "error"),
    [
        ("goal: 9 9", "goal x 9 y 9 is outside the world"),
        ("disc: 9 9 0.1", "disc at x 9 y 9 r 0.1 is outside the world"),
        ("wall: 0.3 0.3 9 0.3", "wall reaches outside the world"),
    ],
)
def test_header_errors_name_line_and_column_even_when_the_file_name_has_a_colon(
    header: str, error: str
) -> None:
    with pytest.raises(WorldMapError) as refused:
        parse_world(f"{header}\n{ROOM}", "at 10:30.txt")
    assert str(refused.value).startswith(f"at 10:30.txt:1:7: {error}")


def test_load_world_reads_a_real_file(tmp_path: Path) -> None:
    path = tmp_path / "room.txt"
    path.write_bytes(
        ("\ufeff" + ROOM.replace("\n", "\r\n")).encode()
    )  # BOM and CRLF, as on Windows
    world = load_world(path)
    assert (len(world.segments), world.name) == (4, "room")


def test_an_origin_places_the_grid_and_every_coordinate_in_the_maps_frame() -> None:
    plain = parse_world(ROOM, "r.txt")
    moved = parse_world("origin: -10.5 3.25\ngoal: -9.5 4\ndisc: -9.5 3.625 0.05\n" + ROOM, "r.txt")
    assert moved.origin_m == (-10.5, 3.25)
    assert (moved.width_m, moved.height_m) == (plain.width_m, plain.height_m)
    assert sorted(moved.segments) == sorted(
        (x1 - 10.5, y1 + 3.25, x2 - 10.5, y2 + 3.25) for x1, y1, x2, y2 in plain.segments
    )
    assert moved.start == (plain.start[0] - 10.5, plain.start[1] + 3.25, 0.0)
    assert moved.goals == ((-9.5, 4.0),)


def test_coordinates_in_the_maps_frame_carry_no_float_noise() -> None:
    # 0.1 is not a binary fraction: -2.9 + 3 * 0.1 computes -2.5999999999999996.
    rows = ["#" * 12, *(["#" + "." * 10 + "#"] * 8), "#" * 12]
    rows[5] = "#...." + ">" + "......#"
    world = parse_world("origin: -2.9 -0.3\ncell: 0.1\n" + "\n".join(rows), "r.txt")
    coordinates = {v for segment in world.segments for v in segment}
    assert coordinates == {round(v, 9) for v in coordinates}
    assert coordinates >= {-2.8, -1.8, -0.2, 0.6}  # the walls' inner faces
    assert world.start == (-2.35, 0.15, 0.0)


def test_a_header_start_takes_any_place_and_heading() -> None:
    world = parse_world("start: 0.8 0.6 30\n" + ROOM.replace(">", "."), "s.txt")
    assert world.start == (0.8, 0.6, math.radians(30))


@pytest.mark.parametrize(
    ("header", "error"),
    [
        ("start: 0.8 0.6 30", r"s\.txt:1:8: two starts, the header's and the map's at 4:3"),
        ("start: 9 9 0", r"s\.txt:1:8: the start x 9 y 9 is not on the map's floor"),
        ("start: 0.1 0.6 0", r"s\.txt:1:8: the start x 0.1 y 0.6 is not on the map's floor"),
        ("start: 0.4 0.6 0", r"s\.txt:1:8: the start touches the wall at 4:1"),
        ("start: 0.8 0.6 400", r"s\.txt:1:8: bad value for 'start': '0.8 0.6 400'"),
        ("start: 0.8 0.6", r"s\.txt:1:8: bad value for 'start'"),
        ("origin: 1e308 0", r"s\.txt:1:9: bad value for 'origin'"),
        ("origin: 0 nan", r"s\.txt:1:9: bad value for 'origin'"),
        ("origin: 1 2\norigin: 1 2", r"s\.txt:2:1: 'origin' given twice"),
    ],
)
def test_a_bad_start_or_origin_is_named_with_line_and_column(header: str, error: str) -> None:
    room = ROOM if header.startswith("start: 0.8 0.6 30") else ROOM.replace(">", ".")
    if header.startswith("origin"):
        room = ROOM
    with pytest.raises(WorldMapError, match=error):
        parse_world(f"{header}\n{room}", "s.txt")
