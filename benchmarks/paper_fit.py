"""The paper's unstated deceleration: which labels reproduce its Figure 21.

    python benchmarks/paper_fit.py [--decel A,B,...] [--margin A,B,...] [--seeds N]
                                   [--learn-minutes M] [--run-minutes M] [--workers 2] [--json]

The paper labels a trajectory's points with "a predefined deceleration rate" up to its
collision point and gives no number. Its Figure 21 is the one place the labels show: single
FAM, wall following left and right in the square and the circle, the velocity threshold from
0.65 to 0.95 moved the mean wall clearance from 0.32 to 0.67 m and the mean speed from 0.32 to
0.45 m/s. This fits the deceleration and the margin to those four numbers.

For each world and seed: learn with the paper's learner (collision points by bumps only, the
least experienced choice, no echo memory: `tvl learn --near 0 --memory none`), which drives
at its fixed learning speed, so one log serves every label. Then for each deceleration and
margin: train a single FAM from it (`tvl train --decel A --margin M`) and follow the wall on
each side at thresholds 0.65 and 0.95 with no reflexes (`tvl run --reflex none`). The error
of a setting is the root mean square of the four figures' relative errors against the
paper's; contacts a minute are printed beside it, since the paper's curves are solid (not
collision prone) at both ends.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from timing import TVL

from tvl_cli.analysis.wall_threshold import PAPER_FIG21
from tvl_cli.sim.worldgen import bundled_world_path

WORLDS = ("square", "circle")
SIDES = ("wall-left", "wall-right")


@dataclass(frozen=True, slots=True)
class Fit:
    """What one deceleration and margin gave, averaged over worlds, seeds and sides."""

    decel_mps2: float
    margin_m: float
    clearance_m: dict[float, float]  # by threshold
    speed_mps: dict[float, float]
    contacts_per_min: dict[float, float]
    error: float  # root mean square relative error against PAPER_FIG21


def tvl_json(*args: str | Path) -> dict[str, Any]:
    done = subprocess.run(
        [TVL, *map(str, args), "--json"], check=True, capture_output=True, text=True
    )
    result: dict[str, Any] = json.loads(done.stdout)
    return result


def learn(work: Path, world: str, seed: int, minutes: float) -> Path:
    log = work / f"{world}-s{seed}.h5"
    tvl_json("learn", bundled_world_path(world), "--log", log, "--minutes", str(minutes),
             "--seed", str(seed), "--near", "0", "--memory", "none")  # fmt: skip
    return log


def fit_one(
    work: Path, logs: dict[tuple[str, int], Path], decel: float, margin: float, minutes: float
) -> Fit:
    runs: dict[float, list[dict[str, Any]]] = {t: [] for t in PAPER_FIG21}
    for (world, seed), log in logs.items():
        fam = work / f"{world}-s{seed}-d{decel:g}-m{margin:g}.h5"
        # The paper's labels but for the rate and margin fitted: the driven trajectory's,
        # no faster than its top speed (ours label every way, the tight arcs past the top).
        tvl_json("train", log, "-o", fam, "--decel", str(decel), "--margin", str(margin),
                 "--labels", "bump", "--label-ceiling", "1")  # fmt: skip
        for side in SIDES:
            for threshold in PAPER_FIG21:
                runs[threshold].append(
                    tvl_json(
                        "run",
                        fam,
                        bundled_world_path(world),
                        "--behaviour",
                        side,
                        "--threshold",
                        str(threshold),
                        "--minutes",
                        str(minutes),
                        "--seed",
                        str(seed),
                        "--reflex",
                        "none",
                    )
                )

    def mean(key: str) -> dict[float, float]:
        # A run that never had a wall beside it has no wall clearance: it drops out of that mean.
        means = {}
        for threshold, results in runs.items():
            values = [r[key] for r in results if r[key] is not None]
            means[threshold] = statistics.fmean(values) if values else math.nan
        return means

    clearance, speed = mean("mean_wall_clearance_m"), mean("mean_speed_mps")
    relative = [
        (measured[t] - paper[i]) / paper[i]
        for t, paper in PAPER_FIG21.items()
        for i, measured in enumerate((clearance, speed))
    ]
    error = math.sqrt(statistics.fmean(e * e for e in relative))
    return Fit(decel, margin, clearance, speed, mean("contacts_per_min"), error)


def floats(text: str) -> list[float]:
    return [float(part) for part in text.split(",")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--decel", type=floats, default=[0.05, 0.1, 0.2, 0.3, 0.5, 1.0])
    parser.add_argument("--margin", type=floats, default=[0.0, 0.05, 0.15])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--learn-minutes", type=float, default=15.0)
    parser.add_argument("--run-minutes", type=float, default=5.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as directory, ThreadPoolExecutor(args.workers) as pool:
        work = Path(directory)
        keys = [(w, s) for w in WORLDS for s in range(1, args.seeds + 1)]
        learnt = pool.map(lambda k: learn(work, *k, args.learn_minutes), keys)
        logs = dict(zip(keys, learnt, strict=True))
        settings = [(d, m) for d in args.decel for m in args.margin]
        fits = list(pool.map(lambda s: fit_one(work, logs, *s, args.run_minutes), settings))

    if args.json:
        print(json.dumps([asdict(f) for f in fits], indent=1))
        return
    paper = "  ".join(f"t={t:g}: {c:.2f} m {v:.2f} m/s" for t, (c, v) in PAPER_FIG21.items())
    print(f"paper's Figure 21 ends   {paper}")
    print("decel m/s²  margin m  clearance m (0.65 → 0.95)  speed m/s     contacts/min  error")
    for fit in sorted(fits, key=lambda f: f.error):
        low, high = PAPER_FIG21
        print(
            f"{fit.decel_mps2:10.2f}  {fit.margin_m:8.2f}  "
            f"{fit.clearance_m[low]:.2f} → {fit.clearance_m[high]:.2f}"
            f"{'':14}{fit.speed_mps[low]:.2f} → {fit.speed_mps[high]:.2f}  "
            f"{fit.contacts_per_min[low]:5.1f} {fit.contacts_per_min[high]:5.1f}   "
            f"{fit.error:.3f}"
        )


if __name__ == "__main__":
    main()
