"""What a FAM learnt elsewhere gains from more worlds, more minutes and richer labels, each
apart: diversity against quantity, label content against label count.

    python benchmarks/label_diversity.py [--out DIR] [--config multi ...] [--workers 2]

Experience comes from tuning worlds 11 to 20, each learnt alone by our method (seed 1), and
every FAM is scored on tuning worlds 1 to 10, where none of it was learnt, by `tvl bench
generalization --set tuning --worlds 1-10 --trials 1 --references none`, whose rows of ours
(learning 15 minutes in each world) are the in-world comparison. The training sets:

    worlds  minutes each  minutes in all
    1       15            15     (world 11)
    1       150           150    (world 11, one long session)
    10      1.5           15     (each world's first 1.5 minutes: `tvl train --until-minute`)
    10      15            150

so that worlds change at equal minutes, and minutes at equal worlds. Each set trains with
heard labels (every trajectory at every point, our default) and with bump labels (the driven
trajectory from its bump, the paper's): heard labels are about 6.9 a recorded point against 1
(`benchmarks/label_accuracy.py`), so heard labels from a tenth of the minutes are about as
many labels as bump labels from all of them, and the printed exemplar counts say how many.
The multi FAM is trained unless `--config` (repeatable) names others. Running again reuses the
logs and bench cells already in DIR.
"""

from __future__ import annotations

import argparse
import json
import subprocess
from pathlib import Path

from timing import TVL

EXPERIENCE_WORLDS = range(11, 21)  # the tuning set's second half, as fams/make_general.sh
LONG_WORLD = 11
SHORT_MINUTES, LONG_MINUTES = 15.0, 150.0
FIRST_MINUTES = 1.5  # a tenth of a session: ten worlds in the minutes of one
LABELS = ("heard", "bump")


def tvl(*args: object) -> dict:
    """`tvl ARGS --json`, run to its end."""
    printed = subprocess.run(
        [TVL, *map(str, args), "--json"], check=True, capture_output=True, text=True
    ).stdout
    return json.loads(printed)


def learnt(out: Path, world: int, minutes: float) -> Path:
    log = out / "logs" / f"rooms-s{world}-{minutes:g}min.h5"
    if not log.exists():
        log.parent.mkdir(parents=True, exist_ok=True)
        tvl("learn", f"rooms:{world}", "--minutes", minutes, "--seed", 1, "--log", log)
    return log


def training_sets(out: Path) -> list[tuple[str, int, float, list[Path], float | None]]:
    """(name, worlds, minutes each, logs, --until-minute) of each set."""
    short = [learnt(out, w, SHORT_MINUTES) for w in EXPERIENCE_WORLDS]
    long = learnt(out, LONG_WORLD, LONG_MINUTES)
    n = len(short)
    return [
        (f"1w-{SHORT_MINUTES:g}min", 1, SHORT_MINUTES, short[:1], None),
        (f"1w-{LONG_MINUTES:g}min", 1, LONG_MINUTES, [long], None),
        (f"{n}w-{FIRST_MINUTES:g}min", n, FIRST_MINUTES, short, FIRST_MINUTES),
        (f"{n}w-{SHORT_MINUTES:g}min", n, SHORT_MINUTES, short, None),
    ]


def trained(out: Path, name: str, logs: list[Path], until: float | None, labels: str,
            config: str) -> tuple[Path, int]:  # fmt: skip
    """The FAM and the exemplars it read."""
    fam = out / "fams" / f"{labels}-{name}-{config}.h5"
    fam.parent.mkdir(parents=True, exist_ok=True)
    limit = [] if until is None else ["--until-minute", until]
    found = tvl("train", *logs, "-o", fam, "--config", config, "--labels", labels,
                *limit, "--force")  # fmt: skip
    return fam, found["exemplars"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("results/label-diversity"))
    parser.add_argument("--config", action="append", choices=["single", "multi", "designed"])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    configs = args.config or ["multi"]
    controllers, rows = [], []
    for name, worlds, minutes, logs, until in training_sets(args.out):
        for labels in LABELS:
            for config in configs:
                fam, exemplars = trained(args.out, name, logs, until, labels, config)
                controllers += ["--controller", f"{labels}-{name}-{config}={fam}"]
                rows.append((f"{labels}-{name}-{config}", worlds, minutes, labels, exemplars))
    print("| FAM | worlds | minutes each | labels | exemplars |")
    print("| --- | --- | --- | --- | --- |")
    for fam_name, worlds, minutes, labels, exemplars in rows:
        print(f"| {fam_name} | {worlds} | {minutes:g} | {labels} | {exemplars:,} |")
    print()
    in_world = [arg for config in configs for arg in ("--config", config)]
    bench = [TVL, "bench", "generalization", "--set", "tuning", "--worlds", "1-10",
             "--trials", "1", "--references", "none", *in_world, *controllers,
             "--out", args.out / "bench", "--workers", args.workers, "--markdown"]  # fmt: skip
    subprocess.run([str(a) for a in bench], check=True)


if __name__ == "__main__":
    main()
