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
    """For each trajectory whose table has both inputs `over`: its velocity as they range
    from the sonar's minimum to its maximum, the table's other inputs at `fixed` metres (or
    at the maximum, open space, where not given)."""
    if over[0] == over[1]:
        raise BadInput(f"--over {over[0]},{over[1]}: two different inputs")
    for name, value in fixed.items():
        if not min_range_m <= value <= max_range_m:
            raise BadInput(f"--fix {name}={value:g}: outside {min_range_m:g} to {max_range_m:g} m")
    ranges = np.linspace(min_range_m, max_range_m, GRID_POINTS)
    surfaces = []
    known: set[str] = set()
    for table in fam.config.tables:
        names = [i.name for i in table.inputs]
        known.update(names)
        if not set(over) <= set(names):
            continue
        rings = _rings(table, over, fixed, ranges, max_range_m, sonar_count)
        velocities = fam.velocities(rings)  # (GRID_POINTS ** 2, J)
        for trajectory in table.trajectories:
            column = velocities[:, fam.trajectory_names.index(trajectory)]
            surfaces.append(
                Surface(trajectory, over, ranges, column.reshape(GRID_POINTS, GRID_POINTS))
            )
    unknown = [name for name in (*over, *fixed) if name not in known]
    if unknown or not surfaces:
        raise BadInput(
            f"no table of the FAM has the inputs {', '.join(unknown or over)} together "
            f"(its inputs: {', '.join(sorted(known))})"
        )
    return surfaces


def _rings(
    table: FamTable,
    over: tuple[str, str],
    fixed: dict[str, float],
    ranges: np.ndarray,
    max_range_m: float,
    sonar_count: int,
) -> np.ndarray:
    """(GRID_POINTS ** 2, sonars) rings in which each input of the table reads what is asked:
    its sonars all read the value (an input reads the nearest of its sonars)."""
    x, y = np.meshgrid(ranges, ranges)  # [y, x]
    rings = np.full((x.size, sonar_count), max_range_m)
    for fam_input in table.inputs:
        if fam_input.name == over[0]:
            value = x.ravel()
        elif fam_input.name == over[1]:
            value = y.ravel()
        else:
            value = np.full(x.size, fixed.get(fam_input.name, max_range_m))
        rings[:, list(fam_input.sonars)] = value[:, None]
    return rings
