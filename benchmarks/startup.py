"""Start-up: wall seconds of `tvl --help` and `tvl run --help`, whole process, against a bare
`python -c pass` measured in the same run (the interpreter's own start-up).

    python benchmarks/startup.py [--repeats 15] [--json]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

TVL = str(Path(sys.executable).with_name("tvl"))


def median_s(command: list[str], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        subprocess.run(command, capture_output=True, check=True)
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    figures = {
        "python_s": median_s([sys.executable, "-c", "pass"], args.repeats),
        "tvl_help_s": median_s([TVL, "--help"], args.repeats),
        "tvl_run_help_s": median_s([TVL, "run", "--help"], args.repeats),
    }
    if args.json:
        print(json.dumps(figures))
        return
    base = figures["python_s"]
    print(f"python -c pass   {base:.3f} s")
    for name, label in (("tvl_help_s", "tvl --help"), ("tvl_run_help_s", "tvl run --help")):
        print(f"{label:<16} {figures[name]:.3f} s ({figures[name] / base:.1f}x python's start-up)")


if __name__ == "__main__":
    main()
