"""What one robot's observation is made of: pure functions of what the robot knows.

Every function here takes the robot's own belief map (``int8``: ``UNKNOWN = -1``,
``FREE = 0``, ``OCCUPIED = 100``) and its own cell; none sees ground truth. They
need numpy only (no gymnasium), so they can be tested and reused on their own.

Units: cells. Cells are ``(row, col)``; row 0 is the top of the map.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.grid.occupancy import FREE, OCCUPIED, BeliefGrid
from mrexplore.planning import distance_field, frontier_clusters, frontier_mask

Cell = tuple[int, int]

#: Codes of the egocentric map crop (``obs["map"]``).
CROP_UNKNOWN, CROP_FREE, CROP_OCCUPIED, CROP_OUTSIDE = 0, 1, 2, 3

#: ``move`` mode actions: index -> ``(d_row, d_col)``. 0 stays; 1-8 go N, NE, E,
#: SE, S, SW, W, NW (clockwise from north; north = row - 1).
MOVES: tuple[tuple[int, int], ...] = (
    (0, 0),
    (-1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
    (1, 0),
    (1, -1),
    (0, -1),
    (-1, -1),
)
MOVE_NAMES = ("stay", "N", "NE", "E", "SE", "S", "SW", "W", "NW")

# Belief value seen as uint8 (-1 -> 255) -> crop code.
_CROP_CODES = np.full(256, CROP_UNKNOWN, dtype=np.uint8)
_CROP_CODES[FREE] = CROP_FREE
_CROP_CODES[OCCUPIED] = CROP_OCCUPIED


def egocentric_crop(belief: BeliefGrid, position: Cell, radius: int) -> npt.NDArray[np.uint8]:
    """The ``(2 radius + 1)`` square of the belief centred on ``position``, as crop codes.

    Codes: 0 unknown, 1 free, 2 occupied, 3 outside the map. The robot is at the
    centre ``[radius, radius]``; rows and columns keep the map's orientation.

    >>> belief = np.array([[0, 100], [-1, 0]], dtype=np.int8)
    >>> egocentric_crop(belief, (0, 0), 1).tolist()
    [[3, 3, 3], [3, 1, 2], [3, 0, 1]]
    """
    height, width = belief.shape
    side = 2 * radius + 1
    out = np.full((side, side), CROP_OUTSIDE, dtype=np.uint8)
    row, col = position
    top, left = row - radius, col - radius
    r0, r1 = max(top, 0), min(row + radius + 1, height)
    c0, c1 = max(left, 0), min(col + radius + 1, width)
    if r0 < r1 and c0 < c1:
        window = belief[r0:r1, c0:c1].view(np.uint8)
        out[r0 - top : r1 - top, c0 - left : c1 - left] = _CROP_CODES[window]
    return out


@dataclass(frozen=True)
class CoarseGrid:
    """How an ``H x W`` map is cut into ``size x size`` blocks for :func:`coarse_map`.

    Block ``i`` covers rows ``row_starts[i] : row_starts[i] + row_counts[i]``
    (likewise for columns): ``floor(i H / size)`` onwards, so blocks differ in size
    by at most one cell; when the map is smaller than ``size`` a cell is repeated.
    """

    size: int
    row_starts: npt.NDArray[np.intp]
    row_counts: npt.NDArray[np.intp]
    col_starts: npt.NDArray[np.intp]
    col_counts: npt.NDArray[np.intp]

    @classmethod
    def for_shape(cls, shape: tuple[int, int], size: int) -> CoarseGrid:
        """The blocks of an ``H x W`` map for a ``size x size`` coarse map."""
        row_starts, row_counts = _block_edges(shape[0], size)
        col_starts, col_counts = _block_edges(shape[1], size)
        return cls(size, row_starts, row_counts, col_starts, col_counts)


def _block_edges(length: int, blocks: int) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.intp]]:
    starts = (np.arange(blocks, dtype=np.intp) * length) // blocks
    counts = np.diff(np.append(starts, length))
    counts[counts == 0] = 1  # a map side shorter than the grid: the cell is repeated
    return starts, counts


@numba.njit(cache=True, nogil=True)
def _coarse_counts_kernel(
    belief: npt.NDArray[np.int8],
    row_starts: npt.NDArray[np.intp],
    row_counts: npt.NDArray[np.intp],
    col_starts: npt.NDArray[np.intp],
    col_counts: npt.NDArray[np.intp],
    out: npt.NDArray[np.float32],
) -> None:  # pragma: no cover - compiled
    """Share of known-free (``out[0]``) and known-occupied (``out[1]``) cells per block."""
    for bi in range(row_starts.shape[0]):
        for bj in range(col_starts.shape[0]):
            n_free = 0
            n_occupied = 0
            for r in range(row_starts[bi], row_starts[bi] + row_counts[bi]):
                for c in range(col_starts[bj], col_starts[bj] + col_counts[bj]):
                    value = belief[r, c]
                    if value == FREE:
                        n_free += 1
                    elif value == OCCUPIED:
                        n_occupied += 1
            area = row_counts[bi] * col_counts[bj]
            out[0, bi, bj] = n_free / area
            out[1, bi, bj] = n_occupied / area


def coarse_map(belief: BeliefGrid, grid: CoarseGrid) -> npt.NDArray[np.float32]:
    """The whole belief at low resolution: ``(2, size, size)`` fractions in ``[0, 1]``.

    Channel 0 is the share of each block's cells the robot knows to be free,
    channel 1 the share it knows to be occupied; the rest is unknown.

    >>> belief = np.array([[0, 0], [100, -1]], dtype=np.int8)
    >>> coarse_map(belief, CoarseGrid.for_shape(belief.shape, 1)).ravel().tolist()
    [0.5, 0.25]
    """
    out = np.empty((2, grid.size, grid.size), dtype=np.float32)
    _coarse_counts_kernel(
        belief, grid.row_starts, grid.row_counts, grid.col_starts, grid.col_counts, out
    )
    return out


def move_target(belief: BeliefGrid, position: Cell, action: int) -> Cell | None:
    """The cell that ``move`` action ``action`` (1-8) leads to, or ``None`` if it is invalid.

    A move is valid when the neighbour lies on the map and is known free, and,
    for a diagonal, both cells beside the diagonal are known free (no corner
    cutting), exactly the rule the simulator's paths obey. Other robots do not
    make a move invalid: a robot whose cell is held waits (see ``docs/env.md``).

    >>> belief = np.array([[0, 0], [100, 0]], dtype=np.int8)
    >>> move_target(belief, (0, 0), 3), move_target(belief, (0, 0), 4)
    ((0, 1), None)
    """
    d_row, d_col = MOVES[action]
    row, col = position[0] + d_row, position[1] + d_col
    height, width = belief.shape
    if not (0 <= row < height and 0 <= col < width) or belief[row, col] != FREE:
        return None
    if d_row and d_col and (belief[row, position[1]] != FREE or belief[position[0], col] != FREE):
        return None
    return (row, col)


def move_mask(belief: BeliefGrid, position: Cell) -> npt.NDArray[np.int8]:
    """``(9,)`` int8 mask of the valid ``move`` actions; ``stay`` (0) is always valid.

    >>> belief = np.array([[0, 0], [100, 0]], dtype=np.int8)
    >>> move_mask(belief, (0, 0)).tolist()
    [1, 0, 0, 1, 0, 0, 0, 0, 0]
    """
    mask = np.zeros(len(MOVES), dtype=np.int8)
    mask[0] = 1
    for action in range(1, len(MOVES)):
        if move_target(belief, position, action) is not None:
            mask[action] = 1
    return mask


@dataclass(frozen=True)
class Candidate:
    """One frontier cluster the robot may choose in ``frontier`` mode.

    Attributes:
        target: the cell the robot is sent to: among the cluster's cells that it
            can reach (finite path over known-free cells, not its own cell), the one
            nearest to the cluster's centroid (Euclidean; ties: first in raster
            order). It is the cluster's ``representative`` whenever that is reachable.
        distance: shortest path length to ``target`` over known-free cells (cells).
        size: number of frontier cells in the cluster.
    """

    target: Cell
    distance: float
    size: int


def frontier_candidates(
    belief: BeliefGrid, position: Cell, limit: int, *, min_cluster_size: int = 1
) -> list[Candidate]:
    """The ``limit`` nearest reachable frontier clusters of the robot's own belief.

    Clusters are the 8-connected groups of frontier cells
    (:func:`mrexplore.planning.frontier_clusters`, at least ``min_cluster_size``
    cells). A cluster with no reachable cell is left out. Candidates are ordered by
    path distance to their target, ties broken by the target cell in raster order,
    and cut after ``limit``.

    >>> belief = np.full((3, 5), -1, dtype=np.int8)
    >>> belief[1, :3] = 0
    >>> [(c.target, c.distance, c.size) for c in frontier_candidates(belief, (1, 0), 4)]
    [((1, 1), 1.0, 3)]
    """
    frontier = frontier_mask(belief)
    clusters = frontier_clusters(frontier, min_size=min_cluster_size)
    if not clusters:
        return []
    dist = distance_field(belief == FREE, position, targets=frontier)
    found: list[Candidate] = []
    for cluster in clusters:
        cells = cluster.cells
        at = dist[cells[:, 0], cells[:, 1]]
        reachable = np.isfinite(at) & (at > 0)
        if not reachable.any():
            continue
        offsets = cells[reachable] - np.asarray(cluster.centroid)
        best = int(np.argmin(np.einsum("ij,ij->i", offsets, offsets)))
        row, col = (int(v) for v in cells[reachable][best])
        found.append(Candidate((row, col), float(at[reachable][best]), cluster.size))
    found.sort(key=lambda c: (c.distance, c.target))
    return found[:limit]


def candidate_features(
    candidates: list[Candidate], position: Cell, limit: int
) -> npt.NDArray[np.float32]:
    """``(limit, 5)`` rows ``[valid, d_row, d_col, distance, size]``; unused rows are 0.

    ``d_row, d_col`` is the target relative to the robot's cell.

    >>> candidate_features([Candidate((3, 1), 2.0, 5)], (1, 1), 2).tolist()
    [[1.0, 2.0, 0.0, 2.0, 5.0], [0.0, 0.0, 0.0, 0.0, 0.0]]
    """
    out = np.zeros((limit, 5), dtype=np.float32)
    for slot, candidate in enumerate(candidates[:limit]):
        out[slot] = (
            1.0,
            candidate.target[0] - position[0],
            candidate.target[1] - position[1],
            candidate.distance,
            candidate.size,
        )
    return out


def max_path_length(shape: tuple[int, int]) -> float:
    """An upper bound on any path length on a map of ``shape`` (cells)."""
    return float(shape[0] * shape[1]) * math.sqrt(2.0)
