"""PGM images (Netpbm's grey maps): the binary P5 that map_saver writes, and the plain P2.

Read here rather than through Pillow so that a file whose pixels do not fill the size its
header gives is named as such (a map cut short by a failed copy), and so that the exact
sample values reach map_server's thresholds.
"""

from __future__ import annotations

import re

import numpy as np

BINARY, PLAIN = b"P5", b"P2"
MAX_SAMPLE = 65535  # Netpbm's largest maxval: two bytes a sample
# A header number, after any whitespace and `#` comments (which run to the end of a line).
_HEADER_NUMBER = re.compile(rb"(?:\s|#[^\n]*\n?)*(\d+)")
_COMMENT = re.compile(rb"#[^\n]*")


def decode_pgm(data: bytes, max_pixels: int) -> tuple[np.ndarray, int]:
    """The (rows, columns) samples, top row first, and the maxval; ValueError saying what is
    wrong, before any pixel is read if the image holds more than `max_pixels`."""
    magic = data[:2]
    if magic not in (BINARY, PLAIN):
        raise ValueError("not a PGM image (it does not start with P5 or P2)")
    numbers: list[int] = []
    position = 2
    for name in ("width", "height", "maxval"):
        found = _HEADER_NUMBER.match(data, position)
        if found is None:
            raise ValueError(f"PGM header has no {name}")
        numbers.append(int(found.group(1)))
        position = found.end()
    width, height, maxval = numbers
    if width < 1 or height < 1:
        raise ValueError(f"PGM header gives a size of {width} x {height} pixels")
    if not 1 <= maxval <= MAX_SAMPLE:
        raise ValueError(f"PGM maxval {maxval} is not from 1 to {MAX_SAMPLE}")
    if width * height > max_pixels:
        raise ValueError(over_pixels(width, height, max_pixels))
    # Exactly one whitespace character ends the header.
    if data[position : position + 1] not in (b" ", b"\t", b"\n", b"\r"):
        raise ValueError("PGM header does not end in whitespace after the maxval")
    body = data[position + 1 :]
    samples = _binary(body, width, height, maxval) if magic == BINARY else _plain(body)
    if samples.size != width * height:
        raise ValueError(
            f"holds {samples.size:,} pixels, not the {width} x {height} its header gives"
        )
    if samples.max(initial=0) > maxval:
        raise ValueError(f"a pixel is {int(samples.max())}, above the maxval {maxval}")
    return samples.reshape(height, width), maxval


def over_pixels(columns: int, rows: int, max_pixels: int) -> str:
    """Why an image of this size is refused."""
    return (
        f"image is {columns} x {rows} pixels, over the {max_pixels:,} this machine can read "
        "(half its memory)"
    )


def _binary(body: bytes, width: int, height: int, maxval: int) -> np.ndarray:
    """P5 samples: one byte each up to maxval 255, else two bytes, most significant first."""
    dtype = np.dtype(np.uint8) if maxval < 256 else np.dtype(">u2")
    wanted = width * height * dtype.itemsize
    if len(body) != wanted:
        raise ValueError(
            f"holds {len(body):,} bytes of pixels, not the {wanted:,} its header's "
            f"{width} x {height} needs"
        )
    return np.frombuffer(body, dtype=dtype).astype(np.uint16)


def _plain(body: bytes) -> np.ndarray:
    """P2 samples: decimal numbers separated by whitespace."""
    words = _COMMENT.sub(b" ", body).split()
    if not all(word.isdigit() for word in words):
        raise ValueError("P2 pixels hold something that is not a whole number")
    return np.array([int(word) for word in words], dtype=np.int64)


def encode_pgm(pixels: np.ndarray) -> bytes:
    """A binary P5 image of (rows, columns) uint8 samples, top row first."""
    rows, columns = pixels.shape
    return b"P5\n%d %d\n255\n" % (columns, rows) + np.ascontiguousarray(pixels, np.uint8).tobytes()
