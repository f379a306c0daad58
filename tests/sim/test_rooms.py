"""The `rooms` generator: valid, varied, repeatable worlds whose goal a robot can reach."""

from __future__ import annotations

from collections import deque
from functools import cache

import numpy as np
import pytest

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import clearances_m, static_geometry
from tvl_cli.sim.rooms import PATH_CLEARANCE_M, PIECES, RoomsPlan
from tvl_cli.sim.worldgen import draw_world, generate_world
from tvl_cli.sim.worldmap import WorldMap, parse_world

TUNING, TEST = range(1, 21), range(1001, 1021)


@cache
def rooms(seed: int) -> tuple[str, WorldMap]:
    text = generate_world("rooms", None, None, seed)
    return text, parse_world(text, f"rooms-{seed}")


@cache
def plan(seed: int) -> tuple[tuple[str, ...], RoomsPlan]:
    """The map lines of a rooms world, top first, and the generator's record of it."""
    text, drawn = draw_world("rooms", None, None, seed)
    assert isinstance(drawn, RoomsPlan)
    return tuple(text.split("\n\n", 1)[1].splitlines()), drawn


@pytest.mark.parametrize("seed", [*TUNING, *TEST])
def test_every_world_of_both_seed_sets_parses_with_a_goal(seed: int) -> None:
    _, world = rooms(seed)
    assert len(world.goals) >= 1


@pytest.mark.parametrize("seed", [*TUNING, 1001, 1002, 1003])
def test_the_goal_is_reachable_keeping_clear_of_everything(seed: int) -> None:
    # Flood a 5 cm lattice of body positions with 0.1 m of floor to spare, from the start.
    _, world = rooms(seed)
    step = 0.05
    xs = np.arange(step / 2, world.width_m, step)
    ys = np.arange(step / 2, world.height_m, step)
    points = np.array([(x, y) for y in ys for x in xs])
    clearance = clearances_m(static_geometry(world), points, RobotConfig().radius_m)
    free = (clearance >= PATH_CLEARANCE_M).reshape(len(ys), len(xs))

    def nearest(x: float, y: float) -> tuple[int, int]:
        return int(y // step), int(x // step)

    start, goal = nearest(*world.start[:2]), nearest(*world.goals[0])
    seen, queue = {start}, deque([start])
    while queue:
        r, c = queue.popleft()
        for nr, nc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if (nr, nc) not in seen and free[nr, nc]:
                seen.add((nr, nc))
                queue.append((nr, nc))
    assert goal in seen


def test_the_same_seed_gives_the_same_world_and_others_differ() -> None:
    texts = [rooms(seed)[0] for seed in TUNING]
    assert [generate_world("rooms", None, None, seed) for seed in (1, 7)] == [texts[0], texts[6]]
    assert len(set(texts)) == len(texts)


def test_the_worlds_vary_in_rooms_corridors_and_furniture() -> None:
    plans = [plan(seed)[1] for seed in TUNING]
    assert len({p.rooms for p in plans}) >= 3
    with_corridor = sum(bool(p.corridor_widths_m) for p in plans)
    assert 3 <= with_corridor <= len(plans) - 3
    for piece in PIECES:
        assert sum(piece in p.furniture for p in plans) >= 3, piece


def test_angled_walls_are_both_thin_edges_and_thick_walls() -> None:
    walls = [line.split() for seed in TUNING for line in rooms(seed)[0].splitlines()]
    thicknesses = {float(w[5]) for w in walls if w[:1] == ["wall:"]}
    assert thicknesses == {0.0, 0.1}


@pytest.mark.parametrize("seed", [*TUNING, 1001, 1002, 1003])
def test_doorways_measured_on_the_map_are_0_9_to_1_5_m_wide_and_open(seed: int) -> None:
    rows, drawn = plan(seed)
    assert len(drawn.doorways) >= drawn.rooms - 1  # every room has a way in
    for door in drawn.doorways:
        span = range(door.first, door.first + door.cells)  # rows or columns of the gap
        if door.down_column:
            along = "".join(row[door.line] for row in rows)
            beside = [(rows[r][door.line - 1], rows[r][door.line + 1]) for r in span]
        else:
            along = rows[door.line]
            beside = [(rows[door.line - 1][c], rows[door.line + 1][c]) for c in span]
        gap = along[span.start : span.stop]
        assert (along[span.start - 1], along[span.stop]) == ("#", "#") and "#" not in gap
        assert 0.9 <= door.width_m <= 1.5
        assert all("#" not in pair for pair in beside)  # floor on both sides of the gap


def test_corridors_are_1_to_2_5_m_wide() -> None:
    widths = [w for seed in TUNING for w in plan(seed)[1].corridor_widths_m]
    assert widths and all(1.0 <= w <= 2.5 for w in widths)
