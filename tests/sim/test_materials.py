"""Wall materials: `rough: R x1 y1 x2 y2` rectangles give the walls within them a roughness of
their own, read from text and checked like every header line."""

from __future__ import annotations

import pytest

from tvl_cli.sim.worldheader import WorldMapError
from tvl_cli.sim.worldmap import WorldMap, parse_world

# A 4 x 2 m room of 0.25 m cells, the start in its middle facing +x.
GRID = ["#" * 16] + ["#" + "." * 14 + "#"] * 3 + ["#......>.......#"] + ["#" + "." * 14 + "#"] * 2
GRID += ["#" * 16]


def room(*header: str) -> WorldMap:
    return parse_world("\n".join([*header, *GRID, ""]), "room.txt")


def roughness_of(world: WorldMap) -> dict[tuple[float, ...], float]:
    return dict(zip(world.segments, world.segment_roughness, strict=True))


def test_without_rough_lines_every_wall_has_the_worlds_roughness() -> None:
    assert set(room().segment_roughness) == {0.0}
    assert set(room("roughness: 0.2").segment_roughness) == {0.2}


def test_walls_whose_middle_lies_in_a_rough_rectangle_take_its_roughness() -> None:
    # The left half of the room: its west wall's middle (x = 0.25) is inside, the east
    # wall's (x = 3.75) is not; the long walls' middles (x = 2) are on the edge, inside.
    world = room("roughness: 0.1", "rough: 0.4 0 0 2 2")
    found = roughness_of(world)
    west = next(s for s in found if s[0] == s[2] == 0.25)
    east = next(s for s in found if s[0] == s[2] == 3.75)
    assert found[west] == 0.4
    assert found[east] == 0.1


def test_the_last_rectangle_holding_a_wall_gives_its_roughness() -> None:
    world = room("rough: 0.4 0 0 4 2", "rough: 0.7 0 0 1 2")
    found = roughness_of(world)
    west = next(s for s in found if s[0] == s[2] == 0.25)
    east = next(s for s in found if s[0] == s[2] == 3.75)
    assert (found[west], found[east]) == (0.7, 0.4)


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("rough: 1.5 0 0 2 2", "room.txt:1:8: bad value for 'rough': '1.5 0 0 2 2'"),
        ("rough: 0.3 1 0 1 2", "room.txt:1:8: bad value for 'rough': '0.3 1 0 1 2'"),
        ("rough: 0.3 0 0 2", "room.txt:1:8: bad value for 'rough': '0.3 0 0 2'"),
        ("rough: 0.3 0 0 9 2", "room.txt:1:8: rough rectangle reaches outside"),
    ],
)
def test_a_bad_rough_line_is_refused_where_it_is(line: str, message: str) -> None:
    with pytest.raises(WorldMapError) as refused:
        room(line)
    assert str(refused.value).startswith(message)
