"""Read map files into :class:`~mrexplore.grid.occupancy.GridMap`, and write them back.

Supported inputs (chosen by file extension; the formats are described in
``docs/maps.md``):

========================  =====================================================
``.yaml`` / ``.yml``      ROS ``map_server`` YAML plus its image (PGM, PNG, BMP)
``.pgm``                  a bare PGM image (P5 or P2), read with the ROS defaults
``.png`` / ``.bmp``       a bare image, read with the ROS defaults
``.map``                  MovingAI grid benchmark map (unitless cells)
``.json``                 HouseExpo floor plan (polygon in metres)
========================  =====================================================

Conventions:

* Row 0 of the returned grid is the **top** row of the image (or the first text
  line of a MovingAI map); images are *not* flipped.
* Ground truth has no unknown class: every cell that is not confidently free is
  occupied (``GridMap.occupied`` is a bool array, ``True`` = blocked).
* The outer ring of every returned grid is occupied, so a robot can never leave
  it; a one-cell occupied border is added when the file's own edge has a free
  cell (``meta["border_added"]``).
* Image maps are cropped to the bounding box of their known (free or occupied)
  pixels plus a one-cell margin where the image has one (``meta["crop"]`` holds
  ``[row0, col0, row1, col1]`` in image pixels, end exclusive).
* ``meta["origin"]`` (when the map has a resolution) is ``[x, y, yaw]`` of the
  lower-left corner of the **returned** grid, in metres and radians, as in a ROS
  YAML. The centre of cell ``(row, col)`` of an ``H``-row grid with ``yaw = 0``
  is at ``x = origin_x + (col + 0.5) * resolution_m`` and
  ``y = origin_y + (H - 1 - row + 0.5) * resolution_m``.

Every problem with a file raises :class:`~mrexplore.errors.MapFileError` with a
one-line description. Files are parsed with safe readers only (``yaml.safe_load``,
``json.loads``, our own PGM parser, Pillow with a size check before decoding).
"""

from __future__ import annotations

import json
import math
import os
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, BinaryIO, TypeGuard

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MapFileError, ScenarioError
from mrexplore.grid.catalogue import MAP_SUFFIXES, credit_for_file
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, BoolGrid, GridMap

__all__ = [
    "DEFAULT_FREE_THRESH",
    "DEFAULT_OCCUPIED_THRESH",
    "MAX_CELLS",
    "MAX_SIDE",
    "downsample",
    "load_map",
    "read_pgm",
    "resample_to_cell_size",
    "write_map",
]

#: Largest map accepted, in cells; checked from file headers before allocating.
MAX_CELLS = 100_000_000
#: Largest accepted width or height, in cells.
MAX_SIDE = 100_000
#: ROS ``map_server`` default thresholds on the occupancy probability.
DEFAULT_OCCUPIED_THRESH = 0.65
DEFAULT_FREE_THRESH = 0.196

_PGM_HEADER_LIMIT = 64 * 1024  # bytes of header (comments included) we are willing to scan
_PGM_WHITESPACE = frozenset(b" \t\n\r\v\f")
_MAX_POLYGON_VERTS = 100_000
_MAX_RASTER_WORK = 20_000_000  # edge/row crossings or outline samples for one polygon
_ROS_MODES = ("trinary", "scale", "raw")

# --------------------------------------------------------------------------- helpers


def _one_line(text: object, limit: int = 160) -> str:
    """Collapse whitespace so a message stays on one line, and shorten it."""
    flat = " ".join(str(text).split())
    return flat if len(flat) <= limit else flat[: limit - 3] + "..."


def _describe(value: object) -> str:
    """A short, one-line description of a value read from a file.

    Containers are described by type only: a YAML alias bomb would make ``repr``
    explode, and ``repr`` of a huge integer raises ``ValueError``.
    """
    if value is None or isinstance(value, bool | float):
        return repr(value)
    if isinstance(value, int):
        return repr(value) if value.bit_length() <= 64 else "a huge integer"
    if isinstance(value, str):
        return _one_line(repr(value[:70]), 80)
    return f"a {type(value).__name__}"


def _os_problem(exc: OSError) -> str:
    if isinstance(exc, FileNotFoundError):
        return "no such file"
    if isinstance(exc, IsADirectoryError):
        return "is a directory, not a file"
    if isinstance(exc, PermissionError):
        return "permission denied"
    return f"cannot read: {_one_line(exc.strerror or exc)}"


def _count(number: int) -> str:
    """An integer for a message: exact up to 15 digits, else like ``1e+300``."""
    return str(number) if abs(number) < 10**15 else f"{float(number):.3g}"


def _check_size(path: object, width: int, height: int) -> None:
    """Refuse empty or gigantic maps; called before any raster is allocated."""
    if width < 1 or height < 1:
        raise MapFileError(path, f"map size {width}x{height} is empty")
    if width > MAX_SIDE or height > MAX_SIDE or width * height > MAX_CELLS:
        raise MapFileError(
            path,
            f"map size {_count(width)}x{_count(height)} cells is too large "
            f"(limit {MAX_SIDE} per side and {MAX_CELLS} cells)",
        )


def _read_bytes(path: Path) -> bytes:
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MapFileError(path, _os_problem(exc)) from exc
    if not data:
        raise MapFileError(path, "empty file")
    return data


def _read_text(path: Path) -> str:
    data = _read_bytes(path)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise MapFileError(path, f"not UTF-8 text (bad byte at offset {exc.start})") from exc
    if not text.strip():
        raise MapFileError(path, "empty file")
    return text


def _map_name(path: Path) -> str:
    # A generic stem such as "map" says nothing: use the folder's name then.
    if path.stem.lower() == "map" and path.parent.name:
        return path.parent.name
    return path.stem


def _is_number(value: object) -> TypeGuard[int | float]:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _is_finite_number(value: object) -> TypeGuard[int | float]:
    """A real number (not bool) that converts to a finite float (huge ints do not)."""
    if not _is_number(value):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


def _origin_of(meta: Mapping[str, object]) -> list[float] | None:
    """``meta["origin"]`` as ``[x, y, yaw]`` floats, or ``None`` if absent or malformed."""
    origin = meta.get("origin")
    if (
        isinstance(origin, list | tuple)
        and len(origin) == 3
        and all(_is_finite_number(v) for v in origin)
    ):
        return [float(v) for v in origin]
    return None


# --------------------------------------------------------------------------- PGM


class _PgmHeaderReader:
    """Reads the whitespace-separated header numbers of a PGM, skipping comments."""

    def __init__(self, stream: BinaryIO, path: object) -> None:
        self.stream = stream
        self.path = path
        self.consumed = 2  # the magic number has been read
        self.pending = b""  # a byte read ahead, to be handled by the next number()

    def _byte(self) -> bytes:
        byte = self.stream.read(1)
        self.consumed += len(byte)
        if self.consumed > _PGM_HEADER_LIMIT:
            raise MapFileError(self.path, f"PGM header longer than {_PGM_HEADER_LIMIT} bytes")
        return byte

    def first_separator(self) -> None:
        byte = self._byte()
        if byte == b"":
            raise MapFileError(self.path, "truncated PGM header: missing width")
        if byte[0] not in _PGM_WHITESPACE and byte != b"#":
            raise MapFileError(self.path, "bad PGM header: no whitespace after the magic number")
        self.pending = byte

    def number(self, what: str) -> tuple[int, bytes]:
        """Next decimal number, and the byte that ended it (b"" at end of file)."""
        byte = self.pending or self._byte()
        self.pending = b""
        while True:
            if byte == b"":
                raise MapFileError(self.path, f"truncated PGM header: missing {what}")
            if byte == b"#":
                while byte not in (b"\n", b"\r", b""):
                    byte = self._byte()
            elif byte[0] in _PGM_WHITESPACE:
                byte = self._byte()
            else:
                break
        digits = bytearray()
        while byte.isdigit():
            digits += byte
            if len(digits) > 12:
                raise MapFileError(self.path, f"bad PGM header: {what} has too many digits")
            byte = self._byte()
        if not digits:
            raise MapFileError(
                self.path, f"bad PGM header: expected {what} as a decimal number, got {byte!r}"
            )
        if byte != b"" and byte[0] not in _PGM_WHITESPACE and byte != b"#":
            raise MapFileError(self.path, f"bad PGM header: unexpected byte {byte!r} after {what}")
        if byte == b"#":
            self.pending = byte
        return int(digits), byte


def _parse_p2_raster(path: object, data: bytes, count: int, maxval: int) -> npt.NDArray[np.int64]:
    """First ``count`` decimal numbers of an ASCII (P2) raster, vectorised."""
    data = re.sub(rb"#[^\r\n]*", b" ", data)
    buf = np.frombuffer(data, dtype=np.uint8)
    is_digit = (buf >= ord("0")) & (buf <= ord("9"))
    prev_digit = np.concatenate(([False], is_digit[:-1]))
    next_digit = np.concatenate((is_digit[1:], [False]))
    starts = np.flatnonzero(is_digit & ~prev_digit)
    ends = np.flatnonzero(is_digit & ~next_digit)
    if len(starts) < count:
        raise MapFileError(path, f"truncated raster: expected {count} values, got {len(starts)}")
    raster_end = int(ends[count - 1]) + 1 if count else 0
    is_space = np.isin(buf[:raster_end], np.frombuffer(bytes(_PGM_WHITESPACE), dtype=np.uint8))
    bad = ~(is_digit[:raster_end] | is_space)
    if bad.any():
        offset = int(np.argmax(bad))
        raise MapFileError(
            path, f"bad P2 raster: unexpected byte {bytes(buf[offset : offset + 1])!r}"
        )
    starts = starts[:count]
    ends = ends[:count]
    if int((ends - starts).max(initial=0)) >= 9:
        raise MapFileError(path, "bad P2 raster: a value has too many digits")
    digit_pos = np.flatnonzero(is_digit[:raster_end])
    token = np.cumsum(is_digit[:raster_end] & ~prev_digit[:raster_end])[digit_pos] - 1
    place = ends[token] - digit_pos
    weights = (buf[digit_pos].astype(np.int64) - ord("0")) * (10 ** place.astype(np.int64))
    values = np.bincount(token, weights=weights, minlength=count).astype(np.int64)
    if count and int(values.max()) > maxval:
        raise MapFileError(path, f"pixel value {int(values.max())} exceeds MAXVAL {maxval}")
    return values


def _parse_pgm(path: object, stream: BinaryIO) -> tuple[npt.NDArray[np.uint8 | np.uint16], int]:
    magic = stream.read(2)
    if not magic:
        raise MapFileError(path, "empty file")
    if magic not in (b"P5", b"P2"):
        raise MapFileError(path, f"not a PGM file (magic {magic!r}, expected b'P5' or b'P2')")
    header = _PgmHeaderReader(stream, path)
    header.first_separator()
    width, _ = header.number("width")
    height, _ = header.number("height")
    _check_size(path, width, height)
    maxval, end = header.number("MAXVAL")
    if not 1 <= maxval <= 65535:
        raise MapFileError(path, f"bad PGM header: MAXVAL {maxval} is not in 1..65535")
    if end == b"#":
        raise MapFileError(path, "bad PGM header: expected one whitespace byte after MAXVAL")
    count = width * height
    dtype = np.uint8 if maxval < 256 else np.uint16
    if magic == b"P5":
        nbytes = count * (1 if maxval < 256 else 2)
        raw = stream.read(nbytes)
        if len(raw) < nbytes:
            raise MapFileError(path, f"truncated raster: expected {nbytes} bytes, got {len(raw)}")
        if maxval < 256:
            pixels = np.frombuffer(raw, dtype=np.uint8).reshape(height, width).copy()
        else:
            pixels = np.frombuffer(raw, dtype=">u2").reshape(height, width).astype(np.uint16)
        if maxval not in (255, 65535) and int(pixels.max()) > maxval:
            raise MapFileError(path, f"pixel value {int(pixels.max())} exceeds MAXVAL {maxval}")
        return pixels, maxval
    values = _parse_p2_raster(path, stream.read(), count, maxval)
    return values.reshape(height, width).astype(dtype), maxval


def _read_pgm_with_maxval(path: Path) -> tuple[npt.NDArray[np.uint8 | np.uint16], int]:
    try:
        with path.open("rb") as stream:
            return _parse_pgm(path, stream)
    except OSError as exc:
        raise MapFileError(path, _os_problem(exc)) from exc


def read_pgm(path: str | os.PathLike[str]) -> npt.NDArray[np.uint8 | np.uint16]:
    """Read a PGM image (binary P5 or ASCII P2) as an ``H x W`` array of raw pixels.

    Row 0 is the top of the image. The array is ``uint8`` when MAXVAL < 256 and
    ``uint16`` otherwise (16-bit rasters are big-endian on disk). Comments
    (``#`` to end of line) may appear anywhere in the header; bytes after the
    raster are ignored. The header's size is checked against :data:`MAX_CELLS`
    and :data:`MAX_SIDE` before the raster is read.

    Raises:
        MapFileError: the file is missing, unreadable, not a PGM, or truncated.
    """
    return _read_pgm_with_maxval(Path(path))[0]


# --------------------------------------------------------------------------- images


def _read_pillow(path: Path) -> tuple[npt.NDArray[np.uint32], int, int]:
    """Read a PNG or BMP as ``(channel_sum, channel_count, maxval)``; alpha is ignored."""
    from PIL import Image  # here: a run on a generated map reads no image

    try:
        with warnings.catch_warnings():
            # We apply our own limit (MAX_CELLS) before decoding; Pillow's warning
            # threshold is lower than ours. Its hard error (2x that) still applies.
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            with Image.open(path, formats=["PNG", "BMP"]) as img:
                width, height = img.size
                _check_size(path, width, height)
                img.load()
                mode = img.mode
                if mode.startswith("I;16") or mode == "I":
                    grey16 = np.asarray(img).astype(np.int64)
                    if grey16.size and (grey16.min() < 0 or grey16.max() > 65535):
                        raise MapFileError(path, f"pixel values outside 0..65535 in mode {mode}")
                    return grey16.astype(np.uint32), 1, 65535
                if mode in ("1", "L", "LA"):
                    grey = np.asarray(img.convert("L") if mode == "1" else img, dtype=np.uint32)
                    return (grey[..., 0] if grey.ndim == 3 else grey), 1, 255
                # Palette and colour modes: mean of R, G, B (alpha ignored).
                rgb = np.asarray(img if mode in ("RGB", "RGBA") else img.convert("RGB"))
                return rgb[..., :3].astype(np.uint32).sum(axis=2, dtype=np.uint32), 3, 255
    except MapFileError:
        raise
    except Image.DecompressionBombError as exc:
        raise MapFileError(path, f"image too large: {_one_line(exc)}") from exc
    except (FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        raise MapFileError(path, _os_problem(exc)) from exc
    except Image.UnidentifiedImageError as exc:
        raise MapFileError(path, "not a PNG or BMP image") from exc
    except Exception as exc:  # Pillow's decoders raise many types on corrupt input
        raise MapFileError(path, f"cannot decode image: {_one_line(exc)}") from exc


@dataclass(frozen=True)
class _PixelRule:
    """How a ROS map YAML says to read its image's pixels (see :func:`_trinary`)."""

    negate: bool = False
    occupied_thresh: float = DEFAULT_OCCUPIED_THRESH
    free_thresh: float = DEFAULT_FREE_THRESH
    mode: str = "trinary"


def _trinary(
    pixel_sum: npt.NDArray[np.integer], channels: int, maxval: int, rule: _PixelRule
) -> npt.NDArray[np.int8]:
    """The cell classes ROS ``map_server`` gives an image, through a lookup table.

    ``pixel_sum`` is the sum over ``channels`` colour channels, so the pixel value
    is ``pixel_sum / channels``. Returns ``FREE`` / ``OCCUPIED`` / ``UNKNOWN`` (int8):
    ``FREE`` exactly where map_server publishes the occupancy value 0, ``UNKNOWN``
    where it publishes -1, ``OCCUPIED`` for every other value (1..100).

    * ``trinary`` (wiki.ros.org/map_server, "Value Interpretation"): with ``p =
      pixel / MAXVAL`` and ``occ = p`` if ``negate`` else ``1 - p``: ``occ >
      occupied_thresh`` is 100, ``occ < free_thresh`` is 0, the rest -1.
    * ``scale``: the same, except that the cells between the thresholds get a value
      in 1..99 (known, and not free: ``OCCUPIED`` here). map_server also makes
      transparent pixels -1; alpha is ignored here, as in every mode.
    * ``raw``: the pixel *is* the value, ``round(255 p)`` (Nav2
      ``nav2_map_server/src/map_io.cpp``, ``MapMode::Raw``): 0..100 is the value,
      anything above 100 is -1. The thresholds play no part; ``negate`` must be 0
      (checked by the caller). ROS 1 ``map_server/src/image_loader.cpp`` (``RAW``)
      stores the channel mean truncated to ``unsigned char`` instead, which differs
      only for colour pixels whose mean is in [0.5, 1): Nav2's rounding makes them
      1, occupied here.
    """
    levels = np.arange(maxval * channels + 1, dtype=np.float64) / channels
    p = levels / maxval
    lut = np.full(levels.shape, UNKNOWN, dtype=np.int8)
    if rule.mode == "raw":
        value = np.floor(255.0 * p + 0.5)  # std::round on non-negative values
        lut[value <= 100] = OCCUPIED
        lut[value == 0] = FREE
        return lut[pixel_sum]
    occ = p if rule.negate else 1.0 - p
    if rule.mode == "scale":
        lut[:] = OCCUPIED
    lut[occ < rule.free_thresh] = FREE
    lut[occ > rule.occupied_thresh] = OCCUPIED
    return lut[pixel_sum]


def _read_image_states(path: Path, rule: _PixelRule) -> npt.NDArray[np.int8]:
    if path.suffix.lower() in (".pgm", ".pnm"):
        pixels, maxval = _read_pgm_with_maxval(path)
        pixel_sum: npt.NDArray[np.integer] = pixels
        channels = 1
    else:
        pixel_sum, channels, maxval = _read_pillow(path)
    return _trinary(pixel_sum, channels, maxval, rule)


# --------------------------------------------------------------------------- crop / border


def _crop_and_close(
    path: object, states: npt.NDArray[np.int8]
) -> tuple[BoolGrid, tuple[int, int, int, int], int]:
    """Crop to known cells (+1 margin), collapse to bool, close the outer ring.

    Returns ``(occupied, (row0, col0, row1, col1), border)`` where ``border`` is 1
    if a one-cell occupied ring was added, else 0.
    """
    free = states == FREE
    if not free.any():
        raise MapFileError(path, "the map has no free cell")
    known = states != UNKNOWN
    rows = np.flatnonzero(known.any(axis=1))
    cols = np.flatnonzero(known.any(axis=0))
    height, width = states.shape
    row0, row1 = max(int(rows[0]) - 1, 0), min(int(rows[-1]) + 2, height)
    col0, col1 = max(int(cols[0]) - 1, 0), min(int(cols[-1]) + 2, width)
    occupied = ~free[row0:row1, col0:col1]
    edge_free = (
        not occupied[0].all()
        or not occupied[-1].all()
        or not occupied[:, 0].all()
        or not occupied[:, -1].all()
    )
    if edge_free:
        occupied = np.pad(occupied, 1, constant_values=True)
    return np.ascontiguousarray(occupied), (row0, col0, row1, col1), int(edge_free)


def _shift_origin(
    origin: list[float], right_m: float, up_m: float
) -> list[float]:  # moves a map-frame corner by (right, up) metres in the map's own axes
    x, y, yaw = origin
    cos, sin = math.cos(yaw), math.sin(yaw)
    return [x + cos * right_m - sin * up_m, y + sin * right_m + cos * up_m, yaw]


# --------------------------------------------------------------------------- ROS YAML


_NUMERIC_TEXT = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def _yaml_float(value: object) -> float | None:
    """A finite YAML number as a float, or ``None``.

    Strings that spell a decimal number count too: YAML 1.1 (PyYAML) reads
    ``5e-2`` or ``1.0e5`` as strings (its floats need a dot and a signed exponent),
    while ROS (yaml-cpp's ``as<double>()``) reads them as numbers.
    """
    if isinstance(value, str):
        text = value.strip()
        if len(text) > 64 or not _NUMERIC_TEXT.fullmatch(text):
            return None
        number = float(text)
        return number if math.isfinite(number) else None
    return float(value) if _is_finite_number(value) else None


def _yaml_number(path: Path, doc: Mapping[str, object], key: str, default: float | None) -> float:
    if key not in doc:
        if default is None:
            raise MapFileError(path, f"YAML has no {key!r} field")
        return default
    value = doc[key]
    number = _yaml_float(value)
    if number is None:
        raise MapFileError(path, f"{key!r} must be a number, got {_describe(value)}")
    return number


def _resolve_image(yaml_path: Path, image: str) -> Path:
    folder = yaml_path.parent
    candidate = Path(image)
    if candidate.is_absolute():
        if candidate.is_file():
            return candidate
        fallback = folder / candidate.name
        if fallback.is_file():
            return fallback
        raise MapFileError(
            yaml_path, f"image {_describe(image)} not found (also tried {_describe(str(fallback))})"
        )
    resolved = folder / candidate
    if resolved.is_dir():
        raise MapFileError(yaml_path, f"image {_describe(str(resolved))} is a directory")
    if not resolved.is_file():
        raise MapFileError(yaml_path, f"image file {_describe(str(resolved))} not found")
    return resolved


def _load_ros(path: Path) -> GridMap:
    import yaml  # here: a run on a generated map reads no YAML

    text = _read_text(path)
    try:
        doc = yaml.safe_load(text)
    except yaml.MarkedYAMLError as exc:
        line = exc.problem_mark.line + 1 if exc.problem_mark is not None else "?"
        raise MapFileError(
            path, f"YAML syntax error at line {line}: {_one_line(exc.problem)}"
        ) from exc
    except yaml.YAMLError as exc:
        raise MapFileError(path, f"YAML syntax error: {_one_line(exc)}") from exc
    except (ValueError, TypeError, OverflowError, RecursionError) as exc:
        raise MapFileError(path, f"YAML value cannot be read: {_one_line(exc)}") from exc
    if not isinstance(doc, dict):
        raise MapFileError(path, f"YAML is not a mapping (got {type(doc).__name__})")

    image = doc.get("image")
    if not isinstance(image, str) or not image.strip():
        raise MapFileError(path, "'image' must be a non-empty string (the image file name)")
    resolution = _yaml_number(path, doc, "resolution", None)
    if resolution <= 0:
        raise MapFileError(path, f"'resolution' must be positive, got {resolution}")
    origin_raw = doc.get("origin", [0.0, 0.0, 0.0])
    origin_values = [_yaml_float(v) for v in origin_raw] if isinstance(origin_raw, list) else [None]
    if len(origin_values) not in (2, 3) or any(v is None for v in origin_values):
        raise MapFileError(path, "'origin' must be a list of 2 or 3 numbers [x, y, yaw]")
    origin_file = [float(v) for v in origin_values if v is not None]
    origin_file += [0.0] * (3 - len(origin_file))
    negate_raw = doc.get("negate", 0)
    negate_value = None if isinstance(negate_raw, bool) else _yaml_float(negate_raw)
    if isinstance(negate_raw, bool):
        negate = negate_raw
    elif negate_value in (0.0, 1.0):
        negate = bool(negate_value)
    else:
        raise MapFileError(path, f"'negate' must be 0 or 1, got {_describe(negate_raw)}")
    occupied_thresh = _yaml_number(path, doc, "occupied_thresh", DEFAULT_OCCUPIED_THRESH)
    free_thresh = _yaml_number(path, doc, "free_thresh", DEFAULT_FREE_THRESH)
    for key, value in (("occupied_thresh", occupied_thresh), ("free_thresh", free_thresh)):
        if not 0.0 <= value <= 1.0:
            raise MapFileError(path, f"{key!r} must be in [0, 1], got {value}")
    if free_thresh > occupied_thresh:
        raise MapFileError(
            path, f"'free_thresh' {free_thresh} is greater than 'occupied_thresh' {occupied_thresh}"
        )
    mode = doc.get("mode", "trinary")
    if not isinstance(mode, str) or mode not in _ROS_MODES:
        raise MapFileError(
            path, f"'mode' must be one of {', '.join(_ROS_MODES)}, got {_describe(mode)}"
        )
    if mode == "raw" and negate:
        raise MapFileError(
            path,
            "'negate: 1' with 'mode: raw' is read differently by ROS 1 map_server (which "
            "inverts the pixels first) and Nav2 (which ignores negate in raw mode); store "
            "the occupancy values themselves (0 free, 100 occupied) and set negate: 0",
        )

    try:
        image_path = _resolve_image(path, image)
    except MapFileError:  # a ValueError too: let it through unwrapped
        raise
    except (OSError, ValueError) as exc:
        raise MapFileError(
            path, f"cannot access image {_describe(image)}: {_one_line(exc)}"
        ) from exc
    rule = _PixelRule(negate, occupied_thresh, free_thresh, mode)
    states = _read_image_states(image_path, rule)
    occupied, crop, border = _crop_and_close(image_path, states)
    row0, col0, row1, col1 = crop
    image_rows = states.shape[0]
    origin = _shift_origin(
        origin_file, (col0 - border) * resolution, (image_rows - row1 - border) * resolution
    )
    return GridMap(
        occupied=occupied,
        name=_map_name(path),
        resolution_m=resolution,
        source=str(path),
        credit=credit_for_file(path) or credit_for_file(image_path),
        meta={
            "format": "ros",
            "image": str(image_path),
            "origin": origin,
            "origin_in_file": origin_file,
            "negate": int(negate),
            "occupied_thresh": occupied_thresh,
            "free_thresh": free_thresh,
            "mode": mode,
            "crop": [row0, col0, row1, col1],
            "border_added": bool(border),
        },
    )


def _unitless_map(path: Path, occupied: BoolGrid, meta: dict[str, Any]) -> GridMap:
    """The map of a file that gives no cell size (an image, a MovingAI map)."""
    return GridMap(
        occupied=occupied,
        name=_map_name(path),
        resolution_m=None,
        source=str(path),
        credit=credit_for_file(path),
        meta=meta,
    )


def _load_bare_image(path: Path) -> GridMap:
    states = _read_image_states(path, _PixelRule())
    occupied, crop, border = _crop_and_close(path, states)
    return _unitless_map(
        path,
        occupied,
        {
            "format": "image",
            "negate": 0,
            "occupied_thresh": DEFAULT_OCCUPIED_THRESH,
            "free_thresh": DEFAULT_FREE_THRESH,
            "crop": list(crop),
            "border_added": bool(border),
        },
    )


# --------------------------------------------------------------------------- MovingAI

_MOVINGAI_LUT = np.full(256, 2, dtype=np.uint8)  # 0 free, 1 occupied, 2 invalid
_MOVINGAI_LUT[np.frombuffer(b".GS", dtype=np.uint8)] = 0
_MOVINGAI_LUT[np.frombuffer(b"@OTW", dtype=np.uint8)] = 1


def _load_movingai(path: Path) -> GridMap:
    lines = [line.removesuffix("\r") for line in _read_text(path).split("\n")]
    if len(lines) < 4:
        raise MapFileError(path, "truncated header: expected 'type', 'height', 'width', 'map'")
    type_words = lines[0].split()
    if len(type_words) != 2 or type_words[0].lower() != "type":
        raise MapFileError(path, f"line 1: expected 'type octile', got {_one_line(lines[0], 40)!r}")
    sizes: dict[str, int] = {}
    for number in (1, 2):
        words = lines[number].split()
        if (
            len(words) != 2
            or words[0].lower() not in ("height", "width")
            or not words[1].isdigit()
            or not words[1].isascii()
            or len(words[1]) > 12
        ):
            raise MapFileError(
                path,
                f"line {number + 1}: expected 'height H' or 'width W', "
                f"got {_one_line(lines[number], 40)!r}",
            )
        sizes[words[0].lower()] = int(words[1])
    if len(sizes) != 2:
        raise MapFileError(path, "header must give both 'height' and 'width'")
    if lines[3].strip().lower() != "map":
        raise MapFileError(path, f"line 4: expected 'map', got {_one_line(lines[3], 40)!r}")
    height, width = sizes["height"], sizes["width"]
    _check_size(path, width, height)
    body = lines[4:]
    while body and not body[-1].strip():
        body.pop()
    if len(body) != height:
        raise MapFileError(path, f"map has {len(body)} rows, header says {height}")
    for row, text in enumerate(body):
        if len(text) != width:
            raise MapFileError(path, f"row {row} has {len(text)} cells, header says {width}")
    codes = _MOVINGAI_LUT[
        np.frombuffer("".join(body).encode("ascii", errors="replace"), dtype=np.uint8)
    ].reshape(height, width)
    bad = codes == 2
    if bad.any():
        row, col = divmod(int(np.argmax(bad)), width)
        raise MapFileError(
            path, f"row {row}, column {col}: unknown terrain character {body[row][col]!r}"
        )
    states = np.where(codes == 0, FREE, OCCUPIED).astype(np.int8)
    occupied, _crop, border = _crop_and_close(path, states)
    meta = {"format": "movingai", "type": type_words[1], "border_added": bool(border)}
    return _unitless_map(path, occupied, meta)


# --------------------------------------------------------------------------- HouseExpo


def _polygon_vertices(path: Path, doc: object) -> npt.NDArray[np.float64]:
    if not isinstance(doc, dict):
        raise MapFileError(path, f"JSON is not an object (got {type(doc).__name__})")
    verts = doc.get("verts")
    if not isinstance(verts, list):
        raise MapFileError(path, "'verts' must be a list of [x, y] points")
    if len(verts) < 3:
        raise MapFileError(path, f"'verts' has {len(verts)} points, a polygon needs at least 3")
    if len(verts) > _MAX_POLYGON_VERTS:
        raise MapFileError(path, f"'verts' has more than {_MAX_POLYGON_VERTS} points")
    for index, point in enumerate(verts):
        if (
            not isinstance(point, list)
            or len(point) != 2
            or not all(_is_finite_number(v) for v in point)
        ):
            raise MapFileError(
                path, f"verts[{index}] must be [x, y] with two finite numbers (metres)"
            )
    return np.array(verts, dtype=np.float64)


def _rasterise_polygon(path: Path, verts: npt.NDArray[np.float64], cell_m: float) -> BoolGrid:
    """Occupied grid of a polygon: inside free, outline and outside occupied.

    Cell centres are tested with the even-odd rule: every edge is intersected with
    the horizontal lines through the row centres it spans, the crossings of each
    row are paired left to right, and the cells whose centre lies between a pair
    are inside (all vectorised). Cells the outline passes through are walls too,
    so zero-width interior slits become one-cell walls. A one-cell occupied
    border surrounds the result. Row 0 is the maximum y.
    """
    # Python floats: an overflow gives inf quietly instead of a numpy warning.
    x_min, y_min = (float(v) for v in verts.min(axis=0))
    x_max, y_max = (float(v) for v in verts.max(axis=0))
    span_cols = (x_max - x_min) / cell_m
    span_rows = (y_max - y_min) / cell_m
    if not (math.isfinite(span_cols) and math.isfinite(span_rows)):
        raise MapFileError(path, "polygon extent is too large")
    inner_w = max(1, math.ceil(span_cols - 1e-9))
    inner_h = max(1, math.ceil(span_rows - 1e-9))
    _check_size(path, inner_w + 2, inner_h + 2)
    too_complex = f"polygon is too complex to rasterise at {cell_m} m per cell"

    x1, y1 = verts[:, 0], verts[:, 1]
    x2, y2 = np.roll(x1, -1), np.roll(y1, -1)
    # Candidate rows of each edge (one row of slack each side, filtered exactly below).
    low, high = np.minimum(y1, y2), np.maximum(y1, y2)
    first = np.clip(np.floor((y_max - high) / cell_m - 0.5), 0, inner_h - 1).astype(np.int64)
    last = np.clip(np.floor((y_max - low) / cell_m - 0.5) + 1, 0, inner_h - 1).astype(np.int64)
    counts = np.where(high > low, last - first + 1, 0)
    total = int(counts.sum())
    if total > _MAX_RASTER_WORK:
        raise MapFileError(path, too_complex)
    edge = np.repeat(np.arange(len(x1)), counts)
    rows = first[edge] + np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    centre_y = y_max - (rows + 0.5) * cell_m
    crosses = (y1[edge] > centre_y) != (y2[edge] > centre_y)  # the exact per-row test
    edge, rows, centre_y = edge[crosses], rows[crosses], centre_y[crosses]
    xs = x1[edge] + (centre_y - y1[edge]) * (x2[edge] - x1[edge]) / (y2[edge] - y1[edge])
    order = np.lexsort((xs, rows))  # every row has an even number of crossings
    rows, xs = rows[order], xs[order]
    start = np.clip(np.ceil((xs[0::2] - x_min) / cell_m - 0.5), 0, inner_w).astype(np.int64)
    stop = np.clip(np.ceil((xs[1::2] - x_min) / cell_m - 0.5), 0, inner_w).astype(np.int64)
    change = np.zeros((inner_h, inner_w + 1), dtype=np.int8)
    np.add.at(change, (rows[0::2], start), 1)
    np.add.at(change, (rows[0::2], stop), -1)
    inside = np.cumsum(change[:, :inner_w], axis=1, dtype=np.int8) > 0

    # Outline: sample every edge at a quarter of a cell and mark the cells hit.
    lengths = np.hypot(x2 - x1, y2 - y1)
    samples = np.ceil(lengths / (0.25 * cell_m)).astype(np.int64) + 2
    if int(samples.sum()) > _MAX_RASTER_WORK:
        raise MapFileError(path, too_complex)
    edge = np.repeat(np.arange(len(x1)), samples)
    offsets = np.arange(int(samples.sum())) - np.repeat(np.cumsum(samples) - samples, samples)
    t = offsets / np.repeat(samples - 1, samples)
    px = x1[edge] + t * (x2[edge] - x1[edge])
    py = y1[edge] + t * (y2[edge] - y1[edge])
    cols = np.clip(np.floor((px - x_min) / cell_m).astype(np.int64), 0, inner_w - 1)
    rows = np.clip(np.floor((y_max - py) / cell_m).astype(np.int64), 0, inner_h - 1)
    inside[rows, cols] = False
    return np.pad(~inside, 1, constant_values=True)


def _load_houseexpo(path: Path, cell_m: float) -> GridMap:
    text = _read_text(path)
    try:
        doc = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise MapFileError(path, f"bad JSON: {_one_line(exc)}") from exc
    verts = _polygon_vertices(path, doc)
    occupied = _rasterise_polygon(path, verts, cell_m)
    if occupied.all():
        raise MapFileError(path, "the map has no free cell (polygon smaller than a cell?)")
    # Lower-left corner of the raster: one border cell left of x_min, and one border
    # cell below the last of the rows counted down from y_max.
    origin = [
        float(verts[:, 0].min()) - cell_m,
        float(verts[:, 1].max()) - (occupied.shape[0] - 1) * cell_m,
        0.0,
    ]
    return GridMap(
        occupied=occupied,
        name=_map_name(path),
        resolution_m=cell_m,
        source=str(path),
        credit="HouseExpo (TeaganLi/HouseExpo, MIT)",
        meta={"format": "houseexpo", "origin": origin, "border_added": True},
    )


# --------------------------------------------------------------------------- public API


def _positive_metres(name: str, value: object) -> float:
    if not _is_finite_number(value) or value <= 0:
        raise ScenarioError(f"{name} must be a positive number of metres, got {value!r}")
    return float(value)


def load_map(
    path: str | os.PathLike[str],
    *,
    cell_size_m: float | None = None,
    houseexpo_cell_m: float = 0.1,
) -> GridMap:
    """Load a map file as ground truth (``True`` = occupied, row 0 = top).

    The format follows the extension: ``.yaml``/``.yml`` (ROS ``map_server``),
    ``.pgm``, ``.png``, ``.bmp`` (bare image: negate 0, thresholds 0.65 / 0.196,
    no resolution), ``.map`` (MovingAI) and ``.json`` (HouseExpo polygon).

    ROS images are read as ``map_server`` reads them, on ``p = pixel / MAXVAL``
    (colour: mean of the colour channels, alpha ignored), and a cell is free
    exactly where map_server would publish the occupancy value 0; every other
    cell (100, 1..99, unknown) is occupied. ``mode: trinary`` (the default) and
    ``mode: scale`` apply ``negate`` and the two thresholds (map_server's rule);
    ``mode: raw`` takes the pixel as the value itself (0 free, 1..100 occupied,
    above 100 unknown; Nav2's rule) and refuses ``negate: 1``, on which ROS 1 and
    Nav2 disagree. Numeric fields may be written as strings such as ``5e-2``
    (valid YAML numbers for ROS; strings for YAML 1.1).

    Args:
        path: the map file.
        cell_size_m: metres per cell wanted. A map with a resolution is pooled to
            ``round(cell_size_m / resolution)`` times coarser cells with
            :func:`downsample` (a coarse cell is occupied if any fine cell is);
            the resulting resolution is that factor times the map's, which may
            differ from ``cell_size_m`` by up to half a map cell. Finer cells than
            the map's are refused. A unitless map (MovingAI, bare image) takes
            ``cell_size_m`` as its resolution.
        houseexpo_cell_m: metres per cell used to rasterise a HouseExpo polygon.

    Returns:
        The map, with ``name`` (file stem), ``resolution_m``, ``source`` (the
        path), ``credit`` (for the maps of :mod:`mrexplore.grid.catalogue`) and ``meta``.

    Raises:
        MapFileError: the file is missing, unreadable, malformed or too large.
        ScenarioError: ``cell_size_m`` or ``houseexpo_cell_m`` is not positive.
    """
    map_path = Path(path)
    if cell_size_m is not None:
        cell_size_m = _positive_metres("cell_size_m", cell_size_m)
    houseexpo_cell_m = _positive_metres("houseexpo_cell_m", houseexpo_cell_m)
    try:
        is_dir, exists = map_path.is_dir(), map_path.exists()
    except (OSError, ValueError) as exc:
        raise MapFileError(map_path, f"cannot access: {_one_line(exc)}") from exc
    if is_dir:
        raise MapFileError(map_path, "is a directory, not a map file")
    if not exists:
        raise MapFileError(map_path, "no such file")
    suffix = map_path.suffix.lower()
    if suffix in (".yaml", ".yml"):
        grid_map = _load_ros(map_path)
    elif suffix in (".pgm", ".png", ".bmp"):
        grid_map = _load_bare_image(map_path)
    elif suffix == ".map":
        grid_map = _load_movingai(map_path)
    elif suffix == ".json":
        grid_map = _load_houseexpo(map_path, houseexpo_cell_m)
    else:
        raise MapFileError(
            map_path,
            f"unsupported map format {suffix or '(no extension)'!r}; "
            f"expected one of {', '.join(MAP_SUFFIXES)}",
        )
    if cell_size_m is None:
        return grid_map
    if grid_map.resolution_m is None:
        return replace(grid_map, resolution_m=cell_size_m)
    if cell_size_m < grid_map.resolution_m * (1 - 1e-6):
        raise MapFileError(
            map_path,
            f"cell size {cell_size_m} m is finer than the map's resolution "
            f"{grid_map.resolution_m} m; only coarser cells are supported",
        )
    return resample_to_cell_size(grid_map, cell_size_m)


def downsample(grid_map: GridMap, factor: int) -> GridMap:
    """A ``factor`` times coarser map that never loses a wall.

    A coarse cell covers a ``factor x factor`` block of fine cells and is occupied
    if **any** of them is. The grid is padded with occupied cells at the bottom
    and right to a multiple of ``factor``. ``resolution_m`` (if known) is
    multiplied by ``factor``; ``meta["origin"]`` follows the lower-left corner and
    ``meta["downsample_factor"]`` accumulates. Narrow free passages (narrower than
    a coarse cell) may close.

    Raises:
        ScenarioError: ``factor`` is not a positive integer.

    >>> import numpy as np
    >>> fine = GridMap(np.eye(4, dtype=bool))
    >>> downsample(fine, 2).occupied.tolist()
    [[True, False], [False, True]]
    """
    if isinstance(factor, bool) or not isinstance(factor, int | np.integer) or factor < 1:
        raise ScenarioError(f"downsample factor must be a positive integer, got {factor!r}")
    factor = int(factor)
    if factor == 1:
        return grid_map
    occupied = np.asarray(grid_map.occupied, dtype=bool)
    height = occupied.shape[0]
    coarse_h = -(-height // factor)
    coarse: BoolGrid = _pool_any(occupied, factor)
    meta = dict(grid_map.meta)
    previous = meta.get("downsample_factor", 1)
    meta["downsample_factor"] = (previous if isinstance(previous, int) else 1) * factor
    resolution = grid_map.resolution_m
    origin = _origin_of(meta)
    if resolution is not None and origin is not None:
        meta["origin"] = _shift_origin(origin, 0.0, -(coarse_h * factor - height) * resolution)
    return replace(
        grid_map,
        occupied=coarse,
        resolution_m=None if resolution is None else resolution * factor,
        meta=meta,
    )


def _pool_any(occupied: BoolGrid, factor: int) -> BoolGrid:
    """``factor x factor`` blocks pooled with ``any``; partial blocks at the bottom and
    right count as occupied (as if padded with walls).

    Only the full blocks are reshaped (views of the input), so whatever the factor,
    no array larger than the input is allocated.
    """
    height, width = occupied.shape
    full_h, full_w = height // factor, width // factor
    coarse = np.ones((-(-height // factor), -(-width // factor)), dtype=bool)
    if full_h and full_w:
        block = occupied[: full_h * factor, : full_w * factor]
        rows = block.reshape(full_h, factor, full_w * factor).any(axis=1)
        coarse[:full_h, :full_w] = rows.reshape(full_h, full_w, factor).any(axis=2)
    return coarse


def resample_to_cell_size(grid_map: GridMap, cell_size_m: float) -> GridMap:
    """Pool a map to cells of about ``cell_size_m`` metres with :func:`downsample`.

    The factor is ``round(cell_size_m / resolution_m)``; the new resolution is that
    factor times the old one.

    Raises:
        ScenarioError: the map has no resolution, or ``cell_size_m`` is not
            positive or finer than the map's resolution.
    """
    cell_size_m = _positive_metres("cell_size_m", cell_size_m)
    resolution = grid_map.resolution_m
    if resolution is None:
        raise ScenarioError(f"map {grid_map.name!r} has no resolution to resample from")
    ratio = cell_size_m / resolution
    if ratio < 1 - 1e-6:
        raise ScenarioError(
            f"cell size {cell_size_m} m is finer than the map's resolution {resolution} m; "
            "only coarser cells are supported"
        )
    return downsample(grid_map, max(1, round(ratio)))


def write_map(grid_map: GridMap, yaml_path: str | os.PathLike[str]) -> Path:
    """Write a map as a ROS ``map_server`` pair: ``<stem>.pgm`` next to ``yaml_path``.

    Missing parent folders are created.

    The PGM is 8-bit P5 with 254 = free and 0 = occupied, row 0 at the top. The
    YAML gives the image's relative name, the map's resolution (1.0 as a
    placeholder when it has none, noted in a comment), ``meta["origin"]`` if
    present (else ``[0, 0, 0]``), ``negate: 0``, thresholds 0.65 / 0.196 and
    ``mode: trinary``. :func:`load_map` reads the same ``occupied`` array back
    when the map's outer ring is occupied (as every loaded or generated map's is).

    Returns:
        The YAML path.

    Raises:
        MapFileError: ``yaml_path`` does not end in ``.yaml``/``.yml``, or a file
            cannot be written.
    """
    yaml_file = Path(yaml_path)
    if yaml_file.suffix.lower() not in (".yaml", ".yml"):
        raise MapFileError(yaml_file, "output file name must end in .yaml or .yml")
    pgm_file = yaml_file.with_suffix(".pgm")
    occupied = np.asarray(grid_map.occupied, dtype=bool)
    height, width = occupied.shape
    pixels = np.where(occupied, 0, 254).astype(np.uint8)
    header = f"P5\n# CREATOR: mrexplore write_map\n{width} {height}\n255\n".encode("ascii")

    resolution = grid_map.resolution_m
    origin = _origin_of(grid_map.meta) if resolution is not None else None
    fields = {
        "image": pgm_file.name,
        "resolution": float(resolution) if resolution is not None else 1.0,
        "origin": origin or [0.0, 0.0, 0.0],
        "negate": 0,
        "occupied_thresh": DEFAULT_OCCUPIED_THRESH,
        "free_thresh": DEFAULT_FREE_THRESH,
        "mode": "trinary",
    }
    comments = [f"# Written by mrexplore.grid.io.write_map from {_one_line(grid_map.source)}"]
    if grid_map.credit:
        comments.append(f"# Credit: {_one_line(grid_map.credit, 300)}")
    if resolution is None:
        comments.append("# The source map has no resolution: 1.0 m/cell is a placeholder.")
    import yaml  # here, as in _load_ros

    text = "\n".join(comments) + "\n" + yaml.safe_dump(fields, sort_keys=False)
    try:
        yaml_file.parent.mkdir(parents=True, exist_ok=True)
        pgm_file.write_bytes(header + pixels.tobytes())
        yaml_file.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise MapFileError(yaml_file, f"cannot write: {_one_line(exc.strerror or exc)}") from exc
    return yaml_file
