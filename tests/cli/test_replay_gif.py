"""`tvl replay RUN --gif`: an animated replay, read back with Pillow."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest
from conftest import TVL
from json_schemas import valid
from PIL import Image
from test_bad_numbers import SQUARE, assert_one_line_refusal

from tvl_cli.render.animate import DPI, FIGURE_SIZE_IN

EXAMPLE_LOG = Path(__file__).resolve().parents[2] / "logs" / "square-s1.h5"

pytestmark = pytest.mark.slow  # every test here starts a real `tvl` process


def tvl(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([TVL, *map(str, args)], capture_output=True, text=True, timeout=300)


def test_a_window_of_a_run_becomes_a_gif_of_its_frames(tmp_path: Path) -> None:
    fam, trace, gif = tmp_path / "fam.h5", tmp_path / "run.h5", tmp_path / "run.gif"
    assert tvl("train", EXAMPLE_LOG, "-o", fam).returncode == 0
    ran = tvl("run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.2", "--log", trace)
    assert ran.returncode == 0, ran.stderr
    # Steps 20 to 79 (seconds 2 to 8 at 10 steps a second), every third: 20 frames.
    done = tvl("replay", trace, "--gif", gif, "--from", "2", "--to", "8", "--every", "3", "--json")
    assert done.returncode == 0, done.stderr
    printed = valid("replay", done.stdout)
    assert printed["animation_frames"] == 20 and printed["outputs"]["animation"] == str(gif)
    with Image.open(gif) as image:
        assert image.format == "GIF" and image.n_frames == 20
        assert image.size == tuple(round(side * DPI) for side in FIGURE_SIZE_IN)
    backward = tvl("replay", trace, "--gif", tmp_path / "b.gif", "--from", "8", "--to", "2")
    assert_one_line_refusal(backward, "an empty or backward window")
    assert not (tmp_path / "b.gif").exists()


def test_a_learning_session_becomes_a_gif_of_its_episodes(tmp_path: Path) -> None:
    from tvl_cli.io.logreader import read_log

    gif = tmp_path / "log.gif"
    done = tvl("replay", EXAMPLE_LOG, "--gif", gif, "--to", "20", "--every", "4", "--json")
    assert done.returncode == 0, done.stderr
    (session,) = read_log(EXAMPLE_LOG).sessions
    exemplars = sum(e.exemplar_count for e in session.episodes() if e.end_time_s <= 20)
    frames = valid("replay", done.stdout)["animation_frames"]
    assert frames == -(-exemplars // 4) > 0  # every fourth exemplar of those episodes
    with Image.open(gif) as image:
        assert image.n_frames == frames
    none = tvl("replay", EXAMPLE_LOG, "--gif", tmp_path / "none.gif", "--from", "1", "--to", "2")
    assert_one_line_refusal(none, "no episode of session 0000 ended in that window")


def test_a_video_without_ffmpeg_is_one_line_and_leaves_nothing(tmp_path: Path) -> None:
    from matplotlib.animation import FFMpegWriter

    video = tmp_path / "log.mp4"
    if FFMpegWriter.isAvailable():
        done = tvl("replay", EXAMPLE_LOG, "--mp4", video, "--to", "20", "--json")
        assert done.returncode == 0 and video.read_bytes()[4:8] == b"ftyp", done.stderr
        video.unlink()
    # A search path with no ffmpeg on it: what the machine lacks is exit 1, not bad input.
    nowhere = tmp_path / "bin"
    nowhere.mkdir()
    done = subprocess.run(
        [TVL, "replay", EXAMPLE_LOG, "--mp4", video, "--to", "20"],
        capture_output=True, text=True, timeout=300, env={"PATH": str(nowhere)},
    )  # fmt: skip
    assert done.returncode == 1 and done.stderr == (
        "tvl: error: an MP4 needs ffmpeg, which is not installed (use --gif)\n"
    )
    assert not video.exists()
    both = tvl("replay", EXAMPLE_LOG, "--mp4", video, "--gif", tmp_path / "x.gif")
    assert_one_line_refusal(both, "give --gif or --mp4, not both")


@pytest.mark.parametrize(
    "option", [["--from", "2"], ["--to", "8"], ["--every", "3"], ["--fps", "5"]]
)
def test_an_animation_option_without_an_animation_is_refused(
    tmp_path: Path, option: list[str]
) -> None:
    png = tmp_path / "paths.png"
    done = tvl("replay", EXAMPLE_LOG, "--png", png, *option)
    assert_one_line_refusal(done, f"{option[0]} applies only with --gif or --mp4")
    assert not png.exists()  # refused before anything is drawn


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
@pytest.mark.parametrize("option, name", [("--gif", "log.gif"), ("--png", "log.png")])
def test_a_picture_into_a_directory_that_takes_no_files_is_one_line(option: str, name: str) -> None:
    # /proc refuses a new file even to root, who may write in any directory of its own.
    done = tvl("replay", EXAMPLE_LOG, option, f"/proc/{name}")
    assert_one_line_refusal(done, f"/proc/{name}: cannot write")


@pytest.mark.parametrize(
    "option, name", [("--gif", "log.png"), ("--mp4", "log.gif"), ("--gif", "log")]
)
def test_an_animation_named_for_another_format_is_refused(
    tmp_path: Path, option: str, name: str
) -> None:
    out = tmp_path / name
    done = tvl("replay", EXAMPLE_LOG, option, out, "--to", "20")
    assert_one_line_refusal(done, f"{out}: it is written as ")
    assert done.stderr.count(f"give it the extension .{option[2:]}") == 1
    assert not out.exists()


def test_a_gif_shows_a_progress_bar_on_a_terminal(tmp_path: Path) -> None:
    # stderr a terminal (a pseudo-terminal's), as a person running the command sees it.
    import os
    import pty

    leader, follower = pty.openpty()
    gif = tmp_path / "log.gif"
    with subprocess.Popen(
        [TVL, "replay", EXAMPLE_LOG, "--gif", gif, "--to", "30"],
        stdout=subprocess.DEVNULL,
        stderr=follower,
    ) as process:
        os.close(follower)
        seen = b""
        while True:
            try:
                chunk = os.read(leader, 4096)
            except OSError:  # the process closed its end
                break
            if not chunk:
                break
            seen += chunk
        assert process.wait(timeout=300) == 0
    os.close(leader)
    assert b"drawing frames" in seen and gif.exists()
    # The time it has left, beside the time it took.
    assert re.search(rb"\d:\d\d:\d\d(\x1b\[[0-9;]*m)* left", seen), seen[-400:]
