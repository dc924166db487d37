"""Fuzzing the map readers: whatever the bytes, only MapFileError escapes load_map."""

from __future__ import annotations

import io
import json
import struct
import tempfile
import time
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from mrexplore.errors import MapFileError, MrexploreInputError
from mrexplore.grid import GridMap, load_map

# --------------------------------------------------------------------------- valid seeds


def _room_pixels() -> np.ndarray:
    pixels = np.zeros((6, 8), dtype=np.uint8)
    pixels[1:5, 1:7] = 254
    pixels[2, 3] = 205
    return pixels


def _p5(pixels: np.ndarray) -> bytes:
    height, width = pixels.shape
    return f"P5\n# comment\n{width} {height}\n255\n".encode() + pixels.tobytes()


def _p2(pixels: np.ndarray) -> bytes:
    height, width = pixels.shape
    rows = "\n".join(" ".join(str(v) for v in row) for row in pixels)
    return f"P2\n{width} {height}\n255\n{rows}\n".encode()


def _p5_16(pixels: np.ndarray) -> bytes:
    height, width = pixels.shape
    wide = (pixels.astype(np.uint32) * 257).astype(">u2")
    return f"P5\n{width} {height}\n65535\n".encode() + wide.tobytes()


def _image_bytes(pixels: np.ndarray, fmt: str) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(pixels).save(buffer, format=fmt)
    return buffer.getvalue()


def _png_with_size(width: int, height: int) -> bytes:
    """A PNG whose (valid, CRC-checked) header announces any size, with no pixel data."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)

    def chunk(kind: bytes, body: bytes) -> bytes:
        return (
            struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
        )

    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IEND", b"")


MOVINGAI = b"type octile\r\nheight 4\r\nwidth 5\r\nmap\r\n@@@@@\r\n@..T@\r\n@.@.@\r\n@@@@@\r\n"
HOUSEEXPO = json.dumps(
    {"id": "x", "room_num": 1, "verts": [[0, 0], [3, 0], [3, 2], [1.5, 2], [1.5, 3], [0, 3]]}
).encode()
YAML = b"image: img.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n" + (
    b"occupied_thresh: 0.65\nfree_thresh: 0.196\n"
)

SEEDS: list[tuple[str, bytes]] = [
    (".pgm", _p5(_room_pixels())),
    (".pgm", _p2(_room_pixels())),
    (".pgm", _p5_16(_room_pixels())),
    (".png", _image_bytes(_room_pixels(), "PNG")),
    (".bmp", _image_bytes(_room_pixels(), "BMP")),
    (".map", MOVINGAI),
    (".json", HOUSEEXPO),
    (".yaml", YAML),
]
EXTENSIONS = sorted({ext for ext, _ in SEEDS})


def test_seeds_are_valid() -> None:
    for ext, data in SEEDS:
        grid_map = _load(ext, data)
        assert isinstance(grid_map, GridMap), ext


# --------------------------------------------------------------------------- harness


def _load(ext: str, data: bytes, image: bytes | None = None) -> GridMap | MapFileError:
    """Write ``data`` (and the YAML's image) to a fresh folder and load it."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"map{ext}"
        path.write_bytes(data)
        (Path(folder) / "img.pgm").write_bytes(image if image is not None else _p5(_room_pixels()))
        try:
            grid_map = load_map(path)
        except MapFileError as exc:
            message = str(exc)
            assert message.startswith("map file ") and "\n" not in message
            assert len(message) < 600
            return exc
    occupied = grid_map.occupied
    assert occupied.dtype == bool and occupied.ndim == 2
    assert occupied[0].all() and occupied[-1].all()
    assert occupied[:, 0].all() and occupied[:, -1].all()
    assert not occupied.all()
    return grid_map


@st.composite
def _mutated(draw: st.DrawFn) -> tuple[str, bytes]:
    ext, data = draw(st.sampled_from(SEEDS))
    buffer = bytearray(data)
    for _ in range(draw(st.integers(min_value=1, max_value=4))):
        operation = draw(st.sampled_from(["truncate", "flip", "insert", "delete", "splice"]))
        position = draw(st.integers(min_value=0, max_value=max(len(buffer) - 1, 0)))
        if operation == "truncate":
            del buffer[position:]
        elif operation == "flip" and buffer:
            buffer[position] = draw(st.integers(min_value=0, max_value=255))
        elif operation == "insert":
            buffer[position:position] = draw(st.binary(min_size=1, max_size=8))
        elif operation == "delete":
            del buffer[position : position + draw(st.integers(min_value=1, max_value=8))]
        else:  # copy a run of bytes from elsewhere, which keeps text plausible
            start = draw(st.integers(min_value=0, max_value=max(len(data) - 1, 0)))
            buffer[position:position] = data[start : start + 12]
    return ext, bytes(buffer)


_SIZES = st.one_of(
    st.integers(min_value=0, max_value=12),
    st.integers(min_value=0, max_value=10**12),
    st.sampled_from([99_999_999, 100_000, 100_001, 10_000 * 10_001, 2**31, 2**32 - 1]),
)


@st.composite
def _sized_headers(draw: st.DrawFn) -> tuple[str, bytes]:
    """Valid-looking headers announcing random, often gigantic, sizes."""
    width, height = draw(_SIZES), draw(_SIZES)
    kind = draw(st.sampled_from(["p5", "p2", "map", "png", "json"]))
    raster = draw(st.binary(max_size=64))
    if kind == "p5":
        maxval = draw(st.sampled_from([1, 255, 256, 65535, 65536, 0]))
        return ".pgm", f"P5 {width}\n{height} {maxval}\n".encode() + raster
    if kind == "p2":
        return ".pgm", f"P2\n{width} {height}\n255\n".encode() + b" 1" * len(raster)
    if kind == "map":
        rows = b"\n".join(b"." * min(width, 40) for _ in range(min(height, 40)))
        return ".map", f"type octile\nheight {height}\nwidth {width}\nmap\n".encode() + rows
    if kind == "png":
        if width >= 2**31 or height >= 2**31:
            width, height = width % 2**31, height % 2**31
        return ".png", _png_with_size(width, height) + raster
    scale = draw(st.sampled_from([1e-3, 1.0, 1e3, 1e6, 1e300]))
    verts = [[0, 0], [width * scale, 0], [width * scale, height * scale], [0, height * scale]]
    return ".json", json.dumps({"verts": verts}).encode()


_YAML_VALUES = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
    st.lists(st.floats(min_value=-10, max_value=10), max_size=4),
)


@st.composite
def _yaml_documents(draw: st.DrawFn) -> tuple[str, bytes]:
    """YAML maps with random values for the known keys, as flow-style text."""
    fields = {
        "image": draw(st.one_of(st.just("img.pgm"), _YAML_VALUES)),
        "resolution": draw(st.one_of(st.just(0.05), _YAML_VALUES)),
        "origin": draw(st.one_of(st.just([0, 0, 0]), _YAML_VALUES)),
        "negate": draw(st.one_of(st.just(0), _YAML_VALUES)),
        "occupied_thresh": draw(st.one_of(st.just(0.65), _YAML_VALUES)),
        "free_thresh": draw(st.one_of(st.just(0.196), _YAML_VALUES)),
        "mode": draw(st.one_of(st.just("trinary"), _YAML_VALUES)),
    }
    keep = draw(st.lists(st.sampled_from(sorted(fields)), unique=True, min_size=1))
    return ".yaml", json.dumps({key: fields[key] for key in keep}).encode()  # JSON is YAML


# --------------------------------------------------------------------------- properties

FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FUZZ
@given(case=_mutated())
def test_mutated_files_raise_only_map_file_error(case: tuple[str, bytes]) -> None:
    _load(*case)


@FUZZ
@given(image=_mutated().filter(lambda case: case[0] == ".pgm").map(lambda case: case[1]))
def test_yaml_with_mutated_image_raises_only_map_file_error(image: bytes) -> None:
    _load(".yaml", YAML, image=image)


@FUZZ
@given(case=_sized_headers())
def test_random_header_sizes_are_handled_quickly(case: tuple[str, bytes]) -> None:
    start = time.perf_counter()
    _load(*case)
    assert time.perf_counter() - start < 2.0


@FUZZ
@given(case=_yaml_documents())
def test_random_yaml_fields_raise_only_map_file_error(case: tuple[str, bytes]) -> None:
    _load(*case)


@FUZZ
@given(
    ext=st.sampled_from(EXTENSIONS),
    data=st.one_of(
        st.binary(max_size=200),
        st.text(max_size=200).map(lambda text: text.encode("utf-8", "surrogatepass")),
        st.text(alphabet="P25 \n#0123456789.@TGSOW{}[]:,-x", max_size=200).map(str.encode),
    ),
)
def test_random_bytes_raise_only_map_file_error(ext: str, data: bytes) -> None:
    _load(ext, data)


# --------------------------------------------------------------------------- gigantic headers


@pytest.mark.parametrize(
    ("ext", "data"),
    [
        (".pgm", b"P5\n99999999 99999999\n255\n\x00\x00\x00"),
        (".pgm", b"P2\n99999999 99999999\n255\n1 2 3"),
        (".pgm", b"P5\n10001 10000\n255\n"),
        (".map", b"type octile\nheight 99999999\nwidth 99999999\nmap\n....\n"),
        (".png", _png_with_size(99_999, 99_999)),
        (".png", _png_with_size(2**31 - 1, 2**31 - 1)),
        (".json", json.dumps({"verts": [[0, 0], [1e7, 0], [1e7, 1e7], [0, 1e7]]}).encode()),
    ],
)
def test_gigantic_headers_are_refused_quickly(ext: str, data: bytes) -> None:
    start = time.perf_counter()
    with pytest.raises(MapFileError, match="too large") as info:
        _load_raising(ext, data)
    assert time.perf_counter() - start < 1.0
    assert isinstance(info.value, MrexploreInputError)
    assert any(char.isdigit() for char in info.value.problem), "the message gives the size"


def _load_raising(ext: str, data: bytes) -> GridMap:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"map{ext}"
        path.write_bytes(data)
        return load_map(path)
