"""The reusable search buffers and the fast masks give what the plain formulations
give: FieldWorkspace fields against distance_field (stopped by targets, by
max_distance, or not at all, many searches in a row on one set of buffers), the
compiled resets and minimum against numpy, raster_cells against np.nonzero and
disks_mask against disk_mask, on random grids."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mrexplore.planning import disk_mask, distance_field
from mrexplore.planning.multi_disks import disks_mask
from mrexplore.planning.multi_fields import (
    FieldWorkspace,
    min_touched,
    raster_cells,
    reset_box,
    reset_touched,
)
from mrexplore.strategies.base import reachable_frontier_cells

SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def grids(draw: st.DrawFn) -> tuple[np.ndarray, np.random.Generator]:
    height = draw(st.integers(1, 24))
    width = draw(st.integers(1, 24))
    density = draw(st.floats(0.0, 0.5))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    return rng.random((height, width)) >= density, rng


def _cell(rng: np.random.Generator, shape: tuple[int, ...]) -> tuple[int, int]:
    return int(rng.integers(shape[0])), int(rng.integers(shape[1]))


@SETTINGS
@given(grids())
def test_workspace_fields_equal_distance_field(
    case: tuple[np.ndarray, np.random.Generator],
) -> None:
    passable, rng = case
    work = FieldWorkspace()
    for _ in range(6):  # one set of buffers for every search
        source = _cell(rng, passable.shape)
        mode = int(rng.integers(4))
        targets = rng.random(passable.shape) < 0.1
        if mode == 0:
            expected = distance_field(passable, source)
            field = work.search(passable, source)
        elif mode == 1:
            stop_after = int(rng.integers(1, 4))
            expected = distance_field(passable, source, targets=targets, stop_after=stop_after)
            field = work.search(passable, source, targets=targets, stop_after=stop_after)
        elif mode == 2:
            index = np.flatnonzero(targets)
            expected = distance_field(passable, source, targets=targets)
            field = work.search(passable, source, target_cells=index)
        else:
            bound = float(rng.uniform(0, 10))
            index = np.flatnonzero(targets)
            expected = distance_field(passable, source, targets=targets, max_distance=bound)
            field = work.search(passable, source, target_cells=index, max_distance=bound)
        np.testing.assert_array_equal(field, expected)
        if mode == 1:
            assert work.nearest(targets) == np.min(
                np.where(targets, expected, np.inf), initial=np.inf
            )
        work.release()
        # Released buffers are as new: every distance inf, every state zero.
        assert np.isinf(work._dist).all()
        assert not work._state.any()


@SETTINGS
@given(grids())
def test_compiled_resets_and_minimum_match_numpy(
    case: tuple[np.ndarray, np.random.Generator],
) -> None:
    touched_grid, rng = case
    n_cells = touched_grid.size
    padded = -(-n_cells // 8) * 8
    words = np.zeros(padded // 8, dtype=np.uint64)
    state = words.view(np.uint8)[:n_cells]
    touched = ~touched_grid.reshape(-1)
    state[touched] = rng.integers(1, 5, size=int(touched.sum()), dtype=np.uint8)
    dist = np.full(n_cells, np.inf)
    settled = touched & (rng.random(n_cells) < 0.5)
    dist[settled] = rng.uniform(0, 50, size=int(settled.sum()))
    mask = rng.random(n_cells) < 0.5
    assert min_touched(words, dist, mask) == np.min(np.where(mask, dist, np.inf), initial=np.inf)

    height, width = touched_grid.shape
    top, bottom = sorted(int(v) for v in rng.integers(0, height + 1, size=2))
    left, right = sorted(int(v) for v in rng.integers(0, width + 1, size=2))
    box = np.zeros((height, width), dtype=bool)
    box[top:bottom, left:right] = True
    in_box = box.reshape(-1)
    expected_state, expected_dist = state.copy(), dist.copy()
    expected_state[in_box] = 0
    expected_dist[in_box] = np.inf
    reset_box(state, dist, width, top, bottom, left, right)
    np.testing.assert_array_equal(state, expected_state)
    np.testing.assert_array_equal(dist, expected_dist)

    touched_words = int(np.count_nonzero(words))
    assert reset_touched(words, state, dist) == touched_words
    assert not words.any()
    assert np.isinf(dist).all()


@SETTINGS
@given(grids())
def test_raster_and_reachable_cells_match_nonzero(
    case: tuple[np.ndarray, np.random.Generator],
) -> None:
    mask, rng = case
    index, rows, cols = raster_cells(mask)
    expected_rows, expected_cols = np.nonzero(mask)
    np.testing.assert_array_equal(rows, expected_rows)
    np.testing.assert_array_equal(cols, expected_cols)
    np.testing.assert_array_equal(index, np.flatnonzero(mask))
    dist = np.where(rng.random(mask.shape) < 0.3, np.inf, rng.uniform(0, 5, mask.shape))
    dist[_cell(rng, mask.shape)] = 0.0
    got = reachable_frontier_cells(mask, dist)
    at = dist[expected_rows, expected_cols]  # the plain formulation
    keep = np.isfinite(at) & (at > 0)
    np.testing.assert_array_equal(got[0], expected_rows[keep])
    np.testing.assert_array_equal(got[1], expected_cols[keep])


@SETTINGS
@given(grids(), st.floats(0.0, 30.0), st.integers(0, 5))
def test_disks_mask_equals_disk_mask(
    case: tuple[np.ndarray, np.random.Generator], radius: float, n_centres: int
) -> None:
    grid, rng = case
    height, width = grid.shape
    # Centres inside and a little outside the grid.
    centres = [
        (int(rng.integers(-3, height + 3)), int(rng.integers(-3, width + 3)))
        for _ in range(n_centres)
    ]
    np.testing.assert_array_equal(
        disks_mask(grid.shape, centres, radius), disk_mask(grid.shape, centres, radius)
    )
