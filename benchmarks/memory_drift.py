"""How far odometry misplaces a remembered echo, by how long ago it was heard.

The echo memory places what it heard in the odometry frame and reads it back from where
odometry says the robot is now, so an echo heard S seconds ago is misplaced by the drift of
odometry over those S seconds: its error in heading swings a far echo round, and sliding
along a wall, which the wheels do not see, shifts every echo at once. This measures that
error on a real run: a single FAM trained from logs/lab-s1.h5 avoids in the lab for M
simulated minutes with a trace (`tvl train`, `tvl run --log`, the real processes), and for
every pair of steps S seconds apart, a point R metres ahead of the earlier true pose is
placed by odometry and by the truth as seen from the later pose. It prints the median and
95th percentile of the distance between the two, for each window and range.

    python benchmarks/memory_drift.py [--minutes 10] [--seed 1] [--json]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
from pathlib import Path

import h5py
import numpy as np
from timing import TVL

from tvl_cli.core.robot_config import RobotConfig

ROOT = Path(__file__).resolve().parent.parent
LAB = ROOT / "worlds" / "lab.txt"
EXAMPLE_LOG = ROOT / "logs" / "lab-s1.h5"
WINDOWS_S = (2.0, 5.0, 10.0, 20.0, 40.0, 60.0)
RANGES_M = (1.0, 2.0, 4.0)  # 4 m is the ring's farthest echo


def traced_run(minutes: float, seed: int, directory: Path) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) true poses and (N, 3) odometry after each control step of a lab avoid run."""
    fam, trace = directory / "single.h5", directory / "run.h5"
    subprocess.run([TVL, "train", EXAMPLE_LOG, "-o", fam], check=True, capture_output=True)
    subprocess.run(
        [
            TVL,
            "run",
            fam,
            LAB,
            "--behaviour",
            "avoid",
            "--minutes",
            str(minutes),
            "--seed",
            str(seed),
            "--log",
            trace,
        ],
        check=True,
        capture_output=True,
    )
    with h5py.File(trace, "r") as file:
        return file["pose"][()], file["odometry"][()]


def seen_from(later: np.ndarray, earlier: np.ndarray, range_m: float) -> np.ndarray:
    """(n, 2) where a point range_m ahead of each earlier pose lies, in each later pose's
    own frame (x ahead, y left)."""
    heading = earlier[:, 2]
    point = earlier[:, :2] + range_m * np.column_stack([np.cos(heading), np.sin(heading)])
    offset = point - later[:, :2]
    cos, sin = np.cos(later[:, 2]), np.sin(later[:, 2])
    return np.column_stack(
        [cos * offset[:, 0] + sin * offset[:, 1], -sin * offset[:, 0] + cos * offset[:, 1]]
    )


def misplacement_m(
    pose: np.ndarray, odometry: np.ndarray, window_steps: int, range_m: float
) -> np.ndarray:
    """(n,) metres between where odometry and the truth put an echo heard window_steps ago."""
    truth = seen_from(pose[window_steps:], pose[:-window_steps], range_m)
    believed = seen_from(odometry[window_steps:], odometry[:-window_steps], range_m)
    return np.hypot(*(believed - truth).T)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as directory:
        pose, odometry = traced_run(args.minutes, args.seed, Path(directory))
    period_s = RobotConfig().control_period_s
    rows = []
    for window_s in WINDOWS_S:
        steps = round(window_s / period_s)
        for range_m in RANGES_M:
            error = misplacement_m(pose, odometry, steps, range_m)
            rows.append(
                {
                    "window_s": window_s,
                    "range_m": range_m,
                    "median_m": float(np.median(error)),
                    "p95_m": float(np.percentile(error, 95)),
                }
            )
    if args.json:
        print(json.dumps({"minutes": args.minutes, "seed": args.seed, "rows": rows}, indent=1))
        return
    print(
        f"an echo's misplacement by odometry: a lab avoid run of {args.minutes:g} min, "
        f"seed {args.seed}"
    )
    print(f"  {'heard ago':>9}  {'range':>5}  {'median':>8}  {'95th pct':>8}")
    for row in rows:
        print(
            f"  {row['window_s']:>7g} s  {row['range_m']:>3g} m  "
            f"{100 * row['median_m']:>6.1f} cm  {100 * row['p95_m']:>6.1f} cm"
        )


if __name__ == "__main__":
    main()
