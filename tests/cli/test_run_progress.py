"""A run reports its progress in simulated seconds as it goes, for the bar of `tvl run`."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_bad_numbers import SQUARE

from tvl_cli.commands.run import PROGRESS_EVERY_STEPS, RunRequest, run_fam
from tvl_cli.commands.train import train_from_logs
from tvl_cli.core.config import SINGLE
from tvl_cli.core.training import TrainParams
from tvl_cli.io.famfile import write_fam

EXAMPLE_LOG = Path(__file__).resolve().parents[2] / "logs" / "square-s1.h5"


def test_progress_comes_every_so_many_steps_in_simulated_seconds(tmp_path: Path) -> None:
    trained = train_from_logs([EXAMPLE_LOG], SINGLE, TrainParams())
    fam = tmp_path / "fam.h5"
    write_fam(fam, trained.fam, robot_config=trained.robot, provenance=trained.provenance)
    reported: list[float] = []
    request = RunRequest(fam, SQUARE, "avoid", 0.85, 0.5, seed=1, trace=tmp_path / "run.h5")
    metrics = run_fam(request, reported.append)
    period_s = metrics.sim_s / 300  # 30 simulated seconds of 0.1 s steps
    # The time before the 60th, 120th, ... step: the seconds done when it began.
    expected = [(k * PROGRESS_EVERY_STEPS - 1) * period_s for k in range(1, 6)]
    assert reported == pytest.approx(expected)
    assert (tmp_path / "run.h5").exists()  # the trace was still written beside the reports
