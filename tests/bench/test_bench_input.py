"""`tvl bench` refuses what it cannot run in one line, exit 2, before anything is written; and
its suites are planned as documented (the worlds of a set or a span, the trials of a size, a
cell for each world, trial and entry)."""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest

from tvl_cli.bench.claims_suite import ClaimsRequest
from tvl_cli.bench.claims_suite import plan as claims_plan
from tvl_cli.bench.controllers import METHOD, POLICY, parse_controller
from tvl_cli.bench.generalization_suite import GeneralizationRequest, plan
from tvl_cli.bench.suite_cells import DwaCell, FamFileCell, LearntCell, PolicyCell, cell_id
from tvl_cli.bench.suite_options import parse_span
from tvl_cli.bench.suite_work import do_cell, world_path
from tvl_cli.core.errors import BadInput
from tvl_cli.core.method import DEFAULT, PAPER

Invoke = Callable[..., subprocess.CompletedProcess[str]]
ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--worlds", "0-3"], "--worlds 0-3: give N or A-B, worlds counted from 1"),
        (["--worlds", "5-2"], "--worlds 5-2: give N or A-B"),
        (["--worlds", "19-21"], "--worlds 19-21: the test set's worlds are 1 to 20"),
        (["--worlds", "1001"], "--worlds 1001: the test set's worlds are 1 to 20, counted from 1 "),
        (["--references", "dwa"], "--references dwa: no reference 'dwa' (did you mean"),
        (["--threshold", "1.5"], "--threshold 1.5 is outside (0, 1]"),
        (["--method", "mine.toml"], "--method mine.toml: neither a preset"),
        (["--config", "mine.json"], "mine.json: no such FAM configuration"),
        (["--controller", "x=nowhere.h5"], "nowhere.h5"),
        (["--controller", "lines"], "--controller 'lines': not a method"),
        (["--controller", "math:nothing"], "--controller math:nothing: math has no callable"),
        (["--controller", "no_such_module_here:act"], "cannot import no_such_module_here"),
        (["--controller", "default"], "--controller default: a row of that name is there"),
        (["--workers", "2", "--scheduler", "local:2"], "give --workers or --scheduler, not both"),
        (["--scheduler", "local:0"], "--scheduler local:0: give local, or local:N"),
        (["--pool", "nowhere.h5"], "nowhere.h5"),
        (["--pool", str(ROOT / "worlds" / "square.txt")], "square.txt"),
        (["--pool", str(ROOT / "fams" / "general-single.h5")], "tvl-log"),
        (
            ["--pool", "logs/square-s1.h5", "--pool", "logs/square-s1.h5"],
            "--pool: a log is given twice",
        ),
    ],
)
def test_a_bad_option_is_one_line_and_nothing_is_written(
    invoke_tvl: Invoke, tmp_path: Path, args: list[str], message: str
) -> None:
    out = tmp_path / "out"
    done = invoke_tvl("bench", "generalization", "--size", "tiny", "--out", out, *args)
    assert done.returncode == 2, done.stderr
    assert done.stderr.startswith("tvl: error:") and done.stderr.count("\n") == 1
    assert message in done.stderr
    assert not out.exists()


def test_a_claim_or_a_method_the_claims_do_not_know_is_refused(
    invoke_tvl: Invoke, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    done = invoke_tvl("bench", "claims", "--claim", "fig23", "--out", out)
    assert (done.returncode, done.stderr) == (
        2, "tvl: error: --claim fig23: no such claim (did you mean 'fig27'?)\n"
    )  # fmt: skip
    done = invoke_tvl("bench", "claims", "--method", "paper", "--method", "paper", "--out", out)
    assert done.returncode == 2 and "--method: a method is given twice" in done.stderr
    assert not out.exists()


def test_the_sizes_take_the_sets_first_worlds_and_a_span_any_of_them() -> None:
    quick = plan(GeneralizationRequest(DEFAULT, size="quick", references=()))
    assert quick.world_seeds == [1001, 1002, 1003, 1004, 1005] and quick.trials == [1, 2]
    tuning = plan(GeneralizationRequest(DEFAULT, world_set="tuning", span=(11, 12), size="tiny",
                                        references=()))  # fmt: skip
    assert tuning.world_seeds == [11, 12] and tuning.trials == [1]
    assert sorted(tuning.worlds) == ["rooms-s11", "rooms-s12"]
    assert parse_span("3") == (1, 3) and parse_span("11-20") == (11, 20)


def test_a_cell_for_each_world_trial_and_entry_the_maps_dwa_once_a_world() -> None:
    planned = plan(GeneralizationRequest(DEFAULT, size="tiny", trials=2))
    kinds = [type(cell).__name__ for cell in planned.cells if cell.world == "rooms-s1001"]
    # Each trial: ours (with the oracle labels' runs), the oracle velocities, the ideal sonar,
    # the ring's DWA and Q-learning; the map's DWA once.
    assert kinds.count("LearntCell") == 4 and kinds.count("DwaCell") == 3
    assert kinds.count("QlearnCell") == 2 and kinds.count("OracleCell") == 2
    ours = [c for c in planned.cells if isinstance(c, LearntCell) and c.method == DEFAULT]
    # Every configuration with every behaviour, from one log.
    assert {(r.fam.config.name, r.behaviour) for r in ours[0].runs if r.fam} == {
        (c, b) for c in ("single", "multi", "designed")
        for b in ("avoid", "wall-left", "wall-right", "goal")
    }  # fmt: skip
    ring = [c for c in planned.cells if isinstance(c, DwaCell) and c.sensor == "ring"]
    assert {c.memory for c in ring} == {DEFAULT.memory}  # through our memory
    assert [e.name for e in planned.entries] == [
        "default", "oracle-velocities", "oracle-labels", "ideal-sonar", "dwa-map", "dwa-ring",
        "q-learning",
    ]  # fmt: skip
    assert [e.reads_map for e in planned.entries] == [False, True, True, False, True, False, False]


def test_pooled_rows_are_trained_in_ours_cell_from_its_log_and_the_pool() -> None:
    pool = ((str(ROOT / "logs" / "square-s1.h5"), "0" * 64),)
    planned = plan(GeneralizationRequest(DEFAULT, size="tiny", references=(), pool=pool))
    assert [e.name for e in planned.entries] == ["default", "pooled"]
    assert all(isinstance(cell, LearntCell) for cell in planned.cells)
    for cell in planned.cells:  # one log a world and trial: ours' runs and the pooled ones
        by_entry: dict[str, set] = {}
        for run in cell.runs:
            assert run.fam is not None
            by_entry.setdefault(dict(run.tags)["entry"], set()).add(run.fam.pooled)
        assert by_entry == {"default": {()}, "pooled": {pool}}
    without = plan(GeneralizationRequest(DEFAULT, size="tiny", references=()))
    assert [e.name for e in without.entries] == ["default"]


def test_a_controller_is_known_by_its_form(tmp_path: Path) -> None:
    policy = tmp_path / "mine.py"
    policy.write_text("def act(observation):\n    return 3\n")
    found = parse_controller(f"{policy}:act")
    assert (found.name, found.kind, found.spec) == ("act", POLICY, f"{policy}:act")
    assert parse_controller("paper").kind == METHOD
    assert parse_controller("theirs=paper").method == PAPER
    with pytest.raises(BadInput, match=r"no such file .*ppo\.zip|needs Stable-Baselines3"):
        parse_controller(f"PPO:{tmp_path / 'ppo.zip'}")


def test_a_fam_file_of_another_kind_is_refused(tmp_path: Path) -> None:
    with pytest.raises(BadInput, match=r"log\.h5"):
        parse_controller(str(ROOT / "logs" / "square-s1.h5").replace("square-s1", "log"))
    with pytest.raises(BadInput, match="tvl-fam"):
        parse_controller(str(ROOT / "logs" / "square-s1.h5"))


def _file_cells(spec: str, root: Path) -> list[FamFileCell | PolicyCell]:
    """The cells that score the controller `spec` at the tiny size, their worlds written
    under `root`."""
    request = GeneralizationRequest(
        DEFAULT, size="tiny", references=(), configs=(), controllers=(parse_controller(spec),)
    )
    planned = plan(request)
    for name, text in planned.worlds.items():
        world_path(root, name).parent.mkdir(parents=True, exist_ok=True)
        world_path(root, name).write_text(text)
    return [cell for cell in planned.cells if isinstance(cell, FamFileCell | PolicyCell)]


def test_a_fam_trained_again_at_its_path_is_run_again_and_refused_while_running(
    tmp_path: Path,
) -> None:
    fam = tmp_path / "mine.h5"
    shutil.copy(ROOT / "fams" / "general-single.h5", fam)
    before = _file_cells(f"mine={fam}", tmp_path)
    shutil.copy(ROOT / "fams" / "general-designed.h5", fam)  # another FAM, the same path
    after = _file_cells(f"mine={fam}", tmp_path)
    assert before and len(after) == len(before)
    # Known by the file's contents, not its path: none of the old cells' rows are read back.
    assert not {cell_id(cell) for cell in before} & {cell_id(cell) for cell in after}
    with pytest.raises(BadInput, match=r"--controller .*mine\.h5: the file changed since"):
        do_cell(before[0], tmp_path)


def test_a_policy_file_written_again_is_run_again_and_refused_while_running(
    tmp_path: Path,
) -> None:
    policy = tmp_path / "mine.py"
    policy.write_text("def act(observation):\n    return 3\n")
    before = _file_cells(f"{policy}:act", tmp_path)
    policy.write_text("def act(observation):\n    return 2\n")
    after = _file_cells(f"{policy}:act", tmp_path)
    assert before and len(after) == len(before)
    assert not {cell_id(cell) for cell in before} & {cell_id(cell) for cell in after}
    with pytest.raises(BadInput, match=r"--controller .*mine\.py: the file changed since"):
        do_cell(before[0], tmp_path)


def test_policies_observe_through_ours_unless_told() -> None:
    request = GeneralizationRequest(
        PAPER, "paper", size="tiny", references=(),
        controllers=(parse_controller("math:floor"),),
    )  # fmt: skip
    cells = [c for c in plan(request).cells if isinstance(c, PolicyCell)]
    assert cells and {c.observe for c in cells} == {PAPER}
    assert {r.behaviour for c in cells for r in c.runs} == {"avoid", "goal"}


def test_claims_learn_once_a_log_and_run_every_claim_from_it() -> None:
    worlds, cells, trials = claims_plan(ClaimsRequest(("default",), size="tiny"))
    assert trials == [1] and sorted(worlds) == ["circle", "lab", "obstacles", "square"]
    keys = [(c.world, c.learn_config, c.learn_minutes) for c in cells if isinstance(c, LearntCell)]
    assert len(keys) == len(set(keys))
    square = next(c for c in cells if isinstance(c, LearntCell) and c.world == "square")
    assert {dict(r.tags)["claim"] for r in square.runs} == {"avoid-9min", "fig21", "fig24"}
