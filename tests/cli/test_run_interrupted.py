"""`tvl run` stopped by Ctrl-C or SIGTERM, through the real process: it ends the step under
way, prints what it did, keeps the trace so far and exits 130 (143), as `tvl learn` does."""

from __future__ import annotations

import json
import signal
import subprocess
import time
from pathlib import Path

import pytest
from conftest import TVL, invoke

from tvl_cli.io.runfile import read_run

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
LONG_MINUTES = 10_000.0  # far longer than the test waits
DRIVING_S = 2.0  # wall seconds the run drives before it is stopped

pytestmark = pytest.mark.slow  # every test starts the real `tvl` and signals it


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    trained = tmp_path_factory.mktemp("interrupted") / "single.h5"
    assert invoke("train", EXAMPLE_LOG, "-o", trained).returncode == 0
    return trained


def start_run(fam: Path, trace: Path, *args: str) -> subprocess.Popen[str]:
    """A long `tvl run` writing `trace`, once it has driven for a while."""
    process = subprocess.Popen(
        [TVL, "run", str(fam), str(SQUARE), "--behaviour", "avoid", "--minutes",
         str(LONG_MINUTES), "--log", str(trace), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )  # fmt: skip
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        # The trace is written beside its name while the run goes (HDF5 holds its chunks
        # until it closes the file): once it is there, the run has begun.
        if any(trace.parent.glob(f".{trace.name}.*.tmp")):
            time.sleep(DRIVING_S)
            return process
        time.sleep(0.05)
    process.kill()
    raise AssertionError("the run never started writing its trace")


@pytest.mark.parametrize(("stop", "status"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_stopped_run_keeps_its_trace_so_far_and_exits_as_a_signal_does(
    fam: Path, tmp_path: Path, stop: signal.Signals, status: int
) -> None:
    trace = tmp_path / "run.h5"
    process = start_run(fam, trace, "--json")
    process.send_signal(stop)
    printed, err = process.communicate(timeout=60)
    assert process.returncode == status, err
    assert "Aborted!" not in err
    assert err.splitlines()[-1].startswith(f"stopped by {stop.name} after ")
    assert err.rstrip().endswith(f"{trace} keeps it")
    document = json.loads(printed)
    assert document["status"] == f"interrupted: {stop.name}"
    kept = read_run(trace)
    assert kept.status == f"interrupted: {stop.name}"
    # The trace holds every step the printed metrics count, and no more.
    assert 0 < document["sim_s"] < LONG_MINUTES * 60
    assert kept.metrics["sim_s"] == document["sim_s"]
    assert kept.steps == round(document["sim_s"] / 0.1)
    assert [p.name for p in tmp_path.iterdir()] == ["run.h5"]  # no temporary file left
