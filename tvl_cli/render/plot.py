"""matplotlib pictures of worlds, drawn on a Figure of our own (never pyplot's global state)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle, PathPatch, Rectangle
from matplotlib.path import Path as DrawPath

from tvl_cli.analysis.surface import Surface
from tvl_cli.core.behaviours import GOAL_RADIUS_M
from tvl_cli.core.contacts import BACKOFF, BUMP, NEAR_MISS, steps_beginning
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.core.words import counted
from tvl_cli.render.formats import save_picture
from tvl_cli.sim.worldmap import WorldMap

WALL_COLOUR = "#2b2b2b"
SOLID_COLOUR = "#c8c8c8"  # wall and furniture material behind the outlines
PILLAR_COLOUR = "#8c8c8c"
ROBOT_COLOUR = "#1f77b4"
GOAL_COLOUR = "#f2b701"
TARGET_COLOUR = "crimson"  # the goal a run seeks, and how near counts as reached
OTHER_GOAL_COLOUR = "#8c8c8c"  # the world's goals a run does not seek
START_COLOUR = "#555555"  # where a picture of the robot itself marks the start
WALL_WIDTH_PT = 3.0
UNTRAINED_HATCH = "////"  # over a velocity no exemplar taught
FIGURE_WIDTH_IN = 7.0
MARGIN_M = 0.25  # room around the world for the scale bar and the wall line width


def draw_world(
    ax: Axes,
    world: WorldMap,
    robot_at_start: bool = True,
    target: Sequence[float] | None = None,
    robot_radius_m: float = DEFAULT_ROBOT.radius_m,
) -> None:
    """Walls, pillars, ring walls, the start pose and the goals, in metres on equal axes.

    The start is drawn as the robot standing there; where the picture draws the robot
    itself (a moment of a run, a replay's frames), `robot_at_start` False marks it instead
    with a small open triangle pointing the way the robot started, so that only the robot
    looks like one. A run that seeks the goal `target` (X, Y) draws it ringed at the distance
    that counts as reached, and the world's other goals hollow."""
    x0, y0 = world.origin_m  # the map's frame: the axes read its coordinates
    ax.add_patch(Rectangle((x0, y0), world.width_m, world.height_m, color=SOLID_COLOUR, lw=0))
    ax.add_patch(PathPatch(_floor(world), facecolor="white", lw=0))
    walls = [((x1, y1), (x2, y2)) for x1, y1, x2, y2 in world.segments]
    ax.add_collection(
        LineCollection(walls, colors=WALL_COLOUR, linewidths=WALL_WIDTH_PT, capstyle="projecting")
    )
    for x, y, r in world.discs:
        ax.add_patch(Circle((x, y), r, facecolor=PILLAR_COLOUR, edgecolor=WALL_COLOUR, lw=1))
    for x, y, r in world.rings:
        ax.add_patch(Circle((x, y), r, fill=False, edgecolor=WALL_COLOUR, lw=WALL_WIDTH_PT))

    if robot_at_start:
        _draw_robot_at_start(ax, world.start, robot_radius_m)
    else:
        _mark_start(ax, world.start)
    others = [goal for goal in world.goals if target is None or tuple(goal) != tuple(target)]
    if others:
        gx, gy = zip(*others, strict=True)
        ax.plot(
            gx,
            gy,
            linestyle="none",
            marker="*",
            markersize=14,
            color=GOAL_COLOUR if target is None else "none",
            markeredgecolor="black" if target is None else OTHER_GOAL_COLOUR,
            markeredgewidth=0.6 if target is None else 1.0,
        )
    if target is not None:
        _mark_target(ax, (float(target[0]), float(target[1])))

    # A 1 m scale bar under the bottom-left corner.
    bar_y = y0 - 0.6 * MARGIN_M
    ax.plot([x0, x0 + 1], [bar_y, bar_y], color="black", lw=2, solid_capstyle="butt")
    ax.text(x0 + 0.5, bar_y - 0.05, "1 m", ha="center", va="top", fontsize=8)

    ax.set_xlim(x0 - MARGIN_M, x0 + world.width_m + MARGIN_M)
    ax.set_ylim(y0 - 2.5 * MARGIN_M, y0 + world.height_m + MARGIN_M)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(world.name)


def _draw_robot_at_start(ax: Axes, start: tuple[float, float, float], radius: float) -> None:
    x, y, heading = start
    ax.add_patch(Circle((x, y), radius, facecolor=ROBOT_COLOUR, alpha=0.25, lw=0))
    ax.add_patch(Circle((x, y), radius, fill=False, edgecolor=ROBOT_COLOUR, lw=1.5))
    ax.annotate(
        "",
        xy=(x + 2 * radius * math.cos(heading), y + 2 * radius * math.sin(heading)),
        xytext=(x, y),
        arrowprops={"arrowstyle": "-|>", "color": ROBOT_COLOUR, "lw": 2, "mutation_scale": 15},
    )


def _mark_target(ax: Axes, goal: tuple[float, float]) -> None:
    """The goal a run seeks: a star ringed at the distance that counts as reached."""
    ax.add_patch(
        Circle(goal, GOAL_RADIUS_M, fill=False, edgecolor=TARGET_COLOUR, lw=1.5, ls="--", zorder=3)
    )
    ax.plot(
        *goal,
        linestyle="none",
        marker="*",
        markersize=16,
        color=GOAL_COLOUR,
        markeredgecolor=TARGET_COLOUR,
        markeredgewidth=1.2,
        zorder=6,
    )


def _mark_start(ax: Axes, start: tuple[float, float, float]) -> None:
    x, y, heading = start
    ax.plot(
        [x],
        [y],
        linestyle="none",
        # A triangle points up unturned; turned counter-clockwise to the start heading.
        marker=(3, 0, math.degrees(heading) - 90.0),
        markersize=7,
        markerfacecolor="none",
        markeredgecolor=START_COLOUR,
        markeredgewidth=1.2,
        zorder=3,
        label="start",
    )


def _floor(world: WorldMap) -> DrawPath:
    """The wall outline chained into loops; filled even-odd, it is the open floor."""
    outgoing: dict[tuple[float, float], list[tuple[float, float]]] = {}
    for x1, y1, x2, y2 in world.segments:
        outgoing.setdefault((x1, y1), []).append((x2, y2))
    vertices: list[tuple[float, float]] = []
    codes: list[int] = []  # DrawPath.MOVETO / LINETO, one per vertex
    while outgoing:
        point = next(iter(outgoing))
        vertices.append(point)
        codes.append(int(DrawPath.MOVETO))
        while point in outgoing:  # an outline vertex has as many ways out as in
            ends = outgoing[point]
            following = ends.pop()
            if not ends:
                del outgoing[point]
            point = following
            vertices.append(point)
            codes.append(int(DrawPath.LINETO))
    if not vertices:
        return DrawPath([(0.0, 0.0)])
    return DrawPath(vertices, codes)


def _world_figure(
    world: WorldMap,
    extra_width_in: float = 0.0,
    target: Sequence[float] | None = None,
    robot: RobotConfig = DEFAULT_ROBOT,
) -> tuple[Figure, Axes]:
    aspect = (world.height_m + 3.5 * MARGIN_M) / (world.width_m + 2 * MARGIN_M)
    figure = Figure(figsize=(FIGURE_WIDTH_IN + extra_width_in, FIGURE_WIDTH_IN * aspect + 0.8))
    FigureCanvasAgg(figure)
    ax = figure.add_subplot()
    draw_world(ax, world, target=target, robot_radius_m=robot.radius_m)
    return figure, ax


def _save(figure: Figure, png_path: str | Path) -> None:
    """In the format the file's extension names (PNG for .png), cropped to what is drawn."""
    save_picture(figure, png_path, dpi=120, bbox_inches="tight")


def render_world(world: WorldMap, png_path: str | Path) -> None:
    """Write a picture of the world."""
    figure, _ = _world_figure(world)
    _save(figure, png_path)


# How each event a path marks is drawn: (matplotlib marker, colour, size, legend noun).
PATH_MARKS: dict[str, tuple[str, str, float, str]] = {
    BUMP: ("x", "red", 8, "collision"),
    NEAR_MISS: ("^", "darkorange", 6, "near miss"),
    BACKOFF: (".", "purple", 5, "back-off"),
}


def render_recorded_path(
    world: WorldMap,
    column: Callable[[str], np.ndarray],
    png: Path,
    title: str,
    goal: tuple[float, float] | None,
    robot: RobotConfig = DEFAULT_ROBOT,
) -> None:
    """The picture of a driven path from its recorded columns (`column(name)`: `pose`,
    `speed_mps`, `events`), coloured by speed, its events marked, the goal it sought: the
    `--png` of `tvl run` and `tvl baseline`."""
    marks = path_marks(column("events"))
    poses, speeds = column("pose"), column("speed_mps")
    render_path(world, poses, speeds, marks, png, title=title, goal=goal, robot=robot)


def render_path(
    world: WorldMap,
    poses: Sequence[Sequence[float]] | np.ndarray,
    speeds_mps: Sequence[float] | np.ndarray,
    marks: dict[str, np.ndarray],
    png_path: str | Path,
    title: str,
    goal: tuple[float, float] | None = None,
    robot: RobotConfig = DEFAULT_ROBOT,
) -> None:
    """The world with a path coloured by speed (from stopped to `robot`'s top speed), and the
    steps where events began (`marks`: step indices by event, of PATH_MARKS) marked where the
    robot then was."""
    figure, ax = _world_figure(world, extra_width_in=1.2, target=goal, robot=robot)
    xy = np.asarray(poses, dtype=np.float64).reshape(-1, 3)[:, :2]  # (N, 2) metres
    speed = np.abs(np.asarray(speeds_mps, dtype=np.float64))
    if len(xy) > 1:
        segments = np.stack([xy[:-1], xy[1:]], axis=1)  # (N-1, 2, 2)
        lines = LineCollection(list(segments), cmap="viridis", linewidths=1.6, zorder=4)
        lines.set_array(speed[1:])
        lines.set_clim(0.0, max(robot.v_max_mps))
        ax.add_collection(lines)
        figure.colorbar(lines, ax=ax, label="speed (m/s)", shrink=0.8)
    for event, steps in marks.items():
        marker, colour, size, noun = PATH_MARKS[event]
        if len(steps):
            ax.plot(
                xy[steps, 0],
                xy[steps, 1],
                marker,
                linestyle="none",
                color=colour,
                markersize=size,
                zorder=5,
                label=counted(len(steps), noun),
            )
    if any(len(steps) for steps in marks.values()):
        ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title)
    _save(figure, png_path)


def velocity_axis(ax: Axes, top: np.ndarray, threshold: float) -> LineCollection:
    """The perceived velocities' axis: each trajectory's threshold share of its top speed
    dashed over its bar, the scale to just above the fastest. Returns the dashes."""
    dashes = ax.hlines(
        threshold * top,
        np.arange(len(top)) - 0.4,
        np.arange(len(top)) + 0.4,
        colors="black",
        linestyles="dashed",
        linewidth=1.0,
        label=f"threshold {threshold:g}",
    )
    ax.set_ylim(0.0, 1.05 * top.max())
    ax.set_ylabel("perceived velocity (m/s)")
    return dashes


def path_marks(events: np.ndarray) -> dict[str, np.ndarray]:
    """The steps a path picture marks, from per-step event bits."""
    return {event: steps_beginning(events, event) for event in PATH_MARKS}


def bump_marks(bumped: np.ndarray) -> dict[str, np.ndarray]:
    """The collisions alone, where only the bump sensor was recorded: the steps it closed."""
    return {BUMP: np.flatnonzero(np.diff(np.asarray(bumped, dtype=np.int8), prepend=0) > 0)}


def render_paths(
    world: WorldMap, paths: Sequence[np.ndarray], png_path: str | Path, title: str
) -> None:
    """The world with several paths (N, 2+) drawn one colour each, e.g. learning episodes."""
    figure, ax = _world_figure(world)
    for path in paths:
        ax.plot(path[:, 0], path[:, 1], linewidth=0.6, alpha=0.7, zorder=4)
    ax.set_title(title)
    _save(figure, png_path)


def render_learning_curves(
    minutes: np.ndarray,
    columns: Sequence[str],
    coverage: Sequence[float],
    png_path: str | Path,
    title: str,
) -> None:
    """ΔV, collisions, episodes and coverage per learning minute, one panel each, from (M, k)
    rows and the M coverage fractions at the minutes' ends."""
    figure = Figure(figsize=(6.4, 7.6))
    FigureCanvasAgg(figure)
    minute = minutes[:, columns.index("minute")] + 1
    panels = [
        (minutes[:, columns.index(name)], label)
        for name, label in (
            ("delta_v", "ΔV (m/s per step)"),
            ("collisions", "collisions"),
            ("episodes", "episodes"),
        )
    ]
    panels.append((100.0 * np.asarray(coverage), "coverage (%)"))
    for panel, (values, label) in enumerate(panels, start=1):
        ax = figure.add_subplot(len(panels), 1, panel)
        ax.plot(minute, values, marker="o", markersize=3)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    ax.set_ylim(0, 100)
    ax.set_xlabel("learning minute")
    figure.suptitle(title)
    _save(figure, png_path)


def render_surfaces(surfaces: Sequence[Surface], png_path: str | Path, title: str) -> None:
    """One panel per trajectory: its learnt velocity over two inputs, on one colour scale,
    hatched where it learnt nothing; a trajectory whose table does not read an input says so
    over its panel."""
    columns = min(len(surfaces), 4)
    rows = math.ceil(len(surfaces) / columns)
    figure = Figure(figsize=(3.0 * columns + 1.0, 2.8 * rows + 0.9), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(rows, columns, squeeze=False)
    top = max(float(s.velocity_mps.max()) for s in surfaces) or 1.0
    mesh = None
    for ax, surface in zip(axes.flat, surfaces, strict=False):
        ranges = surface.ranges_m
        mesh = ax.pcolormesh(
            ranges, ranges, surface.velocity_mps, vmin=0.0, vmax=top, cmap="viridis"
        )
        if surface.untrained.any():
            ax.contourf(
                ranges,
                ranges,
                surface.untrained.astype(float),
                levels=[0.5, 1.5],
                colors="none",
                hatches=[UNTRAINED_HATCH],
            )
        unread = f" (reads no {' or '.join(surface.unread)})" if surface.unread else ""
        ax.set_title(f"{surface.trajectory}{unread}", fontsize=9 if unread else 10)
        ax.set_xlabel(f"{surface.over[0]} (m)", fontsize=8)
        ax.set_ylabel(f"{surface.over[1]} (m)", fontsize=8)
        ax.set_aspect("equal")
    for ax in list(axes.flat)[len(surfaces) :]:
        ax.set_visible(False)
    assert mesh is not None
    figure.colorbar(mesh, ax=axes, label="learnt velocity (m/s)", shrink=0.8)
    figure.suptitle(
        f"{title}\nhatched: untrained, at the velocity every entry started at", fontsize=10
    )
    _save(figure, png_path)
