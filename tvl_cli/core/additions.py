"""The registry of what we added to the paper's method, or changed in it: each entry names
the Method field it changes, the flag that sets it, its row of the documentation's table
(docs/method.md, written by docs/additions_table.py), and its ablation setting (the paper's
value, which turns it off)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from tvl_cli.core.labels import BUMP_LABELS, DEFAULT_DECEL_MPS2, DEFAULT_MARGIN_M, HEARD_LABELS
from tvl_cli.core.memory import CLEARED_ABOVE_M, DEFAULT_MEMORY, NO_MEMORY
from tvl_cli.core.method import (
    BLOCKED_WAYS,
    BUMP,
    DEFAULT,
    DEFAULT_NEAR_M,
    ESCAPE,
    GOAL_WARD,
    LEAST_EXPERIENCE,
    NEAR_MISS,
    NOVELTY,
    PAPER,
    TIE,
    WALL_START,
    Method,
    shown_setting,
)


@dataclass(frozen=True, slots=True)
class Addition:
    """One thing we added to the paper's method, or changed in it."""

    name: str
    field: str  # the Method field it changes
    flag: str  # the option that sets that field
    on: str  # how to turn it on, as the flag's value
    row: str  # what it does and why: its row of the documentation's table
    off: Any  # its ablation setting: the field's value that turns it off, the paper's
    # Why DEFAULT leaves it off, when it does: offered as a choice, not made ours.
    not_default: str = ""

    def is_on(self, method: Method) -> bool:
        value = getattr(method, self.field)
        if self.field == "reflexes":
            return self.on in value
        return bool(value != self.off)


ADDITIONS: tuple[Addition, ...] = (
    Addition(
        "gentle labels",
        "decel_mps2",
        "--decel",
        f"{DEFAULT_DECEL_MPS2:g}",
        f"Labels brake at {DEFAULT_DECEL_MPS2:g} m/s², more gently than the rate read off "
        "the paper's Figure 21: a horizon long enough to turn away within (T0 stays fast "
        "until 1.6 m from a wall at threshold 0.85) for a robot that also remembers echoes "
        "and backs off.",
        PAPER.decel_mps2,
    ),
    Addition(
        "blind-zone margin",
        "margin_m",
        "--margin",
        f"{DEFAULT_MARGIN_M:g}",
        f"Labels stop {DEFAULT_MARGIN_M:g} m short of the collision point, the sonar's minimum "
        "range: no speed is learnt for the stretch the ring cannot tell from touching.",
        PAPER.margin_m,
    ),
    Addition(
        "heard labels",
        "labels",
        "--labels",
        HEARD_LABELS,
        "Every recorded point labels all seven trajectories, each from where the body would "
        "come within 0.15 m of the echoes heard from 10 s before the point to 10 s after "
        "it, placed by "
        "odometry (the paper's §2 'accumulated sensor data and odometry'); the driven one "
        "keeps the collision point it met. Points recorded while behaving (`tvl run "
        "--learn-log`) are labelled so too, the driven one no farther than its stretch's "
        "own estimate.",
        BUMP_LABELS,
    ),
    Addition(
        "label headroom",
        "label_ceiling",
        "--label-ceiling",
        f"{DEFAULT.label_ceiling:g}",
        f"Labels run past the trajectory's top speed, up to {DEFAULT.label_ceiling:g} times "
        "it, where a way is clear far beyond its stopping distance: the average a FAM rule "
        "learns of a cluttered place, some ways clear far and some blocked, can then reach "
        "the fast threshold, where capped labels rate the long ways slow. The robot still "
        "drives no faster than the top speed.",
        PAPER.label_ceiling,
    ),
    Addition(
        "headroom on the tight arcs",
        "label_ceiling_radius_m",
        "--label-ceiling-radius",
        f"{DEFAULT.label_ceiling_radius_m:g}",
        f"Only the arcs turning no wider than {DEFAULT.label_ceiling_radius_m:g} m (T2 and T3 "
        "each way) are labelled past their top speed; the wider arcs and the straight way "
        "stay capped. The tight arcs' labels stop changing nearest (0.83 m along T3 at its top "
        "speed, 2.15 m along T0), so theirs are the rules the cap holds under the threshold "
        "most; lifting the long ways too made the robot meet things more without making it "
        "more competent.",
        PAPER.label_ceiling_radius_m,
    ),
    Addition(
        "sonar collision points",
        "near_m",
        "--near",
        f"{DEFAULT_NEAR_M:g}",
        "Learning marks a collision point where a sonar facing ahead, having closed in, reads "
        f"{DEFAULT_NEAR_M:g} m, before any bump: a wall the arc meets alongside, unseen by the "
        "specular ring, counts too (the paper's §5.1 note: collision points further from "
        "objects).",
        0.0,
    ),
    Addition(
        "novelty exploration",
        "exploration",
        "--explore",
        NOVELTY,
        "Learning follows the least experienced of the pairs leading where odometry has not "
        "been, where the paper (§5.2) saw its rule keep to small parts of cluttered worlds.",
        LEAST_EXPERIENCE,
        not_default="it covers more of generated worlds but made no FAM competent sooner",
    ),
    Addition(
        "blocked ways",
        "reflexes",
        "--reflex",
        BLOCKED_WAYS,
        "After a bump or a near miss, the way the robot drove stays out of every choice for "
        "2 s after backing off: what it cannot see (a convex corner) is still there.",
        (),
    ),
    Addition(
        "near-miss back-off",
        "reflexes",
        "--reflex",
        NEAR_MISS,
        "An object inside the ring's 0.15 m blind zone ahead: reverse 0.15 m along the arc, "
        "as after a bump, before touching it.",
        (),
    ),
    Addition(
        "bump back-off",
        "reflexes",
        "--reflex",
        BUMP,
        "A bump while driving forward: reverse 0.15 m along the arc, as learning does; "
        "without it a policy still rating the way fast pushes on.",
        (),
    ),
    Addition(
        "escape by following walls",
        "reflexes",
        "--reflex",
        ESCAPE,
        "Goal seeking that has come no nearer the goal for 20 s follows walls instead, on the "
        "left for 15 s, then on the right for twice as long, and so on, until it is nearer "
        "the goal than ever: the paper's way out of a crevice (§2.1), which it did not build.",
        (),
        not_default="measured, not yet chosen",
    ),
    Addition(
        "goal-ward choice",
        "reflexes",
        "--reflex",
        GOAL_WARD,
        "Seeking a goal, where the fast way ahead that best fits the goal would turn the "
        "robot's back on it (heading more than 90° off it half a metre along), the robot turns "
        "to the nearest view with a fast way toward the goal instead: the paper turns only "
        "when nothing is fast ahead, and wanders off where the way through a gap reads just "
        "under the threshold.",
        (),
        not_default="it reaches more goals, and sooner, but turns on the spot more, so "
        "fewer goal runs keep half the top speed, and it meets more door edges",
    ),
    Addition(
        "ties to the last turn",
        "reflexes",
        "--reflex",
        TIE,
        "Equally good trajectories go to the side the robot last turned to, where the paper "
        "is silent: a robot just turned from a wall does not turn back into it.",
        (),
    ),
    Addition(
        "wall start",
        "reflexes",
        "--reflex",
        WALL_START,
        "Until wall following has found its wall, ties turn away from that side, so the first "
        "wall met ahead is left on the side to follow.",
        (),
    ),
    Addition(
        "echo memory",
        "memory",
        "--memory",
        "patches",
        "The FAM reads a virtual ring: the live ranges, or nearer surfaces heard in the last "
        f"{DEFAULT_MEMORY.window_s:g} s placed by odometry, since a specular ring hears a "
        "slanted wall only square on. While seeking a goal, a beam that hears an echo leaves "
        f"out the remembered patches wider than {2 * CLEARED_ABOVE_M:g} m in it, and the beam "
        "facing the goal every patch (`--memory-clearing toward-goal`): patches close the "
        "gaps between pillars and doors.",
        NO_MEMORY,
    ),
)


def additions_table() -> str:
    """The documentation's table of ADDITIONS (Markdown), as docs/method.md holds it between
    its markers."""
    lines = [
        "| addition | turned on by | ours | the paper's | what it does |",
        "| --- | --- | --- | --- | --- |",
    ]
    for a in ADDITIONS:
        if a.field == "reflexes":
            ours, paper = ("on" if a.is_on(DEFAULT) else "off"), "off"
        else:
            ours, paper = (shown_setting(m.to_dict()[a.field]) for m in (DEFAULT, PAPER))
        why = f" Not ours by default: {a.not_default}." if a.not_default else ""
        lines.append(f"| {a.name} | `{a.flag} {a.on}` | {ours} | {paper} | {a.row}{why} |")
    return "\n".join(lines) + "\n"
