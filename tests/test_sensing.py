"""The line-of-sight disk sensor."""

from __future__ import annotations

import itertools

import numpy as np
import numpy.typing as npt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, new_belief
from mrexplore.planning import bresenham_line, disk_offsets
from mrexplore.sensing import is_visible, observe, visible_cells


def cell_set(rows: npt.NDArray[np.int64], cols: npt.NDArray[np.int64]) -> set[tuple[int, int]]:
    return set(zip(rows.tolist(), cols.tolist(), strict=True))


def disk(shape: tuple[int, int], center: tuple[int, int], radius: float) -> set[tuple[int, int]]:
    return {
        (center[0] + dr, center[1] + dc)
        for dr, dc in disk_offsets(radius).tolist()
        if 0 <= center[0] + dr < shape[0] and 0 <= center[1] + dc < shape[1]
    }


@pytest.mark.parametrize("position", [(10, 10), (0, 0), (3, 19), (20, 5)])
@pytest.mark.parametrize("radius", [0.0, 1.0, 4.0, 7.5, 30.0])
def test_empty_grid_sees_whole_disk(position: tuple[int, int], radius: float) -> None:
    world = np.zeros((21, 20), dtype=bool)
    rows, cols = visible_cells(world, position, radius)
    assert len(rows) == len(cell_set(rows, cols))  # no duplicates
    assert (int(rows[0]), int(cols[0])) == position  # own cell first
    assert cell_set(rows, cols) == disk(world.shape, position, radius)


def test_wall_blocks_but_is_seen() -> None:
    world = np.zeros((11, 11), dtype=bool)
    world[:, 7] = True  # vertical wall
    seen = cell_set(*visible_cells(world, (5, 5), 5.0))
    assert (5, 7) in seen and (3, 7) in seen  # the wall itself
    assert not any(col > 7 for _, col in seen)  # nothing behind it
    assert (5, 6) in seen


def test_diagonal_gap_between_occupied_cells_blocks() -> None:
    world = np.zeros((5, 5), dtype=bool)
    world[0, 1] = world[1, 0] = True
    assert not is_visible(world, (0, 0), (1, 1))
    assert not is_visible(world, (0, 0), (3, 3))
    seen = cell_set(*visible_cells(world, (0, 0), 4.0))
    assert seen == {(0, 0), (0, 1), (1, 0)}
    world[1, 0] = False  # one side open: the diagonal passes
    assert is_visible(world, (0, 0), (1, 1)) and is_visible(world, (0, 0), (3, 3))


def test_squeeze_on_an_inner_step_blocks() -> None:
    world = np.zeros((6, 6), dtype=bool)
    world[1, 2] = world[2, 1] = True  # the step (1, 1) -> (2, 2) squeezes between them
    assert not is_visible(world, (0, 0), (3, 3))
    assert is_visible(world, (0, 0), (1, 1))


def test_bresenham_line_shape() -> None:
    assert bresenham_line((0, 0), (1, 3)).tolist() == [[0, 0], [0, 1], [1, 2], [1, 3]]
    assert bresenham_line((2, 2), (2, 2)).tolist() == [[2, 2]]
    rng = np.random.default_rng(3)
    for _ in range(200):
        start = (int(rng.integers(-20, 20)), int(rng.integers(-20, 20)))
        end = (int(rng.integers(-20, 20)), int(rng.integers(-20, 20)))
        line = bresenham_line(start, end)
        assert tuple(line[0]) == start and tuple(line[-1]) == end
        steps = np.abs(np.diff(line, axis=0))
        assert np.all(steps.max(axis=1) == 1)  # 8-adjacent, no repeats
        assert len(line) == max(abs(end[0] - start[0]), abs(end[1] - start[1])) + 1
        # Mirror symmetry of the rounding rule.
        d_row, d_col = end[0] - start[0], end[1] - start[1]
        mirrored = bresenham_line((0, 0), (-d_row, d_col))
        assert np.array_equal(mirrored[:, 0], -(line[:, 0] - start[0]))
        assert np.array_equal(mirrored[:, 1], line[:, 1] - start[1])


def test_observe_writes_truth_and_returns_only_new_cells() -> None:
    world = np.zeros((9, 9), dtype=bool)
    world[4, 2:7] = True
    belief = new_belief(world.shape)
    rows, cols, values = observe(belief, world, (2, 4), 3.0)
    assert values.dtype == np.int8
    visible = cell_set(*visible_cells(world, (2, 4), 3.0))
    assert cell_set(rows, cols) == visible
    np.testing.assert_array_equal(values, np.where(world[rows, cols], OCCUPIED, FREE))
    known = belief != UNKNOWN
    assert cell_set(*np.nonzero(known)) == visible
    np.testing.assert_array_equal(belief[known], np.where(world[known], OCCUPIED, FREE))
    assert (belief[4, 3:6] == OCCUPIED).all()
    # Nothing new from the same spot; a step reveals only what was unknown.
    assert len(observe(belief, world, (2, 4), 3.0)[0]) == 0
    before = belief.copy()
    rows2, cols2, _ = observe(belief, world, (2, 5), 3.0)
    assert (before[rows2, cols2] == UNKNOWN).all()
    assert cell_set(rows2, cols2) == cell_set(*visible_cells(world, (2, 5), 3.0)) - visible


@st.composite
def worlds(draw: st.DrawFn) -> tuple[npt.NDArray[np.bool_], tuple[int, int], float]:
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    height, width = draw(st.integers(1, 30)), draw(st.integers(1, 30))
    world = rng.random((height, width)) < draw(st.floats(0.0, 0.6))
    position = (draw(st.integers(0, height - 1)), draw(st.integers(0, width - 1)))
    return world, position, draw(st.floats(0.0, 20.0))


@settings(max_examples=150, deadline=None)
@given(worlds())
def test_visible_cells_agree_with_is_visible(
    case: tuple[npt.NDArray[np.bool_], tuple[int, int], float],
) -> None:
    world, position, radius = case
    seen = cell_set(*visible_cells(world, position, radius))
    expected = {
        cell for cell in disk(world.shape, position, radius) if is_visible(world, position, cell)
    }
    assert seen == expected


@settings(max_examples=100, deadline=None)
@given(worlds())
def test_is_visible_follows_the_definition(
    case: tuple[npt.NDArray[np.bool_], tuple[int, int], float],
) -> None:
    """Straight from the rule: free cells strictly between, no diagonal squeeze."""
    world, position, _ = case
    cells = np.argwhere(np.ones(world.shape, dtype=bool))
    for target_row, target_col in cells[:: max(1, len(cells) // 60)].tolist():
        target = (target_row, target_col)
        line = bresenham_line(position, target).tolist()
        blocked = any(world[r, c] for r, c in line[1:-1])
        for (r, c), (nr, nc) in itertools.pairwise(line):
            if r != nr and c != nc and world[nr, c] and world[r, nc]:
                blocked = True
        assert is_visible(world, position, target) == (not blocked)


def test_bad_inputs() -> None:
    world = np.zeros((4, 4), dtype=bool)
    with pytest.raises(MrexploreInputError, match="outside"):
        visible_cells(world, (0, 4), 2.0)
    with pytest.raises(MrexploreInputError, match="shape"):
        observe(new_belief((3, 4)), world, (0, 0), 2.0)
    with pytest.raises(MrexploreInputError, match="C-contiguous"):
        observe(new_belief((4, 8))[:, ::2], world, (0, 0), 2.0)
    with pytest.raises(MrexploreInputError, match="radius"):
        visible_cells(world, (0, 0), float("nan"))


def test_huge_radius_is_capped_to_the_grid() -> None:
    rng = np.random.default_rng(5)
    world = rng.random((12, 9)) < 0.2
    huge = cell_set(*visible_cells(world, (3, 4), 1e9))
    assert huge == cell_set(*visible_cells(world, (3, 4), 20.0))


@pytest.mark.parametrize("seed", range(5))
def test_interior_and_border_paths_agree_with_is_visible(seed: int) -> None:
    """A disk inside the grid takes the unchecked fast path; one over the edge does not."""
    rng = np.random.default_rng(seed)
    world = rng.random((41, 41)) < 0.25
    for position in ((20, 20), (2, 30)):
        seen = cell_set(*visible_cells(world, position, 12.5))
        expected = {
            cell for cell in disk(world.shape, position, 12.5) if is_visible(world, position, cell)
        }
        assert seen == expected
