"""The `rooms` generator: valid, varied, repeatable worlds whose goal a robot can reach."""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest

from tvl_cli.core.config import RobotConfig
from tvl_cli.sim.canvas import CELL_M
from tvl_cli.sim.rooms import DOOR_CELLS, PATH_CLEARANCE_M
from tvl_cli.sim.world import clearances_m, static_geometry
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import WorldMap, parse_world

TUNING, TEST = range(1, 21), range(1001, 1021)


def rooms(seed: int) -> tuple[str, WorldMap]:
    text = generate_world("rooms", None, None, seed)
    return text, parse_world(text, f"rooms-{seed}")


@pytest.mark.parametrize("seed", [*TUNING, *TEST])
def test_every_world_of_both_seed_sets_parses_with_a_goal(seed: int) -> None:
    _, world = rooms(seed)
    assert len(world.goals) >= 1


@pytest.mark.parametrize("seed", [1, 2, 3, 1001, 1002, 1003])
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
    assert rooms(1)[0] == texts[0]
    assert len(set(texts)) == len(texts)


def test_the_worlds_vary_in_rooms_and_furniture() -> None:
    texts = [rooms(seed)[0] for seed in TUNING]
    assert sum("disc:" in t for t in texts) >= 5
    assert sum("wall:" in t for t in texts) >= 5
    wall_cells = [t.count("#") for t in texts]
    assert max(wall_cells) > 1.3 * min(wall_cells)  # some have more rooms than others


def test_doorways_are_0_9_to_1_5_m_wide() -> None:
    assert all(0.9 <= cells * CELL_M <= 1.5 for cells in DOOR_CELLS)
