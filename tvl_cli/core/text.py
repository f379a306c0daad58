"""Bytes a user gave as text, decoded with one clear refusal: a file that is not text (a
picture, an HDF5 file given where a text file goes) is named as such, with where its first
byte that is not UTF-8 lies, never in the codec's own words."""

from __future__ import annotations

from tvl_cli.core.errors import BadInput


def decoded(data: bytes, where: str, error_type: type[BadInput] = BadInput) -> str:
    """`data` as UTF-8 text (a byte-order mark, which some editors write, tolerated);
    `error_type` naming `where`, the line and column of the first byte that is not UTF-8,
    and that the file is not text."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        column = error.start - (data.rfind(b"\n", 0, error.start) + 1) + 1
        raise error_type(
            f"{where}:{line}:{column}: not a text file (byte 0x{data[error.start]:02x} is not "
            "UTF-8: a binary file, or text in another encoding)"
        ) from None
