"""Exact shortest-path distance fields and path extraction on occupancy grids.

Motion model (shared by the whole simulator): a robot moves between 8-connected
cells; a straight step costs 1 cell, a diagonal step ``sqrt(2)`` cells (exact
float64). Corners are never cut: a diagonal step from ``(r, c)`` to
``(r + dr, c + dc)`` is legal only if both ``(r + dr, c)`` and ``(r, c + dc)`` are
passable. With this rule the cells reachable from a source are exactly its
4-connected component.

:func:`distance_field` runs Dijkstra's algorithm with a bucket queue (Dial's
algorithm generalised to real weights). Buckets have width 1.0, the smallest edge
weight: every node whose key lies in ``[k, k + 1)`` goes to bucket ``k``. Relaxing
an edge from such a node gives a key ``>= k + 1``, so no node of bucket ``k`` can
improve another node of bucket ``k`` and all of them are final when bucket ``k``
is reached, in any order. The result is therefore exact (the same float64 values
as a binary-heap Dijkstra that adds edge weights along the same path), not an
approximation. As the largest edge weight is ``sqrt(2) < 2``, keys pending at any
time span at most three consecutive buckets, so three circular buckets suffice.

Units: distances are in cells (path length, not ticks).
"""

from __future__ import annotations

import contextvars
import math

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError, UnreachableTargetError
from mrexplore.grid.occupancy import BoolGrid
from mrexplore.planning._validate import as_bool_grid, as_cell

__all__ = [
    "SQRT2",
    "FieldCounter",
    "UnreachableTargetError",
    "count_field",
    "distance_field",
    "distance_field_kernel",
    "extract_path",
    "path_length",
]

SQRT2: float = math.sqrt(2.0)
"""Cost of a diagonal step, in cells."""

_SETTLED = np.uint8(4)
"""``state`` value of a settled node; 1..3 mean "last pushed to bucket slot 0..2"."""


class FieldCounter:
    """Counts the distance fields (shortest-path searches) computed while it is active.

    Counts every :func:`distance_field`, every
    :func:`~mrexplore.planning.frontier_search.nearest_frontier` search and every
    direct use of :func:`distance_field_kernel` that reports itself with
    :func:`count_field`, made inside ``with counter:`` (in this thread or task;
    the innermost active counter counts). Outside every counter nothing is counted.
    The simulator owns one per run and activates it around each decision, to tell
    the decisions that searched from those that did not (benchmarks' floor ratio).

    >>> import numpy as np
    >>> counter = FieldCounter()
    >>> with counter:
    ...     _ = distance_field(np.ones((3, 3), dtype=bool), (0, 0))
    >>> counter.count
    1
    """

    __slots__ = ("_tokens", "count")

    def __init__(self) -> None:
        self.count = 0
        self._tokens: list[contextvars.Token[FieldCounter | None]] = []

    def __enter__(self) -> FieldCounter:
        self._tokens.append(_active_counter.set(self))
        return self

    def __exit__(self, *exc_info: object) -> None:
        _active_counter.reset(self._tokens.pop())


_active_counter: contextvars.ContextVar[FieldCounter | None] = contextvars.ContextVar(
    "mrexplore_field_counter", default=None
)


def count_field(n: int = 1) -> None:
    """Add ``n`` fields to the active :class:`FieldCounter`, if any (for callers of the
    raw kernel)."""
    counter = _active_counter.get()
    if counter is not None:
        counter.count += n


@numba.njit(cache=True, nogil=True)
def distance_field_kernel(
    passable: npt.NDArray[np.bool_],
    height: int,
    width: int,
    source: int,
    targets: npt.NDArray[np.bool_],
    n_targets: int,
    max_distance: float,
    dist: npt.NDArray[np.float64],
    state: npt.NDArray[np.uint8],
    buckets: npt.NDArray[np.int32],
) -> int:
    """Bucket-queue Dijkstra on a flat grid; the compiled core of :func:`distance_field`.

    For callers that reuse buffers across many fields. All arrays are flat
    (row-major, length ``height * width``) and trusted (no checks).

    Args:
        passable: ``True`` where a robot may stand; ``passable[source]`` must be
            ``True`` (the wrapper makes a copy when it is not).
        height, width: grid shape, cells.
        source: flat index ``row * width + col`` of the source.
        targets: flat boolean mask of cells of interest, or an empty array for none.
        n_targets: how many target cells must be settled before stopping early
            (targets that can never be settled, e.g. impassable ones, must not be
            counted). Ignored when ``targets`` is empty.
        max_distance: cells whose distance exceeds this (cells) are left unsettled.
        dist: output, must be all ``inf`` on entry; on return holds the exact
            distance (cells) of every settled cell and ``inf`` elsewhere.
        state: scratch, must be all zero on entry. On return, ``4`` marks settled
            cells; other entries are unspecified.
        buckets: scratch of shape ``(3, height * width)``, any content.

    Returns:
        The number of settled cells.

    When the search stops early (targets or ``max_distance``) it first finishes the
    bucket it is in, so the settled set is always "every cell closer than some
    threshold": any settled cell's shortest-path predecessors are settled too.
    """
    counts = np.zeros(3, dtype=np.int64)
    use_targets = targets.shape[0] > 0
    remaining = n_targets
    stop = use_targets and remaining <= 0
    inv_width = 1.0 / width

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
            if state[u] == _SETTLED:
                continue  # stale entry: u was settled from a lower bucket
            d = dist[u]
            if d > max_distance:
                stop = True  # leave u queued; reset to inf below
                continue
            state[u] = _SETTLED
            settled += 1
            if use_targets and targets[u]:
                remaining -= 1
                if remaining <= 0:
                    stop = True  # finish this bucket, then stop
            # Exact for any grid that fits in memory: (u + 0.5) / width is at least
            # 0.5 / width away from an integer, far above the rounding error.
            row = int((u + 0.5) * inv_width)
            col = u - row * width
            up = row > 0 and passable[u - width]
            down = row < height - 1 and passable[u + width]
            left = col > 0 and passable[u - 1]
            right = col < width - 1 and passable[u + 1]
            straight = d + 1.0
            diagonal = d + 1.4142135623730951
            # The eight relaxations are written out: a helper taking the arrays
            # costs reference-count updates per call (measured 10x slower), and a
            # loop over directions was 20% slower at 2000 x 2000.
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
            if up and left and passable[u - width - 1]:
                v = u - width - 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if up and right and passable[u - width + 1]:
                v = u - width + 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if down and left and passable[u + width - 1]:
                v = u + width - 1
                if diagonal < dist[v]:
                    dist[v] = diagonal
                    slot_v = next_slot if diagonal < next_key_end else after_slot
                    if state[v] != slot_v + 1:
                        buckets[slot_v, counts[slot_v]] = v
                        counts[slot_v] += 1
                        state[v] = slot_v + 1
                        pending += 1
            if down and right and passable[u + width + 1]:
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
    # Tentative distances of cells still queued are not final: reset them.
    for slot in range(3):
        for i in range(counts[slot]):
            u = buckets[slot, i]
            if state[u] != _SETTLED:
                dist[u] = np.inf
    return settled


def distance_field(
    passable: BoolGrid,
    source: tuple[int, int],
    *,
    targets: BoolGrid | None = None,
    max_distance: float = math.inf,
    stop_after: int | None = None,
) -> npt.NDArray[np.float64]:
    """Exact 8-connected, no-corner-cutting shortest-path distances from ``source``.

    Args:
        passable: ``H x W`` boolean grid, ``True`` where a robot may stand (for a
            belief map, typically ``belief == FREE``). The source cell is always
            treated as passable.
        source: ``(row, col)`` start cell.
        targets: optional ``H x W`` boolean mask. The search stops as soon as every
            reachable target is settled (after finishing the current distance band
            of width 1 cell); if some target is unreachable the whole component is
            searched. Only passable targets (and the source) count.
        max_distance: cells farther than this (cells) are left at ``inf``.
        stop_after: with ``targets``, stop once this many targets are settled (after
            finishing the current band): ``stop_after=1`` finds the nearest targets.

    Returns:
        ``H x W`` float64 array of path lengths in cells; ``np.inf`` where a cell is
        unreachable or was not settled because of an early stop. Every finite value
        is exact, and the finite cells always include every cell that lies on a
        shortest path to a finite cell, so :func:`extract_path` works on any finite
        cell.

    Raises:
        MrexploreInputError: bad grid, source outside the grid, mismatched targets
            or a negative / NaN ``max_distance``.

    Example:
        >>> import numpy as np
        >>> field = distance_field(np.ones((3, 4), dtype=bool), (0, 0))
        >>> round(float(field[2, 3]), 6)  # 2 diagonal steps + 1 straight step
        3.828427
    """
    grid = as_bool_grid(passable, "passable")
    height, width = grid.shape
    row, col = as_cell(source, grid.shape, "source")
    if math.isnan(max_distance) or max_distance < 0:
        raise MrexploreInputError(f"max_distance must be >= 0 cells, got {max_distance!r}")
    n_cells = height * width
    src = row * width + col
    if targets is None:
        target_flat = np.zeros(0, dtype=np.bool_)
        n_targets = 0
    else:
        target_grid = as_bool_grid(targets, "targets")
        if target_grid.shape != grid.shape:
            raise MrexploreInputError(
                f"targets has shape {target_grid.shape}, passable has {grid.shape}"
            )
        target_flat = target_grid.reshape(-1)
        n_targets = int(np.count_nonzero(target_grid & grid))
        if target_flat[src] and not grid[row, col]:
            n_targets += 1
        if stop_after is not None:
            if stop_after < 1:
                raise MrexploreInputError(f"stop_after must be >= 1, got {stop_after}")
            n_targets = min(n_targets, stop_after)
    flat = grid.reshape(-1)
    if not flat[src]:
        flat = flat.copy()
        flat[src] = True
    count_field()
    dist = np.full(n_cells, np.inf)
    state = np.zeros(n_cells, dtype=np.uint8)
    buckets = np.empty((3, n_cells), dtype=np.int32)
    distance_field_kernel(
        flat,
        height,
        width,
        src,
        target_flat,
        n_targets,
        float(max_distance),
        dist,
        state,
        buckets,
    )
    return dist.reshape(height, width)


@numba.njit(cache=True, nogil=True)
def _extract_path_kernel(
    dist: npt.NDArray[np.float64], row: int, col: int, tolerance: float
) -> npt.NDArray[np.int32]:
    """Walk from ``(row, col)`` down to a cell with distance 0; returns ``(K, 2)`` or ``(0, 2)``.

    An empty result means the walk got stuck (no legal predecessor within
    ``tolerance``), i.e. ``dist`` is not a distance field.
    """
    height, width = dist.shape
    # Upper bound on the path length in cells: every step lowers dist by >= 1 - tol.
    capacity = int(dist[row, col]) + 2
    path = np.empty((capacity, 2), dtype=np.int32)
    n = 0
    path[n, 0] = row
    path[n, 1] = col
    n += 1
    r, c = row, col
    while dist[r, c] != 0.0:
        here = dist[r, c]
        up = r > 0 and dist[r - 1, c] < np.inf
        down = r < height - 1 and dist[r + 1, c] < np.inf
        left = c > 0 and dist[r, c - 1] < np.inf
        right = c < width - 1 and dist[r, c + 1] < np.inf
        best_err = np.inf
        best_r = -1
        best_c = -1
        # Fixed order: N, S, W, E, NW, NE, SW, SE; the first smallest error wins.
        for k in range(8):
            if k == 0:
                ok, nr, nc, cost = up, r - 1, c, 1.0
            elif k == 1:
                ok, nr, nc, cost = down, r + 1, c, 1.0
            elif k == 2:
                ok, nr, nc, cost = left, r, c - 1, 1.0
            elif k == 3:
                ok, nr, nc, cost = right, r, c + 1, 1.0
            elif k == 4:
                ok, nr, nc, cost = up and left, r - 1, c - 1, 1.4142135623730951
            elif k == 5:
                ok, nr, nc, cost = up and right, r - 1, c + 1, 1.4142135623730951
            elif k == 6:
                ok, nr, nc, cost = down and left, r + 1, c - 1, 1.4142135623730951
            else:
                ok, nr, nc, cost = down and right, r + 1, c + 1, 1.4142135623730951
            if not ok:
                continue
            candidate = dist[nr, nc]
            if candidate == np.inf:
                continue
            err = abs(candidate + cost - here)
            if err <= tolerance and err < best_err:
                best_err = err
                best_r = nr
                best_c = nc
                if err == 0.0:
                    break  # exact predecessor: cannot do better
        if best_r < 0 or n >= capacity:
            return np.zeros((0, 2), dtype=np.int32)
        r, c = best_r, best_c
        path[n, 0] = r
        path[n, 1] = c
        n += 1
    out = np.empty((n, 2), dtype=np.int32)
    for i in range(n):
        out[i, 0] = path[n - 1 - i, 0]
        out[i, 1] = path[n - 1 - i, 1]
    return out


def extract_path(dist: npt.NDArray[np.float64], target: tuple[int, int]) -> npt.NDArray[np.int32]:
    """Shortest path from the field's source (the cell with distance 0) to ``target``.

    Walks back from ``target``: at each cell it moves to the legal neighbour ``n``
    (no corner cutting; a cell counts as passable when its distance is finite)
    whose ``dist[n] + step_cost`` matches ``dist[cell]`` best, within 1e-9 cells;
    ties go to the first neighbour in the fixed order N, S, W, E, NW, NE, SW, SE.
    On a field from :func:`distance_field` an exact predecessor always exists, so
    ``path_length(path) == dist[target]`` up to floating-point rounding.

    The target must have been settled (finite distance). Fields stopped early by
    :func:`distance_field` keep every cell on a shortest path to a finite cell, so
    any finite target works.

    Args:
        dist: ``H x W`` distance field (cells) from :func:`distance_field`.
        target: ``(row, col)`` goal cell.

    Returns:
        ``(K, 2)`` int32 array of ``(row, col)``: the source first, ``target`` last.

    Raises:
        UnreachableTargetError: ``dist[target]`` is ``inf`` (unreachable or unsettled).
        MrexploreInputError: bad field or target outside the grid, or ``dist`` is not
            a distance field (no predecessor found).

    Example:
        >>> import numpy as np
        >>> field = distance_field(np.ones((3, 3), dtype=bool), (0, 0))
        >>> extract_path(field, (2, 1)).tolist()
        [[0, 0], [1, 1], [2, 1]]
    """
    field = np.asarray(dist)
    if field.ndim != 2 or field.dtype != np.float64:
        raise MrexploreInputError(
            f"dist must be a 2-D float64 distance field, got {field.dtype} {field.shape}"
        )
    row, col = as_cell(target, field.shape, "target")
    value = field[row, col]
    if not value < np.inf:
        raise UnreachableTargetError(f"target {(row, col)} is unreachable from the source")
    if value < 0 or math.isnan(value):
        raise MrexploreInputError(f"dist[{(row, col)}] = {value} is not a distance")
    path = _extract_path_kernel(np.ascontiguousarray(field), row, col, 1e-9)
    if path.shape[0] == 0:
        raise MrexploreInputError(
            f"dist is not a distance field: no predecessor on the way to {(row, col)}"
        )
    return path


def path_length(path: npt.NDArray[np.integer]) -> float:
    """Length of a path of ``(row, col)`` cells, in cells (1 per straight, sqrt(2) per diagonal).

    Steps are summed from the first cell on, in the same order as
    :func:`distance_field` accumulates them. Consecutive cells must be 8-adjacent.

    Raises:
        MrexploreInputError: ``path`` is not ``(K, 2)`` or has a non-adjacent step.
    """
    cells = np.asarray(path)
    if cells.ndim != 2 or cells.shape[1] != 2:
        raise MrexploreInputError(f"path must have shape (K, 2), got {cells.shape}")
    steps = np.abs(np.diff(cells.astype(np.int64), axis=0))
    if steps.size and (steps.max() > 1 or (steps.sum(axis=1) == 0).any()):
        raise MrexploreInputError("path has a step between cells that are not 8-adjacent")
    total = 0.0
    for is_diagonal in (steps.sum(axis=1) == 2).tolist():
        total += SQRT2 if is_diagonal else 1.0
    return total
