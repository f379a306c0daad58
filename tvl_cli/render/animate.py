"""Animated replays, as GIFs (or MP4 videos): a run trace (the robot, its sonar ring and what
it perceived) or a learning session (each episode's trajectory and the velocity labels
learning drew from it); and the same picture of a robot being stepped now, as an RGB array
(the Gymnasium environment's `rgb_array`, and the window of `tvl run --view window`).

Frames are blitted (render.blit): each figure's still parts are drawn once, and a frame draws
only what moves, a few milliseconds where a whole figure takes tens.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TypeVar

import numpy as np
from matplotlib.artist import Artist
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from tvl_cli.core.contacts import EVENTS
from tvl_cli.core.episode import Episode
from tvl_cli.core.errors import BadInput
from tvl_cli.core.ring import beam_lines, mm_to_ring
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.training import TrainParams, episode_labels
from tvl_cli.io.logreader import Session
from tvl_cli.io.moviefile import FrameSink, ffmpeg_path, gif_frames, mp4_frames
from tvl_cli.io.runfile import RunTrace
from tvl_cli.render.blit import Blitter, inks
from tvl_cli.render.plot import ROBOT_COLOUR, draw_world, velocity_axis
from tvl_cli.sim.worldmap import WorldMap, parse_world

DPI = 90  # 810 x 405 frames: their text reads at 100 %, and 200 of them are a GIF of a few MB
WINDOW_DPI = 100  # the frames of a window on screen
FIGURE_SIZE_IN = (9.0, 4.5)
DEFAULT_FPS = 10
DEFAULT_MAX_FRAMES = 200  # without --every, steps are skipped to stay under this
RAY_COLOUR, NO_ECHO_COLOUR = "#d62728", "#e4e4e4"  # an echo, and a beam that heard none
FAST_COLOUR, SLOW_COLOUR = "#2ca02c", "#9ecae1"
BODY_ALPHA, TRAIL_ALPHA = 0.5, 0.6
# What moving parts are drawn in, each kept exact in a GIF's palette.
INKS = inks(
    RAY_COLOUR,
    NO_ECHO_COLOUR,
    FAST_COLOUR,
    SLOW_COLOUR,
    "black",
    (ROBOT_COLOUR, BODY_ALPHA),
    (ROBOT_COLOUR, TRAIL_ALPHA),
)

# Told (frames drawn, frames in all) after each frame: a progress bar.
FrameProgress = Callable[[int, int], None]
Item = TypeVar("Item")


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
    trace: RunTrace,
    out: Path,
    window: Window,
    fps: int = DEFAULT_FPS,
    video: bool = False,
    on_frame: FrameProgress | None = None,
) -> int:
    """Write the window of the run as a GIF (or an MP4 video); the number of frames."""
    if not trace.has_decisions:
        raise BadInput(f"{out}: a format_version 1 trace records no perceptions to animate")
    if trace.steps == 0:
        raise BadInput(f"{out}: the run has no steps")
    if video:
        ffmpeg_path()  # refused before any frame is drawn
    steps = window.steps(trace)
    frame = _TraceFrame(trace, RobotConfig.from_dict(trace.robot_config))
    _write(frame.blitter, frame.draw, steps.tolist(), out, fps, video, on_frame)
    return len(steps)


def animate_session(
    session: Session,
    out: Path,
    window: Window,
    fps: int = DEFAULT_FPS,
    video: bool = False,
    on_frame: FrameProgress | None = None,
) -> int:
    """Write a learning session's episodes that ended within the window as a GIF (or an MP4
    video), a frame per exemplar (or every `window.every`-th); the number of frames."""
    if video:
        ffmpeg_path()
    episodes = [e for e in session.episodes() if window.holds(e.end_time_s)]
    if not episodes:
        raise BadInput(f"{out}: no episode of session {session.name} ended in that window")
    exemplars = [(e, i) for e in episodes for i in range(e.exemplar_count)]
    every = window.every or max(1, math.ceil(len(exemplars) / DEFAULT_MAX_FRAMES))
    frame = _EpisodeFrame(session)
    _write(frame.blitter, frame.draw, exemplars[::every], out, fps, video, on_frame)
    return len(exemplars[::every])


def _write(
    blitter: Blitter,
    draw: Callable[[Item], np.ndarray],
    items: Sequence[Item],
    out: Path,
    fps: int,
    video: bool,
    on_frame: FrameProgress | None,
) -> None:
    """A frame drawn for each of `items`, into `out` as a GIF or an MP4 video."""
    still = blitter.still()
    sink: AbstractContextManager[FrameSink] = (
        mp4_frames(out, fps, still.shape[:2]) if video else gif_frames(out, fps, still, INKS)
    )
    with sink as frames:
        for done, item in enumerate(items, start=1):
            frames.add(draw(item))
            if on_frame is not None:
                on_frame(done, len(items))


def _rays(ring_mm: np.ndarray, pose: np.ndarray, robot: RobotConfig) -> tuple[list, list]:
    """Each transducer's reading as a line from the body's edge to its echo, and its colour."""
    ranges = mm_to_ring(ring_mm)  # metres; 0 where nobody read the ring
    start, end = beam_lines(ranges, pose, robot.radius_m)
    heard = ranges < robot.sonar.max_range_m
    return list(np.stack([start, end], axis=1)), [
        RAY_COLOUR if h else NO_ECHO_COLOUR for h in heard
    ]


class _RobotArtists:
    """The world on the left axes, with the robot's body, heading, trail and rays over it."""

    def __init__(
        self,
        figure: Figure,
        world: WorldMap,
        robot: RobotConfig,
        target: Sequence[float] | None = None,
    ) -> None:
        self.robot = robot
        self.world_ax, self.side_ax = figure.subplots(
            1, 2, gridspec_kw={"width_ratios": (1.6, 1.0)}
        )
        draw_world(self.world_ax, world, robot_at_start=False, target=target)
        (self.trail,) = self.world_ax.plot(
            [], [], color=ROBOT_COLOUR, linewidth=1.0, alpha=TRAIL_ALPHA
        )
        self.body = Circle((0, 0), robot.radius_m, color=ROBOT_COLOUR, alpha=BODY_ALPHA, zorder=6)
        self.world_ax.add_patch(self.body)
        (self.heading,) = self.world_ax.plot([], [], color="black", linewidth=1.5, zorder=7)
        self.rays = LineCollection([], linewidths=0.8, zorder=5)
        self.world_ax.add_collection(self.rays)
        self.title = self.world_ax.set_title("", fontsize=9)

    @property
    def moving(self) -> list[Artist]:
        return [self.trail, self.body, self.heading, self.rays, self.title]

    def place(self, trail_xy: np.ndarray, pose: np.ndarray, ring_mm: np.ndarray) -> list[str]:
        """The robot at `pose` after the trail (N, 2) metres, its rays from `ring_mm`; each
        ray's colour."""
        self.trail.set_data(trail_xy[:, 0], trail_xy[:, 1])
        x, y, theta = pose
        self.body.center = (x, y)
        reach = 1.5 * self.robot.radius_m
        self.heading.set_data([x, x + reach * math.cos(theta)], [y, y + reach * math.sin(theta)])
        segments, colours = _rays(ring_mm, pose, self.robot)
        self.rays.set_segments(segments)
        self.rays.set_color(colours)
        return colours


class RunFrame:
    """A run's frame: world and robot left, the goal it seeks (if it seeks one) ringed;
    right, the seven perceived velocities of the view the robot chose in against the
    threshold, fast ones green, the one driven framed."""

    def __init__(
        self,
        world: WorldMap,
        robot: RobotConfig,
        threshold: float,
        dpi: float = DPI,
        goal: Sequence[float] | None = None,
    ) -> None:
        figure = Figure(figsize=FIGURE_SIZE_IN, dpi=dpi)
        self.robot = robot
        self.artists = _RobotArtists(figure, world, robot, goal)
        bars_ax = self.artists.side_ax
        names = [t.name for t in robot.trajectories]
        top = np.array(robot.v_max_mps)
        self.bars = bars_ax.bar(names, top, color=SLOW_COLOUR, edgecolor="black")
        self.threshold = velocity_axis(bars_ax, top, threshold)
        self.legend = bars_ax.legend(loc="upper right", fontsize=7)
        self.bars_title = bars_ax.set_title("", fontsize=9)
        figure.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))  # room for the titles
        # The threshold and the legend are drawn over the bars, so they move with them.
        self.blitter = Blitter(
            figure,
            [*self.artists.moving, *self.bars, self.threshold, self.legend, self.bars_title],
        )

    def draw(
        self,
        trail_xy: np.ndarray,
        pose: np.ndarray,
        ring_mm: np.ndarray,
        velocities: np.ndarray | None,
        fast: np.ndarray | None,
        driven: int,
        title: str,
        caption: str,
    ) -> np.ndarray:
        """(H, W, 3) uint8 RGB, valid until the next frame: the trail (N, 2) metres, the
        robot at `pose`, its rays from `ring_mm` (16,), the velocities (7,) m/s perceived
        (NaN or None: none) and the `fast` set, trajectory `driven` (-1: none) framed;
        `title` over the world, `caption` over the velocities."""
        self.artists.place(trail_xy, pose, ring_mm)
        shown = np.zeros(len(self.bars)) if velocities is None else np.nan_to_num(velocities)
        for j, bar in enumerate(self.bars):
            bar.set_height(shown[j])
            bar.set_color(FAST_COLOUR if fast is not None and fast[j] else SLOW_COLOUR)
            bar.set_edgecolor("black")
            bar.set_linewidth(2.5 if j == driven else 0.5)
        self.artists.title.set_text(title)
        self.bars_title.set_text(caption)
        return self.blitter.frame()


def run_title(time_s: float, events: Sequence[str]) -> str:
    """Over the world: the simulated time and the events the step began."""
    return f"{time_s:.1f} s  {' '.join(events)}".rstrip()


def run_caption(rotation: int, driver: str | None) -> str:
    """Over the velocities: the view chosen in, and what drove (a reflex, or the policy)."""
    return f"view {rotation}, driven by {driver or 'policy'}"


class _TraceFrame:
    """A run trace's steps, drawn as RunFrame draws them."""

    def __init__(self, trace: RunTrace, robot: RobotConfig) -> None:
        self.trace = trace
        world = parse_world(trace.world_text, trace.world_name)
        threshold = float(trace.parameters.get("threshold", 0.0))
        self.frame = RunFrame(world, robot, threshold, goal=trace.parameters.get("goal"))
        self.blitter = self.frame.blitter

    def draw(self, step: int) -> np.ndarray:
        arrays, period_s = self.trace.arrays, self.trace.period_s
        reflex = int(arrays["reflex"][step])
        return self.frame.draw(
            arrays["pose"][: step + 1, :2],
            arrays["pose"][step],
            arrays["ring_mm"][step],
            arrays["velocities"][step],
            arrays["fast"][step],
            int(arrays["trajectory"][step]),
            run_title(
                (step + 1) * period_s,
                [e for i, e in enumerate(EVENTS) if int(arrays["events"][step]) & (1 << i)],
            ),
            run_caption(
                int(arrays["rotation"][step]),
                self.trace.reflex_names[reflex] if reflex >= 0 else None,
            ),
        )


class _EpisodeFrame:
    """A learning session's frame: the episode's path so far, and the velocity labels
    learning drew along it (what it taught the FAM), the current exemplar marked."""

    def __init__(self, session: Session) -> None:
        self.robot = session.robot_config
        known = {f.name for f in fields(TrainParams)}
        self.params = TrainParams(**{k: v for k, v in session.parameters.items() if k in known})
        figure = Figure(figsize=FIGURE_SIZE_IN, dpi=DPI)
        world = parse_world(session.world_text, session.world_name)
        self.artists = _RobotArtists(figure, world, self.robot)
        self.labels_ax = self.artists.side_ax
        (self.curve,) = self.labels_ax.plot([], [], color=FAST_COLOUR)
        (self.marker,) = self.labels_ax.plot([], [], "o", color="black")
        self.labels_ax.set_xlabel("distance along the trajectory (m)")
        self.labels_ax.set_ylabel("velocity label (m/s)")
        self.labels_ax.set_ylim(0.0, 1.05 * max(self.robot.v_max_mps))
        self.labels_title = self.labels_ax.set_title("", fontsize=9)
        figure.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))  # room for the titles
        # Each episode has a length of its own: the distance axis moves with the frames.
        self.blitter = Blitter(
            figure,
            [
                *self.artists.moving,
                self.curve,
                self.marker,
                self.labels_title,
                self.labels_ax.xaxis,
            ],
        )
        self._labelled: tuple[Episode, np.ndarray] | None = None

    def draw(self, exemplar: tuple[Episode, int]) -> np.ndarray:
        episode, i = exemplar
        self.artists.place(episode.pose[: i + 1, :2], episode.pose[i], episode.ring_mm[i])
        labels = self._labels(episode)
        self.curve.set_data(episode.arc_m, labels)
        self.marker.set_data([episode.arc_m[i]], [labels[i]])
        self.labels_ax.set_xlim(0.0, max(float(episode.arc_m[-1]), 0.1))
        name = self.robot.trajectories[episode.trajectory].name
        ending = "a bump" if episode.bumped else "a near collision" if episode.collided else "free"
        self.artists.title.set_text(f"episode {episode.index}: learning {name}, ended {ending}")
        self.labels_title.set_text(f"ends at {episode.end_time_s:.1f} s")
        return self.blitter.frame()

    def _labels(self, episode: Episode) -> np.ndarray:
        """The episode's labels, worked out once for all its frames."""
        if self._labelled is None or self._labelled[0] is not episode:
            self._labelled = (episode, episode_labels(episode, self.robot, self.params))
        return self._labelled[1]


class RobotFrame:
    """A robot being stepped now, drawn as a run's replay frames are: the world, the body, its
    trail and sonar rays on the left; on the right each sonar's range, where the replay shows
    perception (a caller stepping the simulator itself has no FAM's view to show)."""

    def __init__(self, world: WorldMap, robot: RobotConfig, dpi: float = DPI) -> None:
        figure = Figure(figsize=FIGURE_SIZE_IN, dpi=dpi)
        self.artists = _RobotArtists(figure, world, robot)
        ranges_ax = self.artists.side_ax
        count = robot.sonar.count
        self.bars = ranges_ax.bar(np.arange(count), np.zeros(count), edgecolor="black")
        ranges_ax.set_xticks(np.arange(0, count, 4), [f"S{k}" for k in range(0, count, 4)])
        ranges_ax.set_ylim(0.0, 1.05 * robot.sonar.max_range_m)
        ranges_ax.set_ylabel("sonar range (m)")
        self.ranges_title = ranges_ax.set_title("", fontsize=9)
        figure.tight_layout(rect=(0.0, 0.0, 1.0, 0.95))  # room for the titles
        self.blitter = Blitter(figure, [*self.artists.moving, *self.bars, self.ranges_title])

    def draw(
        self, trail_xy: np.ndarray, pose: np.ndarray, ring_m: np.ndarray, title: str, caption: str
    ) -> np.ndarray:
        """(H, W, 3) uint8 RGB of the trail (N, 2) metres so far, the robot at `pose` and its
        ring (16,) metres; `title` over the world, `caption` over the ranges."""
        colours = self.artists.place(trail_xy, pose, ring_m * 1000.0)
        for bar, range_m, colour in zip(self.bars, ring_m, colours, strict=True):
            bar.set_height(range_m)
            bar.set_facecolor(colour)
        self.artists.title.set_text(title)
        self.ranges_title.set_text(caption)
        return self.blitter.frame().copy()
