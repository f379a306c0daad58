"""Start-up: whole `tvl --help` and `tvl run --help` processes against the interpreter's own
start-up (`python -c pass`), and a first run after installing (compiling the kernels into
an empty cache) against a run that finds them cached.

Every figure is the median of R runs; pairs run in turn, so that their ratio or difference
holds while the machine's speed drifts. With --against DIR, that checkout's tvl prints its
help in turn with this one for paired ratios. The first-run figures time `tvl run` (a
single FAM trained from logs/lab-s1.h5) and `tvl learn` for one simulated minute in the
lab, the first with NUMBA_CACHE_DIR naming a new, empty directory each time.

    python benchmarks/startup.py [--repeats 15] [--against DIR] [--json]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

from timing import (
    TVL,
    Seconds,
    add_against_option,
    figure_line,
    median_seconds,
    paired,
    run_process,
    tvl_in,
)

ROOT = Path(__file__).resolve().parent.parent
LAB = ROOT / "worlds" / "lab.txt"
EXAMPLE_LOG = ROOT / "logs" / "lab-s1.h5"
TARGET_HELP_S = {"--help": 0.2, "run --help": 0.3}
TARGET_FIRST_RUN_EXTRA_S = 2.0
FIRST_RUN_REPEATS = 3  # each compiles every kernel afresh: seconds apiece


def first_run_penalty(
    command: Callable[[dict[str, str] | None], Seconds], repeats: int
) -> tuple[Seconds, float, float]:
    """The cached run's medians, and the median extra CPU and wall seconds of a run with an
    empty kernel cache, pair by pair."""
    command(None)  # the cache holds every kernel the command compiles
    cold: list[Seconds] = []
    warm: list[Seconds] = []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as cache:
            cold.append(command({"NUMBA_CACHE_DIR": cache}))
        warm.append(command(None))
    pairs = list(zip(cold, warm, strict=True))
    return (
        median_seconds(warm),
        statistics.median(c.cpu_s - w.cpu_s for c, w in pairs),
        statistics.median(c.wall_s - w.wall_s for c, w in pairs),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    add_against_option(parser)
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    theirs_tvl = tvl_in(args.against) if args.against else None
    figures: dict[str, dict[str, float | None]] = {}
    python, _, _ = paired(lambda: run_process([sys.executable, "-c", "pass"]), None, args.repeats)
    figures["python"] = {"cpu_s": python.cpu_s, "wall_s": python.wall_s}
    for words in TARGET_HELP_S:
        ours, theirs, ratio = paired(
            lambda words=words: run_process([TVL, *words.split()]),
            (lambda words=words: run_process([theirs_tvl, *words.split()])) if theirs_tvl else None,
            args.repeats,
        )
        figures[words] = {
            "cpu_s": ours.cpu_s,
            "wall_s": ours.wall_s,
            "against_cpu_s": theirs.cpu_s if theirs else None,
            "cpu_ratio_against": ratio,
        }
    with tempfile.TemporaryDirectory() as name:
        fam = Path(name) / "single.h5"
        run_process([TVL, "train", EXAMPLE_LOG, "-o", fam])

        def run(env: dict[str, str] | None) -> Seconds:
            argv = [TVL, "run", fam, LAB, "--behaviour", "avoid", "--minutes", "1"]
            return run_process(argv, env)

        def learn(env: dict[str, str] | None) -> Seconds:
            log = Path(name) / "learn.h5"
            log.unlink(missing_ok=True)
            return run_process([TVL, "learn", LAB, "--log", log, "--minutes", "1"], env)

        for verb, command in (("run", run), ("learn", learn)):
            cached, extra_cpu_s, extra_wall_s = first_run_penalty(command, FIRST_RUN_REPEATS)
            figures[f"first {verb}"] = {
                "cached_cpu_s": cached.cpu_s,
                "cached_wall_s": cached.wall_s,
                "extra_cpu_s": extra_cpu_s,
                "extra_wall_s": extra_wall_s,
            }
    if args.json:
        print(json.dumps(figures))
        return
    print(f"start-up, whole process, medians of {args.repeats} (CPU seconds; wall beside)")
    base = figures["python"]
    print(figure_line(f"python -c pass (wall {base['wall_s']:.3f} s)",
                      f"{base['cpu_s']:.3f} s", None, None))  # fmt: skip
    for words, target in TARGET_HELP_S.items():
        f = figures[words]
        cpu_s = f["cpu_s"]
        assert cpu_s is not None and base["cpu_s"] is not None
        note = f"{cpu_s / base['cpu_s']:.1f}x python's start-up"
        if f["cpu_ratio_against"] is not None:
            note += (
                f"; {f['cpu_ratio_against']:.2f}x the time of {args.against} "
                f"({f['against_cpu_s']:.3f} s), paired"
            )
        print(figure_line(f"tvl {words} (wall {f['wall_s']:.3f} s)", f"{cpu_s:.3f} s",
                          f"<= {target:g} s", cpu_s <= target, note))  # fmt: skip
    print(f"first run after installing, against a cached run, medians of {FIRST_RUN_REPEATS}")
    for verb in ("run", "learn"):
        f = figures[f"first {verb}"]
        extra = f["extra_cpu_s"]
        assert extra is not None
        print(
            figure_line(
                f"tvl {verb}, 1 simulated minute (wall +{f['extra_wall_s']:.2f} s)",
                f"+{extra:.2f} s",
                f"<= +{TARGET_FIRST_RUN_EXTRA_S:g} s",
                extra <= TARGET_FIRST_RUN_EXTRA_S,
                f"cached: {f['cached_cpu_s']:.2f} s",
            )
        )


if __name__ == "__main__":
    main()
