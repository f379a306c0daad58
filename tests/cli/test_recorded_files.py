"""What a trace and a log record of the files beside them: a trace names its FAM by its path
from the trace's folder, so that the two moved together still find each other; a session
of another world added to a log is warned of, in one line. Through the real commands,
in-process."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import h5py
import pytest

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
CIRCLE = ROOT / "worlds" / "circle.txt"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"


# Each test learns, trains, runs or draws: over a second each.
pytestmark = pytest.mark.slow


@pytest.fixture
def shared(invoke_tvl, tmp_path: Path) -> Path:
    """A folder holding a FAM in fams/ and the trace of a run with it in runs/."""
    (tmp_path / "fams").mkdir()
    (tmp_path / "runs").mkdir()
    fam, trace = tmp_path / "fams" / "single.h5", tmp_path / "runs" / "run.h5"
    assert invoke_tvl("train", EXAMPLE_LOG, "-o", fam).returncode == 0
    ran = invoke_tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.1", "--log", trace)
    assert ran.returncode == 0, ran.stderr
    return tmp_path


def test_a_trace_names_its_fam_from_its_own_folder(shared: Path) -> None:
    with h5py.File(shared / "runs" / "run.h5") as f:
        assert json.loads(f.attrs["parameters"])["fam"] == "../fams/single.h5"


def test_moved_together_the_trace_still_finds_its_fam(
    invoke_tvl, shared: Path, tmp_path_factory: pytest.TempPathFactory, monkeypatch
) -> None:
    elsewhere = tmp_path_factory.mktemp("colleague") / "copy"
    shutil.copytree(shared, elsewhere)
    shutil.rmtree(shared / "fams")  # the original FAM is gone: only the copy can explain
    monkeypatch.chdir(elsewhere.parent)  # and from another folder than the run's
    explained = invoke_tvl("explain", "copy/runs/run.h5", "--at", "2", "--json")
    assert explained.returncode == 0, explained.stderr
    assert json.loads(explained.stdout)["inputs"]["fam"]["path"] == "copy/fams/single.h5"
    replayed = json.loads(invoke_tvl("replay", "copy/runs/run.h5", "--json").stdout)
    assert replayed["parameters"]["fam"]["path"] == "copy/fams/single.h5"


def test_a_trace_written_before_names_its_fam_from_where_the_run_was_made(
    invoke_tvl, shared: Path, monkeypatch
) -> None:
    trace = shared / "runs" / "run.h5"
    with h5py.File(trace, "r+") as f:  # as traces recorded it: from the run's own folder
        parameters = json.loads(f.attrs["parameters"])
        f.attrs["parameters"] = json.dumps({**parameters, "fam": "fams/single.h5"})
    monkeypatch.chdir(shared)
    explained = invoke_tvl("explain", "runs/run.h5", "--at", "2")
    assert explained.returncode == 0, explained.stderr


def test_a_session_of_another_world_added_to_a_log_is_warned_of_in_one_line(
    invoke_tvl, tmp_path: Path
) -> None:
    log = tmp_path / "log.h5"
    shutil.copy(EXAMPLE_LOG, log)
    same = invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.1", "--json")
    assert same.returncode == 0 and same.stderr == ""
    other = invoke_tvl("learn", CIRCLE, "--log", log, "--minutes", "0.1", "--json")
    assert other.returncode == 0
    assert other.stderr == (
        f"tvl: warning: {log}: adding a session in circle ({CIRCLE}) to sessions in square: "
        "a FAM trained from this log learns from every world in it\n"
    )
    fam = tmp_path / "fam.h5"
    assert invoke_tvl("train", EXAMPLE_LOG, "-o", fam).returncode == 0
    behaving = invoke_tvl("run", fam, ROOT / "worlds" / "lab.txt", "--behaviour", "avoid",
                          "--minutes", "0.1", "--learn-log", log, "--json")  # fmt: skip
    assert behaving.returncode == 0
    assert behaving.stderr.count("\n") == 1
    assert behaving.stderr.startswith(f"tvl: warning: {log}: adding a session in lab")
    assert "to sessions in circle, square:" in behaving.stderr
