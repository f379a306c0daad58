"""PGM images: the binary P5 and plain P2 forms, comments, two-byte samples, and every way a
file can disagree with its header."""

from __future__ import annotations

import numpy as np
import pytest

from tvl_cli.io.pgm import decode_pgm, encode_pgm

LIMIT = 10_000


def test_encode_then_decode_gives_the_pixels_back() -> None:
    pixels = np.arange(12, dtype=np.uint8).reshape(3, 4) * 20
    samples, maxval = decode_pgm(encode_pgm(pixels), LIMIT)
    assert maxval == 255 and np.array_equal(samples, pixels)


def test_the_encoding_is_a_p5_header_then_the_rows_top_first() -> None:
    assert encode_pgm(np.array([[1, 2], [3, 4]], dtype=np.uint8)) == b"P5\n2 2\n255\n\1\2\3\4"


def test_comments_may_stand_between_the_header_numbers() -> None:
    data = b"P5\n# made by hand\n2 # width\n1\n# depth next\n255\n\x10\x20"
    samples, _ = decode_pgm(data, LIMIT)
    assert samples.tolist() == [[16, 32]]


def test_two_byte_samples_are_read_most_significant_first() -> None:
    samples, maxval = decode_pgm(b"P5 2 1 65535\n\x01\x00\xff\xfe", LIMIT)
    assert maxval == 65535 and samples.tolist() == [[256, 65534]]


def test_a_plain_p2_image_reads_as_its_p5_twin() -> None:
    samples, maxval = decode_pgm(b"P2\n3 2\n9\n0 1 2\n# a comment\n3 4 9\n", LIMIT)
    assert maxval == 9 and samples.tolist() == [[0, 1, 2], [3, 4, 9]]


@pytest.mark.parametrize(
    ("data", "reason"),
    [
        (b"P6\n1 1\n255\n\0\0\0", "not a PGM image (it does not start with P5 or P2)"),
        (b"P5\n1\n", "PGM header has no height"),
        (b"P5\n0 1\n255\n", "PGM header gives a size of 0 x 1 pixels"),
        (b"P5\n1 1\n70000\n\0\0", "PGM maxval 70000 is not from 1 to 65535"),
        (b"P5\n1 1\n255", "PGM header does not end in whitespace after the maxval"),
        (b"P5\n2 2\n255\n\0\0\0", "holds 3 bytes of pixels, not the 4 its header's 2 x 2 needs"),
        (
            b"P5\n200 200\n255\n",
            "image is 200 x 200 pixels, over the 10,000 this machine can read (half its memory)",
        ),
        (b"P5\n1 1\n100\n\xc8", "a pixel is 200, above the maxval 100"),
        (b"P2\n2 2\n255\n1 2 3\n", "holds 3 pixels, not the 2 x 2 its header gives"),
        (b"P2\n1 1\n255\n-1\n", "P2 pixels hold something that is not a whole number"),
    ],
)
def test_a_file_that_disagrees_with_its_header_says_how(data: bytes, reason: str) -> None:
    with pytest.raises(ValueError) as refused:
        decode_pgm(data, LIMIT)
    assert str(refused.value) == reason
