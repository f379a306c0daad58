"""`tvl run --live`: the run drawn in the terminal as it goes, in 80 x 24 characters.

Left, the world in characters with the robot (an arrow by its heading), its path and the
goal; right, the ring of sixteen readings, the seven perceived velocities as bars against
the threshold, what acted this step and the running counts.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
from rich.console import Console, Group
from rich.live import Live
from rich.table import Table
from rich.text import Text

from tvl_cli.agent.drive import Step
from tvl_cli.core.config import RobotConfig
from tvl_cli.core.contacts import BUMP, NEAR_MISS
from tvl_cli.sim.world import clearances_m, static_geometry
from tvl_cli.sim.worldmap import WorldMap

MAP_COLUMNS, MAP_ROWS = 44, 20  # the world's share of an 80 x 24 terminal
REFRESH_PER_S = 4  # redraws a second: enough to follow, cheap beside the simulation
BAR_WIDTH = 16  # characters for a trajectory's top speed
# Arrows by heading, counter-clockwise from east in eighths of a turn.
ARROWS = "→↗↑↖←↙↓↘"


class LiveView:
    """A step sink that keeps what the view shows and paces the run; `panel()` draws it."""

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        threshold: float,
        goal: tuple[float, float] | None,
        pace: float | None,
    ) -> None:
        self.robot, self.threshold, self.goal, self.pace = robot, threshold, goal, pace
        self.scale = max(world.width_m / MAP_COLUMNS, world.height_m / MAP_ROWS)
        self.columns = min(MAP_COLUMNS, math.ceil(world.width_m / self.scale))
        self.rows = min(MAP_ROWS, math.ceil(world.height_m / self.scale))
        self.walls = self._wall_cells(world)
        self.visited: set[tuple[int, int]] = set()
        self.step: Step | None = None
        self.counts = {BUMP: 0, NEAR_MISS: 0}
        self.distance_m = 0.0
        self.caption = ""  # a line of the caller's: while learning, the last minute's counts
        self._started = time.monotonic()

    def __call__(self, step: Step) -> None:
        if self.step is not None:
            (x0, y0, _), (x1, y1, _) = self.step.pose, step.pose
            self.distance_m += math.hypot(x1 - x0, y1 - y0)
        self.step = step
        self.visited.add(self._cell(step.pose[0], step.pose[1]))
        for event in step.events:
            if event in self.counts:
                self.counts[event] += 1
        if self.pace:
            # Hold the simulation back to `pace` simulated seconds a wall second.
            ahead_s = step.time_s / self.pace - (time.monotonic() - self._started)
            if ahead_s > 0:
                time.sleep(ahead_s)

    def panel(self) -> Table:
        layout = Table.grid(padding=(0, 1))
        layout.add_column(width=self.columns)
        layout.add_column()
        layout.add_row(self._map(), Group(*self._side()))
        return layout

    def _cell(self, x: float, y: float) -> tuple[int, int]:
        column = min(max(int(x / self.scale), 0), self.columns - 1)
        row = min(max(self.rows - 1 - int(y / self.scale), 0), self.rows - 1)
        return row, column

    def _wall_cells(self, world: WorldMap) -> set[tuple[int, int]]:
        """Cells within half a cell of an obstacle."""
        rows, columns = np.mgrid[0 : self.rows, 0 : self.columns]
        centres = np.stack(
            [(columns.ravel() + 0.5) * self.scale, (self.rows - rows.ravel() - 0.5) * self.scale],
            axis=1,
        )
        near = clearances_m(static_geometry(world), centres, 0.0) < self.scale / 2
        return {
            (int(r), int(c)) for r, c in zip(rows.ravel()[near], columns.ravel()[near], strict=True)
        }

    def _map(self) -> Text:
        grid = [[" "] * self.columns for _ in range(self.rows)]
        for row, column in self.walls:
            grid[row][column] = "#"
        for row, column in self.visited:
            grid[row][column] = "·"
        if self.goal is not None:
            row, column = self._cell(*self.goal)
            grid[row][column] = "G"
        if self.step is not None:
            x, y, theta = self.step.pose
            row, column = self._cell(x, y)
            grid[row][column] = ARROWS[round(theta / (math.pi / 4)) % 8]
        return Text("\n".join("".join(line) for line in grid))

    def _side(self) -> list[Text]:
        step = self.step
        if step is None:
            return [Text("starting")]
        lines = [Text(f"t {step.time_s:6.1f} s   view {step.decision.rotation:2d}", style="bold")]
        if self.caption:
            lines.append(Text(self.caption))
        if step.ring_m is not None:  # S0..S7, then S8..S15, in metres
            lines.extend(self._ring(step.ring_m, step.decision.perceived_m))
        lines.extend(self._bars(step))
        acted = step.decision.reflex or ("trapped" if step.decision.trapped else "policy")
        lines.append(Text(f"acting: {acted}  {' '.join(step.events)}"))
        minutes = max(step.time_s, 1e-9) / 60.0
        lines.append(
            Text(
                f"bumps {self.counts[BUMP]}  near misses {self.counts[NEAR_MISS]}  "
                f"{self.distance_m / max(step.time_s, 1e-9):.2f} m/s  "
                f"{(self.counts[BUMP] + self.counts[NEAR_MISS]) / minutes:.2f} contacts/min"
            )
        )
        return lines

    @staticmethod
    def _ring(ring_m: np.ndarray, perceived_m: np.ndarray | None) -> list[Text]:
        """The readings in two rows; where the echo memory gave the FAM a nearer range than
        the live reading, that range, in cyan."""
        lines = []
        for half in (range(0, 8), range(8, 16)):
            line = Text()
            for i in half:
                remembered = perceived_m is not None and perceived_m[i] < ring_m[i]
                value = perceived_m[i] if perceived_m is not None and remembered else ring_m[i]
                line.append(f"{value:.1f}", style="cyan" if remembered else "")
                line.append(" " if i != half[-1] else "")
            lines.append(line)
        return lines

    def _bars(self, step: Step) -> list[Text]:
        """A bar per trajectory: perceived velocity, '|' at the threshold, '*' driven."""
        velocities, fast = step.decision.velocities, step.decision.fast
        if velocities is None:  # nothing perceived: exploring, spinning or backing off
            followed = step.decision.trajectory
            name = self.robot.trajectories[followed].name if followed >= 0 else "none"
            return [Text(f"following {name}, no velocities perceived")]
        lines = []
        for j, trajectory in enumerate(self.robot.trajectories):
            top = trajectory.v_max_mps
            v = 0.0 if np.isnan(velocities[j]) else float(velocities[j])
            filled = round(BAR_WIDTH * v / top)
            mark = round(BAR_WIDTH * self.threshold)
            bar = "".join(
                "|" if i == mark else ("█" if i < filled else " ") for i in range(BAR_WIDTH + 1)
            )
            driven = "*" if j == step.decision.trajectory else " "
            style = "green" if fast is not None and fast[j] else ""
            lines.append(Text(f"{driven}{trajectory.name:>3} {bar} {v:.2f}", style=style))
        return lines


@contextmanager
def live_view(view: LiveView, console: Console | None = None) -> Iterator[LiveView]:
    """Redraw the view a few times a second while the block runs, and once at its end."""
    with Live(get_renderable=view.panel, console=console, refresh_per_second=REFRESH_PER_S) as live:
        yield view
        live.refresh()
