"""`tvl run --view window` on a display server without a screen (Xvfb): the run shown in a
window as `tvl replay --gif` draws it, read back off the screen."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import TVL
from windows import OPENS_WINDOWS, run_script, under_xvfb

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"

pytestmark = pytest.mark.slow  # each test starts a display server and a process under it


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from tvl_cli.commands.train import train_from_logs, write_trained
    from tvl_cli.core.fam_config import SINGLE

    trained = train_from_logs([ROOT / "logs" / "square-s1.h5"], SINGLE)
    path = tmp_path_factory.mktemp("window") / "fam.h5"
    write_trained(path, trained)
    return path


def test_the_run_drives_in_a_window_and_prints_as_ever(fam: Path) -> None:
    done = under_xvfb([TVL, "run", str(fam), str(SQUARE), "--behaviour", "avoid", "--minutes",
                       "0.2", "--view", "window", "--json"])  # fmt: skip
    if done.returncode == 1 and "which opens no windows" in done.stderr:
        pytest.skip(done.stderr.strip())
    assert done.returncode == 0, done.stderr
    assert done.stderr == "" and done.stdout.lstrip().startswith("{")


def test_the_window_shows_the_robot_its_rays_and_velocities(fam: Path) -> None:
    script = (
        OPENS_WINDOWS
        + f"""
from pathlib import Path
import numpy as np
from PIL import ImageGrab
from tvl_cli.cli.live import Sight, WindowView
from tvl_cli.commands.run import RunRequest, run_fam
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.render.animate import FAST_COLOUR, RAY_COLOUR
from tvl_cli.render.blit import inks
from tvl_cli.render.plot import ROBOT_COLOUR
from tvl_cli.sim.worldmap import load_world

square = Path({str(SQUARE)!r})
view = WindowView(Sight(load_world(square), RobotConfig(), 0.85))
run_fam(RunRequest(Path({str(fam)!r}), square, "avoid", 0.85, 0.2, seed=1), view)
view.draw()
view.window.hold(0.3)
screen = np.asarray(ImageGrab.grab().convert("RGB")).astype(int)
view.window.close()

def pixels(colour):
    return int((np.abs(screen - inks(colour)[0]).sum(axis=-1) <= 12).sum())

# The body (half see-through over the floor), the rays' red, the fast bars' green.
body, rays, fast = pixels((ROBOT_COLOUR, 0.5)), pixels(RAY_COLOUR), pixels(FAST_COLOUR)
assert body > 200 and rays > 10 and fast > 200, (body, rays, fast)
"""
    )
    run_script(script)
