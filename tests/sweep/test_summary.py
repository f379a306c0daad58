"""What a sweep shows of its rows: settings that differ only in seed as one row of means and
intervals, a plot's points, and every mistyped key refused with the nearest right one."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import pytest

from tvl_cli.analysis.intervals import Interval, t_975
from tvl_cli.analysis.measures import MEASURES
from tvl_cli.core.errors import BadInput
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.sweep.cell import COLUMNS
from tvl_cli.sweep.summary import (
    KEY_LABELS,
    SETTING_KEYS,
    PlotAxes,
    default_plot_path,
    parse_measures,
    parse_plot,
    plot,
    plot_data,
    summarise,
)

CELL = {
    "world": "rooms-s3",
    "learn_config": "single",
    "learn_minutes": 15.0,
    "exploration": None,
    "near_m": None,
    "memory": None,
    "config": "single",
    "minute": None,
    "behaviour": "wall-left",
    "threshold": 0.8,
    "goal": None,
    "run_minutes": 5.0,
    "online": False,
    "competence_every": None,
    "trace": False,
    "method": "default",
    "reflexes": "all",
    "run_memory": None,
}


def row(seed: int, **values: object) -> dict[str, object]:
    """A sweep's row: the cell's grid values, then what its run measured."""
    measured = {"contacts_per_min": 0.0, "mean_speed_mps": 0.3, "mean_wall_clearance_m": 0.5}
    return {"kind": "tvl", **CELL, "seed": seed, **measured, "goal_reached": False, **values}


ROWS = [
    row(1, config="single", threshold=0.7, mean_speed_mps=0.30),
    row(2, config="single", threshold=0.7, mean_speed_mps=0.34),
    row(1, config="single", threshold=0.9, mean_speed_mps=0.40),
    row(2, config="single", threshold=0.9, mean_speed_mps=0.44),
    row(1, config="multi", threshold=0.7, mean_speed_mps=0.20),
    row(2, config="multi", threshold=0.7, mean_speed_mps=0.22),
    row(1, config="multi", threshold=0.9, mean_speed_mps=0.25),
    row(2, config="multi", threshold=0.9, mean_speed_mps=0.27),
]


def test_every_run_metric_has_a_label_with_its_unit_and_every_grid_key_too() -> None:
    assert list(MEASURES) == [f.name for f in fields(RunMetrics)]
    assert list(KEY_LABELS) == list(SETTING_KEYS) == [c for c in COLUMNS if c != "seed"]


def test_a_setting_is_a_row_of_its_seeds_means_and_intervals() -> None:
    summary = summarise(ROWS)
    assert summary.varying == ("config", "threshold")
    shared = {k: v for k, v in CELL.items() if k not in ("config", "threshold")}
    assert summary.fixed == {"kind": "tvl", **shared}
    # Wall following: contacts, speed and the wall clearance.
    assert summary.measures == ("contacts_per_min", "mean_speed_mps", "mean_wall_clearance_m")
    assert [g.key for g in summary.groups] == [
        ("single", 0.7), ("single", 0.9), ("multi", 0.7), ("multi", 0.9)
    ]  # fmt: skip
    first = summary.groups[0].intervals["mean_speed_mps"]
    assert first is not None
    assert first.mean == pytest.approx(0.32)
    # Two seeds: one degree of freedom; the standard error of 0.30 and 0.34 is 0.02.
    assert first.half_width == pytest.approx(t_975(1) * 0.02)


def test_goal_runs_show_the_share_of_goals_reached() -> None:
    runs = [
        row(seed, behaviour="goal", goal="1.0,2.0", goal_reached=seed < 3) for seed in (1, 2, 3)
    ]
    assert summarise(runs).measures == ("contacts_per_min", "mean_speed_mps", "goal_reached")
    chosen = summarise(runs, ("distance_m", "goal_reached"))
    assert chosen.measures == ("distance_m", "goal_reached")
    reached = chosen.groups[0].intervals["goal_reached"]
    assert reached is not None and reached.mean == pytest.approx(2 / 3)


def test_a_plot_has_a_point_for_each_x_on_a_line_for_each_hue() -> None:
    data = plot_data(ROWS, PlotAxes("threshold", "mean_speed_mps", "config"))
    assert list(data.series) == ["single", "multi"]
    assert [x for x, _ in data.series["multi"]] == [0.7, 0.9]
    assert data.series["multi"][1][1].mean == pytest.approx(0.26)
    assert data.pooled == ()


def test_keys_beside_x_and_hue_are_pooled_with_the_seeds() -> None:
    data = plot_data(ROWS, PlotAxes("threshold", "mean_speed_mps"))
    assert data.pooled == ("config",)
    assert list(data.series) == [None]
    low = data.series[None][0][1]  # the four runs at 0.7, of both configurations
    assert (low.n, low.mean) == (4, pytest.approx(0.265))


def test_a_share_is_plotted_as_a_percentage() -> None:
    runs = [row(seed, goal_reached=seed == 1) for seed in (1, 2)]
    ((_, reached),) = plot_data(runs, PlotAxes("config", "goal_reached")).series[None]
    assert reached.mean == 50.0
    assert reached.half_width == pytest.approx(t_975(1) * 50.0)


def test_a_measure_no_run_took_cannot_be_plotted() -> None:
    runs = [row(1, time_to_goal_s=None)]
    with pytest.raises(BadInput, match="--plot y=time_to_goal_s: no run of this sweep took it"):
        plot_data(runs, PlotAxes("config", "time_to_goal_s"))


@pytest.mark.parametrize(
    "text, axes",
    [
        ("x=threshold,y=mean_speed_mps", PlotAxes("threshold", "mean_speed_mps")),
        (" x = world , y=contacts_per_min, hue=config ",
         PlotAxes("world", "contacts_per_min", "config")),
    ],
)  # fmt: skip
def test_a_plot_is_given_as_x_y_and_hue(text: str, axes: PlotAxes) -> None:
    assert parse_plot(text) == axes


@pytest.mark.parametrize(
    "text, message",
    [
        ("x=treshold,y=mean_speed_mps",
         "--plot x=treshold: no grid key 'treshold' (did you mean 'threshold'?)"),
        ("x=threshold,y=speed",
         "--plot y=speed: no measure 'speed' (did you mean 'mean_speed_mps'?)"),
        ("x=threshold,y=mean_sped_mps",
         "no measure 'mean_sped_mps' (did you mean 'mean_speed_mps'?)"),
        ("x=threshold,y=sim_s,hue=confg",
         "--plot hue=confg: no grid key 'confg' (did you mean 'config'?)"),
        ("x=threshold,hu=config,y=sim_s", "no part 'hu' (did you mean 'hue'?)"),
        ("x=threshold,colour=config,y=sim_s", "no part 'colour' (known: x, y, hue)"),
        ("x=threshold", "no y= (x=KEY,y=MEASURE[,hue=KEY])"),
        ("threshold", "'threshold' is not NAME=VALUE"),
        ("x=seed,y=sim_s", "--plot x=seed: the intervals are over the seeds"),
        ("x=config,y=sim_s,hue=config", "x and hue are both 'config'"),
        ("x=config,y=sim_s,x=world", "x is given twice"),
        ("x=zzz,y=sim_s", "no grid key 'zzz' (known: kind, world, learn_config,"),
    ],
)  # fmt: skip
def test_a_bad_plot_is_refused_naming_the_nearest_key(text: str, message: str) -> None:
    with pytest.raises(BadInput) as refused:
        parse_plot(text)
    assert message in str(refused.value)
    assert "\n" not in str(refused.value)


def test_measures_are_named_as_tvl_run_prints_them() -> None:
    assert parse_measures("distance_m, spins") == ("distance_m", "spins")
    with pytest.raises(
        BadInput, match=r"no measure 'contacts_per_mn' \(did you mean 'contacts_per_min'\?\)"
    ):
        parse_measures("distance_m,contacts_per_mn")


def test_the_plot_is_named_for_what_it_shows_beside_the_table() -> None:
    out = Path("results/grid")
    assert default_plot_path(out, PlotAxes("threshold", "mean_speed_mps", "config")) == (
        out / "mean_speed_mps-by-threshold-config.png"
    )
    assert default_plot_path(out, PlotAxes("world", "sim_s")) == out / "sim_s-by-world.png"


@pytest.mark.parametrize(
    "name, starts", [("p.svg", b"<?xml"), ("p.pdf", b"%PDF"), ("p.png", b"\x89PNG")]
)
@pytest.mark.slow  # over a second
def test_the_plot_is_drawn_in_the_format_its_name_gives(
    tmp_path: Path, name: str, starts: bytes
) -> None:
    plot(ROWS, PlotAxes("config", "mean_speed_mps", "threshold"), tmp_path / name)
    assert (tmp_path / name).read_bytes().startswith(starts)


def test_one_seed_draws_a_point_without_an_interval(tmp_path: Path) -> None:
    ((_, alone),) = plot_data(ROWS[:1], PlotAxes("config", "mean_speed_mps")).series[None]
    assert alone == Interval(0.30, None, 1, (0.0, None))
    plot(ROWS[:1], PlotAxes("config", "mean_speed_mps"), tmp_path / "one.png")
    assert (tmp_path / "one.png").read_bytes().startswith(b"\x89PNG")


def test_two_seeds_draw_no_interval_below_what_a_measure_can_be() -> None:
    # Contacts of 0 and 3 a minute: Student's t of two seeds gives 1.5 ± 19.06, which would
    # reach down to -17.6 contacts a minute.
    rows = [
        {**ROWS[0], "seed": seed, "contacts_per_min": rate} for seed, rate in ((1, 0.0), (2, 3.0))
    ]
    ((_, shown),) = plot_data(rows, PlotAxes("config", "contacts_per_min")).series[None]
    assert shown.mean == 1.5 and shown.half_width == pytest.approx(19.06, abs=0.01)
    assert (shown.low, shown.high) == (0.0, pytest.approx(20.56, abs=0.01))
    # A share, as a percentage, stays within 0 and 100 %.
    rows = [{**ROWS[0], "seed": seed, "goal_reached": seed == 1} for seed in (1, 2)]
    ((_, shown),) = plot_data(rows, PlotAxes("config", "goal_reached")).series[None]
    assert (shown.mean, shown.low, shown.high) == (50.0, 0.0, 100.0)
