"""The paper's claims, each run with the paper's method and with tvl's default beside it.

    python benchmarks/paper_claims.py [--seeds N] [--workers 2] [--claim NAME]...
                                      [--method paper|default|FILE.toml]... [--json]

Five claims of the paper (§5), each as one row: what the paper reports, what `--method paper`
gives, what the default method gives, and whether each meets the claim. `--method` (given
once or more) runs other methods instead: a method file tries one reading of the paper.

- avoid-9min: in the square and the circle, avoiding without contacts after under 9 minutes
  of learning (single FAM; a run counts with at most 0.2 contacts a minute, as competence).
- fig21: single FAM wall following at thresholds 0.65 and 0.95 in the square and the circle
  after 15 minutes: mean wall clearance 0.32 -> 0.67 m, mean speed 0.32 -> 0.45 m/s.
- fig22: goal seeking among the obstacles (four goals) after 20 minutes with the single FAM:
  every goal but one found, without collisions (here: without contacts, near misses counted).
- fig24: in the square, the multi FAM collides less than the single (here: fewer contacts a
  minute, near misses counted), both trained from the same 15-minute log.
- fig27: in the lab with the multi FAM, the avoiding speed rises from 0.1 to 0.5 m/s over 45
  minutes of learning.

Every figure is a mean over seeds 1..N (3 by default; the paper ran 5) of 5-minute runs
(3 for goals), all through the `tvl` command. Learning logs are made once per world, FAM
configuration, seed and method, and trained at the minutes each claim needs.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import tempfile
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from functools import cache
from pathlib import Path
from typing import Any

from timing import TVL

from tvl_cli.analysis.results import PAPER_FIG21
from tvl_cli.sim.worldgen import bundled_world_path

METHODS = ("paper", "default")
RUN_MINUTES = 5.0
GOAL_MINUTES = 3.0
COMPETENT_CONTACTS_PER_MIN = 0.2


@dataclass(frozen=True, slots=True)
class Row:
    claim: str
    reported: str
    measured: dict[str, str]  # by method
    met: dict[str, bool]


class Study:
    """Makes logs, FAMs and runs on demand, each once, in one scratch directory."""

    def __init__(self, work: Path, seeds: int, pool: ThreadPoolExecutor) -> None:
        self.work, self.seeds, self.pool = work, range(1, seeds + 1), pool
        self.log = cache(self._log)
        self.fam = cache(self._fam)

    def tvl(self, *args: str | Path) -> dict[str, Any]:
        done = subprocess.run(
            [TVL, *map(str, args), "--json"], check=True, capture_output=True, text=True
        )
        result: dict[str, Any] = json.loads(done.stdout)
        return result

    def _log(self, method: str, world: str, config: str, seed: int, minutes: float) -> Path:
        log = self.work / f"{Path(method).stem}-{world}-{config}-s{seed}-{minutes:g}.h5"
        self.tvl("learn", bundled_world_path(world), "--log", log, "--minutes", str(minutes),
                 "--seed", str(seed), "--config", config, "--method", method)  # fmt: skip
        return log

    def _fam(self, method: str, log: Path, config: str, until: float | None) -> Path:
        fam = log.with_name(f"{log.stem}-{config}-u{until}.fam.h5")
        until_args = () if until is None else ("--until-minute", str(until))
        self.tvl("train", log, "-o", fam, "--config", config, "--method", method, *until_args)
        return fam

    def run(
        self, method: str, fam: Path, world: str, seed: int, *options: str, minutes: float
    ) -> dict[str, Any]:
        return self.tvl("run", fam, bundled_world_path(world), "--seed", str(seed),
                        "--minutes", str(minutes), "--method", method, *options)  # fmt: skip

    def each_seed(self, job: Callable[[int], dict[str, Any]]) -> list[dict[str, Any]]:
        return list(self.pool.map(job, self.seeds))


def mean(runs: Iterable[dict[str, Any]], key: str) -> float:
    return statistics.fmean(r[key] for r in runs if r[key] is not None)


def avoid_9min(study: Study, method: str) -> tuple[str, bool]:
    def job(world: str) -> Callable[[int], dict[str, Any]]:
        def one(seed: int) -> dict[str, Any]:
            log = study.log(method, world, "single", seed, 9.0)
            fam = study.fam(method, log, "single", None)
            return study.run(method, fam, world, seed, "--behaviour", "avoid",
                             minutes=RUN_MINUTES)  # fmt: skip

        return one

    runs = [r for world in ("square", "circle") for r in study.each_seed(job(world))]
    clean = sum(r["contacts_per_min"] <= COMPETENT_CONTACTS_PER_MIN for r in runs)
    rate = mean(runs, "contacts_per_min")
    return f"{clean}/{len(runs)} runs clean, {rate:.2f} contacts/min", clean == len(runs)


def fig21(study: Study, method: str) -> tuple[str, bool]:
    ends: dict[float, list[dict[str, Any]]] = {threshold: [] for threshold in PAPER_FIG21}
    for world in ("square", "circle"):
        for threshold, runs in ends.items():

            def one(seed: int, world: str = world, threshold: float = threshold) -> Any:
                fam = study.fam(method, study.log(method, world, "single", seed, 15.0),
                                "single", None)  # fmt: skip
                return [
                    study.run(
                        method,
                        fam,
                        world,
                        seed,
                        "--behaviour",
                        side,
                        "--threshold",
                        str(threshold),
                        minutes=RUN_MINUTES,
                    )
                    for side in ("wall-left", "wall-right")
                ]

            runs.extend(r for pair in study.pool.map(one, study.seeds) for r in pair)
    clear = {t: mean(rs, "mean_wall_clearance_m") for t, rs in ends.items()}
    speed = {t: mean(rs, "mean_speed_mps") for t, rs in ends.items()}
    low, high = sorted(PAPER_FIG21)
    contacts = mean(ends[low] + ends[high], "contacts_per_min")
    text = (
        f"clearance {clear[low]:.2f} -> {clear[high]:.2f} m, speed {speed[low]:.2f} -> "
        f"{speed[high]:.2f} m/s, {contacts:.1f} contacts/min"
    )
    # Met when each end is within 0.05 (m or m/s) of the paper's.
    met = all(
        abs(clear[t] - c) <= 0.05 and abs(speed[t] - v) <= 0.05 for t, (c, v) in PAPER_FIG21.items()
    )
    return text, met


def fig22(study: Study, method: str) -> tuple[str, bool]:
    goals = study.tvl("world", "show", bundled_world_path("obstacles"))["world"]["goals"]

    def one(seed: int) -> list[dict[str, Any]]:
        fam = study.fam(method, study.log(method, "obstacles", "single", seed, 20.0),
                        "single", None)  # fmt: skip
        return [
            study.run(
                method,
                fam,
                "obstacles",
                seed,
                "--behaviour",
                "goal",
                "--goal",
                f"{x},{y}",
                minutes=GOAL_MINUTES,
            )
            for x, y in goals
        ]

    runs = [r for per_seed in study.pool.map(one, study.seeds) for r in per_seed]
    # A contact is a bump or a near miss: a run that only grazes counts against the claim.
    found = sum(r["goal_reached"] and r["contacts"] == 0 for r in runs)
    reached = sum(bool(r["goal_reached"]) for r in runs)
    text = f"{found}/{len(runs)} goals found without contacts ({reached} reached)"
    return text, found >= len(runs) * (len(goals) - 1) / len(goals)


def fig24(study: Study, method: str) -> tuple[str, bool]:
    def one(seed: int) -> dict[str, dict[str, Any]]:
        log = study.log(method, "square", "single", seed, 15.0)
        return {
            config: study.run(method, study.fam(method, log, config, None), "square", seed,
                              "--behaviour", "avoid", minutes=RUN_MINUTES)
            for config in ("single", "multi")
        }  # fmt: skip

    per_seed = list(study.pool.map(one, study.seeds))
    runs = {config: [s[config] for s in per_seed] for config in ("single", "multi")}
    single, multi = (mean(runs[c], "contacts_per_min") for c in ("single", "multi"))
    # The paper counted collisions: the bumps alone are printed beside every contact.
    bumps = {c: mean(runs[c], "collisions_per_min") for c in ("single", "multi")}
    text = (
        f"contacts/min single {single:.2f}, multi {multi:.2f} "
        f"(bumps alone {bumps['single']:.2f}, {bumps['multi']:.2f})"
    )
    # Both clean leaves nothing for the multi FAM to improve on: the claim is not shown.
    return text, multi < single


def fig27(study: Study, method: str) -> tuple[str, bool]:
    snapshots = (5.0, 15.0, 45.0)

    def one(seed: int) -> list[float]:
        log = study.log(method, "lab", "multi", seed, 45.0)
        return [
            study.run(method, study.fam(method, log, "multi", minute), "lab", seed,
                      "--behaviour", "avoid", minutes=RUN_MINUTES)["mean_speed_mps"]
            for minute in snapshots
        ]  # fmt: skip

    per_seed = list(study.pool.map(one, study.seeds))
    speeds = [statistics.fmean(s[i] for s in per_seed) for i in range(len(snapshots))]
    text = "avoid speed " + ", ".join(
        f"{v:.2f} m/s at {m:g} min" for m, v in zip(snapshots, speeds, strict=True)
    )
    return text, speeds[-1] >= 0.45


CLAIMS: tuple[tuple[str, str, Callable[[Study, str], tuple[str, bool]]], ...] = (
    ("avoid-9min", "square and circle avoided without collisions", avoid_9min),
    ("fig21", "clearance 0.32 -> 0.67 m, speed 0.32 -> 0.45 m/s", fig21),
    ("fig22", "every goal found without collisions but one", fig22),
    ("fig24", "multi collides less than single", fig24),
    ("fig27", "avoid speed 0.1 -> 0.5 m/s over 45 min", fig27),
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--claim", action="append", choices=[c[0] for c in CLAIMS])
    parser.add_argument("--method", dest="methods", action="append", metavar="METHOD")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    methods = args.methods or list(METHODS)

    rows = []
    with tempfile.TemporaryDirectory() as directory, ThreadPoolExecutor(args.workers) as pool:
        study = Study(Path(directory), args.seeds, pool)
        for name, reports, measure in CLAIMS:
            if args.claim and name not in args.claim:
                continue
            measured = {method: measure(study, method) for method in methods}
            rows.append(
                Row(
                    name,
                    reports,
                    {m: t for m, (t, _) in measured.items()},
                    {m: ok for m, (_, ok) in measured.items()},
                )
            )
            if not args.json:
                print(f"{name}: the paper reports {reports}")
                for method in methods:
                    verdict = "met" if rows[-1].met[method] else "MISSED"
                    print(f"  --method {method:8} {verdict:6} {rows[-1].measured[method]}")
    if args.json:
        print(json.dumps([asdict(r) for r in rows], indent=1))


if __name__ == "__main__":
    main()
