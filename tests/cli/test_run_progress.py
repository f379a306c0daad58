"""A run shows each step to a watcher as it goes (the bar or the live view of `tvl run`)."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_bad_numbers import SQUARE

from tvl_cli.commands.run import RunRequest, run_fam
from tvl_cli.commands.train import train_from_logs, write_trained
from tvl_cli.core.fam_config import SINGLE

EXAMPLE_LOG = Path(__file__).resolve().parents[2] / "logs" / "square-s1.h5"


@pytest.mark.slow  # over a second
def test_a_watcher_sees_every_step_in_order_beside_the_trace(tmp_path: Path) -> None:
    trained = train_from_logs([EXAMPLE_LOG], SINGLE)
    fam = tmp_path / "fam.h5"
    write_trained(fam, trained)
    seen: list[float] = []
    request = RunRequest(fam, SQUARE, "avoid", 0.85, 0.5, seed=1, trace=tmp_path / "run.h5")
    metrics = run_fam(request, lambda step: seen.append(step.time_s))
    period_s = metrics.sim_s / 300  # 30 simulated seconds of 0.1 s steps
    assert seen == pytest.approx([k * period_s for k in range(300)])
    assert (tmp_path / "run.h5").exists()  # the trace was written beside the watcher
