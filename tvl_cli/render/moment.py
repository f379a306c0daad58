"""A picture of one moment of a run (`tvl explain --png`): where the robot was and what its
sonar ring read, what it perceived and chose, and the FAM rules that made it so.

Left, the world near the robot: its path so far from the start (a small triangle), its
body, the rays of the ring, and the seven trajectories drawn from it in the view it chose
in, each as long as two seconds at the velocity it perceived, the fast ones green and the
one driven thick, and dotted on to its name, the names fanned out around the robot. Top
right, the perceived velocities against the threshold; bottom right, the strongest of the
rules that fired for the trajectories explained, each rule's words wrapped to its panel.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import Protocol

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from matplotlib.text import Text

from tvl_cli.core.fired_rules import Explanation, FiredRule
from tvl_cli.core.ring import beam_lines
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.render.animate import FAST_COLOUR, NO_ECHO_COLOUR, RAY_COLOUR, SLOW_COLOUR
from tvl_cli.render.formats import save_picture
from tvl_cli.render.plot import ROBOT_COLOUR, draw_world, velocity_axis
from tvl_cli.sim.worldmap import WorldMap

PERCEIVED_COLOUR = "#17becf"  # an echo the memory remembered, nearer than the live reading
AHEAD_S = 2.0  # a trajectory is drawn as far as two seconds at its perceived velocity
# Each trajectory's name stands on its course where that is this far from the robot (the
# tightest turns: where they come farthest): out there the seven courses have fanned apart
# by more than a name is wide, where at the ends of the slow ones they all crowd the body.
NAME_REACH_M = 1.2
NAME_ROOM_M = 0.3  # the view reaches this far beyond a name, for the width of its text
NEAR_M = 3.0  # the world is shown this far around the robot (less where it ends)
MOST_RULES = 10  # the strongest rules listed
RULE_FONT_PT = 7.0
MOMENT_DPI = 110


class ExplainedStep(Protocol):
    """What a picture of a moment reads of its explanation (commands.explain's)."""

    @property
    def step(self) -> int: ...
    @property
    def time_s(self) -> float: ...
    @property
    def ring_m(self) -> list[float] | None: ...
    @property
    def perceived_m(self) -> list[float] | None: ...
    @property
    def rotation(self) -> int: ...
    @property
    def velocities_mps(self) -> list[float | None]: ...
    @property
    def fast(self) -> list[str]: ...
    @property
    def choice(self) -> str | None: ...
    @property
    def driven(self) -> str | None: ...
    @property
    def reflex(self) -> str | None: ...
    @property
    def events(self) -> list[str]: ...
    @property
    def focus(self) -> tuple[str, ...]: ...
    @property
    def why(self) -> Explanation | None: ...


def render_moment(
    world: WorldMap,
    robot: RobotConfig,
    poses: np.ndarray,
    threshold: float,
    moment: ExplainedStep,
    path: Path,
    goal: Sequence[float] | None = None,
) -> None:
    """Draw the moment: the robot at the last of `poses` (N, 3) after the others, the run's
    `threshold` (a fraction of each trajectory's maximum), the `goal` it sought if any."""
    figure = moment_figure(world, robot, poses, threshold, moment, goal)
    save_picture(figure, path, dpi=MOMENT_DPI)


def moment_figure(
    world: WorldMap,
    robot: RobotConfig,
    poses: np.ndarray,
    threshold: float,
    moment: ExplainedStep,
    goal: Sequence[float] | None = None,
) -> Figure:
    """The picture `render_moment` saves."""
    # At the dpi it is saved at: the rules are folded to the panel's width as laid out here.
    figure = Figure(figsize=(13.0, 7.0), dpi=MOMENT_DPI, layout="constrained")
    FigureCanvasAgg(figure)
    grid = figure.add_gridspec(2, 2, width_ratios=(1.1, 1.0), height_ratios=(1.0, 1.2))
    world_ax = figure.add_subplot(grid[:, 0])
    draw_world(world_ax, world, robot_at_start=False, target=goal)
    _draw_robot(world_ax, world, robot, poses, moment)
    _draw_velocities(figure.add_subplot(grid[0, 1]), robot, threshold, moment)
    rules_ax = figure.add_subplot(grid[1, 1])
    sentences = _draw_rules(rules_ax, moment)
    acted = moment.reflex or ("the policy" if moment.choice else "none")
    happened = f", began {', '.join(moment.events)}" if moment.events else ""
    figure.suptitle(
        f"step {moment.step}, ending at {moment.time_s:.1f} s: chose "
        f"{moment.choice or 'nothing'}, drove {moment.driven or 'no trajectory'}, "
        f"acting: {acted}{happened}",
        fontsize=11,
    )
    # Laid out once, the rules' panel has its width, and each rule is wrapped to fit it. The
    # rules are left out of the layout, which is thus the same when the picture is saved.
    figure.draw_without_rendering()
    _wrap_within(rules_ax, sentences)
    return figure


def _draw_robot(
    ax: Axes, world: WorldMap, robot: RobotConfig, poses: np.ndarray, moment: ExplainedStep
) -> None:
    """Over the world drawn: the robot, its path, ring and trajectories, near it."""
    ax.plot(poses[:, 0], poses[:, 1], color=ROBOT_COLOUR, linewidth=1.0, alpha=0.5)
    pose = poses[-1]
    x, y, heading = pose
    ax.add_patch(Circle((x, y), robot.radius_m, color=ROBOT_COLOUR, alpha=0.5, zorder=6))
    reach = 1.5 * robot.radius_m
    ax.plot(
        [x, x + reach * math.cos(heading)],
        [y, y + reach * math.sin(heading)],
        color="black",
        linewidth=1.5,
        zorder=7,
    )
    if moment.ring_m is not None:
        ring = np.array(moment.ring_m)  # (16,) metres
        start, end = beam_lines(ring, pose, robot.radius_m)
        heard = ring < robot.sonar.max_range_m
        ax.add_collection(
            LineCollection(
                list(np.stack([start, end], axis=1)),
                colors=[RAY_COLOUR if h else NO_ECHO_COLOUR for h in heard],
                linewidths=0.9,
                zorder=5,
            )
        )
        if moment.perceived_m is not None:
            perceived = np.array(moment.perceived_m)
            nearer = perceived < ring
            _, remembered = beam_lines(perceived, pose, robot.radius_m)
            if nearer.any():
                ax.plot(
                    remembered[nearer, 0],
                    remembered[nearer, 1],
                    "o",
                    color=PERCEIVED_COLOUR,
                    markersize=4,
                    zorder=6,
                    label="remembered echo",
                )
    names = _draw_trajectories(ax, robot, pose, moment)  # (K, 2) metres
    # Near the robot, as far as the world goes and its trajectories' names wherever they are.
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    named = np.vstack([names - NAME_ROOM_M, names + NAME_ROOM_M, [[x, y]]])  # (2K + 1, 2)
    ax.set_xlim(
        min(max(x - NEAR_M, x0), named[:, 0].min()), max(min(x + NEAR_M, x1), named[:, 0].max())
    )
    ax.set_ylim(
        min(max(y - NEAR_M, y0), named[:, 1].min()), max(min(y + NEAR_M, y1), named[:, 1].max())
    )
    ax.legend(loc="best", fontsize=8)  # the start, and any remembered echoes
    for text in ax.texts:  # the scale bar's label, where the view is cut
        text.set_clip_on(True)
    ax.set_title(f"{world.name}: the ring, and the trajectories in view {moment.rotation}")


def _draw_trajectories(
    ax: Axes, robot: RobotConfig, pose: np.ndarray, moment: ExplainedStep
) -> np.ndarray:
    """Each trajectory from the body's centre, turned to the chosen view, as far as
    AHEAD_S seconds at its perceived velocity, and dotted on along its course to its name
    (NAME_REACH_M from the robot). Where the names stand, (K, 2) metres."""
    facing = pose[2] + 2.0 * math.pi * moment.rotation / robot.sonar.count
    names = []
    for trajectory, velocity in zip(robot.trajectories, moment.velocities_mps, strict=True):
        if velocity is None:
            continue
        k = trajectory.curvature_per_m
        colour = FAST_COLOUR if trajectory.name in moment.fast else SLOW_COLOUR
        driven = trajectory.name == (moment.driven or moment.choice)
        xs, ys = _course(pose[:2], facing, k, np.linspace(0.0, AHEAD_S * velocity, 40))
        ax.plot(xs, ys, color=colour, linewidth=3.0 if driven else 1.5, zorder=8 if driven else 4)
        xs, ys = _course(pose[:2], facing, k, np.linspace(0.0, _name_arc_m(k), 60))
        ax.plot(xs, ys, color=colour, linewidth=1.0, linestyle=":", zorder=3)
        ax.text(
            xs[-1],
            ys[-1],
            trajectory.name,
            fontsize=7,
            ha="center",
            va="center",
            zorder=9,
            bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.8, "lw": 0},
        )
        names.append((xs[-1], ys[-1]))
    return np.array(names).reshape(-1, 2)


def _course(
    start_xy: np.ndarray, facing: float, curvature_per_m: float, arc_m: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The points `arc_m` (N,) metres along a trajectory of that curvature from `start_xy`
    heading `facing`: their xs and ys (N,)."""
    k = curvature_per_m
    ahead = np.sin(k * arc_m) / k if k else arc_m
    aside = (1.0 - np.cos(k * arc_m)) / k if k else np.zeros_like(arc_m)
    x, y = start_xy
    return (
        x + ahead * math.cos(facing) - aside * math.sin(facing),
        y + ahead * math.sin(facing) + aside * math.cos(facing),
    )


def _name_arc_m(curvature_per_m: float) -> float:
    """How far along a course its name stands: where it is NAME_REACH_M from its start, or
    for a turn too tight to come that far, half way round, where it comes farthest."""
    k = abs(curvature_per_m)
    if k == 0.0:
        return NAME_REACH_M
    # A chord of an arc of length s on a circle of radius 1/k is 2/k sin(k s / 2).
    return 2.0 / k * math.asin(min(1.0, NAME_REACH_M * k / 2.0))


def _draw_velocities(ax: Axes, robot: RobotConfig, threshold: float, moment: ExplainedStep) -> None:
    names = [t.name for t in robot.trajectories]
    top = np.array(robot.v_max_mps)
    shown = [0.0 if v is None else v for v in moment.velocities_mps]
    bars = ax.bar(
        names,
        shown,
        color=[FAST_COLOUR if n in moment.fast else SLOW_COLOUR for n in names],
        edgecolor="black",
    )
    for name, bar in zip(names, bars, strict=True):
        bar.set_linewidth(2.5 if name == (moment.driven or moment.choice) else 0.5)
    velocity_axis(ax, top, threshold)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"perceived; fast: {', '.join(moment.fast) or 'none'}", fontsize=10)


def _draw_rules(ax: Axes, moment: ExplainedStep) -> list[Text]:
    """The strongest fired rules as bars of their strength, each read as a sentence (not
    yet wrapped: the sentences)."""
    why = moment.why
    ax.set_xlim(0.0, 1.0)
    ax.set_xlabel("rule strength")
    ax.set_yticks([])
    if why is None or not why.rules:
        ax.text(0.5, 0.5, "the ring was not read: no rule fired", ha="center", va="center")
        ax.set_title("fired rules", fontsize=10)
        return []
    inputs: dict[str, list[str]] = {}
    for reading in why.inputs:
        inputs.setdefault(reading.table, []).append(reading.name)
    rules = sorted(why.rules, key=lambda rule: -rule.strength)[:MOST_RULES]
    rows = np.arange(len(rules))[::-1]  # the strongest at the top
    ax.barh(rows, [r.strength for r in rules], color="#dddddd", edgecolor="#999999")
    sentences = [
        ax.text(0.01, row, _sentence(inputs[rule.table], rule), va="center", fontsize=RULE_FONT_PT)
        for row, rule in zip(rows, rules, strict=True)
    ]
    for sentence in sentences:
        sentence.set_in_layout(False)
    ax.set_ylim(-0.6, max(len(rules), 4) - 0.4)
    focus = " and ".join(moment.focus) or "every trajectory"
    ax.set_title(
        f"the {len(rules)} strongest of {len(why.rules)} fired rules, for {focus}", fontsize=10
    )
    return sentences


def _wrap_within(ax: Axes, sentences: Sequence[Text]) -> None:
    """Each of the `sentences` folded at spaces onto as many lines as keep it within the
    axes, as they are laid out now."""
    renderer = ax.figure.canvas.get_renderer()  # type: ignore[attr-defined]
    pad_px = 2.0 * RULE_FONT_PT * ax.figure.dpi / 72.0  # clear of the frame at any dpi
    for sentence in sentences:
        words = sentence.get_text()
        room_px = ax.bbox.x1 - sentence.get_window_extent(renderer).x0 - pad_px
        columns = len(words)
        while sentence.get_window_extent(renderer).width > room_px and columns > 1:
            # The width a character takes on average, from the width the text takes now.
            wide_px = sentence.get_window_extent(renderer).width
            longest = max(len(line) for line in sentence.get_text().splitlines())
            columns = min(columns - 1, int(longest * room_px / wide_px))
            # The rule's THEN on a line of its own before the IF is folded any further.
            clauses = words.replace(" THEN ", "\nTHEN ").splitlines()
            sentence.set_text(
                "\n".join(
                    textwrap.fill(clause, max(columns, 1), break_long_words=False)
                    for clause in clauses
                )
            )


def _sentence(names: Sequence[str], rule: FiredRule) -> str:
    """A fired rule as `tvl inspect` reads one, its table's inputs `names`."""
    condition = " AND ".join(f"{n} is {s}" for n, s in zip(names, rule.set_names, strict=True))
    then = ", ".join(
        f"{t} = {v:.2f} m/s" for t, v in zip(rule.trajectories, rule.velocities_mps, strict=True)
    )
    return f"IF {condition} THEN {then}"
