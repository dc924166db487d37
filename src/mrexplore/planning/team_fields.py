"""Shortest-path costs from every robot of a team to every target, paths to one goal
and reachability, in reused buffers: the distance work of the centralised and market
strategies.

A strategy that weighs every (robot, target) pair needs one distance field per robot
(:func:`~mrexplore.planning.distance.distance_field` from the robot, read at every
target). This module computes exactly those values, bit for bit, with less around
the searches:

* **Buffers kept per thread** (:class:`TeamBuffers`): an ``H x W`` field written
  into fresh memory pays a page fault per 4 KiB page, as much as a tenth of a search
  at 685 x 744 cells. The buffers are reset in place after each search.
* **Stop at the farthest reachable target**: :func:`distance_field` with ``targets``
  stops once every *reachable* target is settled, but it cannot know which are
  reachable, so one unreachable target (a frontier cell seen across a corner and cut
  off from known-free space) makes it search the source's whole component. Cells a
  robot can reach are exactly its 4-connected component (no corner cutting), so
  after the first field of a component every other source settled in it needs only
  the targets that field reached: its search stops at its farthest one. The values
  read at the targets do not depend on where a search stops (every settled value
  is exact: the float64 sums along the best path, the unique fixed point of the
  bucket Dijkstra), so the costs are those of :func:`distance_field`.
* **One compiled pass** for all sources: search, read the targets, reset.
* **No distances when only reachability is used** (:func:`reachable`): a
  breadth-first flood of the source's 4-connected component gives exactly which
  targets have a finite distance, at a fraction of a field's cost.

Every distance search is counted by :func:`~mrexplore.planning.distance.count_field`
(a :func:`reachable` flood is not a distance field and is not counted).

Units: distances in cells; flat indices are ``row * W + col``.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Sequence

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.planning.distance import count_field, distance_field_kernel, extract_path

__all__ = [
    "Components",
    "TeamBuffers",
    "reachable",
    "team_costs",
    "workspace",
    "workspace_path",
]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]


class TeamBuffers:
    """The buffers of :func:`~mrexplore.planning.distance.distance_field_kernel` for
    grids of ``n_cells`` cells, in their state between searches: ``dist`` all ``inf``,
    ``state`` all zero, ``targets`` all ``False``; ``buckets`` is scratch.

    Plain buffers for the all-sources pass of :func:`team_costs_kernel`, which resets
    by rows; :class:`mrexplore.planning.multi_fields.FieldWorkspace` is the one-search-
    at-a-time workspace that resets only the cells a search touched.
    """

    __slots__ = ("buckets", "dist", "n_cells", "state", "targets")

    def __init__(self, n_cells: int) -> None:
        self.n_cells = n_cells
        self.dist = np.full(n_cells, np.inf)
        self.state = np.zeros(n_cells, dtype=np.uint8)
        self.buckets = np.empty((3, n_cells), dtype=np.int32)
        self.targets = np.zeros(n_cells, dtype=np.bool_)


_local = threading.local()


def workspace(n_cells: int) -> TeamBuffers:
    """This thread's :class:`TeamBuffers` for grids of ``n_cells`` cells (kept for
    the next call; one grid size at a time)."""
    kept: TeamBuffers | None = getattr(_local, "workspace", None)
    if kept is None or kept.n_cells != n_cells:
        kept = _local.workspace = TeamBuffers(n_cells)
    return kept


@numba.njit(cache=True, nogil=True)
def _reset(
    dist: FloatArray,
    state: npt.NDArray[np.uint8],
    height: int,
    width: int,
    row: int,
    farthest: float,
) -> None:
    """Back to ``inf`` / zero after a search from a cell of ``row`` that stopped once it
    had settled its targets, the farthest at ``farthest`` cells (``inf``: the search may
    have run through its whole component, reset everything).

    A search stopping at ``D`` finishes the band ``[floor(D), floor(D) + 1)`` and queues
    cells at most one diagonal step beyond, so every cell it touched lies within
    ``D + 1 + sqrt(2)`` steps, hence within as many rows, of the source: only those rows
    are written (a near goal then costs a few rows, not the whole grid).
    """
    if farthest < np.inf:
        reach = math.ceil(farthest) + 3
        first = max(row - reach, 0) * width
        last = min(row + reach + 1, height) * width
    else:
        first = 0
        last = height * width
    dist[first:last] = np.inf
    state[first:last] = 0


@numba.njit(cache=True, nogil=True)
def team_costs_kernel(
    passable: BoolArray,
    height: int,
    width: int,
    sources: IntArray,
    target_mask: BoolArray,
    target_index: IntArray,
    dist: FloatArray,
    state: npt.NDArray[np.uint8],
    buckets: npt.NDArray[np.int32],
    out: FloatArray,
) -> int:
    """For each source ``s = sources[i]``, ``out[i, j]`` = the distance from ``s`` to
    ``target_index[j]`` (``inf`` when unreachable), as :func:`distance_field` gives it.

    Args:
        passable: flat grid, ``True`` where a robot may stand. A source on a cell
            that is not passable counts as passable during its own search (as in
            :func:`distance_field`); the array is restored before returning.
        height, width: grid shape, cells.
        sources: flat indices of the sources.
        target_mask: flat mask, ``True`` exactly at the cells of ``target_index``.
        target_index: flat indices of the targets, each once.
        dist, state, buckets: a :class:`TeamBuffers`'s buffers (left reset).
        out: ``(len(sources), len(target_index))`` float64, written.

    Returns:
        The number of searches run (one per source).
    """
    n_sources = sources.shape[0]
    n_targets = target_index.shape[0]
    passable_targets = 0
    for j in range(n_targets):
        if passable[target_index[j]]:
            passable_targets += 1
    # Reachable targets of a source, once a field of its component has told: -1 = unknown.
    known = np.full(n_sources, -1, dtype=np.int64)
    for i in range(n_sources):
        src = sources[i]
        toggled = not passable[src]
        if toggled:
            passable[src] = True
            need = passable_targets + (1 if target_mask[src] else 0)
        elif known[i] >= 0:
            need = known[i]
        else:
            need = passable_targets
        distance_field_kernel(
            passable, height, width, src, target_mask, need, np.inf, dist, state, buckets
        )
        reached = 0
        farthest = 0.0
        for j in range(n_targets):
            value = dist[target_index[j]]
            out[i, j] = value
            if value < np.inf:
                reached += 1
                farthest = max(farthest, value)
        if toggled:
            passable[src] = False
        else:
            # A passable source settled here lies in this component: it reaches the
            # same targets (reachable cells are the 4-connected component).
            for k in range(i + 1, n_sources):
                other = sources[k]
                if known[k] < 0 and passable[other] and dist[other] < np.inf:
                    known[k] = reached
        # reached == need: the search stopped at its farthest target (see _reset).
        _reset(dist, state, height, width, src // width, farthest if reached >= need else np.inf)
    return n_sources


def team_costs(
    passable: BoolArray, sources: Sequence[tuple[int, int]], target_index: IntArray
) -> FloatArray:
    """Distances (cells) from each source to each target: ``out[i, j]`` equals
    ``distance_field(passable, sources[i], targets=mask)[target j]`` bit for bit, where
    ``mask`` holds every target; ``inf`` where a target is out of reach.

    Inputs are trusted (the inner-kernel contract): ``passable`` an ``H x W`` bool
    grid, sources inside it, ``target_index`` distinct flat indices ``row * W + col``.
    One field per source is counted (:func:`count_field`).

    >>> free = np.ones((3, 4), dtype=bool)
    >>> team_costs(free, [(0, 0), (2, 3)], np.array([3, 11])).round(3).tolist()
    [[3.0, 3.828], [2.0, 0.0]]
    """
    height, width = passable.shape
    flat = np.array(passable, dtype=np.bool_, copy=True).reshape(-1)  # toggled in place
    space = workspace(height * width)
    index = np.ascontiguousarray(target_index, dtype=np.int64)
    out = np.empty((len(sources), index.shape[0]))
    if not len(sources):
        return out
    src = np.array([int(r) * width + int(c) for r, c in sources], dtype=np.int64)
    space.targets[index] = True
    try:
        count_field(len(sources))
        team_costs_kernel(
            flat,
            height,
            width,
            src,
            space.targets,
            index,
            space.dist,
            space.state,
            space.buckets,
            out,
        )
    finally:
        space.targets[index] = False
    return out


def workspace_path(
    passable: BoolArray, start: tuple[int, int], goal: tuple[int, int]
) -> npt.NDArray[np.int32] | None:
    """:func:`~mrexplore.planning.paths.path_to` (the same path, or ``None``), with its
    search in this thread's :class:`TeamBuffers` instead of fresh arrays.

    Inputs are trusted: ``passable`` an ``H x W`` bool grid, both cells inside it.

    >>> free = np.ones((2, 3), dtype=bool)
    >>> workspace_path(free, (0, 0), (0, 2)).tolist()
    [[0, 0], [0, 1], [0, 2]]
    >>> free[:, 1] = False
    >>> workspace_path(free, (0, 0), (1, 2)) is None
    True
    """
    height, width = passable.shape
    flat = np.ascontiguousarray(passable, dtype=np.bool_).reshape(-1)
    src = int(start[0]) * width + int(start[1])
    target = int(goal[0]) * width + int(goal[1])
    n_targets = int(flat[target])
    if not flat[src]:  # as distance_field: the source always counts as passable
        n_targets += int(target == src)
        flat = flat.copy()
        flat[src] = True
    space = workspace(height * width)
    space.targets[target] = True
    reached = math.inf
    try:
        count_field()
        distance_field_kernel(
            flat,
            height,
            width,
            src,
            space.targets,
            n_targets,
            math.inf,
            space.dist,
            space.state,
            space.buckets,
        )
        dist = space.dist.reshape(height, width)
        reached = float(dist[goal])
        if not np.isfinite(reached):
            return None
        return extract_path(dist, goal)
    finally:
        space.targets[target] = False
        # Stopped at the goal, or at once with no target; otherwise a whole component.
        farthest = reached if reached < math.inf else (0.0 if n_targets == 0 else math.inf)
        _reset(space.dist, space.state, height, width, int(start[0]), farthest)


@numba.njit(cache=True, nogil=True, inline="always")
def _neighbour4(u: int, k: int, height: int, width: int) -> int:
    """The ``k``-th 4-neighbour of flat cell ``u`` (up, down, left, right), ``-1`` off
    the grid."""
    row = u // width
    col = u - row * width
    if k == 0:
        return u - width if row > 0 else -1
    if k == 1:
        return u + width if row < height - 1 else -1
    if k == 2:
        return u - 1 if col > 0 else -1
    return u + 1 if col < width - 1 else -1


@numba.njit(cache=True, nogil=True)
def reachable_kernel(
    passable: BoolArray,
    height: int,
    width: int,
    source: int,
    target_mask: BoolArray,
    target_index: IntArray,
    visited: npt.NDArray[np.uint8],
    queue: npt.NDArray[np.int32],
    out: BoolArray,
) -> int:
    """``out[j]`` = whether ``target_index[j]`` is reachable from ``source``: a
    breadth-first flood of the source's 4-connected component (the source counts as
    passable), stopped once every target it can find is found.

    ``visited`` must be all zero and is left so; ``queue`` is scratch of ``H W`` cells.
    Returns the number of cells flooded.
    """
    need = 0
    for j in range(target_index.shape[0]):
        if passable[target_index[j]] or target_index[j] == source:
            need += 1
    visited[source] = 1
    queue[0] = source
    head = 0
    tail = 1
    found = 1 if target_mask[source] else 0
    while head < tail and found < need:
        u = queue[head]
        head += 1
        for k in range(4):
            v = _neighbour4(u, k, height, width)
            if v < 0:
                continue
            if passable[v] and visited[v] == 0:
                visited[v] = 1
                queue[tail] = v
                tail += 1
                if target_mask[v]:
                    found += 1
    for j in range(target_index.shape[0]):
        out[j] = visited[target_index[j]] != 0
    for i in range(tail):
        visited[queue[i]] = 0
    return tail


def reachable(passable: BoolArray, source: tuple[int, int], target_index: IntArray) -> BoolArray:
    """Whether each target can be reached from ``source``: exactly
    ``np.isfinite(distance_field(passable, source, targets=mask))`` at the targets, without
    the distances (a flood of the 4-connected component, which is what a robot can reach
    with no corner cutting). Not a distance field: not counted by :func:`count_field`.

    Inputs are trusted: ``passable`` an ``H x W`` bool grid, ``source`` inside it,
    ``target_index`` distinct flat indices ``row * W + col``.

    >>> free = np.ones((3, 3), dtype=bool)
    >>> free[:, 1] = False
    >>> reachable(free, (0, 0), np.array([6, 2])).tolist()
    [True, False]
    """
    height, width = passable.shape
    flat = np.ascontiguousarray(passable, dtype=np.bool_).reshape(-1)
    space = workspace(height * width)
    index = np.ascontiguousarray(target_index, dtype=np.int64)
    out = np.empty(index.shape[0], dtype=np.bool_)
    space.targets[index] = True
    try:
        reachable_kernel(
            flat,
            height,
            width,
            int(source[0]) * width + int(source[1]),
            space.targets,
            index,
            space.state,
            space.buckets[0],
            out,
        )
    finally:
        space.targets[index] = False
    return out


@numba.njit(cache=True, nogil=True)
def _find(parent: npt.NDArray[np.int32], cell: int) -> int:
    while parent[cell] != cell:
        parent[cell] = parent[parent[cell]]  # path halving
        cell = parent[cell]
    return cell


@numba.njit(cache=True, nogil=True)
def _join_cells(
    parent: npt.NDArray[np.int32], passable: BoolArray, height: int, width: int, cells: IntArray
) -> None:
    """Union every cell of ``cells`` (passable) with its passable 4-neighbours."""
    for k in range(cells.shape[0]):
        u = cells[k]
        for d in range(4):
            v = _neighbour4(u, d, height, width)
            if v < 0:
                continue
            if passable[v]:
                a = _find(parent, u)
                b = _find(parent, v)
                if a != b:
                    if a < b:
                        parent[b] = a
                    else:
                        parent[a] = b


@numba.njit(cache=True, nogil=True)
def _reachable_by_roots(
    parent: npt.NDArray[np.int32],
    passable: BoolArray,
    height: int,
    width: int,
    source: int,
    target_index: IntArray,
    out: BoolArray,
) -> None:
    """``out[j]``: ``target_index[j]`` is the source or a passable cell of its component
    (a source that is not passable joins the components of its passable 4-neighbours)."""
    roots = np.full(4, -1, dtype=np.int64)
    if passable[source]:
        roots[0] = _find(parent, source)
    else:
        row = source // width
        col = source - row * width
        if row > 0 and passable[source - width]:
            roots[0] = _find(parent, source - width)
        if row < height - 1 and passable[source + width]:
            roots[1] = _find(parent, source + width)
        if col > 0 and passable[source - 1]:
            roots[2] = _find(parent, source - 1)
        if col < width - 1 and passable[source + 1]:
            roots[3] = _find(parent, source + 1)
    for j in range(target_index.shape[0]):
        t = target_index[j]
        hit = t == source
        if not hit and passable[t]:
            root = _find(parent, t)
            for k in range(4):
                if roots[k] == root:
                    hit = True
        out[j] = hit


@numba.njit(cache=True, nogil=True)
def _added_cells(kept: BoolArray, passable: BoolArray, added: IntArray) -> int:
    """Write the cells passable now and not in ``kept`` to ``added`` and mark them in
    ``kept``; returns how many, or -1 as soon as a cell of ``kept`` is no longer passable
    (``kept`` is then partly updated: rebuild)."""
    n_added = 0
    for i in range(passable.shape[0]):
        if passable[i] != kept[i]:
            if kept[i]:
                return -1
            kept[i] = True
            added[n_added] = i
            n_added += 1
    return n_added


class Components:
    """The 4-connected components of one robot's passable cells, kept across calls.

    A robot's known-free cells mostly only grow, so the union-find of the last call is
    brought up to date by joining the cells that became passable since (a cell that
    stopped being passable, e.g. under sensor noise, rebuilds it from scratch).
    :meth:`reachable` then answers exactly what :func:`reachable` answers, without a
    flood: the cost is one comparison of the grid with the last one, plus the new cells.
    """

    __slots__ = ("parent", "passable")

    def __init__(self) -> None:
        self.parent: npt.NDArray[np.int32] | None = None
        self.passable: BoolArray | None = None

    def reachable(
        self, passable: BoolArray, source: tuple[int, int], target_index: IntArray
    ) -> BoolArray:
        """:func:`reachable` (the same answer), from the kept components.

        >>> free = np.ones((3, 3), dtype=bool)
        >>> free[:, 1] = False
        >>> components = Components()
        >>> components.reachable(free, (0, 0), np.array([6, 2])).tolist()
        [True, False]
        >>> free[1, 1] = True
        >>> components.reachable(free, (0, 0), np.array([6, 2])).tolist()
        [True, True]
        """
        height, width = passable.shape
        flat = np.ascontiguousarray(passable, dtype=np.bool_).reshape(-1)
        kept, parent = self.passable, self.parent
        n_added = -1
        if parent is not None and kept is not None and kept.shape == flat.shape:
            added = np.empty(flat.size, dtype=np.int64)  # pages touched only when written
            n_added = _added_cells(kept, flat, added)
            added = added[:n_added]
        if parent is None or n_added < 0:  # first call, another grid, or a cell lost
            parent = self.parent = np.arange(flat.size, dtype=np.int32)
            self.passable = flat.copy()
            added = np.flatnonzero(flat)
        if added.size:
            _join_cells(parent, flat, height, width, added)
        out = np.empty(target_index.shape[0], dtype=np.bool_)
        _reachable_by_roots(
            parent,
            flat,
            height,
            width,
            int(source[0]) * width + int(source[1]),
            np.ascontiguousarray(target_index, dtype=np.int64),
            out,
        )
        return out
