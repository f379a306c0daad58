"""A sweep's table in a terminal: each setting's mean ± interval, rounded, with units in the
headers, in tables no wider than the terminal, no number cut or folded."""

from __future__ import annotations

import io

import pytest
from rich.console import Console

from tvl_cli.analysis.intervals import Group, Interval
from tvl_cli.analysis.measures import MEASURES
from tvl_cli.cli.sweep_view import sweep_tables
from tvl_cli.sweep.summary import SweepSummary, summarise


def rendered(summary: SweepSummary, width: int) -> list[str]:
    console = Console(width=width, record=True, file=io.StringIO())
    for table in sweep_tables(summary, width):
        console.print(table)
    return console.export_text().splitlines()


def rows(measured: dict[str, float]) -> list[dict[str, object]]:
    """Runs of two worlds with long names and two configurations, three seeds each."""
    made = []
    for world in ("rooms-12x9.5-s1001-rough0.5", "rooms-12x9.5-s1002-rough0.5"):
        for config in ("single", "multi"):
            for seed in (1, 2, 3):
                values = {key: value * (1 + 0.1 * seed) for key, value in measured.items()}
                made.append({
                    "kind": "tvl", "world": world, "seed": seed, "config": config,
                    "learn_minutes": 15.0, "behaviour": "goal", "threshold": 0.8,
                    "goal": "3.5,2.0", "run_minutes": 5.0, "method": "default",
                    "reflexes": "all",
                    **values, "goal_reached": seed != 2,
                })  # fmt: skip
    return made


EVERY_MEASURE = {name: 1234.5678 for name in MEASURES if name != "goal_reached"}


@pytest.mark.parametrize("width", [80, 100, 120])
def test_every_measure_fits_the_terminal_whole(width: int) -> None:
    summary = summarise(rows(EVERY_MEASURE), tuple(MEASURES))
    lines = rendered(summary, width)
    assert max(map(len, lines)) <= width
    text = "\n".join(lines)
    for group in summary.groups:
        for measure, shown in group.intervals.items():
            assert shown is not None and shown.half_width is not None
            scale, places = MEASURES[measure].scale, MEASURES[measure].decimals
            if measure == "goal_reached":  # two of three: 67 % ± 143 would reach past 0 and 100
                assert shown.clipped and (shown.low, shown.high) == (0.0, 1.0)
                whole = f"{shown.mean * scale:.{places}f} (0–100)"
            else:
                whole = f"{shown.mean * scale:.{places}f} ± {shown.half_width * scale:.{places}f}"
            assert whole in text, whole
    assert "…" not in text  # nothing cut short
    tables = sum(line.startswith("┏") for line in lines)
    assert tables > 1
    for group in summary.groups:  # each table repeats the settings it shows numbers of
        assert text.count(group.key[0]) == tables * 2  # the world's two configurations


def test_headers_carry_units_and_the_setting_and_its_seeds_lead() -> None:
    summary = summarise(rows({"contacts_per_min": 0.4, "mean_speed_mps": 0.31}))
    lines = rendered(summary, 80)
    assert max(map(len, lines)) <= 80
    tops = [i for i, line in enumerate(lines) if line.startswith("┏")]
    rules = [i for i, line in enumerate(lines) if line.startswith("┡")]
    # Every table's headers, each of which may wrap at its spaces.
    header = " ".join(
        " ".join(lines[top + 1 : rule]) for top, rule in zip(tops, rules, strict=True)
    )
    for label in ("world", "config", "seeds", "contacts/min", "speed (m/s)", "goal reached (%)"):
        assert all(word in header for word in label.split()), label
    first = next(line for line in lines if "rooms-12x9.5-s1001-rough0.5" in line)
    speed = summary.groups[0].intervals["mean_speed_mps"]
    assert speed is not None and speed.half_width is not None
    assert f"{speed.mean:.3f} ± {speed.half_width:.3f}" in first
    # Two goals of three as a percentage, beside the first setting in the second table: its
    # interval, 67 ± 143, cut at what a share can be.
    assert "67 (0–100)" in [line for line in lines if "rooms-12x9.5-s1001-rough0.5" in line][2]
    assert first.split("│")[3].strip() == "3"


def test_one_seed_shows_its_mean_alone_and_a_measure_not_taken_a_dash() -> None:
    alone = Group(
        ("single",), 1, {"mean_speed_mps": Interval(0.3, None, 1), "mean_wall_clearance_m": None}
    )
    summary = SweepSummary(("config",), {}, ("mean_speed_mps", "mean_wall_clearance_m"), [alone])
    (line,) = [line for line in rendered(summary, 80) if "single" in line]
    assert [cell.strip() for cell in line.split("│")[1:-1]] == ["single", "1", "0.300", "–"]
