"""Generalization levers: `tvl bench generalization` once per option that may carry
competence further.

    python benchmarks/generalization_levers.py [--set tuning|test] [--size quick|full]
                                               [--lever NAME ...] [--out DIR]

Each lever is a method (fields over ours: learning, sensing) and a threshold for the runs;
this writes each lever's method file, runs the suite with it (no reference but the map's
DWA, the speed reference) and prints one Markdown row per lever: competent runs, contacts a
minute, goals reached and avoid speed for each shipped FAM configuration. Develop on the
tuning set (the default); the test worlds are for reporting a chosen lever. Each lever's
cells are kept in DIR/LEVER, so a lever run again is read back, not run.
"""

from __future__ import annotations

import argparse
import json
import subprocess
from pathlib import Path
from typing import Any

from timing import TVL

# Lever name -> (fields of the method over ours, the runs' threshold).
EDGES_NEAR_025 = {"sonar": "edges", "near_m": 0.25}
LEVERS: dict[str, tuple[dict[str, Any], float]] = {
    "default": ({}, 0.85),
    "near 0.25": ({"near_m": 0.25}, 0.85),
    "near 0.35": ({"near_m": 0.35}, 0.85),
    "edges": ({"sonar": "edges"}, 0.85),
    "edges, near 0.25": (EDGES_NEAR_025, 0.85),
    "edges, near 0.35": ({"sonar": "edges", "near_m": 0.35}, 0.85),
    # A firmer brake in the labels: a shorter horizon for every trajectory to be fast.
    "decel 0.3": ({"decel_mps2": 0.3}, 0.85),
    "edges, near 0.25, decel 0.2": ({**EDGES_NEAR_025, "decel_mps2": 0.2}, 0.85),
    # Choice dynamics: the threshold of the runs. Lower lets slower trajectories count as
    # fast, so the robot spins less; higher keeps more clearance (paper Fig. 21).
    "threshold 0.7": ({}, 0.7),
    "threshold 0.92": ({}, 0.92),
    "edges, near 0.25, threshold 0.7": (EDGES_NEAR_025, 0.7),
    "edges, near 0.25, threshold 0.92": (EDGES_NEAR_025, 0.92),
}


def method_file(fields: dict[str, Any], path: Path) -> Path:
    """A method file of the lever's fields (TOML takes these values as JSON writes them)."""
    path.write_text("".join(f"{key} = {json.dumps(value)}\n" for key, value in fields.items()))
    return path


def measure(lever: str, world_set: str, size: str, out: Path) -> list[dict[str, Any]]:
    """The suite's figures of ours with this lever, one a configuration."""
    fields, threshold = LEVERS[lever]
    folder = out / lever.replace(", ", "-").replace(" ", "-")
    folder.mkdir(parents=True, exist_ok=True)
    method = method_file(fields, folder / "method.toml") if fields else "default"
    command = [TVL, "bench", "generalization", "--set", world_set, "--size", size,
               "--method", str(method), "--threshold", str(threshold),
               "--references", "dwa-map", "--out", str(folder), "--json"]  # fmt: skip
    printed = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    figures: list[dict[str, Any]] = json.loads(printed)["figures"]
    return [f for f in figures if f["role"] == "method"]


FIGURES = ("competent", "contacts/min", "goals", "avoid m/s")


def header(configs: list[str]) -> str:
    cells = ["lever", *(f"{figure} {config}" for figure in FIGURES for config in configs)]
    return "| " + " | ".join(cells) + " |\n|" + " --- |" * len(cells)


def row(lever: str, figures: list[dict[str, Any]]) -> str:
    cells = [
        lever,
        *(f"{f['competent']}/{f['runs']}" for f in figures),
        *(f"{f['contacts_per_min']['mean']:.2f}" for f in figures),
        *(f"{f['goals_reached']}/{f['goal_runs']}" for f in figures),
        *(f"{f['avoid_speed_mps']['mean']:.2f}" for f in figures),
    ]
    return "| " + " | ".join(cells) + " |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=("tuning", "test"), default="tuning", dest="world_set")
    parser.add_argument("--size", choices=("tiny", "quick", "full"), default="quick")
    parser.add_argument("--out", type=Path, default=Path("results") / "levers")
    parser.add_argument(
        "--lever", action="append", choices=list(LEVERS), help="only these (repeatable)"
    )
    args = parser.parse_args()
    for number, lever in enumerate(args.lever or list(LEVERS)):
        figures = measure(lever, args.world_set, args.size, args.out / args.world_set)
        if number == 0:
            print(header([f["config"] for f in figures]))
        print(row(lever, figures), flush=True)


if __name__ == "__main__":
    main()
