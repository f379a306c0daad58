"""World generators: every kind parses, the lab is seeded, the shipped worlds are generated."""

from __future__ import annotations

from pathlib import Path

import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.sim.worldgen import KINDS, SMOOTH, Materials, bundled_world_path, generate_world
from tvl_cli.sim.worldmap import WorldMap, load_world, parse_world

ROOT = Path(__file__).resolve().parents[2]


def generated(kind: str, seed: int = 1) -> WorldMap:
    return parse_world(generate_world(kind, None, None, seed), kind)


@pytest.mark.parametrize("kind", KINDS)
def test_every_kind_at_its_smallest_size_parses(kind: str) -> None:
    width_m, height_m = KINDS[kind].min_size_m
    world = parse_world(generate_world(kind, width_m, height_m, 1), kind)
    assert (world.width_m, world.height_m) == (width_m, height_m)


@pytest.mark.parametrize("kind", KINDS)
def test_shipped_world_is_the_generator_output_named_for_its_kind(kind: str) -> None:
    """The shipped worlds are the generator's seed-1 layouts under their kind's name alone,
    the name grids, traces and figures know them by."""
    made = generate_world(kind, None, None, 1)
    named = parse_world(made, kind).name
    text = made.replace(f"\nname: {named}\n", f"\nname: {kind}\n", 1)
    assert (ROOT / "worlds" / f"{kind}.txt").read_text(encoding="utf-8") == text
    assert bundled_world_path(kind).read_text(encoding="utf-8") == text
    assert load_world(bundled_world_path(kind)).name == kind


def test_unknown_bundled_world_is_bad_input() -> None:
    with pytest.raises(BadInput, match="no bundled world 'moon'"):
        bundled_world_path("moon")


def test_size_below_the_kind_minimum_is_bad_input() -> None:
    with pytest.raises(BadInput, match=r"a corridor world is from 3\.5 x 3\.5 m"):
        generate_world("corridor", 2.0, 5.0, 1)


def test_lab_same_seed_gives_the_same_text() -> None:
    assert generate_world("lab", None, None, 7) == generate_world("lab", None, None, 7)


def test_lab_different_seeds_give_different_layouts() -> None:
    assert generated("lab", 1).text != generated("lab", 2).text


@pytest.mark.parametrize("seed", range(20))
def test_lab_is_a_furnished_eight_by_six_room_for_any_seed(seed: int) -> None:
    world = generated("lab", seed)
    assert (world.width_m, world.height_m) == (8.0, 6.0)
    assert len(world.segments) > 12  # desks and benches add outlines to the 4 walls
    assert any(r >= 0.15 for _, _, r in world.discs)  # a pillar


def test_lab_desks_have_one_cell_table_tops_sticking_out() -> None:
    rows = [line for line in generated("lab").text.splitlines() if line.startswith("#")]

    def open_(r: int, c: int) -> bool:
        return rows[r][c] != "#"

    thin = [
        (r, c)
        for r in range(1, len(rows) - 1)
        for c in range(1, len(rows[r]) - 1)
        if not open_(r, c)
        and ((open_(r - 1, c) and open_(r + 1, c)) or (open_(r, c - 1) and open_(r, c + 1)))
    ]
    assert thin


def test_circle_ring_has_a_two_metre_radius_around_the_start() -> None:
    world = generated("circle")
    (x, y, r), (sx, sy, _) = world.rings[0], world.start
    assert r == 2.0
    assert ((sx - x) ** 2 + (sy - y) ** 2) ** 0.5 < r


def test_corridor_is_a_loop_about_1_2_m_wide() -> None:
    world = generated("corridor")
    assert len(world.segments) == 8  # outer walls and the block the corridor loops around
    _, sy, _ = world.start
    below = max(y1 for _, y1, _, y2 in world.segments if y1 == y2 and y1 < sy)
    above = min(y1 for _, y1, _, y2 in world.segments if y1 == y2 and y1 > sy)
    assert above - below == 1.25


def test_obstacles_has_pillars_between_the_start_and_four_goals() -> None:
    world = generated("obstacles")
    assert len(world.goals) == 4
    start_x = world.start[0]
    assert all(start_x < x < min(gx for gx, _ in world.goals) for x, _, _ in world.discs[:5])


def test_narrow_puts_the_goal_inside_a_passage_0_75_m_wide() -> None:
    world = generated("narrow")
    ((gx, gy),) = world.goals
    walls_over_goal = [
        y1 for x1, y1, x2, y2 in world.segments if y1 == y2 and min(x1, x2) < gx < max(x1, x2)
    ]
    below = max(y for y in walls_over_goal if y < gy)
    above = min(y for y in walls_over_goal if y > gy)
    assert above - below == 0.75


@pytest.mark.parametrize(
    "kind, size_m, seed, materials, name",
    [
        ("rooms", None, 7, SMOOTH, "rooms-s7"),
        ("lab", None, 1, SMOOTH, "lab-s1"),
        ("square", None, 5, SMOOTH, "square"),  # unseeded: the seed changes nothing
        ("square", (6.0, 5.0), 1, SMOOTH, "square-6x5"),
        ("rooms", (12.0, 9.5), 3, SMOOTH, "rooms-12x9.5-s3"),
        ("rooms", None, 2, Materials(0.5), "rooms-s2-rough0.5"),
        ("rooms", None, 2, Materials(1.0, 0.6), "rooms-s2-rough1-roughness0.6"),
    ],
)
def test_a_generated_world_is_named_for_what_sets_it_apart(
    kind: str,
    size_m: tuple[float, float] | None,
    seed: int,
    materials: Materials,
    name: str,
) -> None:
    width_m, height_m = size_m or (None, None)
    text = generate_world(kind, width_m, height_m, seed, materials)
    assert parse_world(text, "made").name == name
