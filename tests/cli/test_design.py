"""`tvl design` on the command line, run in process: a configuration `train` and `learn` take."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import invoke as tvl
from json_schemas import valid

EXAMPLE_LOG = Path(__file__).resolve().parents[2] / "logs" / "square-s1.h5"
SQUARE = Path(__file__).resolve().parents[2] / "worlds" / "square.txt"


@pytest.fixture(scope="module")
def designed(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    output = tmp_path_factory.mktemp("design") / "inputs.json"
    done = tvl("design", EXAMPLE_LOG, "-o", output, "--budget", "2000", "--json")
    assert done.returncode == 0, done.stderr
    return output, valid("design", done.stdout)


def test_the_summary_describes_the_file_written(designed: tuple[Path, dict]) -> None:
    output, printed = designed
    written = json.loads(output.read_text())
    assert printed["outputs"] == {"config": str(output)}
    assert printed["config"] == written["name"] == "inputs"
    assert printed["inputs"]["budget_rules"] == 2000 >= printed["rules"]
    assert printed["inputs"]["logs"][0]["sha256"] == written["design"]["logs_sha256"][0]
    assert [t["name"] for t in printed["tables"]] == [t["name"] for t in written["tables"]]
    assert printed["choices"] == written["design"]["choices"]
    assert [s["config"] for s in printed["heldout"]] == ["inputs", "single", "multi", "designed"]
    assert sum(t["rules"] for t in printed["tables"]) == printed["rules"]


def test_the_inputs_are_chosen_by_the_labels_of_the_method_given(
    designed: tuple[Path, dict], tmp_path: Path
) -> None:
    """Ours labels every trajectory from the echoes heard; the paper's the driven one from
    its bump: the same log gives other data, and other choices."""
    _, ours = designed
    done = tvl("design", EXAMPLE_LOG, "-o", tmp_path / "paper.json", "--budget", "2000",
               "--paper", "--json")  # fmt: skip
    assert done.returncode == 0, done.stderr
    paper = valid("design", done.stdout)
    assert paper["inputs"]["method"]["labels"] == "bump"
    assert ours["inputs"]["method"]["labels"] == "heard"
    assert paper["choices"] != ours["choices"]


@pytest.mark.slow  # over a second
def test_train_and_learn_take_the_file_as_config(
    designed: tuple[Path, dict], tmp_path: Path
) -> None:
    output, printed = designed
    done = tvl("train", EXAMPLE_LOG, "--config", output, "-o", tmp_path / "fam.h5", "--json")
    assert done.returncode == 0, done.stderr
    trained = valid("train", done.stdout)
    assert trained["inputs"]["config_file"]["path"] == str(output)
    assert trained["config"] == "inputs" and trained["rules_total"] == printed["rules"]
    assert trained["exemplars"] > 0 and trained["rules_touched"] > 0
    done = tvl("learn", SQUARE, "--log", tmp_path / "l.h5", "--minutes", "0.2", "--config", output)
    assert done.returncode == 0, done.stderr


@pytest.mark.slow  # over a second: learns, runs or draws at length
def test_the_same_seed_writes_the_same_file(designed: tuple[Path, dict], tmp_path: Path) -> None:
    output, _ = designed
    again = tmp_path / "inputs.json"
    done = tvl("design", EXAMPLE_LOG, "-o", again, "--budget", "2000", "--seed", "1")
    assert done.returncode == 0, done.stderr
    assert again.read_bytes() == output.read_bytes()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((), "Missing argument 'LOGS...'"),
        ((EXAMPLE_LOG, "--budget", "13"), "--budget 13: too small for one input per table"),
        (("unreadable.h5",), "unreadable.h5"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(
    args: tuple[str | Path, ...], message: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "unreadable.h5").write_text("not HDF5")
    monkeypatch.chdir(tmp_path)
    done = tvl("design", *args, "-o", "out.json")
    assert done.returncode == 2
    assert len(done.stderr.splitlines()) == 1 and message in done.stderr
    assert done.stderr.startswith("tvl: error:")
    assert not (tmp_path / "out.json").exists()
