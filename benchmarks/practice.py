"""What practice adds: FAMs trained also on what the robot heard while behaving, beside those
trained on exploring alone and those trained on as many minutes more of exploring.

    python benchmarks/practice.py DIR [--worlds A-B] [--minutes 3] [--workers 2] [--json]

DIR is a `tvl bench generalization` directory (its worlds, learning logs, FAMs and rows).
For every world in the span, every trial (seed) the bench ran and every shipped
configuration, through the real `tvl` process:

- **practised**: the bench's FAM drives each behaviour for --minutes in its world, with the
  trial's seed plus PRACTICE_SEED_OFFSET (never a seed the bench's runs drove), learning
  while behaving into a practice log (`tvl run --learn-log`); a FAM is trained from the
  bench's learning log and that practice log (`tvl train`: heard labels label every way at
  every point of both, core.heard);
- **explored more**: `tvl learn` explores the world for as many minutes as the practice took
  (every behaviour's), seeded alike, into a second log; a FAM is trained from both logs.

Each FAM then makes the bench's runs again (every behaviour, the bench's seeds and goals).
The first row is the bench's own runs of its FAMs, read from its rows. Each row counts the
runs competent (core.competence, as the bench counts them), the contacts (and a minute of the
runs' simulated time, since a goal run ends at its goal), the goals reached and the avoid
runs' mean speed, per configuration.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import fields
from pathlib import Path
from typing import Any

from bench_dir import CONFIGS, seeds, world_path

from tvl_cli.core.competence import is_competent_run
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.sweep.layout import learning_tag

BEHAVIOURS = ("avoid", "wall-left", "wall-right", "goal")
# A practice run's seed is its trial's plus this: a stretch of road the bench never drove.
PRACTICE_SEED_OFFSET = 10
TVL = str(Path(sys.executable).with_name("tvl"))
ROWS = ("explored (the bench's FAMs)", "practised", "explored more")


def tvl(*args: str | Path | float) -> str:
    """Run `tvl` with these arguments; its standard output. Any failure stops the benchmark."""
    done = subprocess.run([TVL, *map(str, args)], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"tvl {' '.join(map(str, args))}: {done.stderr.strip()}")
    return done.stdout


def competent(row: dict[str, Any]) -> bool:
    """As the bench counts a run: a row holds a run's metrics, as `tvl run --json` prints them."""
    metrics = RunMetrics(**{f.name: row[f.name] for f in fields(RunMetrics)})
    return is_competent_run(metrics, row["behaviour"])


class Bench:
    """The bench directory's worlds, logs, FAMs and rows of ours."""

    def __init__(self, directory: Path) -> None:
        self.directory = directory
        rows = [json.loads(line) for line in (directory / "results.jsonl").open()]
        self.ours = [
            r
            for r in rows
            if r["kind"] == "tvl" and r["entry"] == "default" and r["minute"] is None
        ]
        self.goals = {r["world"]: r["goal"] for r in self.ours if r["behaviour"] == "goal"}

    def world(self, world: int) -> Path:
        return world_path(self.directory, world)

    def log(self, world: int, seed: int) -> Path:
        """The trial's learning log, by our method (every configuration's FAM trains on it)."""
        (found,) = self.directory.glob(f"logs/rooms-s{world}-s{seed}-*{learning_tag(DEFAULT)}.h5")
        return found

    def fam(self, world: int, seed: int, config: str) -> Path:
        return self.directory / "fams" / f"{self.log(world, seed).stem}-{config}.h5"

    def trials(self, world: int) -> list[int]:
        return sorted({r["seed"] for r in self.ours if r["world"] == f"rooms-s{world}"})

    def behaving(self, world: int, behaviour: str) -> list[str]:
        """What `tvl run` is told beyond the FAM for this behaviour here."""
        goal = ["--goal", self.goals[f"rooms-s{world}"]] if behaviour == "goal" else []
        return ["--behaviour", behaviour, *goal]


def practise(bench: Bench, out: Path, world: int, seed: int, config: str, minutes: float) -> Path:
    """The practice log of one FAM: every behaviour, one after another, into one log."""
    log = out / "practice" / f"rooms-s{world}-s{seed}-{config}.h5"
    if not log.exists():
        partial = log.with_suffix(".partial.h5")
        partial.unlink(missing_ok=True)
        for behaviour in BEHAVIOURS:
            tvl("run", bench.fam(world, seed, config), bench.world(world),
                *bench.behaving(world, behaviour), "--seed", seed + PRACTICE_SEED_OFFSET,
                "--minutes", minutes, "--learn-log", partial)  # fmt: skip
        partial.rename(log)
    return log


def explore_more(bench: Bench, out: Path, world: int, seed: int, minutes: float) -> Path:
    """A second learning log of the world, as many minutes as a practice."""
    log = out / "explored" / f"rooms-s{world}-s{seed}.h5"
    if not log.exists():
        partial = log.with_suffix(".partial.h5")
        partial.unlink(missing_ok=True)
        tvl("learn", bench.world(world), "--log", partial, "--seed",
            seed + PRACTICE_SEED_OFFSET, "--minutes", minutes * len(BEHAVIOURS))  # fmt: skip
        partial.rename(log)
    return log


def train(out: Path, logs: Sequence[Path], config: str) -> Path:
    fam = out.with_name(f"{out.name}-{config}.h5")
    if not fam.exists():
        tvl("train", *logs, "-o", fam, "--config", config)
    return fam


def runs(bench: Bench, fam: Path, world: int, seed: int, config: str) -> list[dict[str, Any]]:
    """The bench's runs of one cell again, with another FAM."""
    rows = []
    for behaviour in BEHAVIOURS:
        argv: list[str | Path | float] = [
            "run",
            fam,
            bench.world(world),
            *bench.behaving(world, behaviour),
        ]
        printed = json.loads(tvl(*argv, "--seed", seed, "--json"))
        rows.append({**printed, "behaviour": behaviour, "config": config})
    return rows


def cell(bench: Bench, out: Path, world: int, seed: int, minutes: float) -> dict[str, list]:
    """Every row's runs of one world and trial, each configuration."""
    explored = explore_more(bench, out, world, seed, minutes)
    found: dict[str, list[dict[str, Any]]] = {row: [] for row in ROWS[1:]}
    for config in CONFIGS:
        practice = practise(bench, out, world, seed, config, minutes)
        learnt = bench.log(world, seed)
        fams = {
            "practised": train(
                out / "fams" / f"practised-s{world}-s{seed}", [learnt, practice], config
            ),
            "explored more": train(
                out / "fams" / f"explored-s{world}-s{seed}", [learnt, explored], config
            ),
        }
        for row, fam in fams.items():
            found[row] += runs(bench, fam, world, seed, config)
    return found


def summary(rows: Sequence[dict[str, Any]]) -> dict[str, dict[str, float]]:
    """Per configuration: runs, competent runs, contacts, goals reached, avoid speed."""
    out = {}
    for config in CONFIGS:
        mine = [r for r in rows if r["config"] == config]
        avoid = [r["mean_speed_mps"] for r in mine if r["behaviour"] == "avoid"]
        out[config] = {
            "runs": len(mine),
            "competent": sum(competent(r) for r in mine),
            "contacts": sum(r["contacts"] for r in mine),
            # over the runs' simulated time: a goal run ends at its goal
            "contacts_per_min": sum(r["contacts"] for r in mine)
            * 60
            / sum(r["sim_s"] for r in mine),
            "goals": sum(bool(r["goal_reached"]) for r in mine if r["behaviour"] == "goal"),
            "avoid_speed_mps": sum(avoid) / len(avoid) if avoid else float("nan"),
        }
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bench", type=Path, help="a `tvl bench generalization` directory")
    parser.add_argument("--worlds", default="1-20", help="rooms seeds A-B of the bench's worlds")
    parser.add_argument("--minutes", type=float, default=3.0, help="practice a behaviour, min")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    bench = Bench(args.bench)
    out = args.bench / "practice"
    for folder in ("practice", "explored", "fams"):
        (out / folder).mkdir(parents=True, exist_ok=True)
    cells = [(w, s) for w in seeds(args.worlds) for s in bench.trials(w)]
    rows: dict[str, list[dict[str, Any]]] = {row: [] for row in ROWS}
    worlds = {f"rooms-s{w}" for w, _ in cells}
    rows[ROWS[0]] = [r for r in bench.ours if r["world"] in worlds and r["config"] in CONFIGS]
    with ThreadPoolExecutor(args.workers) as pool:
        for found in pool.map(lambda c: cell(bench, out, c[0], c[1], args.minutes), cells):
            for row, more in found.items():
                rows[row] += more
    figures = {row: summary(found) for row, found in rows.items()}
    if args.json:
        print(json.dumps({"minutes": args.minutes, "worlds": args.worlds, "rows": figures}))
        return
    print(f"worlds {args.worlds}, {len(cells)} trials; practice {args.minutes:g} min a behaviour")
    print("| row | configuration | competent | contacts (a minute) | goals | avoid m/s |")
    print("| --- | --- | --- | --- | --- | --- |")
    for row, by_config in figures.items():
        for config, f in by_config.items():
            contacts = f"{f['contacts']} ({f['contacts_per_min']:.2f})"
            print(f"| {row} | {config} | {f['competent']} / {f['runs']} | {contacts} "
                  f"| {f['goals']} | {f['avoid_speed_mps']:.3f} |")  # fmt: skip


if __name__ == "__main__":
    main()
