"""Generalization levers: the benchmark once per option that may carry competence further.

    python benchmarks/generalization_levers.py [--set tuning|test] [--full] [--workers 2]
                                               [--lever NAME ...]

Each lever is a set of `benchmarks/generalization.py` options (learning, sensing, the
threshold of the runs, learning while behaving); this runs the benchmark with each (its
`--quick` subset unless `--full`) and prints one markdown row per lever: competent runs,
contacts a minute, goals reached and avoid speed for each shipped FAM configuration.
Develop on `--set tuning` (the default); the test worlds are for reporting a chosen lever.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

BENCHMARK = Path(__file__).resolve().parent / "generalization.py"
# The pair most of the levers below are tried beside: edge echoes and a farther collision point.
EDGES_NEAR_025 = ["--sonar", "edges", "--near", "0.25"]
# Lever name -> the benchmark's options; "default" is the shipped learner and sonar.
LEVERS: dict[str, list[str]] = {
    "default": [],
    "near 0.25": ["--near", "0.25"],
    "near 0.35": ["--near", "0.35"],
    "edges": ["--sonar", "edges"],
    "edges, near 0.25": EDGES_NEAR_025,
    "edges, near 0.35": ["--sonar", "edges", "--near", "0.35"],
    # A firmer brake in the labels: a shorter horizon for every trajectory to be fast.
    "decel 0.3": ["--decel", "0.3"],
    "edges, near 0.25, decel 0.2": [*EDGES_NEAR_025, "--decel", "0.2"],
    # Choice dynamics: the threshold of the runs. Lower lets slower trajectories count as
    # fast, so the robot spins less; higher keeps more clearance (paper Fig. 21).
    "threshold 0.7": ["--threshold", "0.7"],
    "threshold 0.92": ["--threshold", "0.92"],
    "edges, near 0.25, threshold 0.7": [*EDGES_NEAR_025, "--threshold", "0.7"],
    "edges, near 0.25, threshold 0.92": [*EDGES_NEAR_025, "--threshold", "0.92"],
    # Learning while behaving (`tvl run --learn`): each run goes on training its FAM.
    "learn": ["--learn"],
    "edges, near 0.25, learn": [*EDGES_NEAR_025, "--learn"],
    "edges, near 0.25, threshold 0.92, learn": [*EDGES_NEAR_025, "--threshold", "0.92", "--learn"],
    # The paper's whole method beside ours: its labels, bump-only collision points, no reflexes.
    "paper": ["--paper"],
}


def measure(options: list[str], world_set: str, full: bool, workers: int) -> dict[str, Any]:
    """The benchmark's summary with these options."""
    # A lever's row holds no reference: only the map's DWA runs, for the speed reference.
    command = [sys.executable, str(BENCHMARK), "--set", world_set, "--json", "--no-ceiling"]
    command += ["--map-reference-only"]
    command += ["--workers", str(workers), *([] if full else ["--quick"]), *options]
    printed = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    summary: dict[str, Any] = json.loads(printed)["summary"]
    return summary


FIGURES = ("competent", "contacts/min", "goals", "avoid m/s")


def configs_of(summary: dict[str, Any]) -> list[str]:
    """The FAM configurations the benchmark trained, in its order."""
    return list(summary["runs"])


def header(configs: list[str]) -> str:
    cells = ["lever", *(f"{figure} {config}" for figure in FIGURES for config in configs)]
    return "| " + " | ".join(cells) + " |\n|" + " --- |" * len(cells)


def row(lever: str, summary: dict[str, Any]) -> str:
    columns = [summary["runs"][config] for config in configs_of(summary)]
    cells = [
        lever,
        *(f"{c['competent']}/{c['runs']}" for c in columns),
        *(f"{c['contacts_per_min']:.2f}" for c in columns),
        *(f"{c['goals_reached']}/{c['goal_runs']}" for c in columns),
        *(f"{c['avoid_speed_mps']:.2f}" for c in columns),
    ]
    return "| " + " | ".join(cells) + " |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=("tuning", "test"), default="tuning", dest="world_set")
    parser.add_argument("--full", action="store_true", help="all 20 worlds and 3 trials")
    parser.add_argument("--workers", type=int, default=2, help="parallel processes")
    parser.add_argument(
        "--lever", action="append", choices=list(LEVERS), help="only these (repeatable)"
    )
    args = parser.parse_args()
    for number, lever in enumerate(args.lever or list(LEVERS)):
        summary = measure(LEVERS[lever], args.world_set, args.full, args.workers)
        if number == 0:
            print(header(configs_of(summary)))
        print(row(lever, summary), flush=True)


if __name__ == "__main__":
    main()
