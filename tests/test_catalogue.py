"""The catalogue of shipped maps: files, licences, names, user map folders, the CLI."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import mrexplore.maps
from mrexplore import cli
from mrexplore.errors import UnknownIdError
from mrexplore.grid import generate_map, load_map, write_map
from mrexplore.grid.catalogue import (
    CATALOGUE,
    DATA_DIR,
    MAPS_ENV,
    MapEntry,
    credit_for_file,
    lookup,
    resolve_map_name,
    user_maps,
)
from mrexplore.grid.occupancy import GridMap
from mrexplore.sim import Scenario
from mrexplore.sim.world import load_scenario_map, resolve_map

IDS = [entry.name for entry in CATALOGUE]
ROS = [entry for entry in CATALOGUE if entry.kind == "ros"]
MOVINGAI = [entry for entry in CATALOGUE if entry.kind == "movingai"]
#: The maps the documentation promises (README, docs/maps.md).
DOCUMENTED = {
    "intel",
    "aws-small-house",
    "willow-full",
    "willow-2010",
    "depot",
    "warehouse",
    "lse-arena",
    "room-32-32-4",
    "room-64-64-8",
    "room-64-64-16",
    "maze-128-128-10",
    "random-64-64-10",
    "warehouse-20-40-10-2-2",
    "den312d",
    "ht_chantry",
    "Berlin_1_256",
}


def _key(name: str) -> str:
    return name.lower().replace("_", "-")


def _same_map(a: GridMap, b: GridMap) -> None:
    np.testing.assert_array_equal(a.occupied, b.occupied)
    assert a.resolution_m == b.resolution_m
    assert a.name == b.name
    assert a.credit == b.credit
    assert a.meta == b.meta


def _ros_image(entry: MapEntry) -> Path:
    return Path(str(load_map(entry.path).meta["image"]))


# --------------------------------------------------------------------------- the table


def test_the_documented_maps_ship() -> None:
    assert {entry.name for entry in CATALOGUE} == DOCUMENTED
    assert mrexplore.maps.names() == [entry.name for entry in CATALOGUE]
    kinds = [entry.kind for entry in CATALOGUE]
    assert set(kinds) == {"ros", "movingai"}
    assert kinds == sorted(kinds, key=lambda kind: kind != "ros"), "ROS maps first"


def test_names_are_unique_under_the_lookup_key() -> None:
    keys = [_key(entry.name) for entry in CATALOGUE]
    assert len(set(keys)) == len(keys)
    for entry in CATALOGUE:
        for spelling in (entry.name, entry.name.upper(), entry.name.replace("-", "_")):
            assert lookup(spelling) is entry
            assert mrexplore.maps.info(spelling) is entry
        assert lookup(_key(entry.name).replace("-", "_").title()) is entry
    assert lookup("nowhere") is None


@pytest.mark.parametrize("entry", CATALOGUE, ids=IDS)
def test_entry_file_ships_in_the_package_and_loads(entry: MapEntry) -> None:
    assert entry.path.is_file()
    assert entry.path.parent == DATA_DIR
    assert entry.path == mrexplore.maps.path(entry.name)
    assert Path(entry.file).stem == entry.name
    assert entry.path.suffix == (".yaml" if entry.kind == "ros" else ".map")
    grid_map = load_map(entry.path)
    assert grid_map.name == entry.name
    assert (~grid_map.occupied).any()
    assert credit_for_file(entry.path) == entry.credit != ""
    assert len(entry.source_sha256) == 64
    int(entry.source_sha256, 16)
    if entry.kind == "ros":
        image = _ros_image(entry)
        assert image.parent == DATA_DIR and image.is_file()
        assert credit_for_file(image) == entry.credit


@pytest.mark.parametrize("entry", CATALOGUE, ids=IDS)
def test_licence_file_ships_and_is_not_empty(entry: MapEntry) -> None:
    assert entry.licence
    assert entry.licence_path.is_file()
    assert entry.licence_path.parent == DATA_DIR / "licenses"
    assert entry.licence_path.read_text(encoding="utf-8").strip()


def test_credits_readme_ships_and_names_every_map() -> None:
    text = (DATA_DIR / "README.md").read_text(encoding="utf-8")
    for entry in CATALOGUE:
        assert entry.name in text


@pytest.mark.parametrize("entry", ROS, ids=[entry.name for entry in ROS])
def test_ros_image_is_8_bit_greyscale_png(entry: MapEntry) -> None:
    path = _ros_image(entry)
    assert path.suffix == ".png"
    with Image.open(path) as image:
        assert image.format == "PNG"
        assert image.mode == "L"
        pixels = np.asarray(image)
    assert pixels.dtype == np.uint8


@pytest.mark.parametrize("entry", MOVINGAI, ids=[entry.name for entry in MOVINGAI])
def test_movingai_map_is_the_published_file(entry: MapEntry) -> None:
    """MovingAI maps are copied unchanged: the shipped file has the source's digest."""
    assert hashlib.sha256(entry.path.read_bytes()).hexdigest() == entry.source_sha256


# --------------------------------------------------------------------------- mrexplore.maps


@pytest.mark.parametrize("entry", CATALOGUE, ids=IDS)
def test_maps_load_by_name_equals_load_map(entry: MapEntry) -> None:
    _same_map(mrexplore.maps.load(entry.name), load_map(entry.path))
    if entry.kind == "ros":
        _same_map(
            mrexplore.maps.load(entry.name.upper(), cell_size_m=0.2),
            load_map(entry.path, cell_size_m=0.2),
        )


def test_maps_info_of_an_unknown_name_lists_the_names() -> None:
    with pytest.raises(UnknownIdError, match="intel"):
        mrexplore.maps.info("nowhere")
    with pytest.raises(UnknownIdError):
        mrexplore.maps.load("nowhere")


def test_summaries_match_the_loaded_maps() -> None:
    summaries = mrexplore.maps.summaries()
    assert [summary.entry for summary in summaries] == list(CATALOGUE)
    for summary in summaries:
        grid_map = load_map(summary.entry.path)
        assert (summary.height, summary.width) == grid_map.shape
        assert summary.resolution_m == grid_map.resolution_m
        assert 0 < summary.explorable_cells <= int((~grid_map.occupied).sum())


# --------------------------------------------------------------------------- names and paths


@pytest.mark.parametrize(
    "name",
    [
        "intel.yaml",
        "intel.png",
        "den312d.map",
        "maps/intel",
        "./intel",
        "../intel",
        "a/b/room-64-64-8",
        f"data{os.sep}intel",
    ],
)
def test_resolve_map_name_leaves_paths_alone(
    name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _user_map(tmp_path, "intel", seed=1)
    _user_map(tmp_path, "room-64-64-8", seed=2)
    monkeypatch.setenv(MAPS_ENV, str(tmp_path))
    assert resolve_map_name(name) is None


def test_a_path_with_a_catalogue_stem_loads_that_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    mine = _user_map(tmp_path, "intel", seed=1)
    monkeypatch.chdir(tmp_path)
    assert resolve_map("intel.yaml") == Path("intel.yaml")
    assert resolve_map(str(mine)) == mine
    loaded = load_scenario_map(Scenario(map="intel.yaml"))
    np.testing.assert_array_equal(loaded.occupied, load_map(mine).occupied)
    assert loaded.source == "intel.yaml"
    assert loaded.credit == "", "a user's own intel.yaml is not the Intel lab map"
    assert resolve_map("intel") == mrexplore.maps.path("intel")


def test_credit_follows_the_bytes_not_the_name(tmp_path: Path) -> None:
    entry = mrexplore.maps.info("den312d")
    copy = tmp_path / "renamed.map"
    shutil.copyfile(entry.path, copy)
    assert load_map(copy).credit == entry.credit  # the original's bytes, any name
    impostor = tmp_path / "den312d.map"
    impostor.write_text(entry.path.read_text().replace("@", "T", 1))
    assert load_map(impostor).credit == ""


def test_a_user_map_name_with_a_dot_loads_by_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    yaml_path = _user_map(tmp_path, "willow-2010-02-18-0.10", seed=3)
    monkeypatch.setenv(MAPS_ENV, str(tmp_path))
    assert resolve_map_name("willow-2010-02-18-0.10") == yaml_path
    assert load_scenario_map(Scenario(map="willow-2010-02-18-0.10")).source == str(yaml_path)


def test_resolve_map_name_finds_catalogue_maps() -> None:
    for entry in CATALOGUE:
        assert resolve_map_name(entry.name) == entry.path
        assert resolve_map(entry.name) == entry.path
    assert resolve_map_name("nowhere") is None
    with pytest.raises(UnknownIdError):
        resolve_map("nowhere")


# --------------------------------------------------------------------------- user folders


def _user_map(folder: Path, stem: str, seed: int) -> Path:
    return write_map(generate_map("office", 30, 24, seed=seed), folder / f"{stem}.yaml")


def test_a_user_map_loads_by_stem_through_the_env_var(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    yaml_path = _user_map(tmp_path, "mine", seed=1)
    with pytest.raises(UnknownIdError, match="mine"):
        load_scenario_map(Scenario(map="mine"))
    monkeypatch.setenv(MAPS_ENV, str(tmp_path))
    assert user_maps() == {"mine": yaml_path}
    assert resolve_map_name("mine") == yaml_path
    loaded = load_scenario_map(Scenario(map="mine"))
    np.testing.assert_array_equal(loaded.occupied, load_map(yaml_path).occupied)
    assert loaded.source == str(yaml_path)
    assert loaded.credit == ""


def test_user_folders_are_searched_in_order(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    first, second = tmp_path / "first", tmp_path / "second"
    in_first = _user_map(first, "mine", seed=1)
    _user_map(second, "mine", seed=2)
    only_second = _user_map(second, "theirs", seed=3)
    missing = tmp_path / "missing"
    monkeypatch.setenv(MAPS_ENV, os.pathsep.join(str(p) for p in (missing, first, second)))
    assert user_maps() == {"mine": in_first, "theirs": only_second}
    assert load_scenario_map(Scenario(map="mine")).source == str(in_first)
    assert load_scenario_map(Scenario(map="theirs")).source == str(only_second)


def test_catalogue_and_generator_names_win_over_user_files(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _user_map(tmp_path, "intel", seed=1)
    _user_map(tmp_path, "lse_arena", seed=2)
    _user_map(tmp_path, "office", seed=3)
    monkeypatch.setenv(MAPS_ENV, str(tmp_path))
    assert set(user_maps()) == {"intel", "lse_arena", "office"}
    for name in ("intel", "lse_arena"):
        entry = lookup(name)
        assert entry is not None
        assert resolve_map_name(name) == entry.path
        _same_map(load_scenario_map(Scenario(map=name)), load_map(entry.path))
    assert resolve_map("office") is None
    assert load_scenario_map(Scenario(map="office")).source.startswith("generator:office")


# --------------------------------------------------------------------------- command line


def test_cli_maps_lists_every_catalogue_map_with_its_licence(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert cli.main(["maps"]) == 0
    out = capsys.readouterr().out
    rows: dict[str, list[str]] = {}
    for line in out.splitlines():
        words = line.split()
        entry = lookup(words[0]) if words else None
        if entry is not None and words[0] == entry.name:
            rows[entry.name] = words
    assert set(rows) == {entry.name for entry in CATALOGUE}
    for entry in CATALOGUE:
        assert entry.licence in rows[entry.name]


def test_cli_run_on_a_catalogue_map_credits_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    argv = ["run", "--map", "intel", "--cell-size", "0.2", "--sensor-range", "3m"]
    argv += ["--robots", "2", "--max-ticks", "20", "--out", str(out)]
    assert cli.main(argv) == 0
    capsys.readouterr()
    result = json.loads((out / "result.json").read_text())
    assert "Intel" in result["map_credit"]
    assert result["map_credit"] == mrexplore.maps.info("intel").credit
    assert result["map_name"] == "intel"
    assert result["ticks"] <= 20
