"""Frontier detection and clustering."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import FrontierCluster, frontier_clusters, frontier_mask

U, F, W = UNKNOWN, FREE, OCCUPIED  # unknown, free, wall


@st.composite
def beliefs(draw: st.DrawFn) -> npt.NDArray[np.int8]:
    """Random belief maps up to 30 x 30 mixing unknown, free and occupied cells."""
    height = draw(st.integers(1, 30))
    width = draw(st.integers(1, 30))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    weights = rng.dirichlet(np.ones(3))
    return rng.choice(np.array([U, F, W], dtype=np.int8), size=(height, width), p=weights)


def brute_force_mask(belief: npt.NDArray[np.int8]) -> npt.NDArray[np.bool_]:
    height, width = belief.shape
    mask = np.zeros(belief.shape, dtype=bool)
    for r in range(height):
        for c in range(width):
            if belief[r, c] != F:
                continue
            for nr, nc in ((r - 1, c), (r + 1, c), (r, c - 1), (r, c + 1)):
                if 0 <= nr < height and 0 <= nc < width and belief[nr, nc] == U:
                    mask[r, c] = True
    return mask


def test_hand_made_belief() -> None:
    belief = np.array(
        [
            [F, F, F, U],
            [F, W, F, U],
            [F, F, W, U],
            [U, F, F, F],
        ],
        dtype=np.int8,
    )
    expected = np.array(
        [
            [0, 0, 1, 0],
            [0, 0, 1, 0],
            [1, 0, 0, 0],
            [0, 1, 0, 1],
        ],
        dtype=bool,
    )
    np.testing.assert_array_equal(frontier_mask(belief), expected)


def test_grid_border_is_not_unknown() -> None:
    belief = np.zeros((3, 3), dtype=np.int8)
    assert not frontier_mask(belief).any()
    # Diagonal unknown neighbours do not make a frontier.
    belief[0, 0] = U
    assert frontier_mask(belief).sum() == 2  # (0, 1) and (1, 0), not (1, 1)


@settings(max_examples=150, deadline=None)
@given(beliefs())
def test_frontier_definition(belief: npt.NDArray[np.int8]) -> None:
    mask = frontier_mask(belief)
    assert mask.dtype == np.bool_ and mask.shape == belief.shape
    np.testing.assert_array_equal(mask, brute_force_mask(belief))


def check_clusters(mask: npt.NDArray[np.bool_], clusters: list[FrontierCluster]) -> None:
    """Clusters partition the mask into its 8-connected components, in raster order."""
    labels, n_labels = ndimage.label(mask, structure=np.ones((3, 3), dtype=int))
    assert len(clusters) == n_labels
    covered = np.zeros(mask.shape, dtype=int)
    first_cells = []
    for cluster in clusters:
        cells = cluster.cells
        assert cells.dtype == np.int32 and cells.shape == (cluster.size, 2)
        flat = cells[:, 0].astype(np.int64) * mask.shape[1] + cells[:, 1]
        assert np.all(np.diff(flat) > 0), "cells are not in raster order"
        assert mask[cells[:, 0], cells[:, 1]].all()
        covered[cells[:, 0], cells[:, 1]] += 1
        # One cluster = exactly one 8-connected component.
        component = labels[cells[0, 0], cells[0, 1]]
        assert (labels == component).sum() == cluster.size
        assert (labels[cells[:, 0], cells[:, 1]] == component).all()
        centroid = cells.mean(axis=0)
        assert cluster.centroid == pytest.approx(tuple(centroid))
        assert cluster.representative in {(int(r), int(c)) for r, c in cells}
        squared = ((cells - centroid) ** 2).sum(axis=1)
        rep = np.array(cluster.representative)
        assert ((rep - centroid) ** 2).sum() == pytest.approx(squared.min())
        first_cells.append(int(flat[0]))
    np.testing.assert_array_equal(covered, mask.astype(int))
    assert first_cells == sorted(first_cells)


@settings(max_examples=150, deadline=None)
@given(beliefs())
def test_clusters_partition_the_frontier(belief: npt.NDArray[np.int8]) -> None:
    mask = frontier_mask(belief)
    check_clusters(mask, frontier_clusters(mask))


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(0.0, 0.7))
def test_clusters_of_arbitrary_masks(seed: int, density: float) -> None:
    rng = np.random.default_rng(seed)
    mask = rng.random((int(rng.integers(1, 40)), int(rng.integers(1, 40)))) < density
    check_clusters(mask, frontier_clusters(mask))


def test_min_size_and_representative_tie_break() -> None:
    mask = np.zeros((5, 6), dtype=bool)
    mask[0, 0:2] = True  # two cells: centroid (0, 0.5), tie -> first in raster order
    mask[3, 3:6] = True  # three cells: representative is the middle one
    mask[4, 0] = True  # single cell
    clusters = frontier_clusters(mask)
    assert [c.size for c in clusters] == [2, 3, 1]
    assert clusters[0].representative == (0, 0)
    assert clusters[0].centroid == (0.0, 0.5)
    assert clusters[1].representative == (3, 4)
    big = frontier_clusters(mask, min_size=2)
    assert [c.size for c in big] == [2, 3]
    assert frontier_clusters(np.zeros((3, 3), dtype=bool)) == []


def test_diagonal_cells_join_one_cluster() -> None:
    mask = np.eye(4, dtype=bool)
    clusters = frontier_clusters(mask)
    assert len(clusters) == 1
    assert clusters[0].cells.tolist() == [[0, 0], [1, 1], [2, 2], [3, 3]]


def test_bad_inputs() -> None:
    with pytest.raises(MrexploreInputError, match="int8"):
        frontier_mask(np.zeros((3, 3), dtype=np.int64))  # type: ignore[arg-type]  # on purpose
    with pytest.raises(MrexploreInputError, match="min_size"):
        frontier_clusters(np.ones((2, 2), dtype=bool), min_size=0)
