"""`tvl demo`: the whole pipeline on the bundled square arena, in seconds."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from tvl_cli.commands.learn import LearnRequest, LearnResult, learn_to_log
from tvl_cli.commands.run import RunRequest, run_fam
from tvl_cli.commands.train import train_from_logs, write_trained
from tvl_cli.core.behaviours import DEFAULT_THRESHOLD
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam_config import MULTI, SINGLE
from tvl_cli.core.learn_params import LearnParams
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.metrics import RunMetrics
from tvl_cli.io.json_documents import document, world_input
from tvl_cli.sim.worldgen import bundled_world_path

DEMO_WORLD = "square"
DEMO_SEED = 1
LEARN_MINUTES = 15.0
RUN_MINUTES = 3.0
BEHAVIOURS = ("avoid", "wall-left")


@dataclass(frozen=True, slots=True)
class DemoRow:
    config: str
    behaviour: str
    threshold: float
    fam: Path
    metrics: RunMetrics
    png: Path


@dataclass(frozen=True, slots=True)
class DemoResult:
    directory: Path
    learning: LearnResult
    rows: list[DemoRow]

    def document(self) -> dict[str, Any]:
        """The learning, then each run's metrics as `tvl run --json` prints them."""
        learnt = self.learning.request
        inputs = {
            "world": world_input(learnt.world),
            "seed": DEMO_SEED,
            "learn_minutes": learnt.learn.minutes,
            "run_minutes": RUN_MINUTES,
        }
        return document(
            "demo",
            inputs,
            outputs={"directory": str(self.directory), "log": str(learnt.log)},
            learning=self.learning.session_record(),
            runs=[
                {
                    "config": r.config,
                    "behaviour": r.behaviour,
                    "threshold": r.threshold,
                    "fam": str(r.fam),
                    "png": str(r.png),
                    **asdict(r.metrics),
                }
                for r in self.rows
            ],
        )


def run_demo(directory: Path, force: bool, say: Callable[[str], None]) -> DemoResult:
    """Learn in the square, train single and multi FAMs from the log, run two behaviours."""
    if directory.exists() and not directory.is_dir():
        raise BadInput(f"{directory}: is a file, not a directory for the demo")
    if directory.exists() and any(directory.iterdir()) and not force:
        raise BadInput(f"{directory}: exists and is not empty (use --force to write into it)")
    directory.mkdir(parents=True, exist_ok=True)
    world = directory / f"{DEMO_WORLD}.txt"
    shutil.copyfile(bundled_world_path(DEMO_WORLD), world)
    log = directory / "learn.h5"
    log.unlink(missing_ok=True)  # a demo always starts a fresh log
    say(f"learning for {LEARN_MINUTES:g} simulated minutes in {world} ...")
    learning = learn_to_log(
        LearnRequest(world, log, DEMO_SEED, "single", LearnParams(minutes=LEARN_MINUTES), DEFAULT)
    )
    rows = []
    for config in (SINGLE, MULTI):
        say(f"training the {config.name} FAM from {log} ...")
        fam_path = directory / f"{config.name}.h5"
        write_trained(fam_path, train_from_logs([log], config, DEFAULT))
        for behaviour in BEHAVIOURS:
            say(f"running {behaviour} with the {config.name} FAM ...")
            png = directory / f"{config.name}-{behaviour}.png"
            metrics = run_fam(
                RunRequest(
                    fam_path, world, behaviour, DEFAULT_THRESHOLD, RUN_MINUTES, DEMO_SEED, png=png
                )
            )
            rows.append(DemoRow(config.name, behaviour, DEFAULT_THRESHOLD, fam_path, metrics, png))
    return DemoResult(directory, learning, rows)
