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

import hashlib
import io
import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from tvl_cli.core.errors import BadInput
from tvl_cli.core.text import decoded
from tvl_cli.io.atomic import atomic_output
from tvl_cli.io.pgm import decode_pgm, encode_pgm, over_pixels

TRINARY, SCALE, RAW = "trinary", "scale", "raw"
MODES = (TRINARY, SCALE, RAW)
REQUIRED_KEYS = ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh")
MAX_YAML_BYTES = 1 << 16  # a map's YAML is a few lines
# The longest image name a YAML file may give: a path of several folders (Linux allows 4,096
# bytes in all, 255 a name).
MAX_IMAGE_NAME = 1024
# Nesting a map's YAML never needs: its origin is a list in a mapping, three levels.
MAX_YAML_DEPTH = 20
# A value quoted in an error message is cut to this many characters.
_QUOTED_CHARS = 60
# An image file's bytes a pixel at most: two in a 16-bit P5, about four in a plain P2 one.
IMAGE_BYTES_PER_PIXEL = 4
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

# What map_saver writes in trinary mode, and the thresholds it writes beside them. ROS 1's
# free_thresh 0.196 keeps grey 205 (p = 0.196) unknown when the map is read again; Nav2's
# default of 0.25 would read it as free.
FREE_PIXEL, OCCUPIED_PIXEL, UNKNOWN_PIXEL = 254, 0, 205
# The name of an exported image of its own: its map's name, then 16 hex digits of its hash.
_OWN_IMAGE = re.compile(r".+\.[0-9a-f]{16}\.pgm")
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


def read_occupancy_map(path: Path, max_pixels: int) -> OccupancyMap:
    """Read a map's YAML file and its image, of at most `max_pixels` (what the machine can
    hold); BadInput naming the file and what is wrong."""
    meta = read_map_yaml(path)
    sums, channels, maxval, opaque = _read_image(meta, max_pixels)
    free, occupied = _classify(sums, channels, maxval, opaque, meta)
    grey = maxval == 255 and opaque is None and meta.mode == TRINARY
    unknown_grey_free = int((free & (sums == channels * UNKNOWN_PIXEL)).sum()) if grey else 0
    return OccupancyMap(meta, free, occupied, unknown_grey_free)


def read_map_yaml(path: Path) -> MapYaml:
    """The YAML file's keys, checked as map_server checks them."""
    text = _read_bytes(path, MAX_YAML_BYTES, "a map's YAML is a few lines")
    try:
        doc = yaml.load(decoded(text, str(path)), Loader=_MapYamlLoader)
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
    if not (isinstance(image, str) and 0 < len(image) <= MAX_IMAGE_NAME and image.isprintable()):
        raise BadInput(f"{path}: 'image' is {_shown(image)}, not the name of an image file")
    resolution = _number(doc["resolution"], "resolution", path)
    if resolution <= 0:
        raise BadInput(f"{path}: 'resolution' is {resolution:g}, not a size in metres above 0")
    origin = doc["origin"]
    if not (isinstance(origin, list) and len(origin) == 3):
        raise BadInput(f"{path}: 'origin' is {_shown(origin)}, not [x, y, yaw]")
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
        raise BadInput(f"{path}: 'negate' is {_shown(negate)}, not 0 or 1")
    mode = doc.get("mode", TRINARY)
    if mode not in MODES:
        raise BadInput(f"{path}: 'mode' is {_shown(mode)}, not one of {', '.join(MODES)}")
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


class _MapYamlLoader(yaml.SafeLoader):
    """PyYAML's safe loader, refusing what no map's YAML holds and what could make reading
    one run away: an alias (`*name`, which a "billion laughs" file nests to build more data
    than a machine holds from a few lines), and nesting deeper than MAX_YAML_DEPTH (which
    would exhaust Python's recursion in the composer)."""

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            mark = self.peek_event().start_mark
            raise yaml.composer.ComposerError(
                None, None, "an alias (*name): a map's YAML repeats nothing", mark
            )
        if self._depth >= MAX_YAML_DEPTH:
            mark = self.peek_event().start_mark
            raise yaml.composer.ComposerError(
                None, None, f"nested deeper than {MAX_YAML_DEPTH} levels", mark
            )
        self._depth += 1
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


def _shown(value: Any) -> str:
    """A value as a message quotes it: its repr, cut short."""
    text = repr(value)
    return text if len(text) <= _QUOTED_CHARS else f"{text[: _QUOTED_CHARS - 3]}..."


def _number(value: Any, key: str, path: Path) -> float:
    # YAML reads `true` as a bool, which Python would count as 1.
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise BadInput(f"{path}: {key!r} holds {_shown(value)}, not a number")
    try:
        number = float(value)
    except OverflowError:  # an integer of hundreds of digits
        number = math.inf
    if not math.isfinite(number):
        raise BadInput(f"{path}: {key!r} holds {_shown(value)}, not a finite number")
    return number


def _read_bytes(path: Path, limit: int, why: str) -> bytes:
    try:
        if path.is_dir():
            raise BadInput(f"{path}: is a directory, not a file")
        with path.open("rb") as file:
            data = file.read(limit + 1)
    except FileNotFoundError:
        raise BadInput(f"{path}: no such file") from None
    except OSError as error:
        raise BadInput(f"{path}: cannot read ({error.strerror})") from None
    if len(data) > limit:
        raise BadInput(f"{path}: file is over {limit:,} bytes ({why})")
    return data


def _read_image(meta: MapYaml, max_pixels: int) -> tuple[np.ndarray, int, int, np.ndarray | None]:
    """Each pixel's sum over the channels map_server averages, how many channels that is,
    the largest sample, and where the pixel is opaque (None for an image without alpha)."""
    where = meta.image
    limit = IMAGE_BYTES_PER_PIXEL * max_pixels
    data = _read_bytes(where, limit, f"the image of {meta.path}, {max_pixels:,} pixels at most")
    if data.startswith(PNG_SIGNATURE):
        return _png(data, meta, max_pixels)
    try:
        samples, maxval = decode_pgm(data, max_pixels)
    except ValueError as error:
        raise BadInput(f"{where}: {error}") from None
    return samples, 1, maxval, None  # grey: its red, green and blue are the sample


def _png(
    data: bytes, meta: MapYaml, max_pixels: int
) -> tuple[np.ndarray, int, int, np.ndarray | None]:
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
    if columns * rows > max_pixels:
        raise BadInput(f"{where}: {over_pixels(columns, rows, max_pixels)}")
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
    path: Path,
    image: Path,
    free: np.ndarray,
    occupied: np.ndarray,
    resolution_m: float,
    origin_m: tuple[float, float],
) -> None:
    """Write a map as map_saver does in trinary mode: the PGM `image` beside the YAML file
    `path`, its bottom-left corner at origin_m with no yaw.

    The two are written as one: at no moment does the YAML file name an image other than
    its own, so a reader (or a kill) finds the old map whole or the new one whole. The new
    image is first written under a name of its own, its content's hash (`NAME.<hash>.pgm`),
    and the YAML renamed into place naming it; then the image takes its usual name and the
    YAML is renamed again naming that; then the image of its own goes. A kill in between
    leaves a whole new map that names the image of its own."""
    pixels = np.full(free.shape, UNKNOWN_PIXEL, dtype=np.uint8)  # (rows, columns), top first
    pixels[free] = FREE_PIXEL
    pixels[occupied] = OCCUPIED_PIXEL
    data = encode_pgm(pixels)
    own = image.with_name(f"{image.stem}.{hashlib.sha256(data).hexdigest()[:16]}.pgm")
    named_before = _image_named_by(path)
    try:
        _write_bytes(own, data)
        _write_yaml(path, own, resolution_m, origin_m)
    except BaseException:
        if named_before != own:
            own.unlink(missing_ok=True)
        raise
    _write_bytes(image, data)
    _write_yaml(path, image, resolution_m, origin_m)
    own.unlink(missing_ok=True)
    if named_before is not None and _OWN_IMAGE.fullmatch(named_before.name):
        # The image of its own that an export killed midway left the map naming.
        named_before.unlink(missing_ok=True)


def _write_bytes(path: Path, data: bytes) -> None:
    with atomic_output(path) as temporary:
        temporary.write_bytes(data)


def _write_yaml(
    path: Path, image: Path, resolution_m: float, origin_m: tuple[float, float]
) -> None:
    document = {
        "image": image.name,
        "mode": TRINARY,
        "resolution": resolution_m,
        "origin": [origin_m[0], origin_m[1], 0.0],
        "negate": 0,
        "occupied_thresh": SAVED_OCCUPIED_THRESH,
        "free_thresh": SAVED_FREE_THRESH,
    }
    with atomic_output(path) as temporary:
        # Flow style for the origin only, as map_saver writes it: `origin: [0.0, 0.0, 0.0]`.
        text = yaml.safe_dump(document, sort_keys=False, default_flow_style=None)
        temporary.write_text(text, encoding="utf-8")


def _image_named_by(path: Path) -> Path | None:
    """The image an existing map's YAML file names, or None (no map there, or no image
    named in it that can be made out)."""
    try:
        return read_map_yaml(path).image
    except BadInput:
        return None
