"""A FAM's learnt velocity over two of its inputs, the others held fixed: the numbers of
`tvl inspect --png`, drawn by render.plot."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import FamConfig, FamTable

GRID_POINTS = 60  # per input: finer than any partition, coarse enough to infer at once


@dataclass(frozen=True, slots=True)
class Surface:
    trajectory: str
    over: tuple[str, str]  # the inputs along x and y
    ranges_m: np.ndarray  # (GRID_POINTS,) the values both inputs take, metres
    velocity_mps: np.ndarray  # (GRID_POINTS, GRID_POINTS), [y, x]
    experience: np.ndarray  # (GRID_POINTS, GRID_POINTS), [y, x]: 0 where nothing was learnt
    unread: tuple[str, ...] = ()  # of `over`, those the trajectory's table does not read:
    # its velocity is the same all along them

    @property
    def untrained(self) -> np.ndarray:
        """(GRID_POINTS, GRID_POINTS) bool, [y, x]: where no rule that fires has learnt
        anything, so the velocity is the one every entry started at."""
        return self.experience <= 0.0


def shared_inputs(config: FamConfig) -> tuple[str, str]:
    """The two inputs the most of the configuration's tables read together, so that a
    picture over them has a panel for the most trajectories; of pairs as many tables
    share, the first in the tables' order (single: front, front-left)."""
    tables = [[fam_input.name for fam_input in table.inputs] for table in config.tables]
    pairs = [(a, b) for names in tables for i, a in enumerate(names) for b in names[i + 1 :]]
    if not pairs:
        raise BadInput(f"no table of the {config.name} FAM reads two inputs to draw over")
    return max(pairs, key=lambda pair: sum(set(pair) <= set(names) for names in tables))


def velocity_surfaces(
    fam: Fam,
    over: tuple[str, str],
    fixed: dict[str, float],
    min_range_m: float,
    max_range_m: float,
    sonar_count: int,
) -> list[Surface]:
    """For every trajectory: its velocity as the inputs `over` range from the sonar's minimum
    to its maximum, the other inputs at `fixed` metres (or at the maximum, open space, where
    not given). A trajectory whose table reads one of `over` or neither has a panel all the
    same: its velocity does not change along what it does not read."""
    if over[0] == over[1]:
        raise BadInput(f"--over {over[0]},{over[1]}: two different inputs")
    for name, value in fixed.items():
        if not min_range_m <= value <= max_range_m:
            raise BadInput(f"--fix {name}={value:g}: outside {min_range_m:g} to {max_range_m:g} m")
    sonars = _sonars_of_inputs(fam.config)
    unknown = [name for name in (*over, *fixed) if name not in sonars]
    if unknown or not any(set(over) <= set(_names(table)) for table in fam.config.tables):
        raise BadInput(
            f"no table of the FAM has the inputs {', '.join(unknown or over)} together "
            f"(its inputs: {', '.join(sorted(sonars))})"
        )
    ranges = np.linspace(min_range_m, max_range_m, GRID_POINTS)
    rings = _rings(sonars, over, fixed, ranges, max_range_m, sonar_count)
    velocities = fam.velocities(rings)  # (GRID_POINTS ** 2, J)
    experience = fam.experience(rings)
    grid = (GRID_POINTS, GRID_POINTS)
    surfaces = []
    for table in fam.config.tables:
        unread = tuple(name for name in over if name not in _names(table))
        for trajectory in table.trajectories:
            j = fam.trajectory_names.index(trajectory)
            surfaces.append(
                Surface(
                    trajectory,
                    over,
                    ranges,
                    velocities[:, j].reshape(grid),
                    experience[:, j].reshape(grid),
                    unread,
                )
            )
    order = {name: index for index, name in enumerate(fam.trajectory_names)}
    return sorted(surfaces, key=lambda surface: order[surface.trajectory])


def _names(table: FamTable) -> list[str]:
    return [fam_input.name for fam_input in table.inputs]


def _sonars_of_inputs(config: FamConfig) -> dict[str, tuple[int, ...]]:
    """Each input's sonars, by its name (an input of one name reads the same sonars in
    every table that has it)."""
    return {i.name: tuple(i.sonars) for table in config.tables for i in table.inputs}


def _rings(
    sonars: dict[str, tuple[int, ...]],
    over: tuple[str, str],
    fixed: dict[str, float],
    ranges: np.ndarray,
    max_range_m: float,
    sonar_count: int,
) -> np.ndarray:
    """(GRID_POINTS ** 2, sonars) rings in which the inputs `over` and `fixed` read what is
    asked: their sonars all read the value (an input reads the nearest of its sonars); the
    other sonars see open space."""
    x, y = np.meshgrid(ranges, ranges)  # [y, x]
    rings = np.full((x.size, sonar_count), max_range_m)
    for name, value in fixed.items():
        rings[:, list(sonars[name])] = value
    rings[:, list(sonars[over[0]])] = x.ravel()[:, None]
    rings[:, list(sonars[over[1]])] = y.ravel()[:, None]
    return rings
