"""RRT-based frontier detection (Umari & Mukhopadhyay 2017), on an occupancy grid.

H. Umari, S. Mukhopadhyay, "Autonomous robotic exploration based on multiple
rapidly-exploring randomized trees", IEEE/RSJ IROS 2017; the frontier detector
used by the decentralised market strategy (``market-occupancy``). Our copy of the
paper's text is not at hand: the values below are those of the authors' public code,
``hasauino/rrt_exploration`` (launch files, ``global_rrt_detector.cpp``,
``local_rrt_detector.cpp``, ``filter.py``) and its simulation package
``hasauino/rrt_exploration_tutorials``; this module is our own code.

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
in a store, which :meth:`RrtFrontierDetector.points` filters as Umari's filter
node does: a point is dropped when it stops being a frontier cell (a free cell
with an unknown 4-neighbour), and the rest are clustered by mean shift
(:func:`mean_shift`; ``clustering="greedy"``: :func:`thin_points`, our earlier
version). The filter node's information-gain test is applied by the strategy to
the points it lists (``market-occupancy``'s ``rrt_filter_radius`` and
``rrt_filter_min_gain``, :func:`mrexplore.planning.gain.filter_by_gain`), after it
keeps the points the robot can reach.

Defaults and where they come from (cells; Umari's values are in metres, converted
at 0.2 m per cell, the cell of the project's real-map runs, e.g. ``mrexplore
reproduce market2018``: a robot-sized cell; the strategy knows no cell size):

* **Sampling budget** (``samples`` per tree per :meth:`~RrtFrontierDetector.step`,
  one step per tick; the strategy's default from :func:`samples_per_tick`).
  Principle, chosen before measuring: a uniform sample falls in a region of area
  ``a`` with probability ``a / (H W)``, so with a fixed count per tick (our earlier
  20) a frontier of a given size is found the later the bigger the map. The budget
  is therefore a *density*: ``sample_density`` samples per tree per tick per sensor
  footprint (``pi r**2``, the area a robot senses from one cell) of the sampled
  map, ``ceil(sample_density * H * W / (pi r**2))``; default 1, so every
  footprint-sized region of any map receives one sample per tree per tick on
  average. A tick is the time a robot takes to travel one cell. Umari's detectors
  run one iteration per cycle of a fixed wall-clock rate (``ros::Rate
  rate(100)``: 100 iterations per second for the global detector and for each
  local one) while the robots drive at up to 0.3 m/s (``max_vel_x: 0.3`` in the
  tutorials' ``base_local_planner_params.yaml``): at least 333 iterations per
  metre travelled, 67 per 0.2 m cell. Their density per unit area is not known
  (their maps' areas are not given), so the density is ours; on the Intel map at
  0.2 m per cell (186 x 172 cells, 15-cell sensor) it gives 46 samples per tree per
  tick, the order of Umari's 67.
* **Growth step** ``eta`` = 5 cells = 1 m. Umari's launch files set the local
  detectors' ``eta`` to 1 m (``<arg name="eta" value="1.0"/>``) and the global
  detector's ``Geta`` to 15 m with one robot (``single.launch``, ``simple.launch``)
  and to 1 m with three robots on the merged map (``three_robots.launch``, the
  setting of a multi-robot team); their README: "a very large value will cause the
  tree to grow faster and hence detect frontier points faster, but a large growth
  rate also implies that the tree will be missing small corners in the map". Both
  trees use ``eta`` by default (the three-robot launch file); ``global_eta`` sets
  the global tree's apart (75 cells = the single-robot 15 m). Our earlier default
  was the sensor range.
* **Mean-shift bandwidth** = 1.5 cells = 0.3 m: Umari's filter clusters the
  stored points with scikit-learn's ``MeanShift(bandwidth=0.3)`` (flat kernel,
  every point a seed) and keeps the cluster centres as its new store.
* **Information-gain filter** (in the strategy): Umari's filter drops a centre
  whose ``informationGain`` within ``info_radius * 0.5`` (``info_radius`` 1 m) is
  under 0.2 m² (unknown cells times the squared resolution): 2.5 cells and 5 cells.

Grid specifics (our interpretations):

* Vertices are continuous ``(row, col)`` positions in cells; a position lies in
  the cell of the nearest integer coordinates. Edges are walked in steps of at
  most half a cell (Umari: a fifth of the map resolution).
* The frontier point reported is a known-free cell 4-adjacent to the first
  unknown cell the edge meets (not the unknown point itself, which a robot
  could not plan a path to over known-free cells), so every reported point is
  a frontier cell in the grid sense, and a robot standing on it sees the
  unknown cell (a stored point therefore never outlives a visit).
* Edges do not cut corners: a diagonal step beside an occupied cell meets an
  obstacle, as a robot's move would.
* Iterations run one after the other as Umari's loop does (each sample searches
  the vertices the earlier ones added; the local tree is reset at the first
  frontier point it detects), in one compiled kernel per tree and step; the
  global tree's ``samples`` come first, then the local tree's.
* A free edge shorter than ``vertex_spacing`` (a sample that fell next to a
  vertex already in the tree) is walked, and may detect a frontier, but adds
  no vertex: the trees stop densifying over explored space, so their size, and
  the cost of the nearest-vertex search, stay bounded by the free area over
  ``vertex_spacing**2``. A tree also stops adding vertices after ``max_vertices``.
* Mean-shift centres are continuous; each is replaced by the stored point
  nearest to it (a frontier cell a robot can be sent to), the cluster's
  representative, as the grid detector's cluster representative is the cell
  nearest the centroid.
* The global tree is the robot's own, grown over its own map. Umari runs one
  global detector on the merged map (their README: "In multi-robot configuration,
  it is intended to have only a single instance of this node running"); in the
  simulator a robot's map *is* its merged map (its own scans and whatever the
  communication model delivered), so a tree per robot over it is the decentralised
  equivalent: with unlimited communication every robot's map is the merged map and
  every robot's tree is a copy of Umari's one tree (independent samples); under
  limited communication each robot grows it on what it knows. A tree shared by the
  team would need the robots to share memory, or messages the paper's byte model
  does not have.

Units: cells. Randomness: only the generator passed in (the robot's own).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, BeliefGrid
from mrexplore.planning.frontiers import frontier_mask

__all__ = [
    "CLUSTERINGS",
    "EDGE_FREE",
    "EDGE_FRONTIER",
    "EDGE_OBSTACLE",
    "RrtFrontierDetector",
    "RrtTree",
    "mean_shift",
    "nearest_vertex",
    "samples_per_tick",
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

CLUSTERINGS = ("mean-shift", "greedy")
"""How :meth:`RrtFrontierDetector.points` merges stored points."""

MEAN_SHIFT_MAX_ITER = 300
"""Iterations per seed at most (scikit-learn's ``MeanShift`` default)."""


def samples_per_tick(shape: tuple[int, int], sensor_range: float, density: float) -> int:
    """Samples per tree per tick: ``density`` per sensor footprint ``pi r**2`` of the map.

    ``ceil(density * H * W / (pi r**2))``, at least 1 (the budget principle of the
    module docstring).

    >>> samples_per_tick((186, 172), 15.0, 1.0)
    46
    >>> samples_per_tick((40, 40), 8.0, 1.0), samples_per_tick((80, 80), 8.0, 1.0)
    (8, 32)
    """
    if not (sensor_range > 0 and math.isfinite(sensor_range)):
        raise MrexploreInputError(f"sensor range {sensor_range}: must be finite and > 0")
    if not (density > 0 and math.isfinite(density)):
        raise MrexploreInputError(f"sample density {density}: must be finite and > 0")
    footprint = math.pi * sensor_range * sensor_range
    return max(1, math.ceil(density * shape[0] * shape[1] / footprint - 1e-9))


@numba.njit(cache=True, nogil=True)
def _nearest(vertices: npt.NDArray[np.float64], n: int, row: float, col: float) -> int:
    """Index of the vertex among the first ``n`` nearest to ``(row, col)`` (first of ties)."""
    best = 0
    best_d2 = math.inf
    for v in range(n):
        d_row = vertices[v, 0] - row
        d_col = vertices[v, 1] - col
        d2 = d_row * d_row + d_col * d_col
        if d2 < best_d2:
            best_d2 = d2
            best = v
    return best


@numba.njit(cache=True, nogil=True)
def _steer(
    from_row: float, from_col: float, to_row: float, to_col: float, eta: float
) -> tuple[float, float]:
    """From ``from`` towards ``to`` by at most ``eta`` (Umari's ``Steer``)."""
    d_row = to_row - from_row
    d_col = to_col - from_col
    length = math.sqrt(d_row * d_row + d_col * d_col)
    if length <= eta:
        return to_row, to_col
    scale = eta / length
    return from_row + d_row * scale, from_col + d_col * scale


@numba.njit(cache=True, nogil=True)
def _nearest_many(vertices: npt.NDArray[np.float64], samples: npt.NDArray[np.float64]) -> IntArray:
    out = np.empty(samples.shape[0], dtype=np.int64)
    for s in range(samples.shape[0]):
        out[s] = _nearest(vertices, vertices.shape[0], samples[s, 0], samples[s, 1])
    return out


@numba.njit(cache=True, nogil=True)
def _steer_many(
    nearest: npt.NDArray[np.float64], samples: npt.NDArray[np.float64], eta: float
) -> FloatArray:
    out = np.empty_like(samples)
    for s in range(samples.shape[0]):
        out[s, 0], out[s, 1] = _steer(
            nearest[s, 0], nearest[s, 1], samples[s, 0], samples[s, 1], eta
        )
    return out


def nearest_vertex(vertices: FloatArray, samples: FloatArray) -> IntArray:
    """Index of the vertex nearest to each sample (Euclidean; ties to the lowest index).

    >>> vertices = np.array([[0.0, 0.0], [5.0, 5.0]])
    >>> nearest_vertex(vertices, np.array([[1.0, 1.0], [4.0, 6.0]])).tolist()
    [0, 1]
    """
    return _nearest_many(
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.ascontiguousarray(samples, dtype=np.float64),
    )


def steer(nearest: FloatArray, samples: FloatArray, eta: float) -> FloatArray:
    """Move from each ``nearest`` towards its sample by at most ``eta`` cells.

    >>> steer(np.array([[0.0, 0.0]]), np.array([[0.0, 10.0]]), 4.0).tolist()
    [[0.0, 4.0]]
    """
    return _steer_many(
        np.ascontiguousarray(nearest, dtype=np.float64),
        np.ascontiguousarray(samples, dtype=np.float64),
        float(eta),
    )


@numba.njit(cache=True, nogil=True)
def _state(belief: npt.NDArray[np.int8], row: int, col: int) -> int:
    height, width = belief.shape
    if row < 0 or row >= height or col < 0 or col >= width:
        return OCCUPIED  # off the map
    return int(belief[row, col])


@numba.njit(cache=True, nogil=True)
def _walk(
    belief: npt.NDArray[np.int8], start_row: float, start_col: float, end_row: float, end_col: float
) -> tuple[int, int, int]:
    """``(outcome, frontier row, frontier col)`` of one edge (see :func:`walk_edges`)."""
    d_row = end_row - start_row
    d_col = end_col - start_col
    n_steps = max(1, math.ceil(math.sqrt(d_row * d_row + d_col * d_col) * 2.0))
    prev_r = math.floor(start_row + 0.5)
    prev_c = math.floor(start_col + 0.5)
    for k in range(1, n_steps + 1):
        t = k / n_steps
        r = math.floor(start_row + d_row * t + 0.5)
        c = math.floor(start_col + d_col * t + 0.5)
        if r == prev_r and c == prev_c:
            continue
        here = _state(belief, r, c)
        diagonal = r != prev_r and c != prev_c
        side = _state(belief, r, prev_c) if diagonal else FREE
        other = _state(belief, prev_r, c) if diagonal else FREE
        if here == OCCUPIED or side == OCCUPIED or other == OCCUPIED:
            return EDGE_OBSTACLE, -1, -1
        if here == UNKNOWN or side == UNKNOWN or other == UNKNOWN:
            if diagonal and side != UNKNOWN and other != UNKNOWN:
                cell_r, cell_c = r, prev_c  # into unknown between two free cells: beside it
            else:
                cell_r, cell_c = prev_r, prev_c
            if _state(belief, cell_r, cell_c) != FREE:
                return EDGE_OBSTACLE, -1, -1  # the edge did not start on known-free space
            return EDGE_FRONTIER, cell_r, cell_c
        prev_r = r
        prev_c = c
    return EDGE_FREE, -1, -1


@numba.njit(cache=True, nogil=True)
def _walk_edges_kernel(
    belief: npt.NDArray[np.int8],
    starts: npt.NDArray[np.float64],
    ends: npt.NDArray[np.float64],
    outcome: npt.NDArray[np.int8],
    cells_out: npt.NDArray[np.int64],
) -> None:
    for e in range(starts.shape[0]):
        result, row, col = _walk(belief, starts[e, 0], starts[e, 1], ends[e, 0], ends[e, 1])
        outcome[e] = result
        cells_out[e, 0] = row
        cells_out[e, 1] = col


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


@numba.njit(cache=True, nogil=True)
def _grow_kernel(
    belief: npt.NDArray[np.int8],
    vertices: npt.NDArray[np.float64],
    n_vertices: int,
    samples: npt.NDArray[np.float64],
    eta: float,
    spacing: float,
    max_vertices: int,
    reset_at: npt.NDArray[np.float64],
    reset: bool,
    found: npt.NDArray[np.int64],
) -> tuple[int, int]:
    """Umari's loop over ``samples``: ``(vertices now, frontier points written to found)``.

    ``vertices`` has room for ``n_vertices + len(samples)`` rows. With ``reset``
    (the local tree), the tree restarts at ``reset_at`` after each frontier point.
    """
    n_found = 0
    for s in range(samples.shape[0]):
        nearest = _nearest(vertices, n_vertices, samples[s, 0], samples[s, 1])
        from_row = vertices[nearest, 0]
        from_col = vertices[nearest, 1]
        new_row, new_col = _steer(from_row, from_col, samples[s, 0], samples[s, 1], eta)
        d_row = new_row - from_row
        d_col = new_col - from_col
        length = math.sqrt(d_row * d_row + d_col * d_col)
        if length <= 1e-9:
            continue
        outcome, row, col = _walk(belief, from_row, from_col, new_row, new_col)
        if outcome == EDGE_FRONTIER:
            found[n_found, 0] = row
            found[n_found, 1] = col
            n_found += 1
            if reset:
                vertices[0, 0] = reset_at[0]
                vertices[0, 1] = reset_at[1]
                n_vertices = 1
        elif outcome == EDGE_FREE and length >= spacing and n_vertices < max_vertices:
            vertices[n_vertices, 0] = new_row
            vertices[n_vertices, 1] = new_col
            n_vertices += 1
    return n_vertices, n_found


def thin_points(
    points: npt.NDArray[np.number], radius: float, *, inclusive: bool = False
) -> IntArray:
    """Indices of a greedy subset (in the given order) of points ``radius`` apart.

    Each kept point removes the later points closer than ``radius`` (``inclusive``:
    at most ``radius``, as scikit-learn's mean-shift removes near-duplicate centres).

    >>> thin_points(np.array([[0, 0], [0, 1], [0, 5]]), 2.0).tolist()
    [0, 2]
    >>> thin_points(np.array([[0, 0], [0, 2]]), 2.0, inclusive=True).tolist()
    [0]
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
        alive &= d2 > radius2 if inclusive else d2 >= radius2
    return np.asarray(kept, dtype=np.int64)


@numba.njit(cache=True, nogil=True)
def _mean_shift_kernel(
    points: npt.NDArray[np.float64],
    bandwidth: float,
    max_iter: int,
    centres: npt.NDArray[np.float64],
    intensity: npt.NDArray[np.int64],
) -> None:
    """Flat-kernel mean shift from every point (scikit-learn's ``_mean_shift_single_seed``)."""
    n = points.shape[0]
    bandwidth2 = bandwidth * bandwidth
    stop = 1e-3 * bandwidth
    for s in range(n):
        row = points[s, 0]
        col = points[s, 1]
        count = 0
        for iteration in range(max_iter + 1):
            sum_row = 0.0
            sum_col = 0.0
            count = 0
            for p in range(n):
                d_row = points[p, 0] - row
                d_col = points[p, 1] - col
                if d_row * d_row + d_col * d_col <= bandwidth2:
                    sum_row += points[p, 0]
                    sum_col += points[p, 1]
                    count += 1
            new_row = sum_row / count  # the seed's window holds the seed at first
            new_col = sum_col / count
            shift = math.sqrt((new_row - row) ** 2 + (new_col - col) ** 2)
            row = new_row
            col = new_col
            if shift <= stop or iteration == max_iter:
                break
        centres[s, 0] = row
        centres[s, 1] = col
        intensity[s] = count


def mean_shift(points: npt.NDArray[np.number], bandwidth: float) -> FloatArray:
    """Cluster centres of ``points`` by flat-kernel mean shift, densest first.

    As scikit-learn's ``MeanShift(bandwidth)`` (Umari's filter): every point seeds a
    climb to the mean of the points within ``bandwidth`` until it moves less than
    ``1e-3 * bandwidth`` (at most 300 iterations); the converged centres, densest
    window first (then by coordinates, descending), each remove the later centres
    within ``bandwidth``.

    >>> blobs = np.array([[0, 0], [0, 1], [1, 0], [10, 10], [10, 11]])
    >>> mean_shift(blobs, 2.0).round(3).tolist()
    [[0.333, 0.333], [10.0, 10.5]]
    """
    if not (bandwidth > 0 and math.isfinite(bandwidth)):
        raise MrexploreInputError(f"mean-shift bandwidth {bandwidth}: must be finite and > 0")
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    if pts.shape[0] == 0:
        return np.zeros((0, 2))
    centres = np.empty_like(pts)
    intensity = np.empty(pts.shape[0], dtype=np.int64)
    _mean_shift_kernel(pts, float(bandwidth), MEAN_SHIFT_MAX_ITER, centres, intensity)
    centres, first = np.unique(centres, axis=0, return_index=True)  # equal climbs: one centre
    intensity = intensity[first]
    order = np.lexsort((-centres[:, 1], -centres[:, 0], -intensity))
    centres = centres[order]
    return np.asarray(centres[thin_points(centres, bandwidth, inclusive=True)])


@dataclass
class RrtTree:
    """A tree's vertices (continuous ``(row, col)`` positions, cells); edges are not needed.

    The vertices are the first ``size`` rows of a buffer that grows by doubling.
    """

    buffer: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    size: int = 0

    @property
    def vertices(self) -> FloatArray:
        return self.buffer[: self.size]

    @classmethod
    def rooted(cls, root: tuple[float, float]) -> RrtTree:
        tree = cls()
        tree.reset(root)
        return tree

    def reset(self, root: tuple[float, float]) -> None:
        if self.buffer.shape[0] == 0:
            self.buffer = np.zeros((64, 2))
        self.buffer[0] = root
        self.size = 1

    def reserve(self, extra: int) -> None:
        """Make room for ``extra`` more vertices."""
        need = self.size + extra
        if need > self.buffer.shape[0]:
            grown = np.zeros((max(need, 2 * self.buffer.shape[0]), 2))
            grown[: self.size] = self.buffer[: self.size]
            self.buffer = grown

    def add(self, points: FloatArray) -> None:
        self.reserve(points.shape[0])
        self.buffer[self.size : self.size + points.shape[0]] = points
        self.size += points.shape[0]


@dataclass
class RrtFrontierDetector:
    """One robot's RRT frontier detector: a global tree, a local tree, a point store.

    Attributes:
        eta: growth step of the local tree, and of the global tree unless
            ``global_eta`` is set (cells).
        samples: samples (Umari's iterations) per tree per :meth:`step`.
        global_eta: growth step of the global tree; 0 = ``eta`` (cells).
        clustering: ``"mean-shift"`` (Umari's filter) or ``"greedy"`` (:func:`thin_points`).
        bandwidth: mean-shift bandwidth (cells).
        cluster_radius: with ``greedy``, stored points closer than this are merged (cells).
        max_vertices: a tree adds no vertex beyond this size.
        vertex_spacing: a free edge shorter than this (cells) adds no vertex.
    """

    eta: float
    samples: int = 10
    global_eta: float = 0.0
    clustering: str = "mean-shift"
    bandwidth: float = 1.5
    cluster_radius: float = 4.0
    max_vertices: int = 20000
    vertex_spacing: float = 1.0
    global_tree: RrtTree | None = None
    local_tree: RrtTree | None = None
    store: IntArray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))

    def __post_init__(self) -> None:
        if self.clustering not in CLUSTERINGS:
            raise MrexploreInputError(
                f"clustering {self.clustering!r}: expected one of {', '.join(CLUSTERINGS)}"
            )

    def step(
        self, belief: BeliefGrid, position: tuple[int, int], rng: np.random.Generator
    ) -> IntArray:
        """Run ``samples`` iterations on each tree; return the frontier cells detected now.

        Stored points that are no longer frontier cells of ``belief`` are dropped, so
        after a step the store holds frontier cells only.
        """
        root = (float(position[0]), float(position[1]))
        if self.global_tree is None:
            self.global_tree = RrtTree.rooted(root)
        if self.local_tree is None:
            self.local_tree = RrtTree.rooted(root)
        height, width = belief.shape
        samples = rng.random((2 * self.samples, 2)) * np.array([height, width]) - 0.5
        grid = np.ascontiguousarray(belief, dtype=np.int8)
        found = np.empty((self.samples, 2), dtype=np.int64)
        detected = []
        trees = (
            (self.global_tree, self.global_eta or self.eta, False),
            (self.local_tree, self.eta, True),
        )
        for index, (tree, eta, reset) in enumerate(trees):
            tree.reserve(self.samples)
            tree.size, n_found = _grow_kernel(
                grid,
                tree.buffer,
                tree.size,
                samples[index * self.samples : (index + 1) * self.samples],
                float(eta),
                float(self.vertex_spacing),
                int(self.max_vertices),
                np.array(root),
                reset,
                found,
            )
            detected.append(found[:n_found].copy())
        points = np.concatenate(detected)
        store = self.store
        if store.shape[0]:  # points explored since: gone (Umari's filter clears old points)
            store = store[frontier_mask(grid)[store[:, 0], store[:, 1]]]
        self.store = np.concatenate([store, points])
        if self.store.shape[0] > STORE_COMPACT:
            self.points(belief)  # cluster now: keeps the store (and its cost) bounded
        return points

    def points(self, belief: BeliefGrid) -> IntArray:
        """The filtered store: ``(M, 2)`` frontier cells, oldest first (also kept as the store).

        Points that are no longer frontier cells are dropped; the rest are merged by
        mean shift (each centre replaced by the stored point nearest to it) or, with
        ``clustering="greedy"``, thinned to ``cluster_radius`` apart, oldest kept.
        """
        store = self.store
        if store.shape[0] == 0:
            return store
        store = store[frontier_mask(belief)[store[:, 0], store[:, 1]]]
        if self.clustering == "greedy":
            store = store[thin_points(store, self.cluster_radius)]
        elif store.shape[0] > 1:
            centres = mean_shift(store, self.bandwidth)
            nearest = np.unique(nearest_vertex(store.astype(np.float64), centres))
            store = store[nearest]
        self.store = store
        return store.copy()
