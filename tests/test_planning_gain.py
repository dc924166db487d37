"""Information gain against brute-force counting."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import disk_offsets, information_gain
from mrexplore.planning.gain import _gain_disk_kernel, _half_widths
from mrexplore.sensing import is_visible


@st.composite
def cases(
    draw: st.DrawFn,
) -> tuple[npt.NDArray[np.int8], npt.NDArray[np.int64], float, npt.NDArray[np.bool_]]:
    """A random belief, candidates inside it, a radius and an exclusion mask."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    height, width = draw(st.integers(1, 25)), draw(st.integers(1, 25))
    belief = rng.choice(
        np.array([UNKNOWN, FREE, OCCUPIED], dtype=np.int8),
        size=(height, width),
        p=rng.dirichlet(np.ones(3)),
    )
    n_candidates = draw(st.integers(0, 30))
    candidates = np.stack(
        [rng.integers(0, height, n_candidates), rng.integers(0, width, n_candidates)], axis=1
    )
    radius = draw(st.floats(0.0, 12.0))
    exclude = rng.random((height, width)) < draw(st.floats(0.0, 0.5))
    return belief, candidates, radius, exclude


def brute_force_gain(
    belief: npt.NDArray[np.int8],
    candidates: npt.NDArray[np.int64],
    radius: float,
    exclude: npt.NDArray[np.bool_] | None = None,
    line_of_sight: bool = False,
) -> list[int]:
    height, width = belief.shape
    gains = []
    for row, col in candidates.tolist():
        count = 0
        for r in range(height):
            for c in range(width):
                if (r - row) ** 2 + (c - col) ** 2 > radius * radius:
                    continue
                if belief[r, c] != UNKNOWN or (exclude is not None and exclude[r, c]):
                    continue
                if line_of_sight and not is_visible(belief == OCCUPIED, (row, col), (r, c)):
                    continue
                count += 1
        gains.append(count)
    return gains


def test_disk_offsets_match_definition() -> None:
    for radius in (0.0, 0.5, 1.0, 1.5, 2.0, 3.3, 7.0):
        offsets = disk_offsets(radius)
        reach = int(radius) + 1
        expected = [
            [dr, dc]
            for dr in range(-reach, reach + 1)
            for dc in range(-reach, reach + 1)
            if dr * dr + dc * dc <= radius * radius
        ]
        assert offsets.tolist() == expected
    assert len(disk_offsets(50.0)) == 7845
    with pytest.raises(ValueError):
        disk_offsets(5.0)[0, 0] = 1  # cached arrays are read-only


@settings(max_examples=120, deadline=None)
@given(cases())
def test_gain_equals_brute_force(
    case: tuple[npt.NDArray[np.int8], npt.NDArray[np.int64], float, npt.NDArray[np.bool_]],
) -> None:
    belief, candidates, radius, exclude = case
    gains = information_gain(belief, candidates, radius)
    assert gains.dtype == np.int64 and gains.shape == (len(candidates),)
    assert gains.tolist() == brute_force_gain(belief, candidates, radius)
    excluded = information_gain(belief, candidates, radius, exclude=exclude)
    assert excluded.tolist() == brute_force_gain(belief, candidates, radius, exclude)
    assert np.all(excluded <= gains)


@settings(max_examples=60, deadline=None)
@given(cases())
def test_direct_and_prefix_kernels_agree(
    case: tuple[npt.NDArray[np.int8], npt.NDArray[np.int64], float, npt.NDArray[np.bool_]],
) -> None:
    belief, candidates, radius, exclude = case
    if len(candidates) == 0:
        return
    widths = _half_widths(radius)
    for use_exclude in (False, True):
        direct = _gain_disk_kernel(belief, exclude, use_exclude, candidates, widths, False)
        prefix = _gain_disk_kernel(belief, exclude, use_exclude, candidates, widths, True)
        np.testing.assert_array_equal(direct, prefix)


def test_few_and_many_candidates_agree() -> None:
    """Many candidates take the prefix-sum kernel, a few the direct one."""
    rng = np.random.default_rng(7)
    belief = rng.choice(np.array([UNKNOWN, FREE, OCCUPIED], dtype=np.int8), size=(80, 90))
    everywhere = np.argwhere(np.ones(belief.shape, dtype=bool))
    gains = information_gain(belief, everywhere, 6.0)
    few = information_gain(belief, everywhere[::1500], 6.0)
    np.testing.assert_array_equal(gains[::1500], few)
    assert few.tolist() == brute_force_gain(belief, everywhere[::1500], 6.0)


@settings(max_examples=60, deadline=None)
@given(cases())
def test_line_of_sight_gain(
    case: tuple[npt.NDArray[np.int8], npt.NDArray[np.int64], float, npt.NDArray[np.bool_]],
) -> None:
    belief, candidates, radius, exclude = case
    candidates = candidates[:8]
    plain = information_gain(belief, candidates, radius, exclude=exclude)
    seen = information_gain(belief, candidates, radius, exclude=exclude, line_of_sight=True)
    assert np.all(seen <= plain)
    assert seen.tolist() == brute_force_gain(belief, candidates, radius, exclude, True)


def test_wall_hides_unknown_cells() -> None:
    belief = np.full((7, 7), UNKNOWN, dtype=np.int8)
    belief[:, 3] = OCCUPIED
    belief[:, :3] = FREE
    candidate = np.array([[3, 1]])
    assert information_gain(belief, candidate, 5.0).item() > 0
    assert information_gain(belief, candidate, 5.0, line_of_sight=True).item() == 0


def test_bad_inputs() -> None:
    belief = np.full((4, 4), UNKNOWN, dtype=np.int8)
    with pytest.raises(MrexploreInputError, match="outside"):
        information_gain(belief, np.array([[4, 0]]), 2.0)
    with pytest.raises(MrexploreInputError, match=r"\(K, 2\)"):
        information_gain(belief, np.array([1, 2, 3]), 2.0)
    with pytest.raises(MrexploreInputError, match="radius"):
        information_gain(belief, np.array([[0, 0]]), -1.0)
    with pytest.raises(MrexploreInputError, match="exclude"):
        information_gain(belief, np.array([[0, 0]]), 1.0, exclude=np.ones((2, 2), bool))
    assert information_gain(belief, np.zeros((0, 2), dtype=int), 3.0).shape == (0,)


def test_huge_radius_counts_the_whole_grid() -> None:
    belief = np.full((6, 7), UNKNOWN, dtype=np.int8)
    belief[0, 0] = FREE
    assert information_gain(belief, np.array([[5, 6]]), 1e12).tolist() == [41]
    assert information_gain(belief, np.array([[5, 6]]), 1e12, line_of_sight=True).tolist() == [41]
