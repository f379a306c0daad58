"""Large worlds through the real `tvl`: a hall of 10,000 walls learns in seconds, the largest
world a machine allows runs in reasonable time and within its memory, a world of more walls
than the physics is built from in seconds is refused up front in one line, and Ctrl-C stops
learning in a large world within a second."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
from cluttered_hall import hall_of_walls
from conftest import TVL

from tvl_cli.sim import world_budget

pytestmark = pytest.mark.slow


def run_measured(*args: object, env: dict[str, str] | None = None) -> tuple[int, str, float, int]:
    """Exit status, stderr, CPU seconds and peak resident bytes of a whole `tvl` process."""
    process = subprocess.Popen(
        [TVL, *map(str, args)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env=None if env is None else {**os.environ, **env},
    )
    assert process.stderr is not None
    with process.stderr:
        stderr = process.stderr.read()
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, stderr, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024


def test_a_hall_of_ten_thousand_walls_learns_in_seconds(tmp_path: Path) -> None:
    world = tmp_path / "hall.txt"
    world.write_text(hall_of_walls(10_000))
    code, stderr, cpu_s, _ = run_measured(
        "learn", world, "--log", tmp_path / "log.h5", "--minutes", "0.2"
    )
    assert code == 0, stderr
    assert cpu_s < 30.0


def open_hall(side: int) -> str:
    """A square world of side x side cells of 5 cm: walls round open floor."""
    rows = ["#" * side, *(["#" + "." * (side - 2) + "#"] * (side - 2)), "#" * side]
    rows[5] = "#....>" + rows[5][6:]
    return "cell: 0.05\n" + "\n".join(rows) + "\n"


def test_the_largest_world_a_machine_allows_runs_in_time_and_within_its_memory(
    tmp_path: Path,
) -> None:
    """On a machine of 1 GiB (TVL_MEMORY_MIB), the largest world file is 4.4 MB: an open
    hall of 2,090 x 2,090 cells of 5 cm. Half a simulated minute of running in it takes
    seconds, and the process stays within the machine's memory."""
    memory = {world_budget.MEMORY_VARIABLE: "1024"}
    largest = (512 << 20) // world_budget.BYTES_PER_CELL
    # A hall of side x side cells is side + 1 bytes a row (its line break), and 11 more.
    side = int((math.sqrt(1 + 4 * (largest - 11)) - 1) / 2)
    world = tmp_path / "hall.txt"
    world.write_text(open_hall(side))
    assert largest - 2 * side < len(world.read_bytes()) <= largest
    fam = tmp_path / "fam.h5"
    trained = subprocess.run(
        [TVL, "train", Path(__file__).resolve().parents[2] / "logs" / "lab-s1.h5", "-o", fam],
        capture_output=True,
        check=False,
    )
    assert trained.returncode == 0
    code, stderr, cpu_s, peak = run_measured(
        "run", fam, world, "--behaviour", "avoid", "--minutes", "0.5", env=memory
    )
    assert code == 0, stderr
    assert cpu_s < 60.0 and peak < 1 << 30, (cpu_s, peak)
    bigger = tmp_path / "bigger.txt"
    bigger.write_text(open_hall(side + 2))
    code, stderr, _, _ = run_measured(
        "run", fam, bigger, "--behaviour", "avoid", "--minutes", "0.5", env=memory
    )
    assert code == 2 and stderr.startswith(f"tvl: error: {bigger}: file is over ")


def test_a_checkerboard_of_six_hundred_cells_a_side_is_refused_up_front(tmp_path) -> None:
    """360,000 cells, half of them walls with four sides each: 700,000 wall segments."""
    side = 600
    inner = [
        "#" + "".join(".#"[(r + c) % 2] for c in range(1, side - 1)) + "#" for r in range(side)
    ]
    rows = ["#" * side, *inner[1:-1], "#" * side]
    rows[5] = "#....>" + "." * (side - 7) + "#"
    rows[4] = rows[6] = "#" + "." * (side - 2) + "#"
    world = tmp_path / "board.txt"
    world.write_text("cell: 0.05\n" + "\n".join(rows) + "\n")
    log = tmp_path / "l.h5"
    code, stderr, cpu_s, _ = run_measured("learn", world, "--log", log, "--minutes", "0.1")
    assert code == 2 and stderr.count("\n") == 1
    assert stderr.startswith(f"tvl: error: {world}: a world of ")
    assert "wall segments, over the 250,000 whose physics starts in seconds" in stderr
    assert cpu_s < 10.0
    assert not log.exists()


def cpu_seconds_so_far(pid: int) -> float:
    """The CPU seconds (user and system) a running process has taken, from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def test_ctrl_c_stops_learning_in_a_large_world_within_a_second(tmp_path: Path) -> None:
    """Within a second of the process's CPU: on a machine shared with other work the wall
    clock stretches by however much the others take."""
    world = tmp_path / "hall.txt"
    world.write_text(hall_of_walls(10_000))
    log = tmp_path / "log.h5"
    process = subprocess.Popen(
        # Long enough that learning is still going on when the signal comes: 30 simulated
        # minutes here can take under two seconds.
        [TVL, "learn", str(world), "--log", str(log), "--minutes", "600"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 120
    while not log.exists():  # learning has begun: the log is open
        assert process.poll() is None and time.monotonic() < deadline
        time.sleep(0.05)
    time.sleep(2.0)  # well into learning
    before = cpu_seconds_so_far(process.pid)
    process.send_signal(signal.SIGINT)
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    assert process.returncode == 130
    assert usage.ru_utime + usage.ru_stime - before < 1.0
