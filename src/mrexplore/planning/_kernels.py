"""The bucket-queue Dijkstra shared by :mod:`mrexplore.planning`'s searches.

:func:`~mrexplore.planning.distance.distance_field_kernel` (passability from a
boolean grid, stop at targets or a distance) and the nearest-frontier search of
:mod:`~mrexplore.planning.frontier_search` (passability read from the belief, stop
at the first frontier band) are one search with different passability and stop
rules; :func:`bucket_search` is that search, written once, so both give the same
distances in the same order. See :mod:`~mrexplore.planning.distance` for why three
circular buckets of width 1 cell give exact distances.

The eight relaxations are written out in the loop: a helper taking the arrays
costs reference-count updates per call, even inlined (measured 6-10x slower), and a
loop over directions was 20% slower at 2000 x 2000.

Units: cells (8-connected, straight step 1, diagonal ``sqrt(2)``, no corner cutting).
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

SETTLED = np.uint8(4)
"""``state`` value of a settled cell; 1..3 mean "last pushed to bucket slot 0..2"."""


@numba.njit(cache=True, nogil=True)
def bucket_search(
    grid: npt.NDArray[np.bool_] | npt.NDArray[np.int8],
    open_value: bool | int,
    height: int,
    width: int,
    source: int,
    targets: npt.NDArray[np.bool_],
    n_targets: int,
    max_distance: float,
    find_frontier: bool,
    dist: npt.NDArray[np.float64],
    state: npt.NDArray[np.uint8],
    buckets: npt.NDArray[np.int32],
    order: npt.NDArray[np.int32],
) -> tuple[int, int]:  # pragma: no cover - compiled
    """Bucket-queue Dijkstra from ``source`` on a flat grid; all arrays trusted.

    Args:
        grid: flat (row-major) grid; a cell is passable when it equals
            ``open_value`` (``True`` in a passability grid, ``FREE`` in a belief).
            The source is always passable.
        height, width: grid shape, cells.
        source: flat index ``row * width + col``.
        targets, n_targets: a flat mask of cells of interest (or an empty array)
            and how many of them must be settled before stopping early.
        max_distance: cells farther than this (cells) are left unsettled.
        find_frontier: also stop after the band in which the first frontier cell
            other than the source is settled (an open cell with a 4-neighbour equal
            to ``-1``, ``UNKNOWN``), and return the frontier cell of least
            distance, then least index.
        dist: output, all ``inf`` on entry; on return the exact distance of every
            settled cell, ``inf`` elsewhere.
        state: scratch, all zero on entry; on return ``SETTLED`` on settled cells
            and zero elsewhere.
        buckets: scratch ``(3, height * width)``, any content.
        order: output: the settled cells in the order they were settled, or an
            empty array not to record them.

    Returns:
        ``(settled, goal)``: how many cells were settled, and the flat index of the
        chosen frontier cell (``-1`` if none or without ``find_frontier``).

    When the search stops early it first finishes the bucket it is in, so the
    settled set is always "every cell closer than some threshold": any settled
    cell's shortest-path predecessors are settled too.
    """
    counts = np.zeros(3, dtype=np.int64)
    use_targets = targets.shape[0] > 0
    remaining = n_targets
    stop = use_targets and remaining <= 0
    inv_width = 1.0 / width
    record_order = order.shape[0] > 0
    # The source is passable even when the grid says otherwise; testing for it only
    # then keeps the common case to one comparison per neighbour.
    source_blocked = grid[source] != open_value
    goal = -1
    goal_dist = np.inf

    dist[source] = 0.0
    buckets[0, 0] = source
    counts[0] = 1
    state[source] = 1
    pending = 1  # entries in all buckets, stale ones included
    settled = 0
    key = 0
    while pending > 0:
        slot = key % 3
        n_in_bucket = counts[slot]
        if n_in_bucket == 0:
            key += 1
            continue
        if key > max_distance:
            break
        # Relaxing from key k gives keys in [k + 1, k + 1 + sqrt(2)) < k + 3:
        # bucket k + 1 when below k + 2, else bucket k + 2. Nothing is pushed to
        # this bucket while we scan it, so ``n_in_bucket`` stays valid.
        next_slot = (slot + 1) % 3
        after_slot = (slot + 2) % 3
        next_key_end = key + 2.0
        for i in range(n_in_bucket):
            u = buckets[slot, i]
            if state[u] == SETTLED:
                continue  # stale entry: u was settled from a lower bucket
            d = dist[u]
            if d > max_distance:
                stop = True  # leave u queued; reset to inf below
                continue
            state[u] = SETTLED
            settled += 1
            if record_order:
                order[settled - 1] = u
            if use_targets and targets[u]:
                remaining -= 1
                if remaining <= 0:
                    stop = True  # finish this bucket, then stop
            # Exact for any grid that fits in memory: (u + 0.5) / width is at least
            # 0.5 / width away from an integer, far above the rounding error.
            row = int((u + 0.5) * inv_width)
            col = u - row * width
            if find_frontier and u != source and grid[u] == open_value:
                if (
                    (row > 0 and grid[u - width] == -1)
                    or (row < height - 1 and grid[u + width] == -1)
                    or (col > 0 and grid[u - 1] == -1)
                    or (col < width - 1 and grid[u + 1] == -1)
                ):
                    stop = True  # finish this band, then stop
                    if d < goal_dist or (d == goal_dist and u < goal):
                        goal_dist = d
                        goal = u
            up = row > 0 and (
                grid[u - width] == open_value or (source_blocked and u - width == source)
            )
            down = row < height - 1 and (
                grid[u + width] == open_value or (source_blocked and u + width == source)
            )
            left = col > 0 and (grid[u - 1] == open_value or (source_blocked and u - 1 == source))
            right = col < width - 1 and (
                grid[u + 1] == open_value or (source_blocked and u + 1 == source)
            )
            straight = d + 1.0
            diagonal = d + 1.4142135623730951
            # The eight relaxations are written out (see the module's docstring).
            # A settled v has dist[v] < key + 1 <= the new distance: never updated.
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
            if (
                up
                and left
                and (
                    grid[u - width - 1] == open_value
                    or (source_blocked and u - width - 1 == source)
                )
            ):
                v = u - width - 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if (
                up
                and right
                and (
                    grid[u - width + 1] == open_value
                    or (source_blocked and u - width + 1 == source)
                )
            ):
                v = u - width + 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if (
                down
                and left
                and (
                    grid[u + width - 1] == open_value
                    or (source_blocked and u + width - 1 == source)
                )
            ):
                v = u + width - 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if (
                down
                and right
                and (
                    grid[u + width + 1] == open_value
                    or (source_blocked and u + width + 1 == source)
                )
            ):
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
    # Tentative distances of cells still queued are not final: reset them (and
    # their state, so that only settled cells are marked).
    for slot in range(3):
        for i in range(counts[slot]):
            u = buckets[slot, i]
            if state[u] != SETTLED:
                dist[u] = np.inf
                state[u] = 0
    return settled, goal
