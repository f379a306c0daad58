"""`--method paper|default|FILE.toml` and `--paper` on every command that learns, trains or
behaves, through the command line in-process: one method for each way of naming it, finer
options over it, and every file and --json recording it."""

from __future__ import annotations

import json
import shutil
from dataclasses import replace
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from tvl_cli.cli.main import main
from tvl_cli.core.method import (
    BEHAVING_FIELDS,
    DEFAULT,
    PAPER,
    method_record,
)
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import read_log
from tvl_cli.io.methodfile import read_method
from tvl_cli.io.runfile import read_run

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
GOLDEN_FAM = ROOT / "tests" / "data" / "golden-fam-v2.h5"
GOLDEN_LOG = ROOT / "tests" / "data" / "golden-log-v1.h5"
RUN = ("--behaviour", "avoid", "--minutes", "0.2")
# The paper's method as a method file, every field by name.
PAPER_TOML = """
decel_mps2 = 0.2
margin_m = 0.05
labels = "bump"
label_ceiling = 1.0
label_ceiling_radius_m = inf
near_m = 0.0
exploration = "least-experience"
reflexes = []
wall_rule = "first-seen"
sonar = "real"
memory = { kind = "none" }
"""


def tvl(*args: object) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, [str(a) for a in args])
    return done.exit_code, done.stdout, done.stderr


def printed(*args: object) -> dict:
    code, out, err = tvl(*args, "--json")
    assert code == 0, err
    return json.loads(out)


@pytest.fixture(scope="module")
def learnt(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A log and its online FAM by our method, and by the paper's; and the paper's file."""
    top = tmp_path_factory.mktemp("method")
    (top / "paper.toml").write_text(PAPER_TOML)
    files = {"dir": top, "file": top / "paper.toml"}
    for name, chosen in (("ours", ()), ("paper", ("--paper",))):
        files[f"{name}_log"], files[f"{name}_fam"] = top / f"{name}.h5", top / f"{name}-fam.h5"
        code, _, err = tvl("learn", SQUARE, "--log", files[f"{name}_log"], "--minutes", "0.5",
                           "--fam", files[f"{name}_fam"], *chosen)  # fmt: skip
        assert code == 0, err
    return files


def _three_ways(learnt: dict[str, Path]) -> list[tuple[str, ...]]:
    return [("--paper",), ("--method", "paper"), ("--method", str(learnt["file"]))]


def test_learn_by_the_paper_named_three_ways_records_one_method(
    learnt: dict[str, Path], tmp_path: Path
) -> None:
    logs = [tmp_path / f"{i}.h5" for i in range(3)]
    records = [
        printed("learn", SQUARE, "--log", log, "--minutes", "0.1", *way)["inputs"]["method"]
        for log, way in zip(logs, _three_ways(learnt), strict=True)
    ]
    assert records == [method_record(PAPER)] * 3
    ours = printed("learn", SQUARE, "--log", tmp_path / "ours.h5", "--minutes", "0.1")
    assert ours["inputs"]["method"] == method_record(DEFAULT)


@pytest.mark.slow
def test_train_run_and_the_baselines_by_the_paper_named_three_ways_agree(
    learnt: dict[str, Path], tmp_path: Path
) -> None:
    for i, way in enumerate(_three_ways(learnt)):
        fam = tmp_path / f"{i}.h5"
        trained = printed("train", learnt["paper_log"], "-o", fam, *way)["inputs"]["method"]
        assert trained == method_record(PAPER)
        assert printed("run", fam, SQUARE, *RUN, *way)["inputs"]["method"] == method_record(PAPER)
        dwa = printed("baseline", "dwa", SQUARE, "--minutes", "0.1", "--sensor", "ring", *way)
        live_ring = PAPER.memory.to_dict()
        assert dwa["inputs"]["method"] == {"preset": None, "reflexes": [], "memory": live_ring}


def test_a_run_takes_its_own_choices_from_the_method_and_the_rest_from_its_fam(
    learnt: dict[str, Path],
) -> None:
    ours = printed("run", learnt["ours_fam"], SQUARE, *RUN)["inputs"]["method"]
    assert ours == method_record(DEFAULT)
    # The paper's reflexes and memory on a FAM learnt by our method: neither preset.
    mixed = printed("run", learnt["ours_fam"], SQUARE, *RUN, "--paper")["inputs"]["method"]
    assert mixed["preset"] is None
    paper = method_record(PAPER)
    assert {n: mixed[n] for n in BEHAVING_FIELDS} == {n: paper[n] for n in BEHAVING_FIELDS}
    assert mixed["near_m"] == DEFAULT.near_m and mixed["decel_mps2"] == DEFAULT.decel_mps2


def test_train_keeps_the_logs_collision_points_and_takes_its_own_labels(
    learnt: dict[str, Path], tmp_path: Path
) -> None:
    made = printed("train", learnt["ours_log"], "-o", tmp_path / "f.h5", "--paper")["inputs"][
        "method"
    ]
    labels = (made["near_m"], made["decel_mps2"])
    assert made["preset"] is None and labels == (DEFAULT.near_m, PAPER.decel_mps2)
    assert read_fam(tmp_path / "f.h5").made_by.record() == made


def test_a_fam_from_logs_that_learnt_differently_says_so_and_is_no_preset(
    learnt: dict[str, Path], tmp_path: Path
) -> None:
    fam = tmp_path / "f.h5"
    logs = (learnt["paper_log"], learnt["ours_log"])
    made = printed("train", *logs, "-o", fam, "--paper")["inputs"]["method"]
    assert made == method_record(PAPER) | {
        "preset": None,
        "sessions_differ_in": ["near_m"],
    }
    ran = printed("run", fam, SQUARE, *RUN, "--paper")["inputs"]["method"]
    assert ran == method_record(PAPER) | {"preset": None, "sessions_differ_in": ["near_m"]}


def test_every_file_records_the_method_it_was_made_by(
    learnt: dict[str, Path], tmp_path: Path
) -> None:
    (session,) = read_log(learnt["paper_log"]).sessions
    assert session.method == PAPER
    assert read_fam(learnt["paper_fam"]).method == PAPER
    trace = tmp_path / "run.h5"
    code, _, err = tvl("run", learnt["paper_fam"], SQUARE, *RUN, "--paper", "--log", trace)
    assert code == 0, err
    assert read_run(trace).method == PAPER
    shown = printed("replay", trace)
    assert shown["method"] == method_record(PAPER)
    code, out, _ = tvl("replay", learnt["ours_log"])
    assert code == 0 and "session 0000 method: default" in out
    code, out, _ = tvl("inspect", learnt["paper_fam"], "--top", "1")
    assert code == 0 and out.splitlines()[0] == "method: paper"
    assert printed("inspect", learnt["paper_fam"], "--top", "1")["method"]["preset"] == "paper"


def test_files_from_before_methods_were_recorded_say_so(
    learnt: dict[str, Path], tmp_path: Path
) -> None:
    # A version 2 FAM kept its labels where the reader does not find them, and no learning
    # choice: each is named unrecorded; it reads through its memory.
    code, out, _ = tvl("inspect", GOLDEN_FAM, "--top", "1")
    unknown = "decel_mps2, margin_m, near_m, exploration unrecorded"
    capped = "label_ceiling 1, label_ceiling_radius_m inf"  # no file before then lifted labels
    assert code == 0
    assert out.splitlines()[0] == (
        f"method: default, except labels bump, {capped}, memory patches ({unknown})"
    )
    assert read_log(GOLDEN_LOG).sessions[0].made_by.unrecorded
    # A version 1 session without the record read its method from its parameters.
    old = tmp_path / "old.h5"
    shutil.copy(learnt["ours_log"], old)
    with h5py.File(old, "r+") as f:
        f.attrs["format_version"] = 1
        group = f["sessions/0000"]
        del group.attrs["method"]
        group.attrs["parameters"] = json.dumps({"explore": "random", "near_m": 0.0})
    (session,) = printed("replay", old)["sessions"]
    assert session["method"]["exploration"] == "random" and session["method"]["near_m"] == 0
    assert session["method"]["unrecorded"] == ["decel_mps2", "margin_m"]
    assert "session 0000 method: default, except " in tvl("replay", old)[1]
    run = printed("run", GOLDEN_FAM, SQUARE, *RUN, "--paper")["inputs"]["method"]
    assert run["preset"] is None and run["reflexes"] == []
    assert run["unrecorded"] == ["decel_mps2", "margin_m", "near_m", "exploration"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--paper", "--decel", "0.1"), "--decel cannot be given with --paper, which fixes it"),
        (("--method", "paper", "--near", "0.2"),
         "--near cannot be given with --method paper, which fixes it"),
        (("--paper", "--explore", "novelty"), "--explore cannot be given with --paper"),
        (("--paper", "--label-ceiling", "1.5"), "--label-ceiling cannot be given with --paper"),
        (("--label-ceiling", "0.5"), "--label-ceiling 0.5 must be 1 or more and at most 3"),
        (("--paper", "--memory-window", "5"), "--memory-window cannot be given with --paper"),
        (("--paper", "--method", "paper"), "give --method or --paper, not both"),
        (("--method", "nowhere.toml"), "--method nowhere.toml: neither a preset (paper, default)"),
        (("--method", "papr"), "nor a method file (did you mean 'paper'?)"),
    ],
)  # fmt: skip
def test_contradictions_and_unknown_methods_are_one_line_and_exit_2(
    args: tuple[str, ...], message: str, tmp_path: Path
) -> None:
    log = tmp_path / "log.h5"
    code, _, err = tvl("learn", SQUARE, "--log", log, *args)
    assert code == 2 and len(err.splitlines()) == 1 and message in err, err
    assert not log.exists()


def test_finer_options_that_agree_with_the_paper_or_change_ours_are_taken(
    tmp_path: Path,
) -> None:
    agreeing = printed("learn", SQUARE, "--log", tmp_path / "a.h5", "--minutes", "0.1",
                       "--paper", "--decel", "0.2", "--sonar", "edges")  # fmt: skip
    assert agreeing["inputs"]["method"] == method_record(PAPER) | {
        "preset": None,
        "sonar": "edges",
    }
    changed = printed("learn", SQUARE, "--log", tmp_path / "b.h5", "--minutes", "0.1",
                      "--method", "default", "--decel", "0.5")["inputs"]["method"]  # fmt: skip
    assert (changed["preset"], changed["decel_mps2"]) == (None, 0.5)


def test_a_bad_method_file_is_one_line_naming_the_file_and_key(tmp_path: Path) -> None:
    bad = tmp_path / "m.toml"
    bad.write_text("decel_mps2 = 0.5\nreflex = []\n")
    code, _, err = tvl("run", GOLDEN_FAM, SQUARE, *RUN, "--method", bad)
    assert code == 2
    assert err == f"tvl: error: {bad}: unknown key 'reflex' (did you mean 'reflexes'?)\n"
    bad.write_text("decel_mps2 = 0.5\nmargin_m = ]\n")
    code, _, err = tvl("train", GOLDEN_LOG, "-o", tmp_path / "f.h5", "--method", bad)
    assert code == 2 and err.startswith(f"tvl: error: {bad}:2:") and len(err.splitlines()) == 1


def test_the_example_method_file_is_the_papers_with_the_echo_memory() -> None:
    example = read_method(ROOT / "experiments" / "methods" / "paper-remembering.toml")
    assert example.differs(PAPER) == ["memory"] and example.memory == DEFAULT.memory


# Each file of the memory's settings (experiments/methods/memory/) and the one setting its
# name says it changes from ours.
MEMORY_SETTING_FILES = {
    "window-10": ("window_s", 10.0),
    "window-30": ("window_s", 30.0),
    "window-40": ("window_s", 40.0),
    "window-60": ("window_s", 60.0),
    "range-2": ("range_m", 2.0),
    "range-3": ("range_m", 3.0),
    "range-0.92": ("range_m", 0.92),
    "patch-0.15": ("patch_m", 0.15),
    "points": ("kind", "points"),
    "clearing-always": ("clearing", "always"),
}


def test_each_memory_settings_file_changes_ours_in_the_setting_it_is_named_for() -> None:
    folder = ROOT / "experiments" / "methods" / "memory"
    assert sorted(path.stem for path in folder.glob("*.toml")) == sorted(MEMORY_SETTING_FILES)
    ours = DEFAULT.memory.to_dict()
    for stem, (key, value) in MEMORY_SETTING_FILES.items():
        method = read_method(folder / f"{stem}.toml")
        assert method.differs(DEFAULT) == ["memory"], stem
        memory = method.memory.to_dict()
        assert {k for k in memory if memory[k] != ours[k]} == {key}, stem
        assert memory[key] == value, stem


def lifted(fam_path: Path, radius: str) -> dict:
    """The method `tvl train` records of the example square log's FAM, written to `fam_path`,
    its labels lifted to 1.5 times the top speed on the arcs no wider than `radius`."""
    trained = printed("train", ROOT / "logs" / "square-s1.h5", "-o", fam_path,
                      "--label-ceiling", "1.5", "--label-ceiling-radius", radius)  # fmt: skip
    made_by: dict = trained["inputs"]["method"]
    return made_by


def test_labels_past_the_top_speed_train_a_fam_that_says_so_and_drives_no_faster(
    tmp_path: Path,
) -> None:
    fam_path = tmp_path / "lifted.h5"
    made_by = lifted(fam_path, "inf")
    assert made_by["label_ceiling"] == 1.5 and made_by["preset"] is None
    assert made_by["label_ceiling_radius_m"] is None  # every trajectory
    fam_file = read_fam(fam_path)
    assert (fam_file.method.label_ceiling, fam_file.method.label_ceiling_radius_m) == (1.5, None)
    # Somewhere the way was clear far enough for a rule to learn more than the top speed: the
    # single table holds every trajectory, each column against its own top.
    tops = np.array([t.v_max_mps for t in fam_file.robot_config.trajectories])
    assert (fam_file.fam.velocity_table(0) > tops).any()
    assert (fam_file.fam.velocity_table(0) <= 1.5 * tops + 1e-9).all()
    top = tops.max()
    ran = printed("run", fam_path, SQUARE, *RUN)
    assert 0.0 < ran["mean_drive_speed_mps"] <= top


def test_labels_past_the_top_speed_on_the_tight_arcs_leave_the_long_ways_capped(
    tmp_path: Path,
) -> None:
    fam_path = tmp_path / "tight.h5"
    assert lifted(fam_path, "1")["label_ceiling_radius_m"] == 1.0
    fam_file = read_fam(fam_path)
    assert fam_file.method.label_ceiling_radius_m == 1.0
    tops = np.array(fam_file.robot_config.v_max_mps)
    tight = np.array(fam_file.robot_config.radii_m) <= 1.0  # T3 and T2 each way
    velocities = fam_file.fam.velocity_table(0)  # (rules, trajectories) m/s
    assert (velocities[:, ~tight] <= tops[~tight] + 1e-9).all()
    assert (velocities[:, tight] > tops[tight]).any()


# Each labels file (experiments/methods/labels/) and the labels it stands for: ours before
# the tight arcs were lifted (braking at 0.1 m/s², capped), changed as its name says; or
# ours, with one of its label settings as before.
BEFORE = replace(DEFAULT, decel_mps2=0.1, label_ceiling=1.0)
LIFTS = (1.25, 1.5)
LABELS_FILES = {
    **{f"decel-{d:g}": replace(BEFORE, decel_mps2=d) for d in (0.09, 0.1, 0.13, 0.16, 0.2)},
    **{
        f"ceiling-{c:g}": replace(BEFORE, label_ceiling=c, label_ceiling_radius_m=None)
        for c in LIFTS
    },
    **{f"tight-{c:g}": replace(BEFORE, label_ceiling=c, label_ceiling_radius_m=1.0) for c in LIFTS},
    "ours-every-way": replace(DEFAULT, label_ceiling_radius_m=None),
    "ours-decel-0.1": replace(DEFAULT, decel_mps2=0.1),
}


def test_each_labels_file_is_the_labels_it_is_named_for() -> None:
    folder = ROOT / "experiments" / "methods" / "labels"
    assert sorted(path.stem for path in folder.glob("*.toml")) == sorted(LABELS_FILES)
    for stem, method in LABELS_FILES.items():
        assert read_method(folder / f"{stem}.toml") == method, stem
