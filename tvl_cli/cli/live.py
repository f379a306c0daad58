"""The run drawn as it goes: `tvl run --live`, in the terminal, and `--view window`.

In the terminal, in 80 x 24 characters: left, the world in characters with the robot (an
arrow by its heading), its path and the goal; right, the ring of sixteen readings, the seven
perceived velocities as bars against the threshold, what acted this step and the running
counts. In a window, the frames of `tvl replay --gif`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
from rich.console import Console, Group
from rich.live import Live
from rich.table import Table
from rich.text import Text

from tvl_cli.agent.drive import Step
from tvl_cli.core.contacts import BUMP, NEAR_MISS
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.geometry import clearances_m, static_geometry
from tvl_cli.sim.worldmap import WALL, WorldMap, layout

MAP_COLUMNS, MAP_ROWS = 44, 20  # the world's share of an 80 x 24 terminal
REFRESH_PER_S = 4  # redraws a second: enough to follow, cheap beside the simulation
BAR_WIDTH = 16  # characters for a trajectory's top speed
# Arrows by heading, counter-clockwise from east in eighths of a turn.
ARROWS = "→↗↑↖←↙↓↘"


@dataclass(frozen=True, slots=True)
class Sight:
    """What a view of a run shows it in: the world, the robot, the threshold (a fraction of
    each trajectory's maximum) its bars mark, the goal sought (None: none), and the pace
    (simulated seconds a wall second; None: flat out)."""

    world: WorldMap
    robot: RobotConfig
    threshold: float
    goal: tuple[float, float] | None = None
    pace: float | None = None


class LiveView:
    """A step sink that keeps what the view shows and paces the run; `panel()` draws it."""

    def __init__(self, sight: Sight) -> None:
        world = sight.world
        self.robot, self.threshold, self.goal = sight.robot, sight.threshold, sight.goal
        self.pace = sight.pace
        self.origin = world.origin_m  # the map's frame: where the view's bottom-left lies
        self.scale = max(world.width_m / MAP_COLUMNS, world.height_m / MAP_ROWS)
        self.columns = min(MAP_COLUMNS, math.ceil(world.width_m / self.scale))
        self.rows = min(MAP_ROWS, math.ceil(world.height_m / self.scale))
        self.walls = self._wall_cells(world)
        self.visited: set[tuple[int, int]] = set()
        self.step: Step | None = None
        self.perceived: Step | None = None  # the last step that perceived velocities
        self.counts = {BUMP: 0, NEAR_MISS: 0}
        self.distance_m = 0.0
        self.caption = ""  # a line of the caller's: while learning, the last minute's counts
        self._started = time.monotonic()

    def __call__(self, step: Step) -> None:
        if self.step is not None:
            (x0, y0, _), (x1, y1, _) = self.step.pose, step.pose
            self.distance_m += math.hypot(x1 - x0, y1 - y0)
        self.step = step
        if step.decision.velocities is not None:
            self.perceived = step
        self.visited.add(self._cell(step.pose[0], step.pose[1]))
        for event in step.events:
            if event in self.counts:
                self.counts[event] += 1
        _hold_back(step.time_s, self.pace, self._started)

    def panel(self) -> Table:
        layout = Table.grid(padding=(0, 1))
        layout.add_column(width=self.columns)
        layout.add_column()
        layout.add_row(self._map(), Group(*self._side()))
        return layout

    def _cell(self, x: float, y: float) -> tuple[int, int]:
        x, y = x - self.origin[0], y - self.origin[1]
        column = min(max(int(x / self.scale), 0), self.columns - 1)
        row = min(max(self.rows - 1 - int(y / self.scale), 0), self.rows - 1)
        return row, column

    def _wall_cells(self, world: WorldMap) -> set[tuple[int, int]]:
        """Cells whose centre is in a wall's material, or within half a cell of an obstacle.
        The material counts apart: where the view's cells line up with the map's, an outer
        wall runs along their edges, exactly half a cell from either side's centre."""
        rows, columns = np.mgrid[0 : self.rows, 0 : self.columns]
        centres = np.array(self.origin) + np.stack(
            [(columns.ravel() + 0.5) * self.scale, (self.rows - rows.ravel() - 0.5) * self.scale],
            axis=1,
        )
        near = clearances_m(static_geometry(world), centres, 0.0) < self.scale / 2
        solid = _in_material(world, centres)
        walls = near | solid
        return {
            (int(r), int(c))
            for r, c in zip(rows.ravel()[walls], columns.ravel()[walls], strict=True)
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
        """A bar per trajectory: perceived velocity, '|' at the threshold, '*' driven. On a
        step that perceived nothing (a spin, a back-off, an episode of learning), the bars
        of the last step that did, dimmed, under the time they were perceived at."""
        shown = step if step.decision.velocities is not None else self.perceived
        if shown is None:
            followed = step.decision.trajectory
            name = self.robot.trajectories[followed].name if followed >= 0 else "none"
            return [Text(f"following {name}, no velocities perceived")]
        velocities, fast = shown.decision.velocities, shown.decision.fast
        assert velocities is not None
        lines = []
        if shown is not step:
            lines.append(Text(f"{_doing(step)}: as perceived at {shown.time_s:.1f} s", "dim"))
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
            faded = "" if shown is step else "dim "
            lines.append(Text(f"{driven}{trajectory.name:>3} {bar} {v:.2f}", f"{faded}{style}"))
        return lines


def _doing(step: Step) -> str:
    """What a step that perceived nothing did, in a word or two."""
    decision = step.decision
    if decision.reflex:
        return decision.reflex
    if decision.trapped:
        return "trapped"
    return "spinning" if decision.trajectory < 0 else "following"


def _hold_back(time_s: float, pace: float | None, started: float) -> None:
    """Hold the simulation back to `pace` simulated seconds a wall second (None: flat out)
    since the wall-clock moment `started`."""
    if pace:
        ahead_s = time_s / pace - (time.monotonic() - started)
        if ahead_s > 0:
            time.sleep(ahead_s)


class WindowView:
    """A step sink that shows the run in a window as `tvl replay --gif` draws it, a few
    frames a wall second, and paces the run."""

    def __init__(self, sight: Sight) -> None:
        from tvl_cli.render.animate import FIGURE_SIZE_IN, WINDOW_DPI, RunFrame
        from tvl_cli.render.window import FrameWindow

        self.robot, self.pace = sight.robot, sight.pace
        # Opened first: without a display, the run stops before anything is drawn.
        width_in, height_in = FIGURE_SIZE_IN
        size_px = (round(height_in * WINDOW_DPI), round(width_in * WINDOW_DPI))
        self.window = FrameWindow(f"tvl run: {sight.world.name}", size_px, WINDOW_DPI)
        self.frame = RunFrame(sight.world, sight.robot, sight.threshold, WINDOW_DPI, sight.goal)
        self.window.show(self.frame.blitter.still())
        self.trail: list[tuple[float, float]] = []
        self.step: Step | None = None
        self._started = time.monotonic()

    def __call__(self, step: Step) -> None:
        self.step = step
        self.trail.append((step.pose[0], step.pose[1]))
        _hold_back(step.time_s, self.pace, self._started)
        if self.window.due():
            self.draw()

    def draw(self) -> None:
        """The last step, in the window."""
        from tvl_cli.render.animate import run_caption, run_title

        step = self.step
        if step is None:
            return
        decision = step.decision
        ring_m = np.zeros(self.robot.sonar.count) if step.ring_m is None else step.ring_m
        frame = self.frame.draw(
            np.array(self.trail),
            np.array(step.pose),
            ring_m * 1000.0,
            decision.velocities,
            decision.fast,
            decision.trajectory,
            run_title(step.time_s + self.robot.control_period_s, step.events),
            run_caption(decision.rotation, decision.reflex or None),
        )
        self.window.show(frame)


@contextmanager
def window_view(view: WindowView) -> Iterator[WindowView]:
    """Show the run's last step once the block ends, a moment, then close the window."""
    from tvl_cli.render.window import LAST_FRAME_S

    try:
        yield view
        view.draw()
        view.window.hold(LAST_FRAME_S)
    finally:
        view.window.close()


def _in_material(world: WorldMap, points: np.ndarray) -> np.ndarray:
    """(N,) bool: whether each of the (N, 2) points, metres, lies in a wall cell of the map."""
    map_rows, _ = layout(world)
    x0, y0 = world.origin_m
    row = np.floor(len(map_rows) - (points[:, 1] - y0) / world.cell_m).astype(int)
    column = np.floor((points[:, 0] - x0) / world.cell_m).astype(int)
    return np.array(
        [
            0 <= r < len(map_rows) and 0 <= c < len(map_rows[r]) and map_rows[r][c] == WALL
            for r, c in zip(row, column, strict=True)
        ],
        dtype=bool,
    )


@contextmanager
def live_view(view: LiveView, console: Console | None = None) -> Iterator[LiveView]:
    """Redraw the view a few times a second while the block runs, and once at its end."""
    with Live(get_renderable=view.panel, console=console, refresh_per_second=REFRESH_PER_S) as live:
        yield view
        live.refresh()
