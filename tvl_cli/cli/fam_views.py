"""How a FAM looks in a terminal: a training's summary, its rules as sentences, where two
FAMs differ, and one ring explained in its rules."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from tvl_cli.cli.console import folded, out
from tvl_cli.cli.tables import facts, number, table
from tvl_cli.core.memory import NOT_CHOSEN
from tvl_cli.core.method import DEFAULT, FIELDS, describe_record
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT_NAME, profile_name

if TYPE_CHECKING:
    # Named for their types only: a command's `--help` imports this module.
    from collections.abc import Iterable

    from tvl_cli.analysis.famdiff import FamDifference
    from tvl_cli.analysis.rules import Rule
    from tvl_cli.commands.train import TrainSummary
    from tvl_cli.core.fired_rules import Explanation
    from tvl_cli.core.method import MethodChoice


def train_summary(summary: TrainSummary, output: Path, choice: MethodChoice) -> None:
    rows = [
        ("configuration", summary.fam.config.name),
        ("method", trained_method(summary.method_record(), choice)),
        ("episodes", summary.episodes),
        ("exemplars used", summary.exemplars),
        ("rules touched", f"{summary.rules_touched} of {summary.rules_total}"),
        ("rules never touched", summary.rules_total - summary.rules_touched),
        ("time (s)", summary.wall_s),
        *(("trained once", repeat.text()) for repeat in summary.repeated_sessions),
    ]
    out.print(facts(rows, title=f"trained → {output}"))


def trained_method(record: dict[str, Any], choice: MethodChoice) -> str:
    """A trained FAM's method in words, naming the differences from ours that came from how
    its logs were learnt rather than from the options `choice` gave."""
    given = {name for name, _ in choice.settings}
    if choice.method is not None:
        given.update(FIELDS)
    if choice.memory != NOT_CHOSEN:
        given.add("memory")
    ours = DEFAULT.to_dict()
    inherited = [n for n in FIELDS if n in record and record[n] != ours[n] and n not in given]
    described = describe_record(record)
    return (
        f"{described} ({', '.join(inherited)}: as its logs were learnt)" if inherited else described
    )


def say_method(record: dict[str, Any] | None) -> None:
    out.print(f"method: {describe_record(record)}", soft_wrap=True, markup=False)


def say_robot(robot: RobotConfig) -> None:
    """The robot a FAM was learnt on, where it is not the paper's (every command's default)."""
    name = profile_name(robot)
    if name != DEFAULT_ROBOT_NAME:
        out.print(f"robot: {name or f'one of its own, {2 * robot.radius_m:g} m across'}")


def rules(found: Iterable[Rule]) -> None:
    """Rules as sentences, each folded at the width of the terminal (at most TEXT_WIDTH)
    under its first line."""
    for rule in found:
        out.print(folded_rule(rule.sentence()), soft_wrap=True, markup=False)


# Where a rule's sentence joins words a fold must not part: `front is VN`, `T1L = 0.43 m/s`,
# `0.43 -> 0.51 m/s`, `(experience 12.7)`.
_JOINS = (" is ", " = ", " -> ", " m/s", "(experience ")
_NO_BREAK = "\u00a0"


def folded_rule(sentence: str) -> str:
    """A rule's sentence folded between its conditions and its parts, never inside one."""
    for join in _JOINS:
        sentence = sentence.replace(join, join.replace(" ", _NO_BREAK))
    return folded(sentence).replace(_NO_BREAK, " ")


def fam_difference(d: FamDifference, first: Path, second: Path) -> None:
    columns = ("trajectory", "rules differing", "mean |change| (m/s)")
    differences = table(
        *columns,
        title=f"{first} → {second} ({d.config}, tolerance {d.tolerance_mps:g} m/s)",
        right=columns[1:],
    )
    for t in d.trajectories:
        differences.add_row(
            t.trajectory, f"{t.differing} of {t.rules}", number(t.mean_abs_change_mps, 3)
        )
    if (robots := d.robots_sentence()) is not None:
        out.print(folded(robots), highlight=False, markup=False)
    out.print(differences)
    for rule in d.largest:
        out.print(folded_rule(rule.sentence()), markup=False, soft_wrap=True)


def explanation(e: Explanation) -> None:
    inputs = table("table", "input", "sonars", "range (m)", "memberships", title="inputs")
    for i in e.inputs:
        fired = ", ".join(f"{s.name} {s.degree:.2f}" for s in i.fired)
        sonars = ",".join(f"S{s}" for s in i.sonars)
        inputs.add_row(i.table, i.name, sonars, f"{i.value_m:.3f}", fired)
    out.print(inputs)
    rules = table("table", "IF", "strength", "THEN (m/s, experience)", title="rules that fire")
    for r in e.rules:
        then = ", ".join(
            f"{t} = {v:.2f} ({x:.1f})"
            for t, v, x in zip(r.trajectories, r.velocities_mps, r.experience, strict=True)
        )
        rules.add_row(r.table, " AND ".join(r.set_names), f"{r.strength:.3f}", then)
    out.print(rules)
    # What each row holds is said beside it: a title that said it would wrap over the
    # narrow table of one or two trajectories.
    perceived = table("", *e.trajectories, title="perceived", right=e.trajectories)
    perceived.add_row("velocity (m/s)", *(f"{v:.2f}" for v in e.velocities_mps))
    perceived.add_row("experience", *(f"{x:.1f}" for x in e.experience))
    out.print(perceived)
