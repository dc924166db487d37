"""Map readers and writer: the shipped real maps, tiny hand-written files, round trips."""

from __future__ import annotations

import hashlib
import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from PIL import Image

from mrexplore.errors import MapFileError, MrexploreInputError, ScenarioError
from mrexplore.grid import (
    GridMap,
    downsample,
    free_component_of,
    generate_map,
    largest_free_component,
    load_map,
    resample_to_cell_size,
    write_map,
)
from mrexplore.grid.catalogue import CATALOGUE, MapEntry, lookup
from mrexplore.grid.io import read_pgm

ROS = [entry for entry in CATALOGUE if entry.kind == "ros"]


def _entry(name: str) -> MapEntry:
    entry = lookup(name)
    assert entry is not None, f"{name} is not in the catalogue"
    return entry


def _border_occupied(occupied: np.ndarray) -> bool:
    return bool(
        occupied[0].all() and occupied[-1].all() and occupied[:, 0].all() and occupied[:, -1].all()
    )


def _write(path: Path, data: bytes | str) -> Path:
    if isinstance(data, str):
        data = data.encode()
    path.write_bytes(data)
    return path


def _p5(pixels: np.ndarray, *, maxval: int = 255, header_extra: bytes = b"") -> bytes:
    height, width = pixels.shape
    raster = pixels.astype(">u2" if maxval > 255 else np.uint8).tobytes()
    return b"P5\n" + header_extra + f"{width} {height}\n{maxval}\n".encode() + raster


def _image_window(grid_map: GridMap) -> tuple[slice, slice, tuple[slice, slice]]:
    """Image slices of the crop and the matching slices of the grid."""
    crop = grid_map.meta["crop"]
    assert isinstance(crop, list)
    row0, col0, row1, col1 = (int(v) for v in crop)
    border = int(bool(grid_map.meta["border_added"]))
    grid = (
        slice(border, border + row1 - row0),
        slice(border, border + col1 - col0),
    )
    return slice(row0, row1), slice(col0, col1), grid


def _ros_pixels(grid_map: GridMap) -> np.ndarray:
    """The pixels of a ROS map's image (the shipped maps store theirs as 8-bit PNG)."""
    with Image.open(Path(str(grid_map.meta["image"]))) as image:
        assert image.mode == "L", f"{grid_map.meta['image']}: mode {image.mode}, not 8-bit grey"
        return np.asarray(image)


# --------------------------------------------------------------------------- shipped maps


@pytest.mark.parametrize("entry", CATALOGUE, ids=[entry.name for entry in CATALOGUE])
def test_catalogue_map_loads_sensibly(entry: MapEntry) -> None:
    grid_map = load_map(entry.path)
    occupied = grid_map.occupied
    assert occupied.dtype == bool and occupied.ndim == 2
    assert _border_occupied(occupied)
    largest = int(largest_free_component(occupied).sum())
    if entry.name == "lse-arena":
        assert largest > 100
    else:
        assert largest >= 500
        assert largest >= 0.05 * occupied.size
    assert grid_map.credit, "every catalogue map has a credit line"
    assert grid_map.credit == entry.credit
    assert grid_map.source == str(entry.path)
    assert grid_map.name == entry.name
    if entry.kind == "ros":
        assert grid_map.resolution_m is not None and grid_map.resolution_m > 0
    else:
        assert grid_map.resolution_m is None


@pytest.mark.parametrize("entry", ROS, ids=[entry.name for entry in ROS])
def test_ros_maps_follow_the_trinary_rule(entry: MapEntry) -> None:
    """Inside the crop, a cell is free iff 1 - pixel/255 < free_thresh (negate 0)."""
    grid_map = load_map(entry.path)
    assert grid_map.meta["negate"] == 0
    image = _ros_pixels(grid_map)
    free_thresh = float(grid_map.meta["free_thresh"])  # type: ignore[arg-type]
    rows, cols, grid = _image_window(grid_map)
    expected_free = (1.0 - image[rows, cols] / 255.0) < free_thresh
    np.testing.assert_array_equal(~grid_map.occupied[grid], expected_free)


@pytest.mark.parametrize("entry", ROS, ids=[entry.name for entry in ROS])
def test_ros_map_as_original_pgm_loads_the_same(tmp_path: Path, entry: MapEntry) -> None:
    """The shipped PNG written back as a PGM under the source's file name (the AWS map
    as ``aws_small_house/map.pgm``) reads, through the PGM reader, to the same grid,
    and a generic stem such as ``map`` takes its folder's name. Credit follows the
    bytes: the copy has it only where our PGM header happens to equal the original's
    (depot), not where the original carries a GIMP comment."""
    shipped = load_map(entry.path)
    folder = tmp_path / "aws_small_house" if entry.name == "aws-small-house" else tmp_path
    folder.mkdir(exist_ok=True)
    pgm = _write(folder / entry.source_file, _p5(_ros_pixels(shipped)))
    np.testing.assert_array_equal(read_pgm(pgm), _ros_pixels(shipped))
    yaml_lines = [
        f"image: {pgm.name}" if line.startswith("image:") else line
        for line in entry.path.read_text().splitlines()
    ]
    copy = load_map(_write(pgm.with_suffix(".yaml"), "\n".join(yaml_lines) + "\n"))
    np.testing.assert_array_equal(copy.occupied, shipped.occupied)
    assert copy.resolution_m == shipped.resolution_m
    assert copy.meta["origin"] == shipped.meta["origin"]
    assert copy.meta["crop"] == shipped.meta["crop"]
    same_bytes = hashlib.sha256(pgm.read_bytes()).hexdigest() == entry.source_sha256
    assert copy.credit == (entry.credit if same_bytes else "")
    assert load_map(pgm).credit == copy.credit
    expected_name = "aws_small_house" if entry.name == "aws-small-house" else pgm.stem
    assert copy.name == expected_name


def test_intel_unknown_205_is_occupied_and_254_free() -> None:
    grid_map = load_map(_entry("intel").path)
    image = _ros_pixels(grid_map)
    rows, cols, grid = _image_window(grid_map)
    window, cells = image[rows, cols], grid_map.occupied[grid]
    assert set(np.unique(image).tolist()) <= {0, 205, 254}
    assert (window == 205).any()
    assert cells[window == 205].all()
    assert cells[window == 0].all()
    assert not cells[window == 254].any()
    assert grid_map.meta["crop"] != [0, 0, image.shape[0], image.shape[1]], "unknown margin cropped"


def test_lse_arena_239_is_free() -> None:
    grid_map = load_map(_entry("lse-arena").path)
    image = _ros_pixels(grid_map)
    rows, cols, grid = _image_window(grid_map)
    window, cells = image[rows, cols], grid_map.occupied[grid]
    assert (window == 239).any()
    assert not cells[window == 239].any()
    assert cells[window == 0].all()


@pytest.mark.parametrize("name", ["willow-full", "willow-2010"])
def test_willow_grey_walls_are_occupied(name: str) -> None:
    grid_map = load_map(_entry(name).path)
    image = _ros_pixels(grid_map)
    rows, cols, grid = _image_window(grid_map)
    window, cells = image[rows, cols], grid_map.occupied[grid]
    grey = (window > 0) & (window < 205)
    assert grey.any()
    assert cells[grey].all()
    np.testing.assert_array_equal(cells, window <= 205)


def test_movingai_catalogue_map_matches_its_text() -> None:
    path = _entry("Berlin_1_256").path
    assert b"\r\n" in path.read_bytes()
    grid_map = load_map(path)
    text_rows = path.read_text().splitlines()[4:]
    expected = np.array([[ch != "." for ch in row] for row in text_rows])
    border = int(bool(grid_map.meta["border_added"]))
    inner = grid_map.occupied[border : border + 256, border : border + 256]
    np.testing.assert_array_equal(inner, expected)


def test_catalogue_map_resampled_to_coarser_cells() -> None:
    path = _entry("lse-arena").path
    fine = load_map(path)
    coarse = load_map(path, cell_size_m=0.1)
    assert coarse.resolution_m == pytest.approx(0.1)
    assert coarse.shape == (math.ceil(fine.shape[0] / 2), math.ceil(fine.shape[1] / 2))
    with pytest.raises(MapFileError, match="finer"):
        load_map(path, cell_size_m=0.01)


# --------------------------------------------------------------------------- PGM


def test_read_pgm_p5_with_comments_everywhere(tmp_path: Path) -> None:
    data = b"P5# right after the magic\n# a line\n3 # width\n# more\n2\n#max\n255\n" + bytes(
        [0, 128, 255, 1, 2, 3]
    )
    pixels = read_pgm(_write(tmp_path / "a.pgm", data))
    assert pixels.dtype == np.uint8
    assert pixels.tolist() == [[0, 128, 255], [1, 2, 3]]


def test_read_pgm_p2_and_trailing_garbage(tmp_path: Path) -> None:
    data = b"P2\n# CREATOR: hand\n3 2\n# comment\n15\n0 15 7\n 3\n\t2 1 trailing garbage\n"
    pixels = read_pgm(_write(tmp_path / "a.pgm", data))
    assert pixels.tolist() == [[0, 15, 7], [3, 2, 1]]
    p5 = _p5(np.array([[1, 2]], dtype=np.uint8)) + b"GARBAGE"
    assert read_pgm(_write(tmp_path / "b.pgm", p5)).tolist() == [[1, 2]]


def test_read_pgm_16_bit_is_big_endian(tmp_path: Path) -> None:
    pixels = np.array([[0, 256, 65535]], dtype=np.uint16)
    read = read_pgm(_write(tmp_path / "a.pgm", _p5(pixels, maxval=65535)))
    assert read.dtype == np.uint16
    assert read.tolist() == [[0, 256, 65535]]


def test_16_bit_pgm_uses_p_equals_pixel_over_maxval(tmp_path: Path) -> None:
    # 1000: occ 0.98 -> occupied; 60000: occ 0.08 -> free; 40000: occ 0.39 -> unknown.
    pixels = np.full((5, 5), 1000, dtype=np.uint16)
    pixels[1:4, 1:4] = 60000
    pixels[2, 2] = 40000
    grid_map = load_map(_write(tmp_path / "m.pgm", _p5(pixels, maxval=65535)))
    np.testing.assert_array_equal(grid_map.occupied, pixels != 60000)


def test_pgm_errors_are_specific(tmp_path: Path) -> None:
    cases = {
        b"": "empty file",
        b"P6\n1 1\n255\n\x00": "not a PGM",
        b"P5\n2 2\n255\n\x00": "truncated raster: expected 4 bytes, got 1",
        b"P5\n2 2\n": "truncated PGM header: missing MAXVAL",
        b"P5\nx 2\n255\n": "expected width",
        b"P5\n2 2\n0\n": "MAXVAL 0",
        b"P5\n2 2\n70000\n": "MAXVAL 70000",
        b"P2\n2 2\n255\n1 2 3": "truncated raster: expected 4 values, got 3",
        b"P2\n2 1\n7\n1 9": "exceeds MAXVAL",
        b"P5\n0 5\n255\n": "empty",
    }
    for number, (data, message) in enumerate(cases.items()):
        with pytest.raises(MapFileError, match=message):
            read_pgm(_write(tmp_path / f"bad{number}.pgm", data))


def test_gigantic_pgm_header_is_refused_before_allocating(tmp_path: Path) -> None:
    path = _write(tmp_path / "huge.pgm", b"P5\n99999999 99999999\n255\n\x00\x00")
    with pytest.raises(MapFileError, match="99999999x99999999 cells is too large"):
        load_map(path)
    path = _write(tmp_path / "wide.pgm", b"P5\n100001 1\n255\n")
    with pytest.raises(MapFileError, match="too large"):
        load_map(path)


def test_bare_pgm_crops_unknown_margin_and_closes_border(tmp_path: Path) -> None:
    pixels = np.full((8, 10), 205, dtype=np.uint8)  # unknown everywhere
    pixels[3:6, 2:8] = 254  # a free patch touching nothing occupied
    pixels[3, 2] = 0
    grid_map = load_map(_write(tmp_path / "patch.pgm", _p5(pixels)))
    # crop = known bbox (rows 3..5, cols 2..7) plus a one-cell margin of unknown
    assert grid_map.meta["crop"] == [2, 1, 7, 9]
    assert grid_map.meta["border_added"] is False
    assert grid_map.shape == (5, 8)
    assert _border_occupied(grid_map.occupied)
    assert grid_map.occupied[1, 1]  # the 0 pixel
    assert (~grid_map.occupied).sum() == 17


def test_free_cells_on_the_image_edge_get_a_border(tmp_path: Path) -> None:
    pixels = np.full((3, 4), 254, dtype=np.uint8)
    grid_map = load_map(_write(tmp_path / "open.pgm", _p5(pixels)))
    assert grid_map.meta["border_added"] is True
    assert grid_map.shape == (5, 6)
    assert _border_occupied(grid_map.occupied)
    assert (~grid_map.occupied).sum() == 12


# --------------------------------------------------------------------------- ROS YAML


def _ros_pair(folder: Path, pixels: np.ndarray, yaml_text: str, name: str = "m") -> Path:
    _write(folder / f"{name}.pgm", _p5(pixels))
    return _write(folder / f"{name}.yaml", yaml_text)


def _room(inside: int = 254, wall: int = 0) -> np.ndarray:
    pixels = np.full((6, 7), wall, dtype=np.uint8)
    pixels[1:5, 1:6] = inside
    return pixels


def test_yaml_negate_swaps_black_and_white(tmp_path: Path) -> None:
    yaml_text = "image: m.pgm\nresolution: 0.5\norigin: [1.0, 2.0, 0.0]\nnegate: 1\n"
    grid_map = load_map(_ros_pair(tmp_path, _room(inside=0, wall=254), yaml_text))
    assert (~grid_map.occupied).sum() == 20
    assert grid_map.meta["negate"] == 1
    grid_map = load_map(
        _ros_pair(tmp_path, _room(inside=0, wall=254), yaml_text.replace("1\n", "true\n"))
    )
    assert (~grid_map.occupied).sum() == 20


def test_yaml_custom_thresholds(tmp_path: Path) -> None:
    pixels = _room(inside=150)  # occ = 1 - 150/255 = 0.41: unknown with the defaults
    pixels[1, 1] = 254
    base = "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
    default = load_map(_ros_pair(tmp_path, pixels, base + "free_thresh: 0.196\n"))
    assert (~default.occupied).sum() == 1
    loose = load_map(_ros_pair(tmp_path, pixels, base + "free_thresh: 0.5\noccupied_thresh: 0.9\n"))
    assert (~loose.occupied).sum() == 20
    assert loose.meta["free_thresh"] == 0.5
    assert loose.meta["occupied_thresh"] == 0.9
    with pytest.raises(MapFileError, match="no free cell"):
        load_map(_ros_pair(tmp_path, pixels, base + "free_thresh: 0.0\n"))


def test_yaml_relative_image_in_subfolder_and_origin(tmp_path: Path) -> None:
    (tmp_path / "img").mkdir()
    _write(tmp_path / "img" / "pic.pgm", _p5(_room()))
    yaml_path = _write(
        tmp_path / "m.yml",
        "image: img/pic.pgm\nresolution: 0.5\norigin: [1.0, 2.0]\nmode: scale\n",
    )
    grid_map = load_map(yaml_path)
    assert grid_map.resolution_m == 0.5
    assert grid_map.meta["origin"] == [1.0, 2.0, 0.0]  # the whole image is known: no crop
    assert grid_map.name == "m"
    assert (~grid_map.occupied).sum() == 20


def test_yaml_absolute_image_falls_back_to_basename(tmp_path: Path) -> None:
    _write(tmp_path / "map_office_raw.pgm", _p5(_room()))
    yaml_path = _write(
        tmp_path / "office.yaml",
        "image: /home/someone/maps/map_office_raw.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n",
    )
    assert (~load_map(yaml_path).occupied).sum() == 20
    absolute = _write(
        tmp_path / "abs.yaml",
        f"image: {tmp_path / 'map_office_raw.pgm'}\nresolution: 0.05\norigin: [0, 0, 0]\n",
    )
    assert (~load_map(absolute).occupied).sum() == 20


def test_yaml_crop_moves_the_origin(tmp_path: Path) -> None:
    pixels = np.full((10, 12), 205, dtype=np.uint8)
    pixels[4:7, 5:9] = 254  # known block: rows 4..6, cols 5..8
    yaml_path = _ros_pair(tmp_path, pixels, "image: m.pgm\nresolution: 0.5\norigin: [-1, -2, 0]\n")
    grid_map = load_map(yaml_path)
    assert grid_map.meta["crop"] == [3, 4, 8, 10]
    # lower-left corner of the crop: column 4 -> x = -1 + 4 * 0.5; bottom row 7 of 10 -> 2 rows up
    assert grid_map.meta["origin"] == pytest.approx([1.0, -1.0, 0.0])


@pytest.mark.parametrize(
    ("yaml_text", "message"),
    [
        ("image: 5\nresolution: 0.05\n", "'image' must be a non-empty string"),
        ("resolution: 0.05\n", "'image' must be"),
        ("image: m.pgm\nresolution: abc\n", "'resolution' must be a number, got 'abc'"),
        ("image: m.pgm\nresolution: true\n", "'resolution' must be a number"),
        ("image: m.pgm\nresolution: -1\n", "'resolution' must be positive"),
        ("image: m.pgm\n", "YAML has no 'resolution' field"),
        ("image: m.pgm\nresolution: 0.05\norigin: [1]\n", "'origin' must be a list"),
        ("image: m.pgm\nresolution: 0.05\norigin: [a, b, c]\n", "'origin' must be a list"),
        ("image: m.pgm\nresolution: 0.05\nnegate: 2\n", "'negate' must be 0 or 1, got 2"),
        ("image: m.pgm\nresolution: 0.05\noccupied_thresh: 1.5\n", "must be in \\[0, 1\\]"),
        ("image: m.pgm\nresolution: 0.05\nfree_thresh: [1]\n", "got a list"),
        ("image: m.pgm\nresolution: 0.05\nfree_thresh: 0.9\n", "greater than 'occupied_thresh'"),
        ("image: m.pgm\nresolution: 0.05\nmode: fancy\n", "'mode' must be one of"),
        ("image: none.pgm\nresolution: 0.05\n", "image file .* not found"),
        ("image: /nowhere/none.pgm\nresolution: 0.05\n", "not found \\(also tried"),
        ("image: sub\nresolution: 0.05\n", "is a directory"),
        ("- 1\n- 2\n", "YAML is not a mapping \\(got list\\)"),
        ("image: [unclosed\n", "YAML syntax error at line"),
        ("a: !!python/object:os.system x\n", "YAML syntax error"),
        ("   \n", "empty file"),
        ("resolution: 0x" + "f" * 5000 + "\nimage: m.pgm\n", "got a huge integer"),
    ],
)
def test_yaml_errors_are_specific(tmp_path: Path, yaml_text: str, message: str) -> None:
    _write(tmp_path / "m.pgm", _p5(_room()))
    (tmp_path / "sub").mkdir()
    path = _write(tmp_path / "m.yaml", yaml_text)
    with pytest.raises(MapFileError, match=message) as info:
        load_map(path)
    assert "\n" not in str(info.value)
    assert str(info.value).startswith(f"map file {path}")


def test_non_utf8_yaml(tmp_path: Path) -> None:
    with pytest.raises(MapFileError, match="not UTF-8"):
        load_map(_write(tmp_path / "m.yaml", b"image: \xff\xfe.pgm\n"))


def test_file_level_errors(tmp_path: Path) -> None:
    with pytest.raises(MapFileError, match="no such file"):
        load_map(tmp_path / "missing.yaml")
    with pytest.raises(MapFileError, match="is a directory"):
        load_map(tmp_path)
    with pytest.raises(MapFileError, match=r"unsupported map format '\.txt'"):
        load_map(_write(tmp_path / "m.txt", "hello"))
    with pytest.raises(MapFileError, match="empty file"):
        load_map(_write(tmp_path / "m.map", b""))
    if os.name == "posix" and os.geteuid() != 0:
        locked = _write(tmp_path / "locked.map", "type octile\n")
        locked.chmod(0)
        with pytest.raises(MapFileError, match="permission denied"):
            load_map(locked)
    with pytest.raises(ScenarioError, match="cell_size_m"):
        load_map(tmp_path / "missing.yaml", cell_size_m=-1.0)


# --------------------------------------------------------------------------- MovingAI

MOVINGAI = "type octile\nheight 4\nwidth 5\nmap\n@@@@@\n@.GS@\n@TOW@\n@@@@@\n"


def test_movingai_reads_terrain_and_crlf(tmp_path: Path) -> None:
    for name, text in (("lf.map", MOVINGAI), ("crlf.map", MOVINGAI.replace("\n", "\r\n"))):
        grid_map = load_map(_write(tmp_path / name, text))
        assert grid_map.occupied.tolist() == [
            [True] * 5,
            [True, False, False, False, True],
            [True] * 5,
            [True] * 5,
        ]
        assert grid_map.resolution_m is None
        assert grid_map.meta["border_added"] is False


def test_movingai_open_edge_gets_border_and_cell_size(tmp_path: Path) -> None:
    text = "type octile\nheight 2\nwidth 3\nmap\n...\n.@.\n"
    grid_map = load_map(_write(tmp_path / "open.map", text), cell_size_m=0.5)
    assert grid_map.shape == (4, 5)
    assert grid_map.resolution_m == 0.5
    assert _border_occupied(grid_map.occupied)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (MOVINGAI.replace("@.GS@\n", ""), "map has 3 rows, header says 4"),
        (MOVINGAI + "@@@@@\n", "map has 5 rows, header says 4"),
        (MOVINGAI.replace("@.GS@", "@.GS"), "row 1 has 4 cells, header says 5"),
        (MOVINGAI.replace("@TOW@", "@TOW@@"), "row 2 has 6 cells, header says 5"),
        (MOVINGAI.replace("@.GS@", "@.x.@"), "row 1, column 2: unknown terrain character 'x'"),
        (MOVINGAI.replace("@.GS@", "@.é.@"), "row 1, column 2: unknown terrain character 'é'"),
        (MOVINGAI.replace("height 4", "height four"), "line 2: expected 'height H'"),
        (MOVINGAI.replace("map\n", "grid\n"), "line 4: expected 'map'"),
        (MOVINGAI.replace("type octile", "octile"), "line 1: expected 'type octile'"),
        ("type octile\nheight 4\n", "truncated header"),
        (MOVINGAI.replace("height 4", "height 99999999"), "too large"),
        ("type octile\nheight 3\nwidth 3\nmap\n@@@\n@@@\n@@@\n", "no free cell"),
    ],
)
def test_movingai_errors_are_specific(tmp_path: Path, text: str, message: str) -> None:
    with pytest.raises(MapFileError, match=message):
        load_map(_write(tmp_path / "bad.map", text))


# --------------------------------------------------------------------------- HouseExpo


def _houseexpo(verts: list[list[float]] | list[list[int]]) -> str:
    return json.dumps({"id": "test", "room_num": 1, "verts": verts})


def test_houseexpo_square_with_slit(tmp_path: Path) -> None:
    # 10 m x 10 m square; a zero-width wall goes up from the bottom edge at x = 5 to y = 6.
    verts = [[0, 0], [5, 0], [5, 6], [5, 0], [10, 0], [10, 10], [0, 10]]
    path = _write(tmp_path / "house.json", _houseexpo(verts))
    grid_map = load_map(path, houseexpo_cell_m=0.5)
    occupied = grid_map.occupied
    assert grid_map.resolution_m == 0.5
    assert occupied.shape == (22, 22)  # 20 x 20 cells plus the border
    assert _border_occupied(occupied)
    # The slit: column of x = 5 m is interior column 10 -> grid column 11; y in [0, 6] m
    # is interior rows 8..19 -> grid rows 9..20.
    assert occupied[9:21, 11].all()
    assert not occupied[5, 11]  # above the slit tip the room is open
    left, right = (17, 5), (17, 16)
    assert not occupied[left] and not occupied[right]
    both = free_component_of(occupied, [left, right])
    assert both.sum() == (~occupied).sum(), "the two halves connect above the slit"
    assert grid_map.meta["origin"] == pytest.approx([-0.5, -0.5, 0.0])


def test_houseexpo_l_shape_area(tmp_path: Path) -> None:
    verts = [[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]]
    grid_map = load_map(_write(tmp_path / "l.json", _houseexpo(verts)), houseexpo_cell_m=0.1)
    free = int((~grid_map.occupied).sum())
    assert 0.8 * 1200 < free <= 1200  # 12 m^2 at 0.01 m^2 per cell, minus the outline cells


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("{", "bad JSON"),
        ("[1, 2]", "JSON is not an object"),
        ('{"verts": 5}', "'verts' must be a list"),
        ('{"verts": [[0, 0], [1, 1]]}', "at least 3"),
        ('{"verts": [[0, 0], [1, "a"], [1, 1]]}', "verts\\[1\\] must be"),
        ('{"verts": [[0, 0], [1, NaN], [1, 1]]}', "verts\\[1\\] must be"),
        ('{"verts": [[0, 0], [1e6, 0], [0, 1e6]]}', "too large"),
        ('{"verts": [[0, 0], [1e308, 0], [-1e308, 1]]}', "too large"),
        ('{"verts": [[0, 0], [0, 0], [0, 0]]}', "no free cell"),
        ("[" * 100_000 + "]" * 100_000, "bad JSON"),
    ],
)
def test_houseexpo_errors(tmp_path: Path, text: str, message: str) -> None:
    with pytest.raises(MapFileError, match=message):
        load_map(_write(tmp_path / "bad.json", text))


# --------------------------------------------------------------------------- PNG / BMP


def _colour_room() -> np.ndarray:
    rgb = np.zeros((6, 7, 3), dtype=np.uint8)
    rgb[1:5, 1:6] = [254, 254, 254]
    rgb[2, 2] = [205, 205, 205]  # unknown -> occupied
    rgb[3, 3] = [255, 255, 200]  # mean 236.7 -> free
    rgb[3, 4] = [255, 0, 0]  # mean 85 -> occupied
    return rgb


def test_png_colour_mean_and_alpha_ignored(tmp_path: Path) -> None:
    rgb = _colour_room()
    expected = np.ones((6, 7), dtype=bool)
    expected[1:5, 1:6] = False
    expected[2, 2] = expected[3, 4] = True
    Image.fromarray(rgb).save(tmp_path / "rgb.png")
    np.testing.assert_array_equal(load_map(tmp_path / "rgb.png").occupied, expected)
    rgba = np.dstack([rgb, np.zeros((6, 7), dtype=np.uint8)])  # fully transparent
    Image.fromarray(rgba).save(tmp_path / "rgba.png")
    np.testing.assert_array_equal(load_map(tmp_path / "rgba.png").occupied, expected)
    Image.fromarray(rgb).save(tmp_path / "rgb.bmp")
    np.testing.assert_array_equal(load_map(tmp_path / "rgb.bmp").occupied, expected)
    Image.fromarray(rgb).convert("L").save(tmp_path / "grey.png")
    assert load_map(tmp_path / "grey.png").shape == (6, 7)


def test_png_16_bit_grey(tmp_path: Path) -> None:
    grey = np.full((5, 5), 1000, dtype=np.uint16)
    grey[1:4, 1:4] = 65000
    Image.fromarray(grey).save(tmp_path / "deep.png")
    assert (~load_map(tmp_path / "deep.png").occupied).sum() == 9


def test_yaml_with_png_image(tmp_path: Path) -> None:
    Image.fromarray(_colour_room()).save(tmp_path / "pic.png")
    yaml_path = _write(tmp_path / "m.yaml", "image: pic.png\nresolution: 0.1\norigin: [0,0,0]\n")
    assert (~load_map(yaml_path).occupied).sum() == 18


def test_png_errors(tmp_path: Path) -> None:
    with pytest.raises(MapFileError, match="not a PNG or BMP image"):
        load_map(_write(tmp_path / "text.png", "just text"))
    Image.fromarray(_colour_room()).save(tmp_path / "ok.png")
    data = (tmp_path / "ok.png").read_bytes()
    with pytest.raises(MapFileError):
        load_map(_write(tmp_path / "cut.png", data[: len(data) // 2]))


# --------------------------------------------------------------------------- writer, resampling


@pytest.mark.parametrize("name", ["office", "maze", "unstructured", "sheng40"])
def test_write_then_load_round_trips(tmp_path: Path, name: str) -> None:
    original = generate_map(name, 60, 45, seed=4)
    yaml_path = write_map(original, tmp_path / f"{name}.yaml")
    assert yaml_path == tmp_path / f"{name}.yaml"
    assert (tmp_path / f"{name}.pgm").is_file()
    loaded = load_map(yaml_path)
    np.testing.assert_array_equal(loaded.occupied, original.occupied)
    assert loaded.resolution_m == 1.0
    assert loaded.meta["crop"] == [0, 0, 45, 60]
    assert loaded.meta["border_added"] is False
    assert "placeholder" in yaml_path.read_text()


def test_round_trip_keeps_resolution_and_origin(tmp_path: Path) -> None:
    pixels = np.full((10, 12), 205, dtype=np.uint8)
    pixels[3:8, 2:10] = 0
    pixels[4:7, 3:9] = 254
    first = load_map(
        _ros_pair(tmp_path, pixels, "image: m.pgm\nresolution: 0.25\norigin: [3, 4, 0]\n")
    )
    second = load_map(write_map(first, tmp_path / "out" / "copy.yaml"))
    np.testing.assert_array_equal(second.occupied, first.occupied)
    assert second.resolution_m == 0.25
    assert second.meta["origin"] == pytest.approx(first.meta["origin"])


def test_write_map_errors(tmp_path: Path) -> None:
    grid_map = generate_map("blank", 10, 10)
    with pytest.raises(MapFileError, match=r"must end in \.yaml"):
        write_map(grid_map, tmp_path / "m.pgm")
    with pytest.raises(MapFileError, match="cannot write"):
        write_map(grid_map, _write(tmp_path / "a_file", "x") / "m.yaml")


@settings(max_examples=150, deadline=None)
@given(
    occupied=hnp.arrays(
        dtype=bool,
        shape=hnp.array_shapes(min_dims=2, max_dims=2, min_side=1, max_side=23),
        elements=st.booleans(),
    ),
    factor=st.integers(min_value=1, max_value=7),
)
def test_downsample_never_loses_a_wall(occupied: np.ndarray, factor: int) -> None:
    fine = GridMap(occupied=occupied, resolution_m=0.05, meta={"origin": [0.0, 0.0, 0.0]})
    coarse = downsample(fine, factor)
    height, width = occupied.shape
    assert coarse.shape == (math.ceil(height / factor), math.ceil(width / factor))
    assert coarse.resolution_m == pytest.approx(0.05 * factor)
    for row in range(coarse.shape[0]):
        for col in range(coarse.shape[1]):
            block = occupied[row * factor : (row + 1) * factor, col * factor : (col + 1) * factor]
            partial = block.shape != (factor, factor)  # padded with occupied
            assert coarse.occupied[row, col] == (bool(block.any()) or partial)
    # The lower-left corner stays put: the grid grows downwards by the padding.
    pad_rows = coarse.shape[0] * factor - height
    assert coarse.meta["origin"] == pytest.approx([0.0, -pad_rows * 0.05, 0.0])


def test_downsample_and_resample_validation() -> None:
    grid_map = GridMap(occupied=np.zeros((4, 4), dtype=bool), resolution_m=0.05)
    assert downsample(grid_map, 1) is grid_map
    for bad in (0, -2, 1.5, True):
        with pytest.raises(ScenarioError, match="positive integer"):
            downsample(grid_map, bad)  # type: ignore[arg-type]
    assert resample_to_cell_size(grid_map, 0.1).resolution_m == pytest.approx(0.1)
    assert resample_to_cell_size(grid_map, 0.12).resolution_m == pytest.approx(0.1)
    assert resample_to_cell_size(grid_map, 0.05).shape == (4, 4)
    with pytest.raises(ScenarioError, match="finer"):
        resample_to_cell_size(grid_map, 0.03)
    with pytest.raises(ScenarioError, match="no resolution"):
        resample_to_cell_size(GridMap(occupied=np.zeros((4, 4), dtype=bool)), 0.1)
    assert issubclass(MapFileError, MrexploreInputError)
