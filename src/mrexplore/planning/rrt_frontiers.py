"""RRT-based frontier detection (Umari & Mukhopadhyay 2017), on an occupancy grid.

H. Umari, S. Mukhopadhyay, "Autonomous robotic exploration based on multiple
rapidly-exploring randomized trees", IEEE/RSJ IROS 2017; the frontier detector
used by the decentralised market strategy (``market-occupancy``).

Rapidly-exploring random trees grow over the space a robot knows to be free. Each
iteration draws a sample uniformly over the whole map, finds the nearest vertex
``x_nearest`` of the tree, and steers from it towards the sample by at most
``eta`` cells to ``x_new``. The straight edge ``x_nearest -> x_new`` is walked
(as Umari's ``ObstacleFree``):

* it meets an unknown cell before any obstacle: a *frontier point* is detected
  and the edge is not added;
* it meets a known obstacle first: the sample is discarded;
* every cell on it is known free: ``x_new`` joins the tree.

Two kinds of tree (as in Umari's system): a *global* tree rooted at the
robot's start, which is never reset, and a *local* tree rooted at the robot,
which is reset to the robot's current position whenever it detects a frontier
point (so it keeps finding frontiers near the robot). Detected points are kept
in a store and filtered (Umari's filter node): a point is dropped when it stops
being a frontier cell (a free cell with an unknown 4-neighbour), and points
closer than ``cluster_radius`` to an older kept point are merged into it
(greedy, in place of Umari's mean-shift clustering).

Grid specifics (our interpretations):

* Vertices are continuous ``(row, col)`` positions in cells; a position lies in
  the cell of the nearest integer coordinates. Edges are walked in steps of at
  most half a cell (compiled kernel); the nearest-vertex search is a numpy
  distance matrix between the batch of samples and the tree.
* The frontier point reported is a known-free cell 4-adjacent to the first
  unknown cell the edge meets (not the unknown point itself, which a robot
  could not plan a path to over known-free cells), so every reported point is
  a frontier cell in the grid sense, and a robot standing on it sees the
  unknown cell (a stored point therefore never outlives a visit).
* Edges do not cut corners: a diagonal step beside an occupied cell meets an
  obstacle, as a robot's move would.
* Iterations are batched: ``samples`` samples per tree per call to
  :meth:`RrtFrontierDetector.step`, each searching its nearest vertex among the
  vertices present at the start of the batch (one vectorised distance matrix).
  The local tree is reset after a batch that detected a frontier.
* A free edge shorter than ``vertex_spacing`` (a sample that fell next to a
  vertex already in the tree) is walked, and may detect a frontier, but adds
  no vertex: the trees stop densifying over explored space, so their size, and
  the cost of the nearest-vertex search, stay bounded by the free area over
  ``vertex_spacing**2``. The global tree also stops adding vertices after
  ``max_vertices``.

Units: cells. Randomness: only the generator passed in (the robot's own).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, BeliefGrid
from mrexplore.planning.frontiers import frontier_mask

__all__ = [
    "EDGE_FREE",
    "EDGE_FRONTIER",
    "EDGE_OBSTACLE",
    "RrtFrontierDetector",
    "RrtTree",
    "nearest_vertex",
    "steer",
    "thin_points",
    "walk_edges",
]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]

EDGE_FREE = 1
EDGE_OBSTACLE = 0
EDGE_FRONTIER = -1
"""Outcomes of :func:`walk_edges`, with the values of Umari's ``ObstacleFree``."""

STORE_COMPACT = 512
"""Stored points beyond which :meth:`RrtFrontierDetector.step` filters the store."""


def nearest_vertex(vertices: FloatArray, samples: FloatArray) -> IntArray:
    """Index of the vertex nearest to each sample (Euclidean; ties to the lowest index).

    >>> vertices = np.array([[0.0, 0.0], [5.0, 5.0]])
    >>> nearest_vertex(vertices, np.array([[1.0, 1.0], [4.0, 6.0]])).tolist()
    [0, 1]
    """
    d2 = (samples[:, None, 0] - vertices[None, :, 0]) ** 2
    d2 += (samples[:, None, 1] - vertices[None, :, 1]) ** 2
    return np.asarray(np.argmin(d2, axis=1), dtype=np.int64)


def steer(nearest: FloatArray, samples: FloatArray, eta: float) -> FloatArray:
    """Move from each ``nearest`` towards its sample by at most ``eta`` cells.

    >>> steer(np.array([[0.0, 0.0]]), np.array([[0.0, 10.0]]), 4.0).tolist()
    [[0.0, 4.0]]
    """
    delta = samples - nearest
    length = np.hypot(delta[:, 0], delta[:, 1])
    scale = np.where(length > eta, eta / np.maximum(length, 1e-12), 1.0)
    return np.asarray(nearest + delta * scale[:, None], dtype=np.float64)


@numba.njit(cache=True, nogil=True)
def _state(belief: npt.NDArray[np.int8], row: int, col: int) -> int:
    height, width = belief.shape
    if row < 0 or row >= height or col < 0 or col >= width:
        return OCCUPIED  # off the map
    return int(belief[row, col])


@numba.njit(cache=True, nogil=True)
def _walk_edges_kernel(
    belief: npt.NDArray[np.int8],
    starts: npt.NDArray[np.float64],
    ends: npt.NDArray[np.float64],
    outcome: npt.NDArray[np.int8],
    cells_out: npt.NDArray[np.int64],
) -> None:
    for e in range(starts.shape[0]):
        d_row = ends[e, 0] - starts[e, 0]
        d_col = ends[e, 1] - starts[e, 1]
        n_steps = max(1, math.ceil(math.sqrt(d_row * d_row + d_col * d_col) * 2.0))
        prev_r = math.floor(starts[e, 0] + 0.5)
        prev_c = math.floor(starts[e, 1] + 0.5)
        result = EDGE_FREE
        for k in range(1, n_steps + 1):
            t = k / n_steps
            r = math.floor(starts[e, 0] + d_row * t + 0.5)
            c = math.floor(starts[e, 1] + d_col * t + 0.5)
            if r == prev_r and c == prev_c:
                continue
            here = _state(belief, r, c)
            diagonal = r != prev_r and c != prev_c
            side = _state(belief, r, prev_c) if diagonal else FREE
            other = _state(belief, prev_r, c) if diagonal else FREE
            if here == OCCUPIED or side == OCCUPIED or other == OCCUPIED:
                result = EDGE_OBSTACLE
                break
            if here == UNKNOWN or side == UNKNOWN or other == UNKNOWN:
                result = EDGE_FRONTIER
                if diagonal and side != UNKNOWN and other != UNKNOWN:
                    cells_out[e, 0] = r  # into unknown between two free cells: beside it
                    cells_out[e, 1] = prev_c
                else:
                    cells_out[e, 0] = prev_r
                    cells_out[e, 1] = prev_c
                if _state(belief, cells_out[e, 0], cells_out[e, 1]) != FREE:
                    result = EDGE_OBSTACLE  # the edge did not start on known-free space
                    cells_out[e, 0] = -1
                    cells_out[e, 1] = -1
                break
            prev_r = r
            prev_c = c
        outcome[e] = result


def walk_edges(
    belief: BeliefGrid, starts: FloatArray, ends: FloatArray
) -> tuple[npt.NDArray[np.int8], IntArray]:
    """Walk each straight edge ``start -> end``: ``(outcome, frontier cell)`` per edge.

    The edge is sampled every half cell at most, giving a chain of cells in which
    consecutive cells are 8-neighbours. A step meets an *obstacle* when its cell
    is occupied (or off the map) or, for a diagonal step, when one of the two
    cells beside it is (no corner cutting, as robots move); otherwise it meets
    *unknown space* when its cell, or for a diagonal step a cell beside it, is
    unknown. The first step that meets either decides: :data:`EDGE_OBSTACLE`, or
    :data:`EDGE_FRONTIER` with the frontier cell, a known-free cell 4-adjacent to
    the unknown cell met (the previous cell, or for a diagonal step into an
    unknown cell between two free ones, the first cell beside it); no such step:
    :data:`EDGE_FREE`. The second array is ``(-1, -1)`` unless a frontier.

    >>> b = np.array([[0, 0, 0, -1, -1]], dtype=np.int8)
    >>> out, cells = walk_edges(b, np.array([[0.0, 0.0]]), np.array([[0.0, 4.0]]))
    >>> out.tolist(), cells.tolist()
    ([-1], [[0, 2]])
    """
    n = starts.shape[0]
    outcome = np.full(n, EDGE_FREE, dtype=np.int8)
    cells_out = np.full((n, 2), -1, dtype=np.int64)
    if n:
        _walk_edges_kernel(
            np.ascontiguousarray(belief, dtype=np.int8),
            np.ascontiguousarray(starts, dtype=np.float64),
            np.ascontiguousarray(ends, dtype=np.float64),
            outcome,
            cells_out,
        )
    return outcome, cells_out


def thin_points(points: IntArray, radius: float) -> IntArray:
    """Indices of a greedy subset (in the given order) of points at least ``radius`` apart.

    >>> thin_points(np.array([[0, 0], [0, 1], [0, 5]]), 2.0).tolist()
    [0, 2]
    """
    kept: list[int] = []
    if points.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    radius2 = radius * radius
    pts = points.astype(np.float64)
    alive = np.ones(points.shape[0], dtype=bool)
    # Each kept point removes its neighbours at once: one vectorised pass per kept point.
    for i in range(points.shape[0]):
        if not alive[i]:
            continue
        kept.append(i)
        d2 = (pts[:, 0] - pts[i, 0]) ** 2 + (pts[:, 1] - pts[i, 1]) ** 2
        alive &= d2 >= radius2
    return np.asarray(kept, dtype=np.int64)


@dataclass
class RrtTree:
    """A tree's vertices (continuous ``(row, col)`` positions, cells); edges are not needed."""

    vertices: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))

    @classmethod
    def rooted(cls, root: tuple[float, float]) -> RrtTree:
        return cls(np.array([root], dtype=np.float64))

    def reset(self, root: tuple[float, float]) -> None:
        self.vertices = np.array([root], dtype=np.float64)

    def add(self, points: FloatArray) -> None:
        self.vertices = np.concatenate([self.vertices, points])


@dataclass
class RrtFrontierDetector:
    """One robot's RRT frontier detector: a global tree, a local tree, a point store.

    Attributes:
        eta: growth step (cells).
        samples: samples per tree per :meth:`step`.
        cluster_radius: stored points closer than this are merged (cells).
        max_vertices: the global tree adds no vertex beyond this size.
        vertex_spacing: a free edge shorter than this (cells) adds no vertex.
    """

    eta: float
    samples: int = 10
    cluster_radius: float = 4.0
    max_vertices: int = 20000
    vertex_spacing: float = 1.0
    global_tree: RrtTree | None = None
    local_tree: RrtTree | None = None
    store: IntArray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))

    def step(
        self, belief: BeliefGrid, position: tuple[int, int], rng: np.random.Generator
    ) -> IntArray:
        """Grow both trees by one batch; return the frontier cells detected now."""
        root = (float(position[0]), float(position[1]))
        if self.global_tree is None:
            self.global_tree = RrtTree.rooted(root)
        if self.local_tree is None:
            self.local_tree = RrtTree.rooted(root)
        trees = (self.global_tree, self.local_tree)
        height, width = belief.shape
        samples = rng.random((2 * self.samples, 2)) * np.array([height, width]) - 0.5
        starts, ends, owner = [], [], []
        for index, tree in enumerate(trees):
            batch = samples[index * self.samples : (index + 1) * self.samples]
            nearest = tree.vertices[nearest_vertex(tree.vertices, batch)]
            new = steer(nearest, batch, self.eta)
            moved = np.hypot(*(new - nearest).T) > 1e-9
            starts.append(nearest[moved])
            ends.append(new[moved])
            owner.append(np.full(int(moved.sum()), index))
        start, end, tree_of = np.concatenate(starts), np.concatenate(ends), np.concatenate(owner)
        outcome, cells = walk_edges(belief, start, end)
        spacing = self.vertex_spacing
        for index, tree in enumerate(trees):
            mine = tree_of == index
            added = end[mine & (outcome == EDGE_FREE)]
            far = np.hypot(*(added - start[mine & (outcome == EDGE_FREE)]).T) >= spacing
            if index == 0 and tree.vertices.shape[0] >= self.max_vertices:
                continue
            tree.add(added[far])
        found = cells[outcome == EDGE_FRONTIER]
        if (outcome[tree_of == 1] == EDGE_FRONTIER).any():
            self.local_tree.reset(root)
        if found.shape[0]:
            self.store = np.concatenate([self.store, found])
            if self.store.shape[0] > STORE_COMPACT:
                self.points(belief)  # filter now: keeps the store (and its cost) bounded
        return found

    def points(self, belief: BeliefGrid) -> IntArray:
        """The filtered store: ``(M, 2)`` frontier cells, oldest first (also kept as the store)."""
        store = self.store
        if store.shape[0] == 0:
            return store
        store = store[frontier_mask(belief)[store[:, 0], store[:, 1]]]
        store = store[thin_points(store, self.cluster_radius)]
        self.store = store
        return store.copy()
