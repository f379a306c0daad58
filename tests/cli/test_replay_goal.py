"""A replay's frames are large enough to read, and a goal run's frames mark the goal it
seeks apart from the world's others: through `tvl run --log` and `tvl replay --gif`,
in-process, read back with Pillow."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import invoke
from PIL import Image

from tvl_cli.render.plot import GOAL_COLOUR, TARGET_COLOUR

ROOT = Path(__file__).resolve().parents[2]
OBSTACLES = ROOT / "worlds" / "obstacles.txt"
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
SOUGHT = "6.125,2.625"  # the world's second goal of four
READABLE_PX = (800, 400)  # a frame at least this large: 9-point titles read at 100 %


# Each test learns, trains, runs or draws: over a second each.
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("goal") / "fam.h5"
    assert invoke("train", EXAMPLE_LOG, "-o", path).returncode == 0
    return path


def last_frame(fam: Path, folder: Path, *behaviour: str) -> np.ndarray:
    """(H, W, 3) the last frame of a GIF of a short run of `behaviour` in the obstacles."""
    trace, gif = folder / "run.h5", folder / "run.gif"
    ran = invoke("run", fam, OBSTACLES, *behaviour, "--minutes", "0.05", "--log", trace)
    assert ran.returncode == 0, ran.stderr
    drawn = invoke("replay", trace, "--gif", gif)
    assert drawn.returncode == 0, drawn.stderr
    with Image.open(gif) as image:
        assert image.size >= READABLE_PX
        image.seek(image.n_frames - 1)
        return np.asarray(image.convert("RGB"), dtype=int)


def pixels_like(frame: np.ndarray, colour: str) -> int:
    """How many pixels are `colour`, a matplotlib colour, to within the GIF palette's rounding:
    no nearer, since the sonar rays' red lies 45 from the crimson of the sought goal."""
    from matplotlib.colors import to_rgb

    rgb = np.array(to_rgb(colour)) * 255
    return int((np.abs(frame - rgb).sum(axis=2) < 20).sum())


def test_a_goal_run_rings_its_goal_and_hollows_the_others(fam: Path, tmp_path: Path) -> None:
    (tmp_path / "avoid").mkdir()
    (tmp_path / "goal").mkdir()
    avoiding = last_frame(fam, tmp_path / "avoid", "--behaviour", "avoid")
    seeking = last_frame(fam, tmp_path / "goal", "--behaviour", "goal", "--goal", SOUGHT)
    # No goal sought, no ring; the one sought, ringed.
    assert pixels_like(avoiding, TARGET_COLOUR) == 0
    assert pixels_like(seeking, TARGET_COLOUR) > 50  # the ring round it: about 100 pixels
    # Four gold stars where none is sought; one where one is, the others hollow.
    gold_avoiding, gold_seeking = (
        pixels_like(avoiding, GOAL_COLOUR),
        pixels_like(seeking, GOAL_COLOUR),
    )
    assert gold_seeking < 0.5 * gold_avoiding and gold_seeking > 0
