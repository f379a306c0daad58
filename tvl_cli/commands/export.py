"""`tvl export`: a run trace in a standard format for other tools (MCAP, for Foxglove)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.core.errors import BadInput
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.hdf5_header import LOG_FORMAT, FormatError, file_format
from tvl_cli.io.json_documents import document, input_file
from tvl_cli.io.mcapfile import Robot, Scene, write_run_mcap
from tvl_cli.io.runfile import read_run
from tvl_cli.sim.maps.raster import rasterise
from tvl_cli.sim.worldmap import parse_world

# ROS's OccupancyGrid values, which the MCAP's map grid takes: a cell free, occupied, unknown.
FREE, OCCUPIED, OUTSIDE = 0, 100, -1


@dataclass(frozen=True, slots=True)
class Exported:
    run: Path
    output: Path
    steps: int
    messages: dict[str, int]  # by topic

    def document(self) -> dict[str, Any]:
        return document(
            "export",
            {"run": input_file(self.run)},
            outputs={"mcap": str(self.output)},
            steps=self.steps,
            messages=[{"topic": topic, "messages": n} for topic, n in self.messages.items()],
        )


def export_mcap(run: Path, output: Path) -> Exported:
    """Write a run trace as MCAP: poses, the sonar ring, the world and its map, perceived
    velocities and events, timed by the run's simulated clock, in the world's (the map's)
    frame."""
    if file_format(run) == LOG_FORMAT:
        raise BadInput(
            f"{run}: is a learning log; tvl export writes run traces (tvl run --log RUN.h5)"
        )
    trace = read_run(run)
    if trace.steps == 0:  # a recording of nothing would open in Foxglove as an empty scene
        raise BadInput(f"{run}: the run trace has no steps: nothing to export")
    try:
        robot = RobotConfig.from_dict(trace.robot_config)
    except (KeyError, TypeError, ValueError) as error:
        raise FormatError(f"{run}: run trace's robot_config is malformed ({error})") from None
    names = tuple(t.name for t in robot.trajectories)
    if trace.arrays["velocities"].shape[1:] != (len(names),):
        raise FormatError(f"{run}: run trace's velocities are not one per trajectory")
    world = parse_world(trace.world_text, f"{run}: its world")
    raster = rasterise(world)
    occupancy = np.where(raster.outside, OUTSIDE, np.where(raster.occupied, OCCUPIED, FREE))
    scene = Scene(
        world.segments, world.discs, world.rings, occupancy.astype(np.int8), world.cell_m,
        world.origin_m,
    )  # fmt: skip
    messages = write_run_mcap(
        output, trace, scene, Robot(robot.radius_m, robot.sonar.max_range_m, names)
    )
    return Exported(run, output, trace.steps, messages)
