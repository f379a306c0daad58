"""`tvl bench` at its tiny size, for real: every cell's row in one table with ours, the
references and the user's controllers (a Python policy and a FAM file) in the same worlds
with the same seeds; a bench run again runs nothing; a Dask cluster's workers give the rows
of local processes; a bench killed part way goes on where it stopped; and a row is what
`tvl run` gives its FAM."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from conftest import TVL
from json_schemas import valid

from tvl_cli.core.method import DEFAULT
from tvl_cli.sweep.layout import learning_tag

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
# A controller of tvl/SonarRing-v0: straight on while the way ahead is clear, else turn left.
POLICY = """\
def act(observation):
    ahead = min(observation[0], observation[1], observation[15])
    return 3 if ahead > 0.8 else 7
"""
# The cheapest suite that still has every kind of row: one configuration, the map's DWA.
TINY = ["--size", "tiny", "--config", "single", "--references", "dwa-map"]
# Measures of the machine, not of the runs: left out where rows are compared.
TIMING = "cell_cpu_s"


def journal(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]


def comparable(rows: list[dict]) -> list[dict]:
    return sorted(({k: v for k, v in row.items() if k != TIMING} for row in rows), key=str)


@pytest.fixture(scope="module")
def controllers(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A Python policy's file, and a FAM file trained from the example log."""
    folder = tmp_path_factory.mktemp("controllers")
    policy = folder / "turn_left.py"
    policy.write_text(POLICY)
    fam = folder / "square.h5"
    done = subprocess.run(
        [TVL, "train", ROOT / "logs" / "square-s1.h5", "-o", fam], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    return policy, fam


def suite(controllers: tuple[Path, Path]) -> list[object]:
    """The tiny suite's arguments, with both controllers."""
    policy, fam = controllers
    return [*TINY, "--controller", f"turn-left={policy}:act", "--controller", f"square={fam}"]


def again(benched: tuple[Path, dict], controllers: tuple[Path, Path], *extra: str) -> str:
    """What `tvl bench generalization` prints, run again on the benched suite's directory."""
    done = subprocess.run(
        [TVL, "bench", "generalization", *suite(controllers), "--out", benched[0], *extra],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def benched(
    controllers: tuple[Path, Path], tmp_path_factory: pytest.TempPathFactory
) -> tuple[Path, dict]:
    """The tiny suite with both controllers, on two local processes: its directory and its
    JSON document."""
    out = tmp_path_factory.mktemp("bench") / "out"
    where = ["--out", out, "--workers", "2", "--json"]
    done = subprocess.run(
        [TVL, "bench", "generalization", *suite(controllers), *where],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""  # no progress bar without a terminal, nor with --json
    return out, valid("bench generalization", done.stdout)


def test_a_python_policy_and_a_fam_are_scored_beside_ours_in_one_table(
    benched: tuple[Path, dict],
) -> None:
    out, document = benched
    rows = document["rows"]
    assert comparable(rows) == comparable(journal(out))
    worlds = {"rooms-s1001", "rooms-s1002"}
    by_entry = {entry: [r for r in rows if r["entry"] == entry] for entry in
                ("default", "dwa-map", "turn-left", "square")}  # fmt: skip
    for entry, found in by_entry.items():
        assert {r["world"] for r in found} == worlds, entry
        assert {r["seed"] for r in found} == {1}, entry
    # Ours and the FAM file: every behaviour; the policy: the environment's avoid and goal.
    assert sorted(r["behaviour"] for r in by_entry["square"]) == sorted(
        ["avoid", "wall-left", "wall-right", "goal"] * 2
    )
    assert sorted(r["behaviour"] for r in by_entry["turn-left"]) == ["avoid"] * 2 + ["goal"] * 2
    assert {r["role"] for r in by_entry["turn-left"] + by_entry["square"]} == {"controller"}
    assert {r["reads_map"] for r in by_entry["dwa-map"]} == {True}
    # The policy drives: it turns on the spot (spins) and goes straight on.
    assert all(r["distance_m"] > 0 for r in by_entry["turn-left"])
    assert all(r["spins"] > 0 for r in by_entry["turn-left"])
    figures = {(f["entry"], f["config"]): f for f in document["figures"]}
    assert set(figures) == {("default", "single"), ("dwa-map", None), ("turn-left", None),
                            ("square", "single")}  # fmt: skip
    assert figures[("turn-left", None)]["runs"] == 4
    assert figures[("square", "single")]["autopsy"] is not None  # a FAM-driven run's


def test_the_terminal_table_names_each_row_and_what_it_reads(
    benched: tuple[Path, dict], controllers: tuple[Path, Path]
) -> None:
    lines = again(benched, controllers).splitlines()
    assert "8 cells (0 run now, 8 before)" in lines[0]
    assert any(line.startswith("default · single (ours)") for line in lines)
    assert any(line.startswith("dwa-map (reference, reads the map)") for line in lines)
    assert any(line.startswith("turn-left (controller)") for line in lines)
    assert any(line.startswith("square · single (controller)") for line in lines)


def test_the_world_table_gives_each_rows_competent_runs_and_speed_world_by_world(
    benched: tuple[Path, dict], controllers: tuple[Path, Path]
) -> None:
    _, document = benched
    lines = again(benched, controllers, "--by-world", "--markdown").splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| world |"))
    header = [cell.strip() for cell in lines[start].strip("|").split("|")]
    assert header[1:] == ["default · single", "dwa-map", "turn-left", "square · single"]
    table = {}
    for line in lines[start + 2 : start + 4]:
        world, *cells = (cell.strip() for cell in line.strip("|").split("|"))
        table[world] = dict(zip(header[1:], cells, strict=True))
    assert set(table) == {"rooms-s1001", "rooms-s1002"}
    # Each cell, from the journal's rows counted here.
    for world, cells in table.items():
        for column, cell in cells.items():
            entry, _, config = column.partition(" · ")
            key = (world, entry, config or None)
            runs = [r for r in document["rows"] if (r["world"], r["entry"], r.get("config")) == key]
            competent = sum(r["competent"] for r in runs)
            speed = sum(r["mean_speed_mps"] for r in runs) / len(runs)
            assert cell == f"{competent}/{len(runs)}, {speed:.2f} m/s", (world, column)


def test_a_row_is_what_tvl_run_gives_its_fam(benched: tuple[Path, dict], tmp_path: Path) -> None:
    out, document = benched
    row = next(
        r for r in document["rows"] if r["entry"] == "default" and r["behaviour"] == "wall-left"
    )
    fam = out / "fams" / f"{row['world']}-s1-m1.0-single{learning_tag(DEFAULT)}-single.h5"
    world = out / "worlds" / f"{row['world']}.txt"
    done = subprocess.run(
        [TVL, "run", fam, world, "--behaviour", "wall-left", "--minutes", "0.5", "--seed", "1",
         "--json"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    printed = json.loads(done.stdout)
    for key in ("distance_m", "contacts", "spins", "mean_clearance_m", "mean_wall_clearance_m"):
        assert row[key] == printed[key], key


def test_a_dask_clusters_workers_give_the_local_rows(
    benched: tuple[Path, dict], tmp_path: Path
) -> None:
    distributed = pytest.importorskip("distributed")
    out, _ = benched
    elsewhere = tmp_path / "out"
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=":0",
    ) as cluster:
        done = subprocess.run(
            [TVL, "bench", "generalization", *TINY, "--out", elsewhere, "--scheduler",
             cluster.scheduler_address, "--json"],
            capture_output=True, text=True, timeout=600,
        )  # fmt: skip
    assert done.returncode == 0, done.stderr
    document = valid("bench generalization", done.stdout)
    assert (document["done"], document["skipped"]) == (4, 0)
    local = [r for r in journal(out) if r["entry"] in ("default", "dwa-map")]
    assert comparable(journal(elsewhere)) == comparable(local)


def wait_for(found: Callable[[], bool], timeout_s: float = 300.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not found():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.2)


def test_a_killed_bench_goes_on_where_it_stopped(
    benched: tuple[Path, dict], tmp_path: Path
) -> None:
    out, _ = benched
    elsewhere = tmp_path / "out"
    # Its own session, so that its worker processes are killed with it.
    first = subprocess.Popen(
        [TVL, "bench", "generalization", *TINY, "--out", elsewhere, "--workers", "1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    journal_file = elsewhere / "results.jsonl"
    try:
        wait_for(lambda: journal_file.exists() and journal_file.stat().st_size > 0)
    finally:
        os.killpg(first.pid, signal.SIGKILL)
        first.wait()
    kept = {row["cell"] for row in journal(elsewhere)}
    assert 1 <= len(kept) < 4  # some cells ended before the kill, not all
    done = subprocess.run(
        [TVL, "bench", "generalization", *TINY, "--out", elsewhere, "--json"],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    document = json.loads(done.stdout)
    assert (document["done"], document["skipped"]) == (4 - len(kept), len(kept))
    rows = journal(elsewhere)
    assert len(rows) == len({(r["cell"], r["entry"], r.get("config"), r["behaviour"],
                              r["world"]) for r in rows})  # each cell once  # fmt: skip
    local = [r for r in journal(out) if r["entry"] in ("default", "dwa-map")]
    assert comparable(rows) == comparable(local)


def test_the_claims_run_by_each_method_at_the_tiny_size(tmp_path: Path) -> None:
    done = subprocess.run(
        [TVL, "bench", "claims", "--size", "tiny", "--claim", "fig24", "--claim", "fig21",
         "--out", tmp_path / "out", "--json"],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    document = valid("bench claims", done.stdout)
    assert [v["claim"] for v in document["verdicts"]] == ["fig21", "fig24"]
    for verdict in document["verdicts"]:
        assert [m["method"] for m in verdict["verdicts"]] == ["paper", "default"]
    # Figure 21's square and Figure 24's share a log: one cell a method, with both claims.
    square = {r["cell"] for r in document["rows"] if r["world"] == "square"}
    assert len(square) == 2
    rows = document["rows"]
    assert sorted({(r["claim"], r["world"]) for r in rows}) == [
        ("fig21", "circle"), ("fig21", "square"), ("fig24", "square"),
    ]  # fmt: skip
    # Each method's log learnt once, in the bench's logs/.
    logs = sorted(p.name for p in (tmp_path / "out" / "logs").iterdir())
    assert len(logs) == 4  # square and circle, by each method


def test_pooled_rows_train_each_worlds_log_with_the_pool(tmp_path: Path) -> None:
    pool = ROOT / "logs" / "square-s1.h5"
    out = tmp_path / "out"
    done = subprocess.run(
        [TVL, "bench", "generalization", "--size", "tiny", "--config", "single",
         "--references", "none", "--pool", pool, "--out", out, "--json"],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    document = valid("bench generalization", done.stdout)
    [pooled] = document["inputs"]["pool"]
    assert pooled["path"] == str(pool) and len(pooled["sha256"]) == 64
    rows = [r for r in document["rows"] if r["entry"] == "pooled"]
    assert {(r["world"], r["behaviour"]) for r in rows} == {
        (w, b) for w in ("rooms-s1001", "rooms-s1002")
        for b in ("avoid", "wall-left", "wall-right", "goal")
    }  # fmt: skip
    assert {r["role"] for r in rows} == {"method"}
    ours = {(r["world"], r["behaviour"]): r for r in document["rows"] if r["entry"] == "default"}
    # The pooled FAM is another FAM than ours: trained from both logs, its runs differ.
    assert any(r["distance_m"] != ours[r["world"], r["behaviour"]]["distance_m"] for r in rows)
    [fam] = (out / "fams").glob("rooms-s1001-*-pooled-*.h5")
    inspected = subprocess.run([TVL, "inspect", fam, "--json"], capture_output=True, text=True)
    logs = json.loads(inspected.stdout)["provenance"]["logs"]
    assert [log["path"] for log in logs] == [
        str(out / "logs" / f"rooms-s1001-s1-m1.0-single{learning_tag(DEFAULT)}.h5"), str(pool)
    ]  # fmt: skip
