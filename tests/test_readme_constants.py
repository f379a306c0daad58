"""The figures the README quotes for the rules beyond the paper are the code's own."""

from __future__ import annotations

import math
from pathlib import Path

from tvl_cli.agent.motions import BACKOFF_M
from tvl_cli.agent.reflexes import BLOCKED_HALF_WIDTH_RAD, BLOCKED_S, REFLEXES
from tvl_cli.core.behaviours import LOOKAHEAD_M
from tvl_cli.core.config import SonarConfig
from tvl_cli.core.contacts import NEAR_MISS_WITHIN_RAD
from tvl_cli.core.labels import PAPER_DECEL_MPS2, PAPER_MARGIN_M

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
    assert f"deceleration\n  {PAPER_DECEL_MPS2:g} m/s², margin {PAPER_MARGIN_M:g} m" in README
    assert f"judged {LOOKAHEAD_M:g} m along itself" in README
