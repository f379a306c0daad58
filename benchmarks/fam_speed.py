"""FAM speed for the `single` and `multi` configurations, against numpy and simpful.

    python benchmarks/fam_speed.py [--exemplars N] [--repeats R] [--json]

For each configuration: the 112-trajectory foveal perception of one ring (all 16 rotations
x 7 trajectories), batch inference, symmetric training, and the size of the FAM file after
training on N exemplars. Readings are uniform over the sonar range, labels uniform up to
0.6 m/s. Each figure is the median CPU time of R timed runs, beside the same work done in
the same run by the plain numpy references of the compiled kernels
(tests/kernel_references/). A FAM file holds one velocity and one experience per rule and
trajectory, so its size does not grow with the exemplars it learnt from. Finally the same
one-ring inference of the trained `single` FAM (7 velocities and their experience) is run by
simpful, a zero-order Sugeno system with one rule per FAM entry, for the ratio.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
from timing import cpu_seconds, figure_line

from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import BUILTIN_FAM_CONFIGS, SINGLE
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import SONAR_COUNT, RobotConfig
from tvl_cli.io.famfile import write_fam

# The benchmark times the very translation to simpful that the agreement test checks.
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "core"))
from test_fam_simpful import simpful_system

# The numpy references the kernels' tests hold them to.
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from kernel_references.perception_reference import infer_views_reference
from kernel_references.rule_updates_reference import train_table_reference

ROBOT = RobotConfig()
NAMES = tuple(t.name for t in ROBOT.trajectories)
BATCH_RINGS = 100_000
FOVEAL_CALLS = 2_000
REFERENCE_SHARE = 10  # the numpy references do a tenth of the work: they are slow
SIMPFUL_CALLS = 2
TARGET_FOVEAL_US = {"single": 10.0, "multi": 25.0}
TARGET_TRAIN_PER_S = {"single": 5e6, "multi": 2e6}


def exemplars(rng: np.random.Generator, count: int) -> tuple[np.ndarray, ...]:
    """Rings (N, 16) metres, trajectory indices (N,), labels (N,) m/s."""
    sonar = ROBOT.sonar
    rings = rng.uniform(sonar.min_range_m, sonar.max_range_m, (count, SONAR_COUNT))
    return rings, rng.integers(0, len(NAMES), count), rng.uniform(0.0, 0.6, count)


def numpy_fam(fam: Fam) -> Fam:
    """The FAM perceiving and training through the numpy references instead of the kernels."""
    fam._infer_views = infer_views_reference
    fam._train_table = train_table_reference
    return fam


def measure(config_name: str, count: int, repeats: int) -> tuple[Fam, dict[str, float]]:
    """The trained FAM and its figures."""
    rings, trajectories, labels = exemplars(np.random.default_rng(0), count)
    config = BUILTIN_FAM_CONFIGS[config_name]
    share = count // REFERENCE_SHARE

    def train(fams: list[Fam], n: int) -> Callable[[], None]:
        """Training untrained FAMs made beforehand, one a run."""

        def run() -> None:
            fams[-1].train(rings[:n], trajectories[:n], labels[:n], symmetric=True)
            trained.append(fams.pop())

        return run

    trained: list[Fam] = []
    train_s = cpu_seconds(train([Fam(config, NAMES) for _ in range(repeats)], count), repeats)
    fam = trained[-1]
    untrained = [numpy_fam(Fam(config, NAMES)) for _ in range(repeats)]
    numpy_train_s = cpu_seconds(train(untrained, share), repeats)
    reference = numpy_fam(Fam.from_tables(config, NAMES, *_tables(fam)))
    probe = rings[:FOVEAL_CALLS]

    def foveal(f: Fam, n: int) -> Callable[[], None]:
        def run() -> None:
            for ring in probe[:n]:
                f.perceive(ring)

        return run

    foveal(fam, len(probe))()  # loads the kernels
    batch = rings[:BATCH_RINGS]
    figures = {
        "foveal_us": 1e6 * cpu_seconds(foveal(fam, len(probe)), repeats) / len(probe),
        "numpy_foveal_us": 1e6
        * cpu_seconds(foveal(reference, len(probe) // REFERENCE_SHARE), repeats)
        / (len(probe) // REFERENCE_SHARE),
        "one_ring_us": 1e6
        * cpu_seconds(lambda: [fam.velocities(r) for r in probe], repeats)
        / len(probe),
        "batch_rings_per_s": len(batch) / cpu_seconds(lambda: fam.velocities(batch), repeats),
        "numpy_batch_rings_per_s": (len(batch) // REFERENCE_SHARE)
        / cpu_seconds(
            lambda: reference.velocities(batch[: len(batch) // REFERENCE_SHARE]), repeats
        ),
        "train_exemplars_per_s": count / train_s,
        "numpy_train_exemplars_per_s": share / numpy_train_s,
    }
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / f"{config_name}.h5"
        write_fam(
            path, fam, robot_config=ROBOT, method=DEFAULT, provenance={"benchmark": "fam_speed"}
        )
        figures["fam_file_bytes"] = path.stat().st_size
    return fam, figures


def _tables(fam: Fam) -> tuple[list[np.ndarray], list[np.ndarray]]:
    count = len(fam.config.tables)
    return (
        [fam.velocity_table(t) for t in range(count)],
        [fam.experience_table(t) for t in range(count)],
    )


def simpful_seconds(fam: Fam, repeats: int) -> float:
    """CPU seconds for simpful's inference of one ring through the one-table FAM."""
    with contextlib.redirect_stdout(io.StringIO()):  # simpful announces the model type
        system = simpful_system(fam, 0)
    rings = exemplars(np.random.default_rng(1), SIMPFUL_CALLS)[0]
    table = fam.config.tables[0]

    def infer() -> None:
        for ring in rings:
            for k, fam_input in enumerate(table.inputs):
                system.set_variable(f"i{k}", float(ring[list(fam_input.sonars)].min()))
            system.Sugeno_inference(ignore_warnings=True)

    return cpu_seconds(infer, repeats) / len(rings)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--exemplars", type=int, default=1_000_000, help="training exemplars")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs; the median counts")
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
    print(f"median CPU time of {args.repeats} runs; numpy: the kernels' references, same run")
    for name in ("single", "multi"):
        f = results[name]
        config = BUILTIN_FAM_CONFIGS[name]
        print(f"{name}: {config.rule_count:,} rules in {len(config.tables)} table(s)")
        foveal, train = f["foveal_us"], f["train_exemplars_per_s"]
        print(
            figure_line(
                "foveal perception, 16 x 7 = 112 trajectories",
                f"{foveal:.1f} µs",
                f"<= {TARGET_FOVEAL_US[name]:g} µs",
                foveal <= TARGET_FOVEAL_US[name],
                f"{f['numpy_foveal_us'] / foveal:.1f}x as fast as numpy "
                f"({f['numpy_foveal_us']:.1f} µs)",
            )
        )
        print(figure_line("one ring, 7 trajectories", f"{f['one_ring_us']:.1f} µs", None, None))
        print(
            figure_line(
                "batch inference",
                f"{f['batch_rings_per_s']:,.0f} rings/s",
                None,
                None,
                f"{f['batch_rings_per_s'] / f['numpy_batch_rings_per_s']:.1f}x numpy "
                f"({f['numpy_batch_rings_per_s']:,.0f} rings/s)",
            )
        )
        print(
            figure_line(
                "symmetric training",
                f"{train:,.0f} exemplars/s",
                f">= {TARGET_TRAIN_PER_S[name]:,.0f}/s",
                train >= TARGET_TRAIN_PER_S[name],
                f"{train / f['numpy_train_exemplars_per_s']:.1f}x numpy "
                f"({f['numpy_train_exemplars_per_s']:,.0f}/s)",
            )
        )
        print(
            figure_line(
                f"FAM file after {args.exemplars:,} exemplars",
                f"{f['fam_file_bytes'] / 1024:,.0f} KiB",
                None,
                None,
                "(the same for any number of exemplars)",
            )
        )
    s = results["simpful"]
    print(
        figure_line(
            "simpful, one ring through the single FAM",
            f"{1e3 * s['one_ring_s']:.0f} ms",
            None,
            None,
            f"{s['ratio']:,.0f}x the FAM's time",
        )
    )


if __name__ == "__main__":
    main()
