"""FAM speed for the `single` and `multi` configurations, and against simpful.

    python benchmarks/fam_speed.py [--exemplars N] [--repeats R] [--json]

For each configuration: the 112-trajectory foveal perception of one ring (all 16 rotations
x 7 trajectories), batch inference, symmetric training, and the size of the FAM file after
training on N exemplars. Readings are uniform over the sonar range, labels uniform up to
0.6 m/s. A FAM file holds one velocity and one experience per rule and trajectory, so its
size does not grow with the exemplars it learnt from: the figure per million exemplars is
the file size itself. Finally the same one-ring inference of the trained `single` FAM (7
velocities and their experience) is run by simpful, a zero-order Sugeno system with one rule
per FAM entry, for the ratio.
The best of R timed runs counts, as noise on a shared machine only ever adds time.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from tvl_cli.core.config import BUILTIN_FAM_CONFIGS, SINGLE, SONAR_COUNT, RobotConfig
from tvl_cli.core.fam import Fam
from tvl_cli.io.famfile import write_fam

# The benchmark times the very translation to simpful that the agreement test checks.
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "core"))
from test_fam_simpful import simpful_system

ROBOT = RobotConfig()
NAMES = tuple(t.name for t in ROBOT.trajectories)
BATCH_RINGS = 100_000
FOVEAL_CALLS = 2_000
SIMPFUL_CALLS = 2


def exemplars(rng: np.random.Generator, count: int) -> tuple[np.ndarray, ...]:
    """Rings (N, 16) metres, trajectory indices (N,), labels (N,) m/s."""
    sonar = ROBOT.sonar
    rings = rng.uniform(sonar.min_range_m, sonar.max_range_m, (count, SONAR_COUNT))
    return rings, rng.integers(0, len(NAMES), count), rng.uniform(0.0, 0.6, count)


def best_seconds(run: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        run()
        times.append(time.perf_counter() - started)
    return min(times)


def measure(config_name: str, count: int, repeats: int) -> tuple[Fam, dict[str, float]]:
    """The trained FAM and its figures."""
    rings, trajectories, labels = exemplars(np.random.default_rng(0), count)
    config = BUILTIN_FAM_CONFIGS[config_name]
    fams: list[Fam] = []

    def train() -> None:
        fams.append(Fam(config, NAMES))
        fams[-1].train(rings, trajectories, labels, symmetric=True)

    train_s = best_seconds(train, repeats)
    fam = fams[-1]
    probe = rings[:FOVEAL_CALLS]

    def foveal() -> None:
        for ring in probe:
            fam.perceive(ring)

    def one_ring() -> None:
        for ring in probe:
            fam.velocities(ring)

    foveal()  # warm up
    batch = rings[:BATCH_RINGS]
    figures = {
        "foveal_us": 1e6 * best_seconds(foveal, repeats) / len(probe),
        "one_ring_us": 1e6 * best_seconds(one_ring, repeats) / len(probe),
        "batch_rings_per_s": len(batch) / best_seconds(lambda: fam.velocities(batch), repeats),
        "train_exemplars_per_s": count / train_s,
    }
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / f"{config_name}.h5"
        write_fam(path, fam, robot_config=ROBOT, provenance={"benchmark": "fam_speed"})
        figures["fam_file_bytes"] = path.stat().st_size
    return fam, figures


def simpful_seconds(fam: Fam, repeats: int) -> float:
    """Seconds for simpful's inference of one ring through the one-table FAM."""
    with contextlib.redirect_stdout(io.StringIO()):  # simpful announces the model type
        system = simpful_system(fam, 0)
    rings = exemplars(np.random.default_rng(1), SIMPFUL_CALLS)[0]
    table = fam.config.tables[0]

    def infer() -> None:
        for ring in rings:
            for k, fam_input in enumerate(table.inputs):
                system.set_variable(f"i{k}", float(ring[list(fam_input.sonars)].min()))
            system.Sugeno_inference(ignore_warnings=True)

    return best_seconds(infer, repeats) / len(rings)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--exemplars", type=int, default=1_000_000, help="training exemplars")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; the best counts")
    parser.add_argument("--json", action="store_true", help="print only the figures, as JSON")
    args = parser.parse_args()

    results: dict[str, dict[str, float]] = {}
    for name in ("single", "multi"):
        fam, figures = measure(name, args.exemplars, args.repeats)
        results[name] = figures
        if name == SINGLE.name:
            simpful_s = simpful_seconds(fam, min(args.repeats, 2))
            results["simpful"] = {
                "one_ring_s": simpful_s,
                "ratio": simpful_s / (1e-6 * figures["one_ring_us"]),
            }
    if args.json:
        print(json.dumps({"exemplars": args.exemplars, **results}, sort_keys=True))
        return
    for name in ("single", "multi"):
        f = results[name]
        config = BUILTIN_FAM_CONFIGS[name]
        print(f"{name}: {config.rule_count:,} rules in {len(config.tables)} table(s)")
        print(f"  foveal perception, 16 x 7 = 112 trajectories: {f['foveal_us']:.1f} us")
        print(f"  one ring, 7 trajectories:                      {f['one_ring_us']:.1f} us")
        print(f"  batch inference:            {f['batch_rings_per_s']:>12,.0f} rings/s")
        print(f"  symmetric training:         {f['train_exemplars_per_s']:>12,.0f} exemplars/s")
        print(
            f"  FAM file after {args.exemplars:,} exemplars: {f['fam_file_bytes'] / 1024:,.0f} KiB"
            " (the same for any number of exemplars)"
        )
    s = results["simpful"]
    print(
        f"simpful, one ring through the single FAM: {1e3 * s['one_ring_s']:.0f} ms, "
        f"{s['ratio']:,.0f}x the FAM's time"
    )


if __name__ == "__main__":
    main()
