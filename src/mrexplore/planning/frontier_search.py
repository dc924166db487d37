"""The nearest reachable frontier cell and the path to it, in one compiled search.

:func:`nearest_frontier` gives exactly what this sequence gives (same goal, same
path, bit for bit)::

    frontier = frontier_mask(belief)
    targets = frontier.copy(); targets[source] = False
    dist = distance_field(belief == FREE, source, targets=targets, stop_after=1)
    # goal: the reachable frontier cell (not the source) of least distance, the
    # first in raster order among ties; path: extract_path(dist, goal)

but without any pass over the whole map: the bucket-queue Dijkstra behind
:func:`~mrexplore.planning.distance.distance_field_kernel`
(:func:`~mrexplore.planning._kernels.bucket_search`) reads the belief directly (a
cell is passable when it is ``FREE``; the source always is), tests the frontier
rule (``FREE`` with an ``UNKNOWN`` 4-neighbour) only on the cells it settles, and
stops after the distance band of width 1 cell in which the first frontier cell is
settled. Its buffers are kept between calls (one set per grid shape and thread) and
only the cells a search touched are reset afterwards, so a call costs time in
proportion to the area it searched, not to the map.

When no frontier cell is reachable the search covers the source's whole component
and the result is ``None``, as with the sequence above (which also returns no goal
when the map has no frontier at all).

Units: distances in cells (8-connected, diagonal ``sqrt(2)``, no corner cutting).
"""

from __future__ import annotations

import threading
from collections import OrderedDict

import numpy as np
import numpy.typing as npt

from mrexplore.grid.occupancy import BeliefGrid
from mrexplore.planning._kernels import bucket_search
from mrexplore.planning._validate import as_belief_grid, as_cell
from mrexplore.planning.distance import count_field, extract_path

__all__ = ["nearest_frontier"]

_NO_TARGETS = np.zeros(0, dtype=np.bool_)
_MAX_WORKSPACES = 4
"""Buffer sets kept per thread (one per grid shape, least recently used dropped)."""


class _Workspace:
    """Buffers of one grid shape, kept clean between searches."""

    def __init__(self, n_cells: int) -> None:
        self.dist = np.full(n_cells, np.inf)
        self.state = np.zeros(n_cells, dtype=np.uint8)
        self.buckets = np.empty((3, n_cells), dtype=np.int32)
        self.order = np.empty(n_cells, dtype=np.int32)


_local = threading.local()


def _workspace(shape: tuple[int, int]) -> _Workspace:
    cache: OrderedDict[tuple[int, int], _Workspace] | None = getattr(_local, "cache", None)
    if cache is None:
        cache = _local.cache = OrderedDict()
    space = cache.pop(shape, None)
    if space is None:
        space = _Workspace(shape[0] * shape[1])
        while len(cache) >= _MAX_WORKSPACES:
            cache.popitem(last=False)
    cache[shape] = space
    return space


def nearest_frontier(
    belief: BeliefGrid, source: tuple[int, int]
) -> tuple[tuple[int, int], npt.NDArray[np.int32]] | None:
    """The nearest reachable frontier cell of ``belief`` and the shortest path to it.

    Args:
        belief: ``H x W`` int8 belief (``UNKNOWN``/``FREE``/``OCCUPIED``).
        source: the robot's cell ``(row, col)``; always treated as passable and
            never chosen itself.

    Returns:
        ``(goal, path)`` with ``path`` a ``(K, 2)`` int32 array from ``source`` to
        ``goal`` (as :func:`~mrexplore.planning.extract_path` gives it), or ``None``
        when no frontier cell other than ``source`` is reachable.

    Example:
        >>> import numpy as np
        >>> belief = np.zeros((3, 5), dtype=np.int8)
        >>> belief[:, 4] = -1  # unknown column on the right
        >>> goal, path = nearest_frontier(belief, (1, 0))
        >>> goal, path.tolist()
        ((1, 3), [[1, 0], [1, 1], [1, 2], [1, 3]])
    """
    grid = as_belief_grid(belief)
    row, col = as_cell(source, grid.shape, "source")
    height, width = grid.shape
    space = _workspace((height, width))
    flat = np.ascontiguousarray(grid).reshape(-1)
    count_field()
    # The bucket search with FREE (0) cells passable, stopping after the band in
    # which the first frontier cell other than the source is settled.
    settled, goal = bucket_search(
        flat,
        0,
        height,
        width,
        row * width + col,
        _NO_TARGETS,
        0,
        np.inf,
        True,
        space.dist,
        space.state,
        space.buckets,
        space.order,
    )
    touched = space.order[:settled]
    space.state[touched] = 0  # bucket_search left the other cells at 0
    try:
        if goal < 0:
            return None
        goal_cell = (goal // width, goal % width)
        path = extract_path(space.dist.reshape(height, width), goal_cell)
    finally:
        space.dist[touched] = np.inf
    return goal_cell, path
