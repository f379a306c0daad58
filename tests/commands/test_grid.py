"""A sweep's grid: its cells are every combination of its values, goals multiply only the
goal runs, a method is a preset or a file beside the grid, and worlds and configurations are
known by their names."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tvl_cli.agent.explore import LearnParams
from tvl_cli.commands.grid import Cell, read_grid
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.method import DEFAULT, PAPER, MethodChoice
from tvl_cli.sim.worldgen import generate_world

WORLDS = Path(__file__).resolve().parents[2] / "worlds"


def grid_of(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "grid.toml"
    path.write_text(text)
    return path


def test_cells_are_every_combination_with_the_last_key_fastest(tmp_path: Path) -> None:
    grid = read_grid(
        grid_of(
            tmp_path,
            'world = ["square", "circle"]\nseed = [1, 2]\nbehaviour = "avoid"\n'
            "threshold = [0.7, 0.9]\n",
        )
    )
    assert [(c.world, c.seed, c.threshold) for c in grid.cells] == [
        (world, seed, threshold)
        for world in ("square", "circle")
        for seed in (1, 2)
        for threshold in (0.7, 0.9)
    ]
    # What the grid leaves out is what `tvl learn`, `train` and `run` do by default.
    assert grid.cells[0] == Cell(
        "square", 1, "single", 15.0, "avoid", 0.7, None, 5.0, "default", "all"
    )
    assert grid.methods == {"default": DEFAULT}
    assert grid.configs == {"single": SINGLE}


def test_goals_multiply_the_goal_runs_only(tmp_path: Path) -> None:
    text = (
        f'world = "{WORLDS / "obstacles.txt"}"\nseed = 1\nbehaviour = ["avoid", "goal"]\n'
        'goal = ["5.875,3.875", "4.875, 1.625"]\n'
    )
    cells = read_grid(grid_of(tmp_path, text)).cells
    assert [(c.behaviour, c.goal) for c in cells] == [
        ("avoid", None), ("goal", "5.875,3.875"), ("goal", "4.875,1.625")
    ]  # fmt: skip
    assert cells[2].goal_xy() == (4.875, 1.625)


def test_a_goal_run_without_a_goal_seeks_the_worlds_first(tmp_path: Path) -> None:
    text = 'world = "narrow"\nseed = 1\nbehaviour = "goal"\n'
    assert [c.goal for c in read_grid(grid_of(tmp_path, text)).cells] == ["3.625,1.875"]
    square = 'world = "square"\nseed = 1\nbehaviour = "goal"\n'
    with pytest.raises(BadInput, match="world 'square' has no goal"):
        read_grid(grid_of(tmp_path, square))


def test_each_method_runs_with_its_own_reflexes_unless_the_grid_gives_some(
    tmp_path: Path,
) -> None:
    text = 'world = "square"\nseed = 1\nbehaviour = "avoid"\nmethod = ["default", "paper"]\n'
    grid = read_grid(grid_of(tmp_path, text))
    ours, paper = grid.cells
    assert (ours.method, ours.reflexes, paper.method, paper.reflexes) == (
        "default", "all", "paper", "none"
    )  # fmt: skip
    assert grid.methods == {"default": DEFAULT, "paper": PAPER}
    assert ours.learn_params() == paper.learn_params() == LearnParams()
    assert paper.run_method(PAPER) == MethodChoice(PAPER, "paper", (("reflexes", ()),))
    mixed = text + 'reflexes = ["none", "bump,tie"]\n'
    with pytest.raises(BadInput, match="reflexes 'bump,tie' contradicts method \"paper\""):
        read_grid(grid_of(tmp_path, mixed.replace('["default", "paper"]', '"paper"')))
    ours_only = read_grid(grid_of(tmp_path, mixed.replace('["default", "paper"]', '"default"')))
    assert [c.reflexes for c in ours_only.cells] == ["none", "bump,tie"]
    assert ours_only.cells[1].run_method(DEFAULT).settings == (("reflexes", ("bump", "tie")),)


def test_a_method_file_beside_the_grid_is_its_method(tmp_path: Path) -> None:
    (tmp_path / "slow.toml").write_text("decel_mps2 = 0.3\n")
    text = 'world = "square"\nseed = 1\nbehaviour = "avoid"\nmethod = "slow.toml"\n'
    grid = read_grid(grid_of(tmp_path, text))
    assert grid.methods["slow.toml"].decel_mps2 == 0.3
    assert grid.cells[0].reflexes == "all"
    (tmp_path / "bad.toml").write_text("decell = 0.3\n")
    with pytest.raises(BadInput, match=r"bad\.toml: unknown key 'decell' \(did you mean"):
        read_grid(grid_of(tmp_path, text.replace("slow", "bad")))


def test_the_paper_as_a_reflex_setting_points_to_the_method(tmp_path: Path) -> None:
    text = 'world = "square"\nseed = 1\nbehaviour = "avoid"\nreflexes = "paper"\n'
    with pytest.raises(BadInput, match='the paper\'s whole method is method = "paper"'):
        read_grid(grid_of(tmp_path, text))


def test_a_configuration_file_beside_the_grid_is_known_by_its_name(tmp_path: Path) -> None:
    config = json.loads(SINGLE.to_json())
    config["name"] = "mine"
    (tmp_path / "mine.json").write_text(json.dumps(config))
    text = 'world = "square"\nseed = 1\nbehaviour = "avoid"\nconfig = ["single", "mine.json"]\n'
    grid = read_grid(grid_of(tmp_path, text))
    assert [c.config for c in grid.cells] == ["single", "mine"]
    assert grid.configs["mine"].tables == SINGLE.tables


def test_two_worlds_of_one_name_are_refused(tmp_path: Path) -> None:
    (tmp_path / "copy.txt").write_text((WORLDS / "square.txt").read_text())
    text = 'world = ["square", "copy.txt"]\nseed = 1\nbehaviour = "avoid"\n'
    with pytest.raises(BadInput, match=r"worlds 'square' and 'copy\.txt' are both named 'square'"):
        read_grid(grid_of(tmp_path, text))


def test_generated_worlds_of_other_seeds_are_kept_apart_by_their_names(tmp_path: Path) -> None:
    for seed in (3, 7):
        (tmp_path / f"rooms{seed}.txt").write_text(generate_world("rooms", None, None, seed))
    text = 'world = ["rooms3.txt", "rooms7.txt", "rooms"]\nseed = 1\nbehaviour = "avoid"\n'
    grid = read_grid(grid_of(tmp_path, text))
    # The shipped rooms world, generated before names carried the seed, keeps its name.
    assert list(grid.worlds) == ["rooms-s3", "rooms-s7", "rooms"]
    assert [c.world for c in grid.cells] == ["rooms-s3", "rooms-s7", "rooms"]


def test_a_mistyped_key_is_refused_with_the_nearest_one(tmp_path: Path) -> None:
    text = 'world = "square"\nseed = 1\nbehaviour = "avoid"\ntreshold = 0.8\n'
    with pytest.raises(BadInput, match=r"unknown key 'treshold' \(did you mean 'threshold'\?\)"):
        read_grid(grid_of(tmp_path, text))


GOAL_GRID = (
    f'world = ["{WORLDS / "obstacles.txt"}", "narrow"]\nseed = [1, 2]\n'
    'behaviour = ["avoid", "goal"]\nconfig = ["single", "multi"]\nthreshold = [0.7, 0.9]\n'
)


def test_the_cap_counts_the_cells_the_grid_makes(tmp_path: Path) -> None:
    path = grid_of(tmp_path, GOAL_GRID)
    cells = len(read_grid(path).cells)
    # obstacles: avoid and 1 goal; narrow: avoid and its goal; each for 2 seeds, 2
    # configurations and 2 thresholds.
    assert cells == 2 * 2 * 2 * 2 * 2
    assert len(read_grid(path, max_cells=cells).cells) == cells
    with pytest.raises(BadInput, match=rf"{cells:,} cells, over the cap of {cells - 1:,}"):
        read_grid(path, max_cells=cells - 1)


def test_goals_multiply_the_count_as_they_multiply_the_cells(tmp_path: Path) -> None:
    text = (
        f'world = "{WORLDS / "obstacles.txt"}"\nseed = [1, 2]\nbehaviour = ["avoid", "goal"]\n'
        'config = ["single", "multi"]\nthreshold = [0.7, 0.9]\n'
        'goal = ["5.875,3.875", "4.875,1.625", "5.875,1.125"]\n'
    )
    path = grid_of(tmp_path, text)
    cells = len(read_grid(path).cells)
    assert cells == (1 + 3) * 2 * 2 * 2  # avoid and 3 goals
    with pytest.raises(BadInput, match=f"{cells} cells, over the cap of {cells - 1}"):
        read_grid(path, max_cells=cells - 1)
