"""Distance fields and path extraction against a reference Dijkstra (scipy csgraph)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from mrexplore.errors import MrexploreInputError
from mrexplore.planning import (
    SQRT2,
    UnreachableTargetError,
    distance_field,
    extract_path,
    path_length,
)

BoolGrid = npt.NDArray[np.bool_]

# (d_row, d_col, cost) of the eight moves.
MOVES = [
    (dr, dc, SQRT2 if dr and dc else 1.0)
    for dr in (-1, 0, 1)
    for dc in (-1, 0, 1)
    if (dr, dc) != (0, 0)
]


def reference_distances(passable: BoolGrid, source: tuple[int, int]) -> npt.NDArray[np.float64]:
    """scipy Dijkstra on an explicit graph with the same no-corner-cutting moves."""
    height, width = passable.shape
    grid = passable.copy()
    grid[source] = True
    rows, cols = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    heads: list[npt.NDArray[np.int64]] = []
    tails: list[npt.NDArray[np.int64]] = []
    weights: list[npt.NDArray[np.float64]] = []
    for dr, dc, cost in MOVES:
        nr, nc = rows + dr, cols + dc
        inside = (nr >= 0) & (nr < height) & (nc >= 0) & (nc < width)
        ok = inside & grid
        ok[inside] &= grid[nr[inside], nc[inside]]
        if dr and dc:
            ok[inside] &= grid[nr[inside], cols[inside]] & grid[rows[inside], nc[inside]]
        heads.append((rows[ok] * width + cols[ok]).astype(np.int64))
        tails.append((nr[ok] * width + nc[ok]).astype(np.int64))
        weights.append(np.full(int(ok.sum()), cost))
    graph = coo_matrix(
        (np.concatenate(weights), (np.concatenate(heads), np.concatenate(tails))),
        shape=(height * width, height * width),
    ).tocsr()
    return dijkstra(graph, indices=source[0] * width + source[1]).reshape(height, width)


@st.composite
def grids_and_sources(draw: st.DrawFn) -> tuple[BoolGrid, tuple[int, int]]:
    """Random grids up to 30 x 30 with 0-50% obstacles, and a source cell (maybe occupied)."""
    height = draw(st.integers(1, 30))
    width = draw(st.integers(1, 30))
    density = draw(st.floats(0.0, 0.5))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    passable = rng.random((height, width)) >= density
    source = (draw(st.integers(0, height - 1)), draw(st.integers(0, width - 1)))
    return passable, source


def assert_legal_path(path: npt.NDArray[np.int32], passable: BoolGrid) -> None:
    """Adjacent steps, only passable cells, no corner cutting."""
    assert path.dtype == np.int32 and path.ndim == 2 and path.shape[1] == 2
    for r, c in path[1:]:
        assert passable[r, c]
    steps = np.diff(path.astype(np.int64), axis=0)
    assert np.all(np.abs(steps) <= 1)
    assert np.all(np.abs(steps).sum(axis=1) >= 1)
    for (r, c), (dr, dc) in zip(path[:-1], steps, strict=True):
        if dr and dc:
            assert passable[r + dr, c] and passable[r, c + dc], "corner cut"


@settings(max_examples=150, deadline=None)
@given(grids_and_sources())
def test_distance_field_matches_reference(case: tuple[BoolGrid, tuple[int, int]]) -> None:
    passable, source = case
    field = distance_field(passable, source)
    expected = reference_distances(passable, source)
    assert field.shape == passable.shape and field.dtype == np.float64
    np.testing.assert_array_equal(np.isinf(field), np.isinf(expected))
    finite = np.isfinite(expected)
    np.testing.assert_allclose(field[finite], expected[finite], rtol=0, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(grids_and_sources(), st.integers(0, 2**32 - 1))
def test_early_exit_on_targets_gives_same_values(
    case: tuple[BoolGrid, tuple[int, int]], seed: int
) -> None:
    passable, source = case
    rng = np.random.default_rng(seed)
    targets = rng.random(passable.shape) < rng.choice([0.0, 0.01, 0.05, 0.3])
    full = distance_field(passable, source)
    early = distance_field(passable, source, targets=targets)
    np.testing.assert_array_equal(early[targets], full[targets])
    finite = np.isfinite(early)
    np.testing.assert_array_equal(early[finite], full[finite])
    # Every finite cell of an early-stopped field still yields a legal path.
    grid = passable.copy()
    grid[source] = True
    for target in zip(*np.nonzero(finite), strict=True):
        path = extract_path(early, target)
        assert_legal_path(path, grid)
        assert path_length(path) == pytest.approx(early[target], abs=1e-9)


@settings(max_examples=60, deadline=None)
@given(grids_and_sources(), st.floats(0.0, 20.0))
def test_max_distance_cuts_the_field(
    case: tuple[BoolGrid, tuple[int, int]], max_distance: float
) -> None:
    passable, source = case
    full = distance_field(passable, source)
    cut = distance_field(passable, source, max_distance=max_distance)
    within = full <= max_distance
    np.testing.assert_array_equal(cut[within], full[within])
    assert np.all(np.isinf(cut[~within]))


@settings(max_examples=100, deadline=None)
@given(grids_and_sources())
def test_extract_path_is_legal_and_shortest(case: tuple[BoolGrid, tuple[int, int]]) -> None:
    passable, source = case
    field = distance_field(passable, source)
    grid = passable.copy()
    grid[source] = True
    reachable = np.argwhere(np.isfinite(field))
    for target in reachable[:: max(1, len(reachable) // 25)]:
        path = extract_path(field, (int(target[0]), int(target[1])))
        assert tuple(path[0]) == source
        assert tuple(path[-1]) == tuple(target)
        assert_legal_path(path, grid)
        assert abs(path_length(path) - field[tuple(target)]) <= 1e-9
    unreachable = np.argwhere(np.isinf(field))
    if len(unreachable):
        with pytest.raises(UnreachableTargetError):
            extract_path(field, (int(unreachable[0, 0]), int(unreachable[0, 1])))


def test_known_values_on_blank_grid() -> None:
    field = distance_field(np.ones((10, 10), dtype=bool), (0, 0))
    # (3, 5): three diagonal steps, then two straight steps.
    assert field[3, 5] == pytest.approx(2 + 3 * math.sqrt(2), abs=1e-12)
    assert field[9, 9] == pytest.approx(9 * math.sqrt(2), abs=1e-12)
    assert field[0, 7] == 7.0
    assert field[0, 0] == 0.0
    path = extract_path(field, (3, 5))
    assert len(path) == 6
    assert path_length(path) == field[3, 5]


def test_no_corner_cutting() -> None:
    passable = np.array([[True, False], [False, True]])
    assert np.isinf(distance_field(passable, (0, 0))[1, 1])
    passable = np.array([[True, True], [False, True]])
    field = distance_field(passable, (0, 0))
    assert field[1, 1] == 2.0  # around the corner, not sqrt(2)
    assert extract_path(field, (1, 1)).tolist() == [[0, 0], [0, 1], [1, 1]]


def test_occupied_source_counts_as_passable() -> None:
    passable = np.ones((3, 3), dtype=bool)
    passable[1, 1] = False
    field = distance_field(passable, (1, 1))
    assert field[1, 1] == 0.0
    assert field[0, 0] == pytest.approx(SQRT2)


def test_unreachable_target_stays_inf_and_early_exit_still_exact() -> None:
    passable = np.ones((5, 9), dtype=bool)
    passable[:, 4] = False  # wall splits the grid
    targets = np.zeros_like(passable)
    targets[0, 8] = True  # behind the wall
    targets[4, 0] = True
    field = distance_field(passable, (0, 0), targets=targets)
    assert np.isinf(field[0, 8])
    assert field[4, 0] == 4.0
    with pytest.raises(UnreachableTargetError):
        extract_path(field, (0, 8))
    with pytest.raises(ValueError):  # UnreachableTargetError is a ValueError
        extract_path(field, (2, 6))


def test_empty_target_mask_settles_only_the_source() -> None:
    field = distance_field(np.ones((4, 4), dtype=bool), (1, 1), targets=np.zeros((4, 4), bool))
    assert field[1, 1] == 0.0
    assert np.isinf(field).sum() == 15


def test_bad_inputs_raise_input_errors() -> None:
    passable = np.ones((4, 4), dtype=bool)
    with pytest.raises(MrexploreInputError, match="outside"):
        distance_field(passable, (4, 0))
    with pytest.raises(MrexploreInputError, match="2-D"):
        distance_field(np.ones(4, dtype=bool), (0, 0))
    with pytest.raises(MrexploreInputError, match="shape"):
        distance_field(passable, (0, 0), targets=np.ones((3, 3), dtype=bool))
    with pytest.raises(MrexploreInputError, match="max_distance"):
        distance_field(passable, (0, 0), max_distance=-1.0)
    with pytest.raises(MrexploreInputError, match="8-adjacent"):
        path_length(np.array([[0, 0], [0, 2]]))
    bogus = np.full((3, 3), 5.0)
    bogus[0, 0] = 0.0
    with pytest.raises(MrexploreInputError, match="not a distance field"):
        extract_path(bogus, (2, 2))


def test_uint8_truth_is_accepted() -> None:
    passable = np.ones((3, 3), dtype=np.uint8)
    assert distance_field(passable, (0, 0))[2, 2] == pytest.approx(2 * SQRT2)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000), density=st.floats(0.0, 0.4))
def test_stop_after_one_settles_the_nearest_target_exactly(seed: int, density: float) -> None:
    rng = np.random.default_rng(seed)
    passable = rng.random((25, 25)) >= density
    targets = passable & (rng.random((25, 25)) < 0.05)
    source = (12, 12)
    passable[source] = True
    targets[source] = False
    full = distance_field(passable, source)
    early = distance_field(passable, source, targets=targets, stop_after=1)
    reachable = targets & np.isfinite(full)
    if reachable.any():
        assert np.isclose(early[targets].min(), full[reachable].min())
    finite = np.isfinite(early)
    assert np.allclose(early[finite], full[finite])
