"""The nearest reachable frontier cell and the path to it, in one compiled search.

:func:`nearest_frontier` gives exactly what this sequence gives (same goal, same
path, bit for bit)::

    frontier = frontier_mask(belief)
    targets = frontier.copy(); targets[source] = False
    dist = distance_field(belief == FREE, source, targets=targets, stop_after=1)
    # goal: the reachable frontier cell (not the source) of least distance, the
    # first in raster order among ties; path: extract_path(dist, goal)

but without any pass over the whole map: the bucket-queue Dijkstra of
:func:`~mrexplore.planning.distance.distance_field_kernel` reads the belief
directly (a cell is passable when it is ``FREE``; the source always is), tests the
frontier rule (``FREE`` with an ``UNKNOWN`` 4-neighbour) only on the cells it
settles, and stops after the distance band of width 1 cell in which the first
frontier cell is settled. Its buffers are kept between calls (one set per grid
shape and thread) and only the cells a search touched are reset afterwards, so a
call costs time in proportion to the area it searched, not to the map.

When no frontier cell is reachable the search covers the source's whole component
and the result is ``None``, as with the sequence above (which also returns no goal
when the map has no frontier at all).

Units: distances in cells (8-connected, diagonal ``sqrt(2)``, no corner cutting).
"""

from __future__ import annotations

import threading
from collections import OrderedDict

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.grid.occupancy import BeliefGrid
from mrexplore.planning._validate import as_belief_grid, as_cell
from mrexplore.planning.distance import count_field, extract_path

__all__ = ["nearest_frontier"]

_SETTLED = np.uint8(4)
_MAX_WORKSPACES = 4
"""Buffer sets kept per thread (one per grid shape, least recently used dropped)."""


@numba.njit(cache=True, nogil=True)
def _nearest_frontier_kernel(
    belief: npt.NDArray[np.int8],
    height: int,
    width: int,
    source: int,
    dist: npt.NDArray[np.float64],
    state: npt.NDArray[np.uint8],
    buckets: npt.NDArray[np.int32],
    order: npt.NDArray[np.int32],
) -> tuple[int, int]:  # pragma: no cover - compiled
    """Bucket-queue Dijkstra from ``source`` over ``FREE`` cells of the flat ``belief``.

    The relaxation is that of :func:`~mrexplore.planning.distance.distance_field_kernel`
    (same order, same float64 sums, so the same distances). Stops after the band in
    which the first frontier cell other than the source is settled.

    Args:
        dist: all ``inf`` on entry; on return the distance of every settled cell,
            ``inf`` elsewhere. The caller resets ``dist[order[:settled]]`` to ``inf``.
        state: all zero on entry and on return.
        buckets: scratch ``(3, height * width)``.
        order: output: the settled cells, in the order they were settled.

    Returns:
        ``(settled, goal)``: how many cells were settled and the flat index of the
        chosen frontier cell (least distance, then least index), ``-1`` if none.
    """
    counts = np.zeros(3, dtype=np.int64)
    inv_width = 1.0 / width
    dist[source] = 0.0
    buckets[0, 0] = source
    counts[0] = 1
    state[source] = 1
    pending = 1
    settled = 0
    key = 0
    stop = False
    goal = -1
    goal_dist = np.inf
    while pending > 0:
        slot = key % 3
        n_in_bucket = counts[slot]
        if n_in_bucket == 0:
            key += 1
            continue
        next_slot = (slot + 1) % 3
        after_slot = (slot + 2) % 3
        next_key_end = key + 2.0
        for i in range(n_in_bucket):
            u = buckets[slot, i]
            if state[u] == _SETTLED:
                continue
            d = dist[u]
            state[u] = _SETTLED
            order[settled] = u
            settled += 1
            row = int((u + 0.5) * inv_width)
            col = u - row * width
            if u != source and belief[u] == 0:
                if (
                    (row > 0 and belief[u - width] == -1)
                    or (row < height - 1 and belief[u + width] == -1)
                    or (col > 0 and belief[u - 1] == -1)
                    or (col < width - 1 and belief[u + 1] == -1)
                ):
                    stop = True  # finish this band, then stop
                    if d < goal_dist or (d == goal_dist and u < goal):
                        goal_dist = d
                        goal = u
            up = row > 0 and (belief[u - width] == 0 or u - width == source)
            down = row < height - 1 and (belief[u + width] == 0 or u + width == source)
            left = col > 0 and (belief[u - 1] == 0 or u - 1 == source)
            right = col < width - 1 and (belief[u + 1] == 0 or u + 1 == source)
            straight = d + 1.0
            diagonal = d + 1.4142135623730951
            if up:
                v = u - width
                if straight < dist[v]:
                    dist[v] = straight
                    slot_v = next_slot if straight < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if down:
                v = u + width
                if straight < dist[v]:
                    dist[v] = straight
                    slot_v = next_slot if straight < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if left:
                v = u - 1
                if straight < dist[v]:
                    dist[v] = straight
                    slot_v = next_slot if straight < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if right:
                v = u + 1
                if straight < dist[v]:
                    dist[v] = straight
                    slot_v = next_slot if straight < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if up and left and (belief[u - width - 1] == 0 or u - width - 1 == source):
                v = u - width - 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if up and right and (belief[u - width + 1] == 0 or u - width + 1 == source):
                v = u - width + 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if down and left and (belief[u + width - 1] == 0 or u + width - 1 == source):
                v = u + width - 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if down and right and (belief[u + width + 1] == 0 or u + width + 1 == source):
                v = u + width + 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
        if stop:
            break
        pending -= n_in_bucket
        counts[slot] = 0
        key += 1
    # Queued but unsettled cells: tentative distances back to inf, state back to 0.
    for slot in range(3):
        for i in range(counts[slot]):
            u = buckets[slot, i]
            if state[u] != _SETTLED:
                dist[u] = np.inf
                state[u] = 0
    for i in range(settled):
        state[order[i]] = 0
    return settled, goal


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
    settled, goal = _nearest_frontier_kernel(
        flat,
        height,
        width,
        row * width + col,
        space.dist,
        space.state,
        space.buckets,
        space.order,
    )
    try:
        if goal < 0:
            return None
        goal_cell = (goal // width, goal % width)
        path = extract_path(space.dist.reshape(height, width), goal_cell)
    finally:
        space.dist[space.order[:settled]] = np.inf
    return goal_cell, path
