"""Real worlds for comparing kernels with their references: the shipped maps, generated
rooms worlds and a hall large enough that its walls are bucketed by cell, so that each ray
tests only the walls of the cells it crosses."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from cluttered_hall import cluttered_hall

from tvl_cli.sim.geometry import StaticGeometry, static_geometry
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sim.worldmap import load_world, parse_world

WORLDS = Path(__file__).resolve().parents[1] / "worlds"
SHIPPED = sorted(p.stem for p in WORLDS.glob("*.txt"))
ROOMS_SEEDS = (2, 5, 9)


def shipped(name: str) -> StaticGeometry:
    return static_geometry(load_world(WORLDS / f"{name}.txt"))


def rooms(seed: int) -> StaticGeometry:
    return static_geometry(parse_world(generate_world("rooms", None, None, seed), "rooms"))


def hall() -> StaticGeometry:
    geometry = static_geometry(parse_world(cluttered_hall(600, seed=3), "hall"))
    assert geometry.grid.columns * geometry.grid.rows > 1
    return geometry


def checkerboard() -> StaticGeometry:
    """A 3 x 3 m room at 5 cm whose middle is a checkerboard of one-cell walls: walls so
    crowded that the grid's cells shrink to hold a few each."""
    rows = ["#" * 60, *("#" + "." * 58 + "#" for _ in range(58)), "#" * 60]
    rows = [
        row
        if not 10 < r < 50
        else row[:10] + "".join(".#"[(r + c) % 2] for c in range(10, 50)) + row[50:]
        for r, row in enumerate(rows)
    ]
    rows[5] = "#....>" + rows[5][6:]
    geometry = static_geometry(parse_world("cell: 0.05\n" + "\n".join(rows), "checkerboard"))
    assert geometry.grid.cell_m < 0.5
    return geometry


def rough(geometry: StaticGeometry, roughness: float) -> StaticGeometry:
    return geometry.with_roughness(roughness)


def every_world() -> dict[str, StaticGeometry]:
    """Each world by name: the shipped ones, rooms worlds, the hall, a checkerboard, and a
    rough lab and circle (rough walls and a rough ring wall)."""
    worlds = {name: shipped(name) for name in SHIPPED}
    worlds |= {f"rooms-{seed}": rooms(seed) for seed in ROOMS_SEEDS}
    worlds["hall"] = hall()
    worlds["checkerboard"] = checkerboard()
    worlds["rough-lab"] = rough(worlds["lab"], 0.3)
    worlds["rough-circle"] = rough(worlds["circle"], 0.5)
    return worlds


def random_poses(geometry: StaticGeometry, count: int, seed: int) -> np.ndarray:
    """(count, 3) x, y metres within the world's walls' extent, heading rad: anywhere, inside
    obstacles too, where the ring reads surfaces behind its transducers."""
    low = geometry.segments.reshape(-1, 2).min(axis=0)
    high = geometry.segments.reshape(-1, 2).max(axis=0)
    rng = np.random.default_rng(seed)
    return rng.uniform((*low, -math.pi), (*high, math.pi), (count, 3))
