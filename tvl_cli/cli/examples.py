"""Each command's examples, shown under its help (`tvl COMMAND -h`) as click's epilog.

Run from the checkout's top folder, they use its worlds and example logs, and the files the
examples before them write; tests/cli/test_help.py parses every one with its command.
"""

from __future__ import annotations

# The command as typed (a subcommand after its group) -> its examples, one command line each.
EXAMPLES: dict[str, tuple[str, ...]] = {
    "": (
        "tvl demo",
        "tvl learn worlds/square.txt --log square.h5",
        "tvl run -h",
    ),
    "world": (
        "tvl world new rooms --seed 3 -o rooms.txt",
        "tvl world show worlds/lab.txt",
    ),
    "world new": (
        "tvl world new rooms --seed 3 -o rooms.txt",
        "tvl world new corridor --size 8 6 -o corridor.txt",
    ),
    "world show": ("tvl world show worlds/lab.txt", "tvl world show worlds/lab.txt --json"),
    "world check": ("tvl world check rooms.txt",),
    "world render": ("tvl world render worlds/obstacles.txt -o obstacles.png",),
    "world import": ("tvl world import map.yaml -o map.txt --start 1.0,2.0,90",),
    "world export": ("tvl world export worlds/lab.txt -o lab.yaml",),
    "learn": (
        "tvl learn worlds/square.txt --log square.h5",
        "tvl learn worlds/lab.txt --log lab.h5 --minutes 45 --config multi --fam online.h5",
    ),
    "train": (
        "tvl train logs/square-s1.h5 -o single.h5",
        "tvl train logs/square-s1.h5 logs/lab-s1.h5 -o multi.h5 --config multi",
    ),
    "inspect": (
        "tvl inspect single.h5 --trajectory T1L --top 5",
        "tvl inspect multi.h5 --png multi.png",
    ),
    "diff": ("tvl diff single.h5 single-45.h5 --top 5",),
    "design": ("tvl design logs/lab-s1.h5 -o designed.json --budget 20000",),
    "run": (
        "tvl run single.h5 worlds/square.txt --behaviour wall-left --png wall.png",
        "tvl run single.h5 worlds/obstacles.txt --behaviour goal --log goal.h5",
    ),
    "replay": (
        "tvl replay goal.h5 --gif goal.gif",
        "tvl replay logs/square-s1.h5 --png episodes.png --curves curves.png",
    ),
    "explain": (
        "tvl explain goal.h5 --at 7.9",
        "tvl explain goal.h5 --event collision --png why.png",
        "tvl explain goal.h5 --contacts",
    ),
    "demo": ("tvl demo", "tvl demo my-demo --json"),
    "baseline": (
        "tvl baseline dwa worlds/lab.txt --sensor ring",
        "tvl baseline qlearn worlds/square.txt",
    ),
    "baseline dwa": ("tvl baseline dwa worlds/lab.txt --sensor ring --minutes 5",),
    "baseline qlearn": ("tvl baseline qlearn worlds/square.txt --png greedy.png",),
    "sweep": ("tvl sweep experiments/grids/fig21.toml --out results/fig21 --workers 2",),
    "bench": (
        "tvl bench generalization --size quick --workers 2",
        "tvl bench claims --size quick",
    ),
    "bench generalization": (
        "tvl bench generalization --size quick --workers 2",
        "tvl bench generalization --set tuning --worlds 1-10 --method paper --trials 1",
        "tvl bench generalization --size tiny --controller mine=single.h5 --references dwa-map",
        "tvl bench generalization --set tuning --trials 1 --pool fams/general-log.h5",
        "tvl bench generalization --set tuning --trials 1 --by-world --markdown",
    ),
    "bench claims": (
        "tvl bench claims --size quick",
        "tvl bench claims --claim fig21 --method default --scheduler local:2",
    ),
    "export": ("tvl export goal.h5 --mcap goal.mcap",),
    "figure": ("tvl figure fig21 results/fig21/results.jsonl -o fig21.png --table fig21.md",),
    "schema": ("tvl schema", "tvl schema run > run.schema.json"),
}


def examples(command: str) -> str:
    """The epilog of `command`'s help: its examples, kept as written (click's \\b)."""
    return "\b\nExamples:\n" + "\n".join(f"  {line}" for line in EXAMPLES[command])
