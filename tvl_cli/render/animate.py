"""Animated replays of a run trace: the robot, its sonar ring and what it perceived, frame by
frame, as a GIF written by matplotlib's Pillow writer."""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.artist import Artist
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from tvl_cli.core.config import RobotConfig
from tvl_cli.core.contacts import EVENTS
from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.runfile import RunTrace
from tvl_cli.render.plot import ROBOT_COLOUR, draw_world
from tvl_cli.sim.worldmap import parse_world

DPI = 60  # small frames: a minute of replay stays a GIF of a few MB
FIGURE_SIZE_IN = (9.0, 4.5)
DEFAULT_FPS = 10
DEFAULT_MAX_FRAMES = 200  # without --every, steps are skipped to stay under this
RAY_COLOUR, NO_ECHO_COLOUR = "#d62728", "#e4e4e4"  # an echo, and a beam that heard none
FAST_COLOUR, SLOW_COLOUR = "#2ca02c", "#9ecae1"


@dataclass(frozen=True, slots=True)
class Window:
    """Which steps to draw: from and to simulated seconds (None: the run's ends), and every
    how many steps a frame (None: as many as keep the frames under DEFAULT_MAX_FRAMES)."""

    from_s: float | None = None
    to_s: float | None = None
    every: int | None = None

    def steps(self, trace: RunTrace) -> np.ndarray:
        period_s = float(trace.metrics["sim_s"]) / trace.steps
        end_s = trace.steps * period_s
        start_s, stop_s = self.from_s or 0.0, end_s if self.to_s is None else self.to_s
        if not (math.isfinite(start_s) and math.isfinite(stop_s) and 0 <= start_s < stop_s):
            raise BadInput(f"--from {start_s:g} --to {stop_s:g}: an empty or backward window")
        if start_s >= end_s:
            raise BadInput(f"--from {start_s:g}: the run lasted {end_s:g} simulated seconds")
        first, last = int(start_s / period_s), min(math.ceil(stop_s / period_s), trace.steps)
        every = self.every or max(1, math.ceil((last - first) / DEFAULT_MAX_FRAMES))
        return np.arange(first, last, every)


def animate_run(trace: RunTrace, gif: Path, window: Window, fps: int = DEFAULT_FPS) -> int:
    """Write the window of the run as a GIF; the number of frames."""
    if not trace.has_decisions:
        raise BadInput(f"{gif}: a format_version 1 trace records no perceptions to animate")
    if trace.steps == 0:
        raise BadInput(f"{gif}: the run has no steps")
    steps = window.steps(trace)
    robot = RobotConfig.from_dict(trace.robot_config)
    frame = _Frame(trace, robot)
    animation = FuncAnimation(frame.figure, frame.draw, frames=steps.tolist(), blit=False)
    # Pillow names the format by the file's extension, and the file being written has a
    # temporary name: it is made under its own name in a scratch folder, then copied.
    with tempfile.TemporaryDirectory() as scratch, atomic_output(gif) as temporary:
        made = Path(scratch) / "replay.gif"
        animation.save(made, writer=PillowWriter(fps=fps), dpi=DPI)
        temporary.write_bytes(made.read_bytes())
    return len(steps)


class _Frame:
    """The figure and the artists a frame moves: world and robot left, perception right."""

    def __init__(self, trace: RunTrace, robot: RobotConfig) -> None:
        self.trace, self.robot = trace, robot
        self.period_s = float(trace.metrics["sim_s"]) / trace.steps
        self.threshold = float(trace.parameters.get("threshold", 0.0))
        self.figure = Figure(figsize=FIGURE_SIZE_IN)
        FigureCanvasAgg(self.figure)
        world_ax, self.bars_ax = self.figure.subplots(
            1, 2, gridspec_kw={"width_ratios": (1.6, 1.0)}
        )
        draw_world(world_ax, parse_world(trace.world_text, trace.world_name))
        (self.trail,) = world_ax.plot([], [], color=ROBOT_COLOUR, linewidth=1.0, alpha=0.6)
        self.body = Circle((0, 0), robot.radius_m, color=ROBOT_COLOUR, alpha=0.5, zorder=6)
        world_ax.add_patch(self.body)
        (self.heading,) = world_ax.plot([], [], color="black", linewidth=1.5, zorder=7)
        self.rays = LineCollection([], linewidths=0.8, zorder=5)
        world_ax.add_collection(self.rays)
        self.title = world_ax.set_title("", fontsize=9)
        names = [t.name for t in robot.trajectories]
        top = np.array(robot.v_max_mps)
        self.bars = self.bars_ax.bar(names, top, color=SLOW_COLOUR, edgecolor="black")
        self.bars_ax.hlines(
            self.threshold * top,
            np.arange(len(top)) - 0.4,
            np.arange(len(top)) + 0.4,
            colors="black",
            linestyles="dashed",
            linewidth=1.0,
            label=f"threshold {self.threshold:g}",
        )
        self.bars_ax.set_ylim(0.0, 1.05 * top.max())
        self.bars_ax.set_ylabel("perceived velocity (m/s)")
        self.bars_ax.legend(loc="upper right", fontsize=7)
        self.bars_title = self.bars_ax.set_title("", fontsize=9)
        self.figure.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))  # room for the titles

    def draw(self, step: int) -> list[Artist]:
        arrays = self.trace.arrays
        x, y, theta = arrays["pose"][step]
        self.trail.set_data(arrays["pose"][: step + 1, 0], arrays["pose"][: step + 1, 1])
        self.body.center = (x, y)
        reach = 1.5 * self.robot.radius_m
        self.heading.set_data([x, x + reach * math.cos(theta)], [y, y + reach * math.sin(theta)])
        self._draw_rays(arrays["ring_mm"][step], x, y, theta)
        velocities = np.nan_to_num(arrays["velocities"][step], nan=0.0)
        fast, chosen = arrays["fast"][step], int(arrays["trajectory"][step])
        for j, bar in enumerate(self.bars):
            bar.set_height(velocities[j])
            bar.set_color(FAST_COLOUR if fast[j] else SLOW_COLOUR)
            bar.set_edgecolor("black")
            bar.set_linewidth(2.5 if j == chosen else 0.5)
        began = [e for i, e in enumerate(EVENTS) if int(arrays["events"][step]) & (1 << i)]
        self.title.set_text(f"{(step + 1) * self.period_s:.1f} s  {' '.join(began)}")
        reflex = int(arrays["reflex"][step])
        driver = self.trace.reflex_names[reflex] if reflex >= 0 else "policy"
        self.bars_title.set_text(f"view {int(arrays['rotation'][step])}, driven by {driver}")
        return [self.trail, self.body, self.heading, self.rays, *self.bars]

    def _draw_rays(self, ring_mm: np.ndarray, x: float, y: float, theta: float) -> None:
        """Each transducer's reading as a line from the body's edge to its echo."""
        count = len(ring_mm)
        angles = theta + 2.0 * math.pi * np.arange(count) / count
        unit = np.stack([np.cos(angles), np.sin(angles)], axis=1)  # (16, 2)
        start = np.array([x, y]) + self.robot.radius_m * unit
        ranges = ring_mm / 1000.0  # metres; 0 where nobody read the ring
        end = start + ranges[:, None] * unit
        self.rays.set_segments(list(np.stack([start, end], axis=1)))
        heard = ranges < self.robot.sonar.max_range_m
        self.rays.set_color([RAY_COLOUR if h else NO_ECHO_COLOUR for h in heard])
