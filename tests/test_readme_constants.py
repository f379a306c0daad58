"""The figures the README quotes for the rules beyond the paper are the code's own."""

from __future__ import annotations

import math
from pathlib import Path

from tvl_cli.agent.motions import BACKOFF_M
from tvl_cli.agent.novelty import BLOCKED_BEYOND_STOP_M, NOVELTY_BIN_M, NOVELTY_LOOKAHEAD_M
from tvl_cli.agent.reflexes import BLOCKED_HALF_WIDTH_RAD, BLOCKED_S, REFLEXES
from tvl_cli.commands.learn import LOG_WRITE_EVERY_S
from tvl_cli.core.behaviours import LOOKAHEAD_M
from tvl_cli.core.config import EDGE_ECHO_RANGE_M, SonarConfig
from tvl_cli.core.contacts import NEAR_MISS_WITHIN_RAD
from tvl_cli.core.method import PAPER

README = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")


def _row(reflex: str) -> str:
    return next(line for line in README.splitlines() if line.startswith(f"| `{reflex}` |"))


def test_every_reflex_has_a_row_in_the_readme_table() -> None:
    for name in REFLEXES:
        assert _row(name)


def test_blocked_ways_are_quoted_with_their_width_and_time() -> None:
    row = _row("blocked-ways")
    assert f"within {math.degrees(BLOCKED_HALF_WIDTH_RAD):g}°" in row
    assert f"until {BLOCKED_S:g} s after" in row
    assert f"first {BACKOFF_M:g} m" in row


def test_near_misses_are_quoted_with_their_angle_and_blind_zone() -> None:
    row = _row("near-miss")
    assert f"within {math.degrees(NEAR_MISS_WITHIN_RAD):g}° of straight ahead" in row
    assert f"its {SonarConfig().min_range_m:g} m minimum range" in row
    assert f"reverses {BACKOFF_M:g} m" in row
    assert (
        f"within {math.degrees(NEAR_MISS_WITHIN_RAD):g}° of straight ahead"
        in README.split("### What a run counts")[1]
    )


def test_the_paper_labels_and_the_lookahead_are_quoted_as_they_are() -> None:
    assert f"deceleration\n  {PAPER.decel_mps2:g} m/s², margin {PAPER.margin_m:g} m" in README
    assert f"judged {LOOKAHEAD_M:g} m along itself" in README


def test_the_edge_echo_range_is_quoted_as_it_is() -> None:
    section = README.split("### What real sonars hear beyond the specular rule")[1]
    assert f"within {EDGE_ECHO_RANGE_M:.1f} m (a quarter of the maximum range)" in section
    assert SonarConfig().max_range_m / 4 == EDGE_ECHO_RANGE_M


def test_the_novelty_rule_is_quoted_as_it_is() -> None:
    section = README.split("**Where to learn next (`--explore`).**")[1].split("**Coverage.**")[0]
    assert f"in {NOVELTY_BIN_M:g} m square bins" in section
    assert f"in the next {NOVELTY_LOOKAHEAD_M:g} m" in section
    assert f"`--near` and {BLOCKED_BEYOND_STOP_M * 100:g} cm" in " ".join(section.split())


def test_what_a_kill_of_learning_may_lose_is_quoted_as_it_is() -> None:
    files = README.split("## Files")[1].split("## Worlds")[0]
    assert f"span\n  {LOG_WRITE_EVERY_S:g} simulated seconds" in files
    assert f"ended in the last {LOG_WRITE_EVERY_S:g} simulated seconds" in files
    stopping = README.split("Ctrl-C or SIGTERM stops learning")[1].split("\n\n")[0]
    assert f"ended in the last {LOG_WRITE_EVERY_S:g} simulated seconds" in stopping
