"""World generators, the registry, and free-space components."""

from __future__ import annotations

import doctest
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.errors import ScenarioError, UnknownIdError
from mrexplore.grid import (
    GENERATORS,
    free_component_of,
    generate_map,
    largest_free_component,
    list_generators,
)
from mrexplore.grid import components as components_module
from mrexplore.grid import generators as generators_module
from mrexplore.grid import io as io_module
from mrexplore.grid.components import label_free
from mrexplore.grid.generators import SHENG40_OBSTACLES, maze

SIZES = [(40, 40), (100, 60), (300, 300)]
SEEDLESS = {"blank", "sheng40"}


def _check_invariants(occupied: np.ndarray, width: int, height: int) -> None:
    assert occupied.shape == (height, width)
    assert occupied.dtype == bool
    assert occupied[0].all() and occupied[-1].all()
    assert occupied[:, 0].all() and occupied[:, -1].all()
    _labels, count = label_free(occupied)
    assert count == 1, "free space must be one 4-connected component"


@pytest.mark.parametrize("size", SIZES, ids=[f"{w}x{h}" for w, h in SIZES])
@pytest.mark.parametrize("name", sorted(GENERATORS))
def test_generator_invariants(name: str, size: tuple[int, int]) -> None:
    width, height = size
    grid_map = generate_map(name, width, height, seed=7)
    _check_invariants(grid_map.occupied, width, height)
    assert 0.40 <= grid_map.free.mean() <= 0.95 + 0.04 * (name == "blank")
    assert grid_map.name == name
    assert grid_map.source == f"generator:{name}({width}x{height}, seed=7)"
    assert grid_map.resolution_m is None


@pytest.mark.parametrize("name", sorted(GENERATORS))
def test_generators_are_deterministic_per_seed(name: str) -> None:
    first = generate_map(name, 80, 60, seed=11).occupied
    again = generate_map(name, 80, 60, seed=11).occupied
    np.testing.assert_array_equal(first, again)
    other = generate_map(name, 80, 60, seed=12).occupied
    if name in SEEDLESS:
        np.testing.assert_array_equal(first, other)
    else:
        assert not np.array_equal(first, other)


@settings(max_examples=60, deadline=None)
@given(
    name=st.sampled_from(sorted(GENERATORS)),
    width=st.integers(min_value=8, max_value=90),
    height=st.integers(min_value=8, max_value=90),
    seed=st.integers(min_value=0, max_value=2**32),
)
def test_generators_hold_invariants_at_any_size(
    name: str, width: int, height: int, seed: int
) -> None:
    _check_invariants(generate_map(name, width, height, seed=seed).occupied, width, height)


def test_office_has_rooms_and_doors() -> None:
    occupied = generate_map("office", 120, 80, seed=2).occupied
    labels, count = label_free(occupied)
    assert count == 1
    # Walls are one cell thick: closing every 2-wide door would split the floor into rooms.
    from scipy import ndimage

    wall_thick = ndimage.binary_erosion(occupied[1:-1, 1:-1], structure=np.ones((2, 2)))
    assert wall_thick.mean() < 0.02
    rooms, n_rooms = ndimage.label(
        ~ndimage.binary_dilation(occupied, structure=np.ones((3, 3)), border_value=1)
    )
    assert n_rooms >= 10, "doors of width 2 close under a 3x3 dilation, leaving separate rooms"
    del rooms, labels


def test_maze_is_perfect() -> None:
    # Corridor width 1: the maze is a tree, so free cells - free edges == 1.
    occupied = maze(41, 31, np.random.default_rng(5), corridor_width=1)
    free = ~occupied
    edges = np.count_nonzero(free[:, 1:] & free[:, :-1]) + np.count_nonzero(
        free[1:, :] & free[:-1, :]
    )
    assert int(free.sum()) - edges == 1
    _check_invariants(occupied, 41, 31)


def test_sheng40_default_is_a_40x40_square_with_two_obstacles() -> None:
    info = GENERATORS["sheng40"]
    assert info.default_size == (42, 42)
    grid_map = generate_map("sheng40")
    occupied = grid_map.occupied
    assert grid_map.shape == (42, 42)
    interior = occupied[1:-1, 1:-1]
    blocked = sum((r1 - r0) * (c1 - c0) for r0, r1, c0, c1 in SHENG40_OBSTACLES)
    assert int(interior.sum()) == blocked
    from scipy import ndimage

    _labels, obstacles = ndimage.label(interior)
    assert obstacles == 2


def test_registry_and_defaults() -> None:
    names = [info.name for info in list_generators()]
    assert names == sorted(GENERATORS)
    assert {"blank", "unstructured", "cityblock", "office", "corridor", "maze", "sheng40"} <= set(
        names
    )
    for info in list_generators():
        assert info.description and "\n" not in info.description
        grid_map = generate_map(info.name)
        assert grid_map.shape == (info.default_size[1], info.default_size[0])
    assert generate_map("maze", 50).shape == (50, 50)
    assert generate_map("maze", height=30).shape == (30, 30)


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"name": "nope"}, UnknownIdError, "unknown generator 'nope'; known: blank"),
        ({"name": "maze", "width": 7, "height": 20}, ScenarioError, "--size: width 7 is too small"),
        ({"name": "maze", "width": 20, "height": 0}, ScenarioError, "--size: height 0"),
        ({"name": "maze", "width": -5, "height": 20}, ScenarioError, "--size"),
        ({"name": "maze", "width": 10_001, "height": 20}, ScenarioError, "too large"),
        ({"name": "maze", "width": 20.5, "height": 20}, ScenarioError, "whole number"),
        ({"name": "maze", "width": 20, "height": 20, "seed": -1}, ScenarioError, "--seed"),
    ],
)
def test_generate_map_validation(kwargs: dict[str, object], error: type, message: str) -> None:
    with pytest.raises(error, match=message):
        generate_map(**kwargs)  # type: ignore[arg-type]


def test_generators_are_fast() -> None:
    start = time.perf_counter()
    generate_map("office", 500, 500, seed=1)
    office_s = time.perf_counter() - start
    start = time.perf_counter()
    generate_map("maze", 1000, 1000, seed=1)
    maze_s = time.perf_counter() - start
    assert office_s < 1.0
    assert maze_s < 1.0


# --------------------------------------------------------------------------- components


def test_largest_free_component_breaks_ties_by_lowest_label() -> None:
    occupied = np.array(
        [
            [1, 1, 1, 1, 1],
            [0, 0, 1, 0, 0],
            [1, 1, 1, 1, 1],
            [1, 0, 1, 1, 1],
        ],
        dtype=bool,
    )
    mask = largest_free_component(occupied)
    assert mask.tolist()[1] == [True, True, False, False, False]
    assert not largest_free_component(np.ones((3, 3), dtype=bool)).any()


@settings(max_examples=200, deadline=None)
@given(
    height=st.integers(min_value=0, max_value=40),
    width=st.integers(min_value=0, max_value=40),
    occupied_share=st.floats(min_value=0.0, max_value=1.0),
    seed=st.integers(min_value=0, max_value=2**32),
)
def test_label_free_matches_scipy_label_for_label(
    height: int, width: int, occupied_share: float, seed: int
) -> None:
    from scipy import ndimage

    occupied = np.random.default_rng(seed).random((height, width)) < occupied_share
    labels, count = label_free(occupied)
    expected, expected_count = ndimage.label(~occupied, structure=components_module.FOUR_CONNECTED)
    assert count == expected_count
    np.testing.assert_array_equal(labels, expected)
    assert labels.dtype == np.int32


def test_label_free_on_checkerboards_views_and_other_dtypes() -> None:
    from scipy import ndimage

    checkerboard = (np.indices((31, 33)).sum(axis=0) % 2).astype(bool)
    labels, count = label_free(checkerboard)
    assert count == np.count_nonzero(~checkerboard)  # every free cell alone: the most labels
    for occupied in (
        ~checkerboard,
        checkerboard[::2, ::3],  # a strided view
        np.asfortranarray(checkerboard[:, :20]),
        checkerboard.astype(np.uint8) * 7,  # truthy = occupied
    ):
        labels, count = label_free(occupied)
        free = ~np.asarray(occupied, dtype=bool)
        expected, expected_count = ndimage.label(free, structure=components_module.FOUR_CONNECTED)
        assert count == expected_count
        np.testing.assert_array_equal(labels, expected)


def test_diagonal_neighbours_are_not_connected() -> None:
    occupied = np.array([[0, 1], [1, 0]], dtype=bool)
    assert largest_free_component(occupied).sum() == 1


def test_free_component_of_unions_components() -> None:
    occupied = np.array([[0, 1, 0, 1, 0]], dtype=bool)
    mask = free_component_of(occupied, [(0, 0), (0, 4), (0, 1)])
    assert mask.tolist() == [[True, False, False, False, True]]
    assert not free_component_of(occupied, []).any()
    with pytest.raises(ScenarioError, match="outside"):
        free_component_of(occupied, [(1, 0)])


@pytest.mark.parametrize("module", [components_module, generators_module, io_module])
def test_docstring_examples(module: object) -> None:
    failures, _tests = doctest.testmod(module, optionflags=doctest.ELLIPSIS)  # type: ignore[arg-type]
    assert failures == 0
