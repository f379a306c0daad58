"""Occupancy grid maps as ROS map_server and Nav2 keep them: a YAML file naming an image.

    image: room.pgm            # PGM or PNG, relative to the YAML file
    mode: trinary              # or scale, raw (trinary when absent)
    resolution: 0.05           # metres a pixel
    origin: [-2.0, -1.5, 0.0]  # x, y (m) of the image's bottom-left corner, and a yaw (rad)
    negate: 0
    occupied_thresh: 0.65
    free_thresh: 0.25

A pixel is read as map_server reads it (nav2_map_server's map_io): its shade is the mean of
its red, green and blue (and, in trinary mode, its opacity) from 0 (black) to 1 (white); its
occupancy p is 1 - shade, or the shade itself with `negate`. A cell is occupied where
p > occupied_thresh, free where p < free_thresh, and unknown between. In scale mode a pixel
that is not opaque is unknown. In raw mode the pixel value 0 to 100 is p in percent (any other
value unknown), held to the same thresholds.

Images are stored top row first, so the image's bottom row lies at the origin's y.
"""

from __future__ import annotations

import io
import math
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from tvl_cli.core.errors import BadInput
from tvl_cli.core.text import decoded
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.pgm import decode_pgm, encode_pgm

TRINARY, SCALE, RAW = "trinary", "scale", "raw"
MODES = (TRINARY, SCALE, RAW)
REQUIRED_KEYS = ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh")
MAX_YAML_BYTES = 1 << 16  # a map's YAML is a few lines
# A building mapped at 5 cm a pixel (200 x 200 m); the image file at two bytes a pixel, or
# about four in a plain P2 one.
MAX_IMAGE_PIXELS = 4096 * 4096
MAX_IMAGE_BYTES = 4 * MAX_IMAGE_PIXELS
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

# What map_saver writes in trinary mode, and the thresholds it writes beside them. ROS 1's
# free_thresh 0.196 keeps grey 205 (p = 0.196) unknown when the map is read again; Nav2's
# default of 0.25 would read it as free.
FREE_PIXEL, OCCUPIED_PIXEL, UNKNOWN_PIXEL = 254, 0, 205
SAVED_OCCUPIED_THRESH, SAVED_FREE_THRESH = 0.65, 0.196


@dataclass(frozen=True, slots=True)
class MapYaml:
    """What a map's YAML file says; `image` resolved against the YAML file's folder."""

    path: Path
    image: Path
    resolution_m: float
    origin_x_m: float
    origin_y_m: float
    origin_yaw_rad: float
    occupied_thresh: float
    free_thresh: float
    negate: bool
    mode: str


@dataclass(frozen=True, slots=True, eq=False)
class OccupancyMap:
    """A map read as map_server reads it; arrays (rows, columns), top row first."""

    meta: MapYaml
    free: np.ndarray  # bool
    occupied: np.ndarray  # bool; cells neither free nor occupied are unknown
    # Cells of map_saver's unknown grey that the thresholds read as free (Nav2's default
    # free_thresh of 0.25 does): map_server serves them as free, and so do we, but a user
    # who meant them unknown needs telling.
    unknown_grey_free: int = 0

    @property
    def unknown(self) -> np.ndarray:
        return ~(self.free | self.occupied)


def read_occupancy_map(path: Path) -> OccupancyMap:
    """Read a map's YAML file and its image; BadInput naming the file and what is wrong."""
    meta = read_map_yaml(path)
    sums, channels, maxval, opaque = _read_image(meta)
    free, occupied = _classify(sums, channels, maxval, opaque, meta)
    grey = maxval == 255 and opaque is None and meta.mode == TRINARY
    unknown_grey_free = int((free & (sums == channels * UNKNOWN_PIXEL)).sum()) if grey else 0
    return OccupancyMap(meta, free, occupied, unknown_grey_free)


def read_map_yaml(path: Path) -> MapYaml:
    """The YAML file's keys, checked as map_server checks them."""
    text = _read_bytes(path, MAX_YAML_BYTES, "a map's YAML is a few lines")
    try:
        doc = yaml.safe_load(decoded(text, str(path)))
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f":{mark.line + 1}:{mark.column + 1}" if mark is not None else ""
        problem = getattr(error, "problem", None) or "cannot be parsed"
        raise BadInput(f"{path}{where}: not valid YAML ({problem})") from None
    if not isinstance(doc, dict):
        raise BadInput(f"{path}: not a map_server map (expected {', '.join(REQUIRED_KEYS)})")
    missing = [key for key in REQUIRED_KEYS if key not in doc]
    if missing:
        raise BadInput(
            f"{path}: no {', '.join(repr(k) for k in missing)} "
            f"(a map_server map gives {', '.join(REQUIRED_KEYS)})"
        )
    image = doc["image"]
    if not isinstance(image, str) or not image:
        raise BadInput(f"{path}: 'image' is {image!r}, not the name of an image file")
    resolution = _number(doc["resolution"], "resolution", path)
    if resolution <= 0:
        raise BadInput(f"{path}: 'resolution' is {resolution:g}, not a size in metres above 0")
    origin = doc["origin"]
    if not (isinstance(origin, list) and len(origin) == 3):
        raise BadInput(f"{path}: 'origin' is {origin!r}, not [x, y, yaw]")
    x, y, yaw = (_number(value, "origin", path) for value in origin)
    occupied = _number(doc["occupied_thresh"], "occupied_thresh", path)
    free = _number(doc["free_thresh"], "free_thresh", path)
    if not 0.0 <= free < occupied <= 1.0:
        raise BadInput(
            f"{path}: free_thresh {free:g} and occupied_thresh {occupied:g} are not in order "
            "(0 <= free_thresh < occupied_thresh <= 1)"
        )
    negate = doc["negate"]
    if negate not in (0, 1) or isinstance(negate, float):  # YAML's 0, 1, true and false
        raise BadInput(f"{path}: 'negate' is {negate!r}, not 0 or 1")
    mode = doc.get("mode", TRINARY)
    if mode not in MODES:
        raise BadInput(f"{path}: 'mode' is {mode!r}, not one of {', '.join(MODES)}")
    return MapYaml(
        path=path,
        image=path.parent / image,
        resolution_m=resolution,
        origin_x_m=x,
        origin_y_m=y,
        origin_yaw_rad=yaw,
        occupied_thresh=occupied,
        free_thresh=free,
        negate=bool(negate),
        mode=mode,
    )


def _number(value: Any, key: str, path: Path) -> float:
    # YAML reads `true` as a bool, which Python would count as 1.
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise BadInput(f"{path}: {key!r} holds {value!r}, not a number")
    try:
        number = float(value)
    except OverflowError:  # an integer of hundreds of digits
        number = math.inf
    if not math.isfinite(number):
        raise BadInput(f"{path}: {key!r} holds {value!r}, not a finite number")
    return number


def _read_bytes(path: Path, limit: int, why: str) -> bytes:
    if path.is_dir():
        raise BadInput(f"{path}: is a directory, not a file")
    try:
        with path.open("rb") as file:
            data = file.read(limit + 1)
    except FileNotFoundError:
        raise BadInput(f"{path}: no such file") from None
    except OSError as error:
        raise BadInput(f"{path}: cannot read ({error.strerror})") from None
    if len(data) > limit:
        raise BadInput(f"{path}: file is over {limit:,} bytes ({why})")
    return data


def _read_image(meta: MapYaml) -> tuple[np.ndarray, int, int, np.ndarray | None]:
    """Each pixel's sum over the channels map_server averages, how many channels that is,
    the largest sample, and where the pixel is opaque (None for an image without alpha)."""
    where = meta.image
    data = _read_bytes(where, MAX_IMAGE_BYTES, f"the image of {meta.path}")
    if data.startswith(PNG_SIGNATURE):
        return _png(data, meta)
    try:
        samples, maxval = decode_pgm(data, MAX_IMAGE_PIXELS)
    except ValueError as error:
        raise BadInput(f"{where}: {error}") from None
    return samples, 1, maxval, None  # grey: its red, green and blue are the sample


def _png(data: bytes, meta: MapYaml) -> tuple[np.ndarray, int, int, np.ndarray | None]:
    from PIL import Image  # only for a PNG map

    where = meta.image
    # Pillow's errors for a broken file: its own, the codec's OSError, and the SyntaxError and
    # ValueError of a malformed chunk.
    broken = (OSError, SyntaxError, ValueError, Image.DecompressionBombError)
    try:
        with warnings.catch_warnings():
            # Pillow warns of a large image as it opens; its size is checked here instead.
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            image = Image.open(io.BytesIO(data))
    except broken as error:
        raise BadInput(f"{where}: not a readable PNG image ({error})") from None
    columns, rows = image.size
    if columns * rows > MAX_IMAGE_PIXELS:
        raise BadInput(
            f"{where}: image is {columns} x {rows} pixels, "
            f"over the {MAX_IMAGE_PIXELS:,} this tvl reads"
        )
    try:
        image.load()
    except broken as error:
        raise BadInput(f"{where}: not a readable PNG image ({error})") from None
    if image.mode in ("I;16", "I;16B", "I"):  # 16-bit grey
        return np.asarray(image).astype(np.int64), 1, 65535, None
    has_alpha = image.mode in ("LA", "PA", "RGBA") or "transparency" in image.info
    pixels = np.asarray(image.convert("RGBA" if has_alpha else "RGB"), dtype=np.int64)
    colour = pixels[..., :3].sum(axis=2)  # (rows, columns)
    if not has_alpha:
        return colour, 3, 255, None
    alpha = pixels[..., 3]
    if meta.mode == TRINARY:
        # map_server averages the opacity in with the colour in trinary mode.
        return colour + alpha, 4, 255, alpha == 255
    return colour, 3, 255, alpha == 255


def _classify(
    sums: np.ndarray, channels: int, maxval: int, opaque: np.ndarray | None, meta: MapYaml
) -> tuple[np.ndarray, np.ndarray]:
    """map_server's rule, through a table over every possible channel sum: the arithmetic
    is map_server's own, done once per value rather than once per pixel."""
    levels = np.arange(channels * maxval + 1)
    shade = levels / channels / maxval  # (levels,) 0 black to 1 white
    if meta.mode == RAW:
        percent = np.rint(shade * 255.0)
        occupancy = np.where(percent <= 100.0, percent / 100.0, np.nan)
    else:
        occupancy = shade if meta.negate else 1.0 - shade
    free_table = occupancy < meta.free_thresh  # NaN (raw's unknown) compares False
    occupied_table = occupancy > meta.occupied_thresh
    free, occupied = free_table[sums], occupied_table[sums]
    if meta.mode == SCALE and opaque is not None:
        free &= opaque
        occupied &= opaque
    return free, occupied


def write_occupancy_map(
    path: Path, image: Path, free: np.ndarray, occupied: np.ndarray, resolution_m: float
) -> None:
    """Write a map as map_saver does in trinary mode: the PGM `image` beside the YAML file
    `path`, origin at (0, 0) with no yaw. Each file is written whole or not at all."""
    pixels = np.full(free.shape, UNKNOWN_PIXEL, dtype=np.uint8)  # (rows, columns), top first
    pixels[free] = FREE_PIXEL
    pixels[occupied] = OCCUPIED_PIXEL
    document = {
        "image": image.name,
        "mode": TRINARY,
        "resolution": resolution_m,
        "origin": [0.0, 0.0, 0.0],
        "negate": 0,
        "occupied_thresh": SAVED_OCCUPIED_THRESH,
        "free_thresh": SAVED_FREE_THRESH,
    }
    with atomic_output(image) as temporary:
        temporary.write_bytes(encode_pgm(pixels))
    with atomic_output(path) as temporary:
        # Flow style for the origin only, as map_saver writes it: `origin: [0.0, 0.0, 0.0]`.
        text = yaml.safe_dump(document, sort_keys=False, default_flow_style=None)
        temporary.write_text(text, encoding="utf-8")
