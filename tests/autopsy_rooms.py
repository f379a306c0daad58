"""The room the autopsy's tests drive in: a 10 x 6 m room with one wall of the test's."""

from __future__ import annotations

from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import WorldMap, parse_world

ROBOT = RobotConfig()
NAMES = tuple(t.name for t in ROBOT.trajectories)
# The robot starts at (2, 3) facing +x along y = 3 in a 10 x 6 m room.
START_Y = 3.0


def room_with(wall: tuple[float, float, float, float]) -> WorldMap:
    rows = ["#" * 40] + ["#" + "." * 38 + "#"] * 22 + ["#" * 40]
    rows[len(rows) - 1 - 12] = "#" + "." * 7 + ">" + "." * 30 + "#"  # cell (8, 12): (2.1, 3.1)
    header = f"cell: 0.25\nwall: {' '.join(f'{v:.4f}' for v in wall)}\n"
    return parse_world(header + "\n".join(rows) + "\n", "room")
