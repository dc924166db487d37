"""Frontier cells and frontier clusters (Yamauchi 1997).

A *frontier cell* is a known-free cell with at least one unknown cell among its
four orthogonal neighbours (cells outside the grid are not unknown). Frontier
cells are grouped into *clusters*: the 8-connected components of the frontier
mask. Units: cells.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, UNKNOWN, BeliefGrid, BoolGrid
from mrexplore.planning._validate import as_belief_grid, as_bool_grid

__all__ = ["FrontierCluster", "frontier_clusters", "frontier_mask"]


@numba.njit(cache=True, nogil=True)
def _frontier_mask_kernel(belief: npt.NDArray[np.int8], out: npt.NDArray[np.bool_]) -> None:
    height, width = belief.shape
    for r in range(height):
        for c in range(width):
            if belief[r, c] != FREE:
                out[r, c] = False
                continue
            out[r, c] = (
                (r > 0 and belief[r - 1, c] == UNKNOWN)
                or (r < height - 1 and belief[r + 1, c] == UNKNOWN)
                or (c > 0 and belief[r, c - 1] == UNKNOWN)
                or (c < width - 1 and belief[r, c + 1] == UNKNOWN)
            )


def frontier_mask(belief: BeliefGrid) -> BoolGrid:
    """Frontier cells of a belief map.

    Args:
        belief: ``H x W`` int8 belief (``UNKNOWN``/``FREE``/``OCCUPIED``).

    Returns:
        ``H x W`` boolean mask, ``True`` on FREE cells with an UNKNOWN 4-neighbour.

    Example:
        >>> import numpy as np
        >>> belief = np.array([[0, 0, -1], [0, 100, -1]], dtype=np.int8)
        >>> frontier_mask(belief).astype(int).tolist()
        [[0, 1, 0], [0, 0, 0]]
    """
    grid = as_belief_grid(belief)
    out = np.empty(grid.shape, dtype=np.bool_)
    _frontier_mask_kernel(grid, out)
    return out


@dataclass(frozen=True, eq=False)
class FrontierCluster:
    """One 8-connected group of frontier cells (compared by identity: it holds an array).

    Attributes:
        cells: ``(K, 2)`` int32 ``(row, col)`` of the cells, in raster order (read-only).
        size: ``K``, number of cells.
        representative: the cluster cell nearest to the centroid (Euclidean, in
            cells; ties go to the first in raster order). Always a frontier cell,
            unlike the centroid, which may fall off the cluster.
        centroid: mean ``(row, col)`` of the cells, as floats.
    """

    cells: npt.NDArray[np.int32]
    size: int
    representative: tuple[int, int]
    centroid: tuple[float, float]


@numba.njit(cache=True, nogil=True)
def _mask_cells_kernel(
    flat: npt.NDArray[np.bool_], chunks: npt.NDArray[np.uint64]
) -> npt.NDArray[np.int64]:
    """Flat indices of the ``True`` cells, ascending; skips 8 empty cells per test.

    ``chunks`` is the first ``8 * len(chunks)`` bytes of ``flat`` seen as uint64.
    """
    # Two passes (count, then fill) beat a growing buffer: reassigning an array
    # inside the loop costs reference counting on every iteration.
    n_chunks = chunks.shape[0]
    n_cells = 0
    for k in range(n_chunks):
        if chunks[k] != 0:
            for i in range(8 * k, 8 * k + 8):
                n_cells += flat[i]
    for i in range(8 * n_chunks, flat.shape[0]):
        n_cells += flat[i]
    cells = np.empty(n_cells, dtype=np.int64)
    n_cells = 0
    for k in range(n_chunks):
        if chunks[k] != 0:
            for i in range(8 * k, 8 * k + 8):
                if flat[i]:
                    cells[n_cells] = i
                    n_cells += 1
    for i in range(8 * n_chunks, flat.shape[0]):
        if flat[i]:
            cells[n_cells] = i
            n_cells += 1
    return cells


@numba.njit(cache=True, nogil=True)
def _cluster_kernel(
    flat: npt.NDArray[np.bool_], height: int, width: int, cells: npt.NDArray[np.int64]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """Group the mask's cells into 8-connected clusters by flood fill over those cells only.

    Args:
        flat: the mask, flat.
        height, width: grid shape.
        cells: flat indices of the mask's cells, ascending (raster order).

    Returns:
        ``(grouped, starts)``: ``cells`` reordered so that cluster ``k`` is
        ``grouped[starts[k]:starts[k + 1]]``, in raster order inside each cluster;
        clusters numbered by their first cell in raster order.

    Memory is O(number of cells + height): no full-grid label array. A neighbour
    found in the mask is located among ``cells`` by binary search within its row.
    """
    n_cells = cells.shape[0]
    row_start = np.zeros(height + 1, dtype=np.int64)
    for i in range(n_cells):
        row_start[cells[i] // width + 1] += 1
    for r in range(height):
        row_start[r + 1] += row_start[r]
    label = np.full(n_cells, -1, dtype=np.int64)
    stack = np.empty(n_cells, dtype=np.int64)
    n_labels = 0
    for seed in range(n_cells):
        if label[seed] >= 0:
            continue
        label[seed] = n_labels
        stack[0] = seed
        top = 1
        while top > 0:
            top -= 1
            here = stack[top]
            u = cells[here]
            row = u // width
            col = u - row * width
            for r in range(max(row - 1, 0), min(row + 2, height)):
                for c in range(max(col - 1, 0), min(col + 2, width)):
                    v = r * width + c
                    if not flat[v]:
                        continue
                    if r == row:
                        # Same row: the mask cells are consecutive in ``cells``.
                        position = here + (c - col)
                    else:
                        # Binary search for v in this row's slice of ``cells``
                        # (written out: a helper call would cost reference counting).
                        low = row_start[r]
                        high = row_start[r + 1] - 1
                        while low < high:
                            middle = (low + high) // 2
                            if cells[middle] < v:
                                low = middle + 1
                            else:
                                high = middle
                        position = low
                    if label[position] < 0:
                        label[position] = n_labels
                        stack[top] = position
                        top += 1
        n_labels += 1
    # Counting sort by label; stable, so raster order holds inside each cluster.
    starts = np.zeros(n_labels + 1, dtype=np.int64)
    for i in range(n_cells):
        starts[label[i] + 1] += 1
    for k in range(n_labels):
        starts[k + 1] += starts[k]
    fill = starts[:-1].copy()
    grouped = np.empty(n_cells, dtype=np.int64)
    for i in range(n_cells):
        grouped[fill[label[i]]] = cells[i]
        fill[label[i]] += 1
    return grouped, starts


@numba.njit(cache=True, nogil=True)
def _cluster_summary_kernel(
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
    starts: npt.NDArray[np.int64],
    extent: int,
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """Per cluster ``[starts[k], starts[k + 1])``: row sum, column sum, nearest-to-mean index.

    The nearest cell minimises ``K**2`` times its squared distance to the mean,
    computed in integers when that fits in int64 (so mirror-image cells tie
    exactly and the first in raster order wins), else in floats.
    """
    n_clusters = starts.shape[0] - 1
    sum_rows = np.zeros(n_clusters, dtype=np.int64)
    sum_cols = np.zeros(n_clusters, dtype=np.int64)
    nearest = np.zeros(n_clusters, dtype=np.int64)
    for k in range(n_clusters):
        begin = starts[k]
        end = starts[k + 1]
        size = end - begin
        for i in range(begin, end):
            sum_rows[k] += rows[i]
            sum_cols[k] += cols[i]
        best = begin
        if size * extent < 2_000_000_000:
            best_score = np.iinfo(np.int64).max
            for i in range(begin, end):
                dev_r = size * rows[i] - sum_rows[k]
                dev_c = size * cols[i] - sum_cols[k]
                score = dev_r * dev_r + dev_c * dev_c
                if score < best_score:
                    best_score = score
                    best = i
        else:
            mean_r = sum_rows[k] / size
            mean_c = sum_cols[k] / size
            best_float = np.inf
            for i in range(begin, end):
                score_f = (rows[i] - mean_r) ** 2 + (cols[i] - mean_c) ** 2
                if score_f < best_float:
                    best_float = score_f
                    best = i
        nearest[k] = best
    return sum_rows, sum_cols, nearest


def frontier_clusters(mask: BoolGrid, *, min_size: int = 1) -> list[FrontierCluster]:
    """Group frontier cells into 8-connected clusters.

    Args:
        mask: ``H x W`` boolean frontier mask (from :func:`frontier_mask`).
        min_size: clusters with fewer cells are dropped.

    Returns:
        Clusters ordered by their first cell in raster order.

    Example:
        >>> import numpy as np
        >>> mask = np.array([[1, 0, 0, 1], [0, 1, 0, 1]], dtype=bool)
        >>> [(c.size, c.representative) for c in frontier_clusters(mask)]
        [(2, (0, 0)), (2, (0, 3))]
    """
    grid = as_bool_grid(mask, "mask")
    if min_size < 1:
        raise MrexploreInputError(f"min_size must be >= 1 cell, got {min_size}")
    height, width = grid.shape
    flat = grid.reshape(-1)
    cells = _mask_cells_kernel(flat, flat[: flat.shape[0] // 8 * 8].view(np.uint64))
    if cells.shape[0] == 0:
        return []
    grouped, starts = _cluster_kernel(flat, height, width, cells)
    n_labels = starts.shape[0] - 1
    rows, cols = np.divmod(grouped, width)
    sum_rows, sum_cols, nearest = _cluster_summary_kernel(rows, cols, starts, max(height, width))
    all_cells = np.stack([rows, cols], axis=1).astype(np.int32)
    all_cells.setflags(write=False)
    bounds = starts.tolist()
    best_rows, best_cols = rows[nearest].tolist(), cols[nearest].tolist()
    row_sums, col_sums = sum_rows.tolist(), sum_cols.tolist()
    clusters: list[FrontierCluster] = []
    for label in range(n_labels):
        begin, end = bounds[label], bounds[label + 1]
        size = end - begin
        if size < min_size:
            continue
        clusters.append(
            FrontierCluster(
                cells=all_cells[begin:end],
                size=size,
                representative=(best_rows[label], best_cols[label]),
                centroid=(row_sums[label] / size, col_sums[label] / size),
            )
        )
    return clusters
