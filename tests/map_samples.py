"""Occupancy grid maps written byte for byte as ROS map_saver writes them, for the import and
export tests: a PGM of 254 free, 0 occupied and 205 unknown pixels, and its YAML file."""

from __future__ import annotations

from pathlib import Path

import numpy as np

FREE, OCCUPIED, UNKNOWN = 254, 0, 205
NAV2_FREE_THRESH = 0.25  # what Nav2's map_saver writes
ROS1_FREE_THRESH = 0.196  # what ROS 1's map_saver writes

# A 2.0 x 1.5 m room mapped at 5 cm: walls one pixel thick round 38 x 28 free pixels, a
# 0.2 m square block in it, and 205 unknown all round beyond the walls, as SLAM leaves it.
RESOLUTION_M = 0.05
ORIGIN = (-1.0, -2.0, 0.0)
ROWS, COLUMNS = 40, 50  # the image
ROOM_TOP, ROOM_LEFT, ROOM_ROWS, ROOM_COLUMNS = 5, 6, 30, 40  # the walls' outer box, pixels
BLOCK_TOP, BLOCK_LEFT, BLOCK_SIZE = 20, 30, 4  # the block, pixels


def room_pixels() -> np.ndarray:
    """The room's (rows, columns) uint8 pixels, top row first."""
    pixels = np.full((ROWS, COLUMNS), UNKNOWN, dtype=np.uint8)
    bottom, right = ROOM_TOP + ROOM_ROWS, ROOM_LEFT + ROOM_COLUMNS
    pixels[ROOM_TOP:bottom, ROOM_LEFT:right] = OCCUPIED
    pixels[ROOM_TOP + 1 : bottom - 1, ROOM_LEFT + 1 : right - 1] = FREE
    block = (slice(BLOCK_TOP, BLOCK_TOP + BLOCK_SIZE), slice(BLOCK_LEFT, BLOCK_LEFT + BLOCK_SIZE))
    pixels[block] = OCCUPIED
    return pixels


def pgm_bytes(pixels: np.ndarray) -> bytes:
    """A P5 image as ROS 1's map_saver writes it, its comment and all."""
    rows, columns = pixels.shape
    header = f"P5\n# CREATOR: map_saver.cpp {RESOLUTION_M:.3f} m/pix\n{columns} {rows}\n255\n"
    return header.encode() + pixels.tobytes()


def yaml_text(image_name: str, free_thresh: float = NAV2_FREE_THRESH, **changes: object) -> str:
    """The YAML file map_saver writes beside the image; `changes` replace or add keys (None
    removes one)."""
    keys: dict[str, object] = {
        "image": image_name,
        "mode": "trinary",
        "resolution": RESOLUTION_M,
        "origin": "[{:g}, {:g}, {:g}]".format(*ORIGIN),
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": free_thresh,
    }
    keys.update(changes)
    return "".join(f"{key}: {value}\n" for key, value in keys.items() if value is not None)


def write_map(
    directory: Path,
    pixels: np.ndarray | None = None,
    free_thresh: float = NAV2_FREE_THRESH,
    name: str = "room",
    **changes: object,
) -> Path:
    """The room (or `pixels`) as `name`.pgm and `name`.yaml in `directory`; the YAML's path."""
    image = directory / f"{name}.pgm"
    image.write_bytes(pgm_bytes(room_pixels() if pixels is None else pixels))
    path = directory / f"{name}.yaml"
    path.write_text(yaml_text(image.name, free_thresh, **changes))
    return path


def map_frame_of_pixel(row: int, column: int) -> tuple[float, float]:
    """The map-frame centre (x, y) of an image pixel, its rows counted from the top."""
    x = ORIGIN[0] + (column + 0.5) * RESOLUTION_M
    y = ORIGIN[1] + (ROWS - row - 0.5) * RESOLUTION_M
    return x, y
