"""Animation files from RGB frames: a GIF written by Pillow, or an MP4 video by ffmpeg.

A GIF holds at most 256 colours. Every frame is mapped to one palette made once, from the
animation's still background and the colours its moving parts are drawn in, rather than
each frame getting a palette of its own: mapping to a known palette is a lookup, choosing a
palette is a search, and one palette keeps a colour from flickering between frames.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Protocol

import numpy as np
from PIL import Image

from tvl_cli.core.errors import BadInput, EnvironmentFailure
from tvl_cli.io.atomic import atomic_output

GIF_COLOURS = 256


class FrameSink(Protocol):
    def add(self, frame: np.ndarray) -> None:
        """One (H, W, 3) uint8 RGB frame, the next in time."""


def ffmpeg_path() -> str:
    """ffmpeg, which an MP4 needs; EnvironmentFailure (what the machine lacks, not the
    user's input) before any frame is drawn if it is missing."""
    found = shutil.which("ffmpeg")
    if found is None:
        raise EnvironmentFailure("an MP4 needs ffmpeg, which is not installed (use --gif)")
    return found


class _GifFrames:
    """Frames mapped to the palette as they come; written as a GIF when all are in."""

    def __init__(self, background: np.ndarray, inks: np.ndarray) -> None:
        # The background's own colours, then the inks, each kept exactly.
        inks = np.unique(np.asarray(inks, dtype=np.uint8).reshape(-1, 3), axis=0)
        still = Image.fromarray(np.ascontiguousarray(background)).quantize(
            GIF_COLOURS - len(inks), method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE
        )
        entries = np.asarray(still.getpalette() or [], dtype=np.uint8).reshape(-1, 3)
        palette = entries[sorted(index for _, index in still.getcolors(GIF_COLOURS) or ())]
        self.palette = Image.new("P", (1, 1))
        self.palette.putpalette(np.concatenate([palette, inks]).ravel().tolist())
        self.frames: list[Image.Image] = []

    def add(self, frame: np.ndarray) -> None:
        image = Image.fromarray(np.ascontiguousarray(frame))
        self.frames.append(image.quantize(palette=self.palette, dither=Image.Dither.NONE))

    def write(self, path: Path, fps: int) -> None:
        first, *rest = self.frames
        first.save(
            path,
            format="GIF",
            save_all=True,
            append_images=rest,
            duration=round(1000 / fps),
            loop=0,
        )


class _Mp4Pipe:
    """Frames streamed to ffmpeg's standard input as raw RGB, encoded as H.264."""

    def __init__(self, stdin: IO[bytes]) -> None:
        self.stdin = stdin
        self.broken = False  # ffmpeg stopped reading: it failed, and says why on exit

    def add(self, frame: np.ndarray) -> None:
        if self.broken:
            return
        try:
            self.stdin.write(np.ascontiguousarray(frame).tobytes())
        except BrokenPipeError:
            self.broken = True


@contextmanager
def gif_frames(
    out: Path, fps: int, background: np.ndarray, inks: np.ndarray
) -> Iterator[FrameSink]:
    """A GIF at `fps` frames a second of the frames added, written whole or not at all once
    the block ends; `background` (H, W, 3) and `inks` (K, 3) uint8 give its colours."""
    frames = _GifFrames(background, inks)
    yield frames
    if not frames.frames:
        raise BadInput(f"{out}: no frames to write")
    with atomic_output(out) as temporary:
        frames.write(temporary, fps)


@contextmanager
def mp4_frames(out: Path, fps: int, size: tuple[int, int]) -> Iterator[FrameSink]:
    """An MP4 video at `fps` frames a second of the (height, width) frames added, whole or
    not at all."""
    height, width = size
    with atomic_output(out) as temporary:
        command = [
            ffmpeg_path(),
            "-y",
            "-loglevel", "error",
            "-f", "rawvideo",
            "-pix_fmt", "rgb24",
            "-s", f"{width}x{height}",
            "-framerate", str(fps),
            "-i", "-",
            "-f", "mp4",
            "-vcodec", "h264",
            "-pix_fmt", "yuv420p",  # what players expect of H.264
            str(temporary),
        ]  # fmt: skip
        with subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE) as ffmpeg:
            assert ffmpeg.stdin is not None and ffmpeg.stderr is not None
            pipe = _Mp4Pipe(ffmpeg.stdin)
            try:
                yield pipe
            finally:
                try:
                    ffmpeg.stdin.close()
                except BrokenPipeError:
                    pipe.broken = True
            failure = ffmpeg.stderr.read().decode(errors="replace").strip()
        if ffmpeg.returncode != 0:
            reason = failure.splitlines()[-1] if failure else f"exit status {ffmpeg.returncode}"
            raise BadInput(f"{out}: ffmpeg could not write the video ({reason})")
