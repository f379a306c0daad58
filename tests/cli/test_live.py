"""`tvl run --live`: the view drawn into rich's recording console, and its fallback."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from conftest import TVL
from rich.console import Console

from tvl_cli.cli.live import ARROWS, LiveView, Sight
from tvl_cli.commands.run import RunRequest, run_fam
from tvl_cli.commands.train import train_from_logs, write_trained
from tvl_cli.core.fam_config import SINGLE
from tvl_cli.core.method import DEFAULT
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.sim.worldmap import load_world

ROOT = Path(__file__).resolve().parents[2]
LAB = ROOT / "worlds" / "lab.txt"


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    trained = train_from_logs([ROOT / "logs" / "lab-s1.h5"], SINGLE)
    path = tmp_path_factory.mktemp("live") / "fam.h5"
    write_trained(path, trained)
    return path


def test_the_view_fits_a_small_terminal_and_shows_the_run(fam: Path) -> None:
    view = LiveView(Sight(load_world(LAB), RobotConfig(), 0.85))
    metrics = run_fam(RunRequest(fam, LAB, "avoid", 0.85, 0.5, seed=1), view)
    console = Console(record=True, width=80, height=24, color_system=None)
    console.print(view.panel())
    lines = console.export_text().rstrip("\n").splitlines()
    assert len(lines) <= 24 and max(len(line) for line in lines) <= 80
    text = "\n".join(lines)
    assert sum(text.count(arrow) for arrow in ARROWS) == 1  # the robot, once
    assert "#" in text and "·" in text  # walls and the path so far
    for name in ("T3L", "T0", "T3R"):
        assert name in text
    assert f"bumps {metrics.collisions}  near misses {metrics.near_misses}" in text
    assert f"t {metrics.sim_s - 0.1:6.1f} s" in text  # the last step began 0.1 s before the end


@pytest.mark.slow
def test_live_without_a_terminal_falls_back_to_the_plain_output(fam: Path) -> None:
    done = subprocess.run(
        [TVL, "run", str(fam), str(LAB), "--behaviour", "avoid", "--minutes", "0.2", "--live",
         "--json"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.lstrip().startswith("{") and done.stderr == ""
    paced = subprocess.run(
        [TVL, "run", str(fam), str(LAB), "--behaviour", "avoid", "--live", "--pace", "0"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert paced.returncode == 2 and "--pace 0 must be a positive number" in paced.stderr


@pytest.mark.slow
def test_learning_shows_the_trajectory_followed_and_the_last_minute(tmp_path: Path) -> None:
    from tvl_cli.commands.learn import LearnRequest, learn_to_log
    from tvl_cli.core.learn_params import LearnParams

    view = LiveView(Sight(load_world(LAB), RobotConfig(), 0.85))
    view.caption = "minute 1: 3 episodes, 0 collisions"
    request = LearnRequest(LAB, tmp_path / "log.h5", 1, "single", LearnParams(minutes=0.3), DEFAULT)
    learn_to_log(request, watch=view)
    console = Console(record=True, width=80, height=24, color_system=None)
    console.print(view.panel())
    text = console.export_text()
    assert "minute 1: 3 episodes, 0 collisions" in text
    assert "no velocities perceived" in text
    done = subprocess.run(
        [TVL, "learn", str(LAB), "--log", str(tmp_path / "log2.h5"), "--minutes", "0.2",
         "--live", "--json"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0 and done.stdout.lstrip().startswith("{"), done.stderr


@pytest.mark.parametrize("view", ["terminal", "window"])
def test_the_view_draws_the_robot_the_run_drives(
    fam: Path, view: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """With `--sonar`, the view's robot hears as the run's does (its rays' colours, its ring
    scale), not as this simulator's default robot would."""
    from click.testing import CliRunner

    from tvl_cli.cli import live, views
    from tvl_cli.cli.main import main
    from tvl_cli.core.robot_config import SONAR_MODELS

    shown: list[RobotConfig] = []

    class Shown(LiveView):
        """The terminal view, or the window's stand-in where no display is, telling its robot."""

        def __init__(self, sight: Sight) -> None:
            shown.append(sight.robot)
            super().__init__(sight)

    monkeypatch.setattr(live, "LiveView", Shown)
    monkeypatch.setattr(live, "WindowView", Shown)
    monkeypatch.setattr(live, "window_view", live.live_view)
    # A terminal to watch on (CliRunner's output is none).
    monkeypatch.setattr(views, "out", Console(force_terminal=True, width=80, height=24))
    args = ["run", fam, LAB, "--behaviour", "avoid", "--minutes", "0.05", "--sonar", "ideal"]
    done = CliRunner().invoke(main, [*map(str, args), "--view", view])
    assert done.exit_code == 0, done.output
    assert [robot.sonar for robot in shown] == [SONAR_MODELS["ideal"]]
    assert SONAR_MODELS["ideal"] != RobotConfig().sonar


@pytest.mark.slow  # half a simulated minute through the live view
def test_the_bars_stay_while_the_robot_spins(fam: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Through `tvl run --live`: on every step that perceives nothing (a spin, a back-off,
    the steps between two readings) the view still shows the seven bars, as last perceived."""
    from click.testing import CliRunner

    from tvl_cli.cli import live, views
    from tvl_cli.cli.main import main

    blind: list[str] = []  # the side panel on each step that perceived no velocities

    class Watched(LiveView):
        def __call__(self, step) -> None:  # type: ignore[no-untyped-def]
            super().__call__(step)
            if step.decision.velocities is None and self.perceived is not None:
                console = Console(record=True, width=80, color_system=None)
                console.print(*self._side())
                blind.append(console.export_text())

    monkeypatch.setattr(live, "LiveView", Watched)
    monkeypatch.setattr(views, "out", Console(force_terminal=True, width=80, height=24))
    args = ["run", fam, LAB, "--behaviour", "avoid", "--minutes", "0.5", "--live", "--json"]
    done = CliRunner().invoke(main, list(map(str, args)))
    assert done.exit_code == 0, done.output
    spins = json.loads(done.stdout[done.stdout.index("{") :])["spins"]
    assert spins > 0 and any("spinning: as perceived at" in side for side in blind)
    for side in blind:
        assert "as perceived at" in side
        assert all(f"{name} " in side for name in ("T3L", "T2L", "T1L", "T0", "T1R", "T2R", "T3R"))
        assert "no velocities perceived" not in side
