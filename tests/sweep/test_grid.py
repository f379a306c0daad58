"""A sweep's grid: its cells are every combination of its values, goals multiply only the
goal runs, a method is a preset or a file beside the grid, and worlds and configurations are
known by their names."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT, PAPER, MethodChoice, reflexes_text
from tvl_cli.sim.worldgen import generate_world
from tvl_cli.sweep.cell import Cell
from tvl_cli.sweep.grid import read_grid

WORLDS = Path(__file__).resolve().parents[2] / "worlds"
OURS = reflexes_text(DEFAULT.reflexes)  # a cell of our method runs with our reflexes


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
        kind="tvl",
        world="square",
        seed=1,
        learn_config="single",
        learn_minutes=15.0,
        exploration=None,
        near_m=None,
        memory=None,
        config="single",
        minute=None,
        behaviour="avoid",
        threshold=0.7,
        goal=None,
        run_minutes=5.0,
        online=False,
        competence_every=None,
        trace=False,
        method="default",
        reflexes=OURS,
        run_memory=None,
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
        "default", OURS, "paper", "none"
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
    remembering = text.replace('["default", "paper"]', '"paper"') + 'run_memory = "patches"\n'
    with pytest.raises(BadInput, match="run_memory 'patches' contradicts method \"paper\""):
        read_grid(grid_of(tmp_path, remembering))
    unremembering = text.replace('["default", "paper"]', '"paper"') + 'run_memory = "none"\n'
    assert [c.run_memory for c in read_grid(grid_of(tmp_path, unremembering)).cells] == ["none"]


def test_a_method_file_beside_the_grid_is_its_method(tmp_path: Path) -> None:
    (tmp_path / "slow.toml").write_text("decel_mps2 = 0.3\n")
    text = 'world = "square"\nseed = 1\nbehaviour = "avoid"\nmethod = "slow.toml"\n'
    grid = read_grid(grid_of(tmp_path, text))
    assert grid.methods["slow.toml"].decel_mps2 == 0.3
    assert grid.cells[0].reflexes == OURS
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


# --- the keys that write the experiments: kinds, snapshots, parts and sizes ---------------


def test_each_kind_of_cell_varies_only_the_keys_it_reads(tmp_path: Path) -> None:
    text = (
        'kind = ["learn", "tvl", "dwa", "qlearn"]\nworld = "square"\nseed = [1, 2]\n'
        "learn_minutes = 2\nminute = { from = 0, to = 2, step = 1 }\ncompetence_every = 1\n"
        'method = ["default", "paper"]\n'
    )
    cells = read_grid(grid_of(tmp_path, text)).cells
    count = {kind: sum(c.kind == kind for c in cells) for kind in ("learn", "tvl", "dwa", "qlearn")}
    # The learning per seed and method; a run per seed, method and minute 0, 1, 2; each
    # baseline once a seed, whatever the minutes and methods.
    assert count == {"learn": 4, "tvl": 12, "dwa": 2, "qlearn": 2}
    dwa = next(c for c in cells if c.kind == "dwa")
    assert (dwa.minute, dwa.config, dwa.method, dwa.learn_minutes, dwa.reflexes) == (
        None, None, None, None, "none"
    )  # fmt: skip
    qlearn = next(c for c in cells if c.kind == "qlearn")
    assert (qlearn.learn_minutes, qlearn.competence_every) == (2.0, 1.0)
    assert sorted({c.minute for c in cells if c.kind == "tvl"}) == [0.0, 1.0, 2.0]
    assert {c.behaviour for c in cells if c.kind == "learn"} == {None}


def test_the_keys_named_after_the_methods_fields_change_the_method_learnt_by(
    tmp_path: Path,
) -> None:
    text = (
        'world = "square"\nseed = 1\nexploration = ["novelty", "random"]\n'
        'near_m = [0.16, 0]\nmemory = "points"\nmethod = "default"\n'
    )
    cells = read_grid(grid_of(tmp_path, text)).cells
    learnt = {(c.exploration, c.near_m): c.learning_method(DEFAULT) for c in cells}
    assert learnt["random", 0.0].exploration == "random"
    assert learnt["random", 0.0].near_m == 0.0
    assert learnt["novelty", 0.16].near_m == 0.16
    assert {m.memory.kind for m in learnt.values()} == {"points"}
    assert learnt["novelty", 0.16].decel_mps2 == DEFAULT.decel_mps2


@pytest.mark.parametrize(
    ("key", "value"),
    [("exploration", '"novelty"'), ("near_m", "0.16"), ("memory", '"patches"')],
)
def test_a_methods_field_beside_the_papers_method_that_contradicts_it_is_refused(
    tmp_path: Path, key: str, value: str
) -> None:
    text = f'world = "square"\nseed = 1\nmethod = "paper"\n{key} = {value}\n'
    with pytest.raises(BadInput, match=f'{key} .* contradicts method "paper", which fixes it'):
        read_grid(grid_of(tmp_path, text))
    # The paper's own value is no contradiction.
    paper = {"exploration": '"least-experience"', "near_m": "0", "memory": '"none"'}[key]
    agreeing = f'world = "square"\nseed = 1\nmethod = "paper"\n{key} = {paper}\n'
    (cell,) = read_grid(grid_of(tmp_path, agreeing)).cells
    assert cell.learning_method(PAPER) == PAPER


def test_a_run_may_read_through_another_echo_memory_than_its_fam_learnt_with(
    tmp_path: Path,
) -> None:
    text = 'world = "square"\nseed = 1\nrun_memory = ["none", "points"]\n'
    cells = read_grid(grid_of(tmp_path, text)).cells
    ran = {c.run_memory: c.run_method(DEFAULT).over(DEFAULT, ("reflexes",)) for c in cells}
    assert ran["none"].memory == NO_MEMORY
    assert ran["points"].memory.kind == "points"
    # What the run does not change is the learning: the log and FAM are the method's.
    assert {c.learning_method(DEFAULT) for c in cells} == {DEFAULT}
    # Not given, the run reads through the memory its FAM was trained through.
    (own,) = read_grid(grid_of(tmp_path, 'world = "square"\nseed = 1\n')).cells
    assert own.run_memory is None
    assert own.run_method(DEFAULT).over(DEFAULT, ()).memory == DEFAULT.memory


def test_parts_share_the_keys_above_them_and_make_each_cell_once(tmp_path: Path) -> None:
    text = (
        'world = "square"\nseed = [1, 2]\nlearn_minutes = 2\n'
        "[[part]]\nthreshold = [0.7, 0.9]\n[[part]]\nthreshold = 0.9\nonline = [false, true]\n"
    )
    cells = read_grid(grid_of(tmp_path, text)).cells
    assert [(c.seed, c.threshold, c.online) for c in cells] == [
        (1, 0.7, False), (1, 0.9, False), (2, 0.7, False), (2, 0.9, False),
        (1, 0.9, True), (2, 0.9, True),
    ]  # fmt: skip
    assert {c.learn_minutes for c in cells} == {2.0}


SIZED = (
    'world = "square"\nseed = [1, 2, 3, 4, 5]\nlearn_minutes = 20\n'
    "[[part]]\nminute = { from = 0, to = 20, step = 5 }\n[part.tiny]\nminute = 1\n"
    '[[part]]\nkind = "dwa"\n'
    "[quick]\nseed = [1, 2, 3]\n[tiny]\nseed = 1\nlearn_minutes = 1\n"
)


def test_a_size_overrides_the_file_and_a_parts_own_size_the_part(tmp_path: Path) -> None:
    path = grid_of(tmp_path, SIZED)
    full, quick, tiny = (read_grid(path, None, size) for size in ("full", "quick", "tiny"))
    assert len(full.cells) == 5 * 5 + 5 and full.size == "full"
    assert len(quick.cells) == 3 * 5 + 3
    assert [(c.kind, c.seed, c.minute, c.learn_minutes) for c in tiny.cells] == [
        ("tvl", 1, 1.0, 1.0), ("dwa", 1, None, None)
    ]  # fmt: skip


def test_generated_worlds_and_all_of_a_worlds_goals(tmp_path: Path) -> None:
    text = 'world = ["rooms:3", "obstacles"]\nseed = 1\nbehaviour = "goal"\ngoal = "all"\n'
    grid = read_grid(grid_of(tmp_path, text))
    assert list(grid.worlds) == ["rooms-s3", "obstacles"]
    assert grid.worlds["rooms-s3"] == generate_world("rooms", None, None, 3)
    goals = [c.goal for c in grid.cells if c.world == "obstacles"]
    assert len(goals) == 4 == len(set(goals))


def test_a_learner_exploring_with_the_trained_configuration(tmp_path: Path) -> None:
    text = 'world = "square"\nseed = 1\nconfig = ["single", "multi"]\nlearn_config = "same"\n'
    cells = read_grid(grid_of(tmp_path, text)).cells
    assert [(c.config, c.learn_config) for c in cells] == [
        ("single", "single"), ("multi", "multi")
    ]  # fmt: skip


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        (
            'kind = "tlv"',
            r"kind 'tlv' is not one of tvl, learn, dwa, qlearn \(did you mean 'tvl'\?\)",
        ),
        (
            'exploration = "novel"',
            r"exploration 'novel' is not one of .* \(did you mean 'novelty'\?\)",
        ),
        ("near_m = -1", r"near_m -1 must be 0 or more and at most 4 m"),
        ('memory = "patch"', r"memory 'patch' is not one of none, points, patches"),
        (
            'run_memory = "patch"',
            r"run_memory 'patch' is not one of none, points, patches \(did you mean 'patches'\?\)",
        ),
        (
            "competence_every = 1",
            r"'competence_every' is for cells of kind qlearn, and this grid runs tvl",
        ),
        (
            "learn_minutes = 5\nminute = 6",
            r"minute 6 is beyond the longest learning, learn_minutes 5",
        ),
        ("online = 1", r"'online' is 1, expected true or false"),
        (
            "minute = { from = 0, to = 5 }",
            r"'minute' range must be \{ from = A, to = B, step = S \}",
        ),
        (
            'learn_config = "mine.json"',
            r"learn_config 'mine.json' is not one of single, multi, designed, same",
        ),
        ('world = "lab:x"', r"world 'lab:x': KIND:SEED or KIND:FIRST-LAST needs whole-number"),
        ('world = "labs:7"', r"no world kind 'labs' \(did you mean 'lab'\?\)"),
        (
            'behaviour = "goal"\ngoal = ["all", "1,1"]',
            r'goal "all" is every goal of the world: give it alone',
        ),
        ("[full]\nseed = 1", r"no \[full\] table: the file as written is the full size"),
        (
            '[[part]]\nkind = "dwa"\nminute = 1',
            r"'minute' is for cells of kind tvl, and this grid runs dwa",
        ),
    ],
)
def test_a_bad_key_names_the_file_the_key_and_what_is_wrong(
    tmp_path: Path, text: str, problem: str
) -> None:
    base = "seed = 1\n" + ("" if text.startswith("world") else 'world = "square"\n')
    with pytest.raises(BadInput, match=rf"grid\.toml.*: {problem}"):
        read_grid(grid_of(tmp_path, base + text + "\n"))


def test_a_size_the_file_has_no_table_for_is_refused(tmp_path: Path) -> None:
    path = grid_of(tmp_path, 'world = "square"\nseed = 1\n')
    with pytest.raises(BadInput, match=r"grid\.toml: no \[quick\] table for --size quick"):
        read_grid(path, None, "quick")
