"""Large worlds: an imported Nav2 map (the depot, 4,082 wall segments) against the bundled
lab, measured in the same run, each figure beside its target.

    python benchmarks/large_worlds.py [--map MAP.yaml] [--minutes M] [--repeats R]
                                      [--memory] [--json]

- the map imported: a whole `tvl world import MAP.yaml` process (no target);
- its coverage floor, in this process, the kernels loaded first: CPU seconds (<= 2 s);
- `tvl replay LOG` of M simulated minutes of learning in the map (not timed): a whole
  process, start-up included (<= 2 s of CPU);
- a control step, in this process, M simulated minutes each in the map and in the lab: CPU
  microseconds a step, and the map's over the lab's (<= 1.5), of sensing (sim_speed.py's
  wander, a ring read and a physics step every step, and the clearance a run measures) and
  of learning (the paper's explorer); and, with no target, of avoiding with a FAM trained
  from logs/lab-s1.h5, whose steps mix differently from world to world (where the robot
  spins or backs off it reads no ring and chooses nothing);
- with --memory, the peak memory of `tvl learn --minutes 0.1` in a hall of open floor and in
  a checkerboard of walls, each at two sizes: the bytes a grid cell and a wall segment add,
  beside what sim/world_budget.py assumes of them;
- with --limits, whole processes at the limits: `tvl learn --minutes 0.2` in a 100 m hall of
  10,000 `wall:` lines (scale.py's); `tvl run --minutes 0.5` in the largest world file a
  machine of 1 GiB allows (TVL_MEMORY_MIB=1024), an open hall; and `tvl learn` refusing a
  checkerboard of 600 x 600 cells (700,000 wall segments): CPU seconds and peak memory.

Each time is the median of R runs. The map is Nav2's (ros-navigation/navigation2), which the
project keeps outside its checkout: --map names it (default ../shared/maps/nav2/depot.yaml
from the checkout).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import tempfile
from pathlib import Path

import numpy as np
from scale import hall_with_walls
from sim_speed import wander
from timing import TVL, cpu_seconds, figure_line, median_seconds, run_process

from tvl_cli.agent.drive_tvl import behave
from tvl_cli.agent.explore import Learner
from tvl_cli.analysis.coverage import world_floor
from tvl_cli.core.fam import Fam
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.method import DEFAULT
from tvl_cli.io.fam_config_file import resolve_fam_config
from tvl_cli.io.famfile import read_fam
from tvl_cli.sim import world_budget
from tvl_cli.sim.geometry import clearance_m
from tvl_cli.sim.robot import Simulator
from tvl_cli.sim.worldmap import WorldMap, load_world, parse_world

ROOT = Path(__file__).resolve().parent.parent
LAB = ROOT / "worlds" / "lab.txt"
EXAMPLE_LOG = ROOT / "logs" / "lab-s1.h5"
DEPOT = ROOT.parent / "shared" / "maps" / "nav2" / "depot.yaml"
CONTROL_PERIOD_S = 0.1
TARGET_FLOOR_S = 2.0
TARGET_REPLAY_S = 2.0
TARGET_STEP_RATIO = 1.5


def sensing_step_us(world: WorldMap, minutes: float) -> float:
    """CPU microseconds a wandering step (a ring read and a physics step, then the clearance
    a run measures at each pose the wander passed), `minutes` simulated."""
    steps = round(minutes * 60.0 / CONTROL_PERIOD_S)
    sim = Simulator(world, DEFAULT.robot(), np.random.default_rng(1))
    readings: list[tuple[tuple[float, float, float], np.ndarray]] = []
    wandering_s = cpu_seconds(lambda: wander(sim, steps, readings), 1)
    radius_m = sim.robot.radius_m
    poses = [pose for pose, _ in readings]
    clearance_s = cpu_seconds(
        lambda: [clearance_m(sim.geometry, x, y, radius_m) for x, y, _ in poses], 1
    )
    return 1e6 * (wandering_s + clearance_s) / steps


def learning_step_us(world: WorldMap, minutes: float) -> float:
    """CPU microseconds a control step of the paper's explorer, `minutes` simulated."""
    robot = DEFAULT.robot()
    config = resolve_fam_config("single", robot)

    def learn() -> None:
        fam = Fam(config, [t.name for t in robot.trajectories], 0.1)
        Learner(world, robot, fam, LearnParams(minutes=minutes), DEFAULT, 1).run(
            lambda episode: None, lambda minute: None, lambda: None, None
        )

    return 1e6 * cpu_seconds(learn, 1) / (minutes * 60.0 / CONTROL_PERIOD_S)


def behaving_step_us(world: WorldMap, fam_path: Path, minutes: float) -> float:
    """CPU microseconds a control step of avoiding with the FAM, `minutes` simulated."""
    found = read_fam(fam_path)
    robot = DEFAULT.robot()
    method = DEFAULT

    def run() -> None:
        behave(world, robot, found.fam, "avoid", minutes=minutes, seed=1, method=method)

    return 1e6 * cpu_seconds(run, 1) / (minutes * 60.0 / CONTROL_PERIOD_S)


def measured(argv: list[str | Path], env: dict[str, str] | None = None) -> tuple[int, float, int]:
    """A whole process's exit status, CPU seconds and peak resident bytes."""
    process = subprocess.Popen(
        [str(a) for a in argv],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        env=None if env is None else {**os.environ, **env},
    )
    _, status, usage = os.wait4(process.pid, 0)  # this child's own resource usage
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024


def peak_memory_bytes(world_text: str, directory: Path) -> int:
    """The peak resident memory of `tvl learn --minutes 0.1` in a world, bytes."""
    world, log = directory / "w.txt", directory / "w.h5"
    world.write_text(world_text)
    log.unlink(missing_ok=True)
    code, _, peak = measured([TVL, "learn", world, "--log", log, "--minutes", "0.1"])
    if code != 0:
        raise SystemExit(f"tvl learn in a hall exited {code}")
    return peak


def hall(side: int, checkered: bool) -> str:
    """A square world of side x side cells of 5 cm: open floor, or a checkerboard of one-cell
    walls (every wall cell's four sides a segment); its text."""
    rows = []
    for r in range(side):
        if r in (0, side - 1):
            rows.append("#" * side)
            continue
        inner = "".join(
            "#" if checkered and (r + c) % 2 and 10 < c < side - 11 and r > 10 else "."
            for c in range(1, side - 1)
        )
        rows.append(f"#{inner}#")
    rows[5] = "#....>" + rows[5][6:]  # 0.25 m from the wall, 0.3 m from the checkerboard
    return "cell: 0.05\n" + "\n".join(rows) + "\n"


def cells_and_segments(text: str) -> tuple[int, int]:
    world = parse_world(text, "hall")
    return _cells(world), len(world.segments)


def memory_figures(directory: Path) -> dict[str, float]:
    """Bytes a cell and a segment add to a learning process's peak, from two sizes each."""
    figures = {}
    for checkered, sides in ((False, (400, 1600)), (True, (150, 300))):
        small_text, large_text = hall(sides[0], checkered), hall(sides[1], checkered)
        small_cells, small_segments = cells_and_segments(small_text)
        large_cells, large_segments = cells_and_segments(large_text)
        small = peak_memory_bytes(small_text, directory)
        large = peak_memory_bytes(large_text, directory)
        if checkered:  # what the cells themselves add, at the measured rate, taken out
            large -= figures["cell"] * (large_cells - small_cells)
            figures["segment"] = (large - small) / (large_segments - small_segments)
        else:
            figures["cell"] = (large - small) / (large_cells - small_cells)
    return figures


def limit_figures(directory: Path, fam: Path) -> dict[str, float]:
    """CPU seconds and peaks of whole processes at the limits (the module's docstring)."""
    figures = {}
    walls = directory / "walls.txt"
    walls.write_text(hall_with_walls(10_000))
    code, figures["walls_cpu_s"], figures["walls_peak"] = measured(
        [TVL, "learn", walls, "--log", directory / "walls.h5", "--minutes", "0.2"]
    )
    memory = {world_budget.MEMORY_VARIABLE: "1024"}
    largest = (512 << 20) // world_budget.BYTES_PER_CELL
    side = int((math.sqrt(1 + 4 * (largest - 11)) - 1) / 2)  # side + 1 bytes a row, 11 more
    largest_world = directory / "largest.txt"
    largest_world.write_text(open_hall(side))
    figures["largest_bytes"] = largest_world.stat().st_size
    code, figures["largest_cpu_s"], figures["largest_peak"] = measured(
        [TVL, "run", fam, largest_world, "--behaviour", "avoid", "--minutes", "0.5"], memory
    )
    board = directory / "board.txt"
    board.write_text(hall(600, checkered=True))
    refused, figures["board_cpu_s"], _ = measured(
        [TVL, "learn", board, "--log", directory / "board.h5", "--minutes", "0.1"]
    )
    if code != 0 or refused != 2:
        raise SystemExit(f"tvl run in the largest world exited {code}, learn {refused}")
    return figures


def open_hall(side: int) -> str:
    """A square world of side x side cells of 5 cm, walls round open floor, as the file."""
    rows = ["#" * side, *(["#" + "." * (side - 2) + "#"] * (side - 2)), "#" * side]
    rows[5] = "#....>" + rows[5][6:]
    return "cell: 0.05\n" + "\n".join(rows) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", type=Path, default=DEPOT, help="a Nav2 map's YAML file")
    parser.add_argument("--minutes", type=float, default=5.0, help="simulated minutes a run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; medians count")
    parser.add_argument("--memory", action="store_true", help="measure memory a cell, a wall")
    parser.add_argument("--limits", action="store_true", help="time processes at the limits")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    if not args.map.is_file():
        raise SystemExit(f"{args.map}: no such map (give --map MAP.yaml)")
    figures: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as name:
        directory = Path(name)
        world_path, log, fam = directory / "map.txt", directory / "map.h5", directory / "fam.h5"
        imported = median_seconds(
            [
                run_process([TVL, "world", "import", args.map, "-o", world_path, "--force"])
                for _ in range(args.repeats)
            ]
        )
        figures["import_s"] = imported.wall_s
        world, lab = load_world(world_path), load_world(LAB)
        world_floor(lab, DEFAULT.robot())  # the kernels loaded
        sensing_step_us(lab, 0.1)
        figures["floor_s"] = cpu_seconds(lambda: world_floor(world, DEFAULT.robot()), 3)
        run_process([TVL, "learn", world_path, "--log", log, "--minutes", str(args.minutes)])
        replay = median_seconds([run_process([TVL, "replay", log]) for _ in range(args.repeats)])
        figures["replay_cpu_s"], figures["replay_wall_s"] = replay.cpu_s, replay.wall_s
        run_process([TVL, "train", EXAMPLE_LOG, "-o", fam])
        for kind, measure in (
            ("sensing", lambda w: sensing_step_us(w, args.minutes)),
            ("learning", lambda w: learning_step_us(w, args.minutes)),
            ("behaving", lambda w: behaving_step_us(w, fam, args.minutes)),
        ):
            in_map = float(np.median([measure(world) for _ in range(args.repeats)]))
            in_lab = float(np.median([measure(lab) for _ in range(args.repeats)]))
            figures[f"{kind}_step_us"], figures[f"{kind}_lab_step_us"] = in_map, in_lab
            figures[f"{kind}_ratio"] = in_map / in_lab
        if args.memory:
            for what, bytes_each in memory_figures(directory).items():
                figures[f"bytes_per_{what}"] = bytes_each
        if args.limits:
            figures.update(limit_figures(directory, fam))
        figures["segments"], figures["cells"] = len(world.segments), _cells(world)
    if args.json:
        print(json.dumps(figures, indent=1))
        return
    _print(args, figures)


def _cells(world: WorldMap) -> int:
    return round(world.width_m / world.cell_m) * round(world.height_m / world.cell_m)


def _print(args: argparse.Namespace, f: dict[str, float]) -> None:
    print(
        f"{args.map.name}: {f['segments']:,.0f} wall segments, {f['cells']:,.0f} cells; "
        f"medians of {args.repeats}, steps over {args.minutes:g} simulated minutes"
    )
    print(figure_line("import (whole process, wall)", f"{f['import_s']:.2f} s", None, None))
    print(
        figure_line(
            "coverage floor (CPU)",
            f"{f['floor_s']:.2f} s",
            f"<= {TARGET_FLOOR_S:g} s",
            f["floor_s"] <= TARGET_FLOOR_S,
        )
    )
    print(
        figure_line(
            "tvl replay LOG (whole process, CPU)",
            f"{f['replay_cpu_s']:.2f} s ({f['replay_wall_s']:.2f} wall)",
            f"<= {TARGET_REPLAY_S:g} s",
            f["replay_cpu_s"] <= TARGET_REPLAY_S,
        )
    )
    for kind in ("sensing", "learning", "behaving"):
        ratio = f[f"{kind}_ratio"]
        judged = kind != "behaving"  # its steps mix differently from world to world
        print(
            figure_line(
                f"a {kind} step: map / lab (CPU)",
                f"{f[f'{kind}_step_us']:.0f} / {f[f'{kind}_lab_step_us']:.0f} us = {ratio:.2f}x",
                f"<= {TARGET_STEP_RATIO:g}x" if judged else None,
                ratio <= TARGET_STEP_RATIO if judged else None,
            )
        )
    if "walls_cpu_s" in f:
        _print_limits(f)
    if "bytes_per_cell" in f:
        for what, assumed in (
            ("cell", world_budget.BYTES_PER_CELL),
            ("segment", world_budget.BYTES_PER_SEGMENT),
        ):
            print(
                figure_line(
                    f"peak memory a {what} adds (learning)",
                    f"{f[f'bytes_per_{what}']:,.0f} bytes",
                    f"<= {assumed:,} assumed",
                    f[f"bytes_per_{what}"] <= assumed,
                )
            )


def _print_limits(f: dict[str, float]) -> None:
    mib = 2**20
    print(
        figure_line(
            "learn 0.2 min, hall of 10,000 walls",
            f"{f['walls_cpu_s']:.1f} s, {f['walls_peak'] / mib:.0f} MiB",
            None,
            None,
        )
    )
    print(
        figure_line(
            f"run 0.5 min, largest world at 1 GiB ({f['largest_bytes'] / 1e6:.1f} MB)",
            f"{f['largest_cpu_s']:.1f} s, {f['largest_peak'] / mib:.0f} MiB",
            "< 1,024 MiB",
            f["largest_peak"] < 1024 * mib,
        )
    )
    print(
        figure_line(
            "learn refusing a 600 x 600 checkerboard", f"{f['board_cpu_s']:.1f} s", None, None
        )
    )


if __name__ == "__main__":
    main()
