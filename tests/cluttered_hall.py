"""A world large enough that the sonar tests only the walls near the robot."""

from __future__ import annotations

import math

import numpy as np


def cluttered_hall(walls: int, seed: int) -> str:
    """A 30 x 30 m hall's text: short walls at random angles and a few large pillars."""
    rng = np.random.default_rng(seed)
    lines = ["cell: 0.5"]
    for x, y, angle in rng.uniform((2, 2, 0), (28, 28, math.pi), (walls, 3)):
        lines.append(f"wall: {x:.3f} {y:.3f} {x + math.cos(angle):.3f} {y + math.sin(angle):.3f}")
    lines += [f"disc: {x:.2f} {y:.2f} 1.5" for x, y in rng.uniform(4, 26, (3, 2))]
    grid = ["#" * 60] + ["#" + "." * 58 + "#"] * 58 + ["#" * 60]
    grid[1] = "#>" + "." * 57 + "#"
    return "\n".join([*lines, *grid, ""])


def hall_of_walls(count: int) -> str:
    """A 100 x 100 m hall (0.25 m cells) holding `count` thin `wall:` lines 0.5 m long on a
    lattice, the start near a corner: a world of many header walls, as a user might write."""
    side = math.ceil(math.sqrt(count))
    spacing = 96.0 / side
    walls = [
        f"wall: {2 + i * spacing:.3f} {2 + j * spacing:.3f} {2.5 + i * spacing:.3f} "
        f"{2 + j * spacing:.3f}"
        for i in range(side)
        for j in range(side)
    ][:count]
    grid = ["#" * 400, *(["#" + "." * 398 + "#"] * 398), "#" * 400]
    grid[-3] = "#.>" + "." * 396 + "#"
    return "\n".join(["cell: 0.25", *walls, *grid, ""])
