"""ROS map YAML read as ROS reads it (issue 13 B): ``mode: raw`` / ``scale`` and
numbers that YAML 1.1 reads as strings (``resolution: 5e-2``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mrexplore.cli import main
from mrexplore.errors import MapFileError
from mrexplore.grid import load_map


def _p5(pixels: np.ndarray, maxval: int = 255) -> bytes:
    height, width = pixels.shape
    raster = pixels.astype(">u2" if maxval > 255 else np.uint8).tobytes()
    return b"P5\n" + f"{width} {height}\n{maxval}\n".encode() + raster


def _pair(folder: Path, pixels: np.ndarray, yaml_text: str, maxval: int = 255) -> Path:
    (folder / "m.pgm").write_bytes(_p5(pixels, maxval))
    path = folder / "m.yaml"
    path.write_text("image: m.pgm\n" + yaml_text)
    return path


def _raw_room() -> np.ndarray:
    """A raw-mode image: the pixel is the occupancy value (0 free, 100 wall, 255 unknown)."""
    pixels = np.full((9, 10), 255, dtype=np.uint8)  # unknown margin
    pixels[1:8, 1:9] = 100  # walls
    pixels[2:7, 2:8] = 0  # 5 x 6 free room
    return pixels


def _run_json(argv: list[str], capsys: pytest.CaptureFixture[str]) -> dict[str, object]:
    assert main([*argv, "--json"]) == 0, capsys.readouterr().err
    captured = capsys.readouterr()
    assert captured.err == ""
    result: dict[str, object] = json.loads(captured.out)
    return result


# --------------------------------------------------------------------------- raw


def test_raw_mode_is_not_read_inverted(tmp_path: Path) -> None:
    # Before: the trinary rule made the 0-valued room occupied and the 255 margin free.
    grid = load_map(_pair(tmp_path, _raw_room(), "resolution: 0.1\nmode: raw\n"))
    assert grid.meta["mode"] == "raw"
    assert int((~grid.occupied).sum()) == 30
    assert grid.meta["crop"] == [0, 0, 9, 10]  # 255 is unknown, the walls are known
    inside = ~grid.occupied[2:7, 2:8]
    assert inside.all()
    assert grid.occupied[1].all() and grid.occupied[:, 1].all()


def test_raw_mode_values_and_thresholds(tmp_path: Path) -> None:
    pixels = _raw_room()
    pixels[3, 3] = 1  # 1 % occupied is not free
    pixels[4, 4] = 150  # above 100: unknown, not free
    # The thresholds play no part in raw mode (map_server ignores them).
    grid = load_map(_pair(tmp_path, pixels, "resolution: 0.1\nmode: raw\nfree_thresh: 0.5\n"))
    assert int((~grid.occupied).sum()) == 28
    assert grid.occupied[3, 3] and grid.occupied[4, 4]


def test_raw_mode_16_bit_scales_to_8_bits(tmp_path: Path) -> None:
    pixels = _raw_room().astype(np.uint16) * 257  # the same values on 0..65535
    pixels[3, 3] = 128  # round(255 * 128 / 65535) = 0: free
    pixels[4, 4] = 129  # round(0.502) = 1: occupied
    grid = load_map(_pair(tmp_path, pixels, "resolution: 0.1\nmode: raw\n", maxval=65535))
    assert not grid.occupied[3, 3] and grid.occupied[4, 4]
    assert int((~grid.occupied).sum()) == 29


def test_raw_mode_through_the_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _pair(tmp_path, _raw_room(), "resolution: 0.1\nmode: raw\n")
    result = _run_json(["run", "--map", str(path), "--robots", "1", "--max-ticks", "5"], capsys)
    assert result["explorable_cells"] == 30
    assert result["map_shape"] == [9, 10]


def test_raw_mode_with_negate_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _pair(tmp_path, _raw_room(), "resolution: 0.1\nmode: raw\nnegate: 1\n")
    with pytest.raises(MapFileError, match=r"ROS 1 map_server .* Nav2"):
        load_map(path)
    assert main(["run", "--map", str(path), "--robots", "1"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith(f"mrexplore: error: map file {path}: 'negate: 1' with 'mode: raw'")


# --------------------------------------------------------------------------- scale


def test_scale_mode_keeps_in_between_cells_known_and_not_free(tmp_path: Path) -> None:
    pixels = np.full((8, 8), 205, dtype=np.uint8)  # occ = 0.196..: between the thresholds
    pixels[2:6, 2:6] = 0
    pixels[3:5, 3:5] = 254
    trinary = load_map(_pair(tmp_path, pixels, "resolution: 0.1\n"))
    scale = load_map(_pair(tmp_path, pixels, "resolution: 0.1\nmode: scale\n"))
    assert int((~trinary.occupied).sum()) == int((~scale.occupied).sum()) == 4
    assert trinary.meta["crop"] == [1, 1, 7, 7]  # 205 is unknown in trinary mode ...
    assert scale.meta["crop"] == [0, 0, 8, 8]  # ... and a value in 1..99 in scale mode


# --------------------------------------------------------------------------- numbers


def test_exponent_without_a_dot_is_a_number(tmp_path: Path) -> None:
    # Before: "'resolution' must be a number, got '5e-2'" (YAML 1.1 reads it as a string).
    pixels = np.full((6, 7), 0, dtype=np.uint8)
    pixels[1:5, 1:6] = 254
    grid = load_map(
        _pair(
            tmp_path,
            pixels,
            "resolution: 5e-2\norigin: [-1e1, 2E0, 0]\nnegate: 0\n"
            "occupied_thresh: 6.5e-1\nfree_thresh: 1.96e-1\n",
        )
    )
    assert grid.resolution_m == 0.05
    assert grid.meta["origin_in_file"] == [-10.0, 2.0, 0.0]
    assert grid.meta["occupied_thresh"] == 0.65 and grid.meta["free_thresh"] == 0.196
    assert int((~grid.occupied).sum()) == 20


def test_exponent_resolution_through_the_cli(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pixels = np.full((6, 7), 0, dtype=np.uint8)
    pixels[1:5, 1:6] = 254
    path = _pair(tmp_path, pixels, "resolution: 5e-2\norigin: [0, 0, 0]\n")
    argv = ["run", "--map", str(path), "--robots", "1", "--max-ticks", "5", "--sensor-range", "1m"]
    result = _run_json(argv, capsys)
    assert result["map_resolution_m"] == 0.05
    assert result["sensor_range_cells"] == pytest.approx(20.0)


@pytest.mark.parametrize(
    ("yaml_text", "message"),
    [
        ("resolution: 5e-2x\n", "'resolution' must be a number, got '5e-2x'"),
        ("resolution: nan\n", "'resolution' must be a number, got 'nan'"),
        ("resolution: 1e999\n", "'resolution' must be a number"),
        ("resolution: .inf\n", "'resolution' must be a number"),
        ("resolution: '-5e-2'\n", "'resolution' must be positive"),
        ("resolution: 0.05\norigin: [1e1, y, 0]\n", "'origin' must be a list"),
        ("resolution: 0.05\nnegate: '2'\n", "'negate' must be 0 or 1, got '2'"),
        ("resolution: 0.05\nfree_thresh: 2e0\n", "'free_thresh' must be in \\[0, 1\\]"),
    ],
)
def test_bad_numbers_are_still_refused(tmp_path: Path, yaml_text: str, message: str) -> None:
    pixels = np.full((6, 7), 0, dtype=np.uint8)
    pixels[1:5, 1:6] = 254
    with pytest.raises(MapFileError, match=message):
        load_map(_pair(tmp_path, pixels, yaml_text))


def test_negate_as_text_one(tmp_path: Path) -> None:
    pixels = np.full((6, 7), 254, dtype=np.uint8)
    pixels[1:5, 1:6] = 0
    grid = load_map(_pair(tmp_path, pixels, "resolution: 0.5\nnegate: '1'\n"))
    assert grid.meta["negate"] == 1
    assert int((~grid.occupied).sum()) == 20
