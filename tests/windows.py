"""Running code under a display server without a screen (Xvfb), for the tests of windows:
`tvl run --view window` and the Gymnasium environment's human mode. Each skips, saying why,
where there is no Xvfb, no window system matplotlib can use, or no way to read the screen."""

from __future__ import annotations

import shutil
import subprocess
import sys
from collections.abc import Sequence

import pytest

# The exit status of a script that found the window system missing, with the reason printed.
SKIPPED = 77
SCREEN = "1280x800x24"

# Prepended to every script: what it needs, or it exits SKIPPED saying what is missing.
PREAMBLE = f"""
import sys
from PIL import features
if not features.check("xcb"):
    print("this Pillow cannot read an X screen (built without XCB)")
    sys.exit({SKIPPED})
"""


def under_xvfb(argv: Sequence[str], timeout_s: float = 180) -> subprocess.CompletedProcess[str]:
    """Run `argv` on a display server of its own; skip the test if there is none."""
    if shutil.which("xvfb-run") is None:
        pytest.skip("xvfb-run (Debian's xvfb) is not installed: no display server to test on")
    return subprocess.run(
        ["xvfb-run", "--auto-servernum", f"--server-args=-screen 0 {SCREEN}", *argv],
        capture_output=True,
        text=True,
        timeout=timeout_s,
        check=False,
    )


def run_script(script: str) -> subprocess.CompletedProcess[str]:
    """Run a Python script under Xvfb; skip if it found no window system; else it must
    succeed."""
    done = under_xvfb([sys.executable, "-c", PREAMBLE + script])
    if done.returncode == SKIPPED:
        pytest.skip(done.stdout.strip())
    assert done.returncode == 0, done.stderr
    return done


# Prepended where a window may be refused: the reason, and SKIPPED.
OPENS_WINDOWS = f"""
from tvl_cli.core.errors import EnvironmentFailure
from tvl_cli.render.window import FrameWindow
try:
    FrameWindow("probe", (10, 10), 100).close()
except EnvironmentFailure as error:
    print(error)
    sys.exit({SKIPPED})
"""
