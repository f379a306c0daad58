"""The Gymnasium environment's human render mode on a display server without a screen
(Xvfb): Gymnasium's whole checker, render modes and all, and the robot in its window."""

from __future__ import annotations

import pytest
from windows import OPENS_WINDOWS, run_script

pytestmark = pytest.mark.slow  # each test starts a display server and Python under it


def test_the_env_passes_gymnasiums_checker_with_its_window() -> None:
    run_script(OPENS_WINDOWS + """
import gymnasium
from gymnasium.utils.env_checker import check_env
from tvl_cli.gym import ENV_ID
import warnings
warnings.simplefilter("error")  # as pytest runs: any warning fails
env = gymnasium.make(ENV_ID, world="square")
check_env(env.unwrapped)  # every render mode, human included
env.close()
""")  # fmt: skip


def test_human_mode_shows_each_step_at_the_envs_pace() -> None:
    run_script(OPENS_WINDOWS + """
import time
import numpy as np
from PIL import ImageGrab
from tvl_cli.gym.env import SonarRingEnv, ROBOT
from tvl_cli.render.blit import inks
from tvl_cli.render.plot import ROBOT_COLOUR

env = SonarRingEnv("square", render_mode="human")
assert env.reset(seed=1) is not None and env.render() is None
started = time.monotonic()
for _ in range(5):
    env.step(3)  # T0
took_s = time.monotonic() - started
screen = np.asarray(ImageGrab.grab().convert("RGB")).astype(int)
env.close()
body = int((np.abs(screen - inks((ROBOT_COLOUR, 0.5))[0]).sum(axis=-1) <= 12).sum())
assert body > 200, body
# Shown at render_fps, 10 a second: five steps take half a second at least.
assert took_s >= 5 * ROBOT.control_period_s * 0.95, took_s
""")  # fmt: skip
