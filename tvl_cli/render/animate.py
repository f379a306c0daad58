"""Animated replays, as GIFs written by matplotlib's Pillow writer: a run trace (the robot,
its sonar ring and what it perceived) or a learning session (each episode's trajectory and
the velocity labels learning drew from it); and the same picture of a robot being stepped
now, as an RGB array (the Gymnasium environment's `rgb_array`)."""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter
from matplotlib.artist import Artist
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle

from tvl_cli.core.config import RobotConfig
from tvl_cli.core.contacts import EVENTS
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.ring import beam_lines, mm_to_ring
from tvl_cli.core.training import TrainParams, episode_labels
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.logreader import Session
from tvl_cli.io.runfile import RunTrace
from tvl_cli.render.plot import ROBOT_COLOUR, draw_world
from tvl_cli.sim.worldmap import WorldMap, parse_world

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

    def holds(self, time_s: float) -> bool:
        return (self.from_s or 0.0) <= time_s <= (math.inf if self.to_s is None else self.to_s)

    def steps(self, trace: RunTrace) -> np.ndarray:
        period_s = trace.period_s
        end_s = trace.steps * period_s
        start_s, stop_s = self.from_s or 0.0, end_s if self.to_s is None else self.to_s
        if not (math.isfinite(start_s) and math.isfinite(stop_s) and 0 <= start_s < stop_s):
            raise BadInput(f"--from {start_s:g} --to {stop_s:g}: an empty or backward window")
        if start_s >= end_s:
            raise BadInput(f"--from {start_s:g}: the run lasted {end_s:g} simulated seconds")
        first, last = int(start_s / period_s), min(math.ceil(stop_s / period_s), trace.steps)
        every = self.every or max(1, math.ceil((last - first) / DEFAULT_MAX_FRAMES))
        return np.arange(first, last, every)


def animate_run(
    trace: RunTrace, gif: Path, window: Window, fps: int = DEFAULT_FPS, video: bool = False
) -> int:
    """Write the window of the run as a GIF (or an MP4 video); the number of frames."""
    if not trace.has_decisions:
        raise BadInput(f"{gif}: a format_version 1 trace records no perceptions to animate")
    if trace.steps == 0:
        raise BadInput(f"{gif}: the run has no steps")
    writer = _writer(gif, fps, video)
    steps = window.steps(trace)
    frame = _Frame(trace, RobotConfig.from_dict(trace.robot_config))
    _save(frame.figure, frame.draw, steps.tolist(), gif, writer, video)
    return len(steps)


def animate_session(
    session: Session, gif: Path, window: Window, fps: int = DEFAULT_FPS, video: bool = False
) -> int:
    """Write a learning session's episodes that ended within the window as a GIF (or an MP4
    video), a frame per exemplar (or every `window.every`-th); the number of frames."""
    writer = _writer(gif, fps, video)
    episodes = [e for e in session.episodes() if window.holds(e.end_time_s)]
    if not episodes:
        raise BadInput(f"{gif}: no episode of session {session.name} ended in that window")
    exemplars = [(e, i) for e in episodes for i in range(e.exemplar_count)]
    every = window.every or max(1, math.ceil(len(exemplars) / DEFAULT_MAX_FRAMES))
    frame = _EpisodeFrame(session)
    _save(frame.figure, frame.draw, exemplars[::every], gif, writer, video)
    return len(exemplars[::every])


def _writer(out: Path, fps: int, video: bool) -> FFMpegWriter | PillowWriter:
    """Pillow for a GIF; ffmpeg for an MP4 video, where it is installed. Asked before any
    frame is drawn."""
    if not video:
        return PillowWriter(fps=fps)
    if not FFMpegWriter.isAvailable():
        raise BadInput(f"{out}: an MP4 needs ffmpeg, which is not installed (use --gif)")
    return FFMpegWriter(fps=fps)


def _save(
    figure: Figure,
    draw: Callable[[Any], list[Artist]],
    frames: list[Any],
    out: Path,
    writer: FFMpegWriter | PillowWriter,
    video: bool,
) -> None:
    """Draw `figure` once for each of `frames` with `draw`, into `out` as the writer's format."""
    # The writers name the format by the file's extension, and the file being written has a
    # temporary name: it is made under its own name in a scratch folder, then copied.
    with tempfile.TemporaryDirectory() as scratch, atomic_output(out) as temporary:
        # Made only once the output is open: an animation dropped unsaved, as when the output
        # is refused, has matplotlib print a warning under the error's one line.
        animation = FuncAnimation(figure, draw, frames=frames)
        made = Path(scratch) / ("replay.mp4" if video else "replay.gif")
        animation.save(made, writer=writer, dpi=DPI)
        temporary.write_bytes(made.read_bytes())


def _rays(ring_mm: np.ndarray, pose: np.ndarray, robot: RobotConfig) -> tuple[list, list]:
    """Each transducer's reading as a line from the body's edge to its echo, and its colour."""
    ranges = mm_to_ring(ring_mm)  # metres; 0 where nobody read the ring
    start, end = beam_lines(ranges, pose, robot.radius_m)
    heard = ranges < robot.sonar.max_range_m
    return list(np.stack([start, end], axis=1)), [
        RAY_COLOUR if h else NO_ECHO_COLOUR for h in heard
    ]


def _world_axes(figure: Figure, world: WorldMap, robot: RobotConfig) -> tuple:
    """The world, the robot's body, heading, trail and rays on the left; the right axes."""
    world_ax, side_ax = figure.subplots(1, 2, gridspec_kw={"width_ratios": (1.6, 1.0)})
    draw_world(world_ax, world)
    (trail,) = world_ax.plot([], [], color=ROBOT_COLOUR, linewidth=1.0, alpha=0.6)
    body = Circle((0, 0), robot.radius_m, color=ROBOT_COLOUR, alpha=0.5, zorder=6)
    world_ax.add_patch(body)
    (heading,) = world_ax.plot([], [], color="black", linewidth=1.5, zorder=7)
    rays = LineCollection([], linewidths=0.8, zorder=5)
    world_ax.add_collection(rays)
    return world_ax, side_ax, trail, body, heading, rays


def _place(body: Circle, heading: Line2D, pose: np.ndarray, robot: RobotConfig) -> None:
    x, y, theta = pose
    body.center = (x, y)
    reach = 1.5 * robot.radius_m
    heading.set_data([x, x + reach * math.cos(theta)], [y, y + reach * math.sin(theta)])


class _Frame:
    """The figure and the artists a frame moves: world and robot left, perception right."""

    def __init__(self, trace: RunTrace, robot: RobotConfig) -> None:
        self.trace, self.robot = trace, robot
        self.period_s = trace.period_s
        self.threshold = float(trace.parameters.get("threshold", 0.0))
        self.figure = Figure(figsize=FIGURE_SIZE_IN)
        FigureCanvasAgg(self.figure)
        world_ax, self.bars_ax, self.trail, self.body, self.heading, self.rays = _world_axes(
            self.figure, parse_world(trace.world_text, trace.world_name), robot
        )
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
        self.trail.set_data(arrays["pose"][: step + 1, 0], arrays["pose"][: step + 1, 1])
        _place(self.body, self.heading, arrays["pose"][step], self.robot)
        segments, colours = _rays(arrays["ring_mm"][step], arrays["pose"][step], self.robot)
        self.rays.set_segments(segments)
        self.rays.set_color(colours)
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


class _EpisodeFrame:
    """A learning session's frame: the episode's path so far, and the velocity labels
    learning drew along it (what it taught the FAM), the current exemplar marked."""

    def __init__(self, session: Session) -> None:
        self.robot = session.robot_config
        known = {f.name for f in fields(TrainParams)}
        self.params = TrainParams(**{k: v for k, v in session.parameters.items() if k in known})
        self.figure = Figure(figsize=FIGURE_SIZE_IN)
        FigureCanvasAgg(self.figure)
        world_ax, self.labels_ax, self.trail, self.body, self.heading, self.rays = _world_axes(
            self.figure, parse_world(session.world_text, session.world_name), self.robot
        )
        self.title = world_ax.set_title("", fontsize=9)
        (self.curve,) = self.labels_ax.plot([], [], color=FAST_COLOUR)
        (self.marker,) = self.labels_ax.plot([], [], "o", color="black")
        self.labels_ax.set_xlabel("distance along the trajectory (m)")
        self.labels_ax.set_ylabel("velocity label (m/s)")
        self.labels_ax.set_ylim(0.0, 1.05 * max(self.robot.v_max_mps))
        self.labels_title = self.labels_ax.set_title("", fontsize=9)
        self.figure.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))  # room for the titles

    def draw(self, exemplar: tuple[Episode, int]) -> list[Artist]:
        episode, i = exemplar
        self.trail.set_data(episode.pose[: i + 1, 0], episode.pose[: i + 1, 1])
        _place(self.body, self.heading, episode.pose[i], self.robot)
        segments, colours = _rays(episode.ring_mm[i], episode.pose[i], self.robot)
        self.rays.set_segments(segments)
        self.rays.set_color(colours)
        labels = episode_labels(episode, self.robot, self.params)
        self.curve.set_data(episode.arc_m, labels)
        self.marker.set_data([episode.arc_m[i]], [labels[i]])
        self.labels_ax.set_xlim(0.0, max(float(episode.arc_m[-1]), 0.1))
        name = self.robot.trajectories[episode.trajectory].name
        ending = "a bump" if episode.bumped else "a near collision" if episode.collided else "free"
        self.title.set_text(f"episode {episode.index}: learning {name}, ended {ending}")
        self.labels_title.set_text(f"ends at {episode.end_time_s:.1f} s")
        return [self.trail, self.body, self.heading, self.rays, self.curve, self.marker]


class RobotFrame:
    """A robot being stepped now, drawn as a run's replay frames are: the world, the body, its
    trail and sonar rays on the left; on the right each sonar's range, where the replay shows
    perception (a caller stepping the simulator itself has no FAM's view to show)."""

    def __init__(self, world: WorldMap, robot: RobotConfig) -> None:
        self.robot = robot
        self.figure = Figure(figsize=FIGURE_SIZE_IN, dpi=DPI)
        self.canvas = FigureCanvasAgg(self.figure)
        world_ax, ranges_ax, self.trail, self.body, self.heading, self.rays = _world_axes(
            self.figure, world, robot
        )
        self.title = world_ax.set_title("", fontsize=9)
        count = robot.sonar.count
        self.bars = ranges_ax.bar(np.arange(count), np.zeros(count), edgecolor="black")
        ranges_ax.set_xticks(np.arange(0, count, 4), [f"S{k}" for k in range(0, count, 4)])
        ranges_ax.set_ylim(0.0, 1.05 * robot.sonar.max_range_m)
        ranges_ax.set_ylabel("sonar range (m)")
        self.ranges_title = ranges_ax.set_title("", fontsize=9)
        self.figure.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))  # room for the titles

    def draw(
        self, trail_xy: np.ndarray, pose: np.ndarray, ring_m: np.ndarray, title: str, caption: str
    ) -> np.ndarray:
        """(H, W, 3) uint8 RGB of the trail (N, 2) metres so far, the robot at `pose` and its
        ring (16,) metres; `title` over the world, `caption` over the ranges."""
        self.trail.set_data(trail_xy[:, 0], trail_xy[:, 1])
        _place(self.body, self.heading, pose, self.robot)
        segments, colours = _rays(ring_m * 1000.0, pose, self.robot)
        self.rays.set_segments(segments)
        self.rays.set_color(colours)
        for bar, range_m, colour in zip(self.bars, ring_m, colours, strict=True):
            bar.set_height(range_m)
            bar.set_facecolor(colour)
        self.title.set_text(title)
        self.ranges_title.set_text(caption)
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()
