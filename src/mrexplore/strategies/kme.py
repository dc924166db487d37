"""Wu, Puig & Garcia: balanced multi-robot exploration by K-Means regions (KME).

L. Wu, D. Puig, M. A. Garcia, "Balanced multi-robot exploration through a global
optimization strategy", Journal of Physical Agents 4(1), 2010, §IV, eqs. (1)-(7)
and the algorithm of §IV.D; it builds on A. Solanas, M. A. Garcia, "Coordinated
multi-robot exploration through unsupervised clustering of unknown space",
IROS 2004 (the K-Means partition). Doc page: ``docs/strategies/kme.md``.

One decision round (run by a coordinator, see below) does, on the coordinator's
belief:

1. §IV.A, step 6: cluster the unknown cells into ``K`` regions with K-Means,
   ``K`` = the robots taking part. Centroids are warm-started from the previous
   round (random unknown cells the first time, step 3); K-Means runs on a random
   subsample of at most ``max_points`` unknown cells, and every unknown cell
   then joins the region of its nearest centroid.
2. §IV.B, eqs. (1)-(3): the distance ``d(r, R)`` of every robot to every region.
   A region is *accessible* for ``r`` when one of its contour cells ``c`` has a
   free neighbouring frontier cell ``f`` (set ``F_c``) that ``r`` can reach over
   known-free cells; then

       d(r, c_a) = min_{f in F_c} delta(r, f)                                (1)

   with ``delta`` the real path cost. Otherwise every contour cell ``c_i`` gets

       d(r, c_i) = g(r, c) + rho,   rho = l if a known obstacle lies on the
                                    straight line r -> c, else 0             (2)

   (``g`` Euclidean distance, ``l`` the map diagonal), and

       d(r, R) = min_c d(r, c)                                               (3)

3. §IV.B, eqs. (4)-(5): the robot-region assignment minimising the sum of
   ``d(r_i, R_j)`` with one region per robot, solved exactly by
   :func:`scipy.optimize.linear_sum_assignment` (the paper uses an LP solver on
   the same problem; both return an optimum).
4. §IV.C: ``FM``, a subset of the frontier cells at least ``fm_spacing`` (the
   sensor range) apart. ``cc_r`` is the contour cell of ``r``'s region that
   attains ``d(r, R_r)``. Robots whose region is inaccessible choose first, then
   the others, each in id order, the frontier of ``FM`` minimising

       d(r_i, f_j) = delta(r_i, f_j) + g(f_j, cc) + rho1(f_j, cc) + rho2(f_j)  (6)
       T_i = argmin_j d(r_i, f_j)                                              (7)

   (``inf`` when ``f_j`` is not reachable; ``rho1 = l`` if a known obstacle
   lies on the line ``f_j -> cc``; ``rho2 = v`` if another robot already chose
   ``f_j``).
5. §IV.D step 11: robots travel until one of them reaches its target (or needs
   a new goal for another reason, see the re-planning rules); then a new round
   re-decides every robot.

Parameters (rendered from ``Kme.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin kme

=============================  ======  =======  =====  =============================================
name                           symbol  default  unit   meaning
=============================  ======  =======  =====  =============================================
``v``                          v       0.0      cells  penalty rho2 for a frontier already chosen by
                                                       another robot; 0 = `l`
``fm_spacing``                 -       0.0      cells  least distance between two frontiers of FM
                                                       (paper: the sensor range); 0 = sensor range
``fm_order``                   -       nearest  -      order of the greedy FM choice: `nearest`
                                                       (path cost from the closest robot),
                                                       `clusters` (cluster representatives by size,
                                                       then raster), `raster`
``max_points``                 -       3000     cells  unknown cells K-Means runs on (random
                                                       subsample)
``kmeans_iterations``          -       20       -      most Lloyd iterations per round (stops when
                                                       labels settle)
``round_timeout``              -       0        ticks  the coordinator decides with the positions it
                                                       has after this; 0 = 2 x latency x hops + 1
``request_timeout``            -       0        ticks  re-send a request that brought no target; 0 =
                                                       2 x round_timeout + 2
``replan_on_target_explored``  -       false    -      re-plan when the goal is no longer a frontier
                                                       cell
ReplanRules                    -                       shared: ``strategies.base``
FallbackRules                  -                       shared: ``strategies.fallback``
=============================  ======  =======  =====  =============================================

.. params:end

``l`` is the diagonal of the map, ``hypot(height, width)`` cells.

Messages (sizes from :mod:`mrexplore.comm.bytes`):

========  =====================================  ==================================  ======
type      from -> to                             payload                             bytes
========  =====================================  ==================================  ======
status    a robot needing a goal -> broadcast    robot, position, flags (needs goal)  7 + 8
status    every other robot -> coordinator       robot, position, flags (a report)    7 + 8
assign    coordinator -> robot                   robot, target                        7 + 6
========  =====================================  ==================================  ======

The coordinator is the lowest live robot id of each sub-network. A robot that
needs a goal broadcasts its ``status``; hearing it, every robot sends the
coordinator its own position, and the coordinator runs a round as soon as every
robot of its sub-network has reported (or ``round_timeout`` ticks after the
request), then sends each robot whose target changed (and each robot that asked)
an ``assign``. With one hop and a latency of one tick, a robot that arrives at
its target has a new one three ticks later.

Interpretations (where the paper is silent or does not fit a grid simulator):

* **What is clustered.** All unknown cells of the coordinator's belief (§IV.A),
  including those that will never be explored (outside a building, inside thick
  walls); frontier cells join regions through eq. (1), by being 4-adjacent to a
  region's unknown cell (``F_c`` = the free 4-neighbours of ``c``, as a frontier
  cell is a free cell with an unknown 4-neighbour).
* **Contour cells** are unknown cells of a region with a 4-neighbour inside the
  map that is not of the region (known, or another region).
* **Eq. (3).** For an accessible region the minimum runs over its accessible
  contour cells (eq. 1); for an inaccessible one over all its contour cells
  (eq. 2). The symbol ``c_i`` of eq. (2) only exists for inaccessible regions.
* **"An obstacle on the line"** uses the project's line-of-sight rule
  (:mod:`mrexplore.planning.visibility`) over the cells the coordinator knows to
  be occupied; unknown cells do not block. Lines run from the robot (eq. 2) and
  from the frontier (eq. 6).
* **FM** is built greedily, keeping a frontier cell when it is at least
  ``fm_spacing`` from every cell kept so far, candidates in increasing path
  cost from the closest robot of the round (``fm_order=nearest``; the paper
  does not say how FM is drawn; ``clusters`` takes cluster representatives by
  decreasing size first, ``raster`` raster order; see the doc page for the
  comparison). A robot that can reach no cell of FM takes the nearest frontier
  cell it can reach.
* **v** is not given in the paper ("a positive value"); the default is ``l``,
  the same size as the obstacle penalty.
* **K** is the number of robots taking part in the round (those of the
  coordinator's sub-network whose positions arrived in time). A region with no
  unknown cell (possible when ``K`` exceeds the unknown cells) is at distance
  ``10 l`` from every robot so the assignment stays feasible.
* **Who is re-decided.** Every robot of the round gets a new target (§IV.D),
  but a robot whose target did not change gets no message. Robots that did not
  report in time keep their targets, which count as chosen (rho2).
* **When.** A round starts when a robot reaches its target (§IV.D step 11: "Robots
  move to their targets until one robot arrives at its target"), is blocked, has
  no goal, or a re-planning rule of :data:`REPLAN_PARAMS` fires; none does by
  default (``replan_on_target_explored=True``, our earlier default, also starts a
  round once a target stops being a frontier cell: with sensing while moving,
  targets are usually seen before they are reached, and rounds came every 1.5-2
  ticks).
* **Limited communication.** Each sub-network has its own coordinator, which
  clusters the unknown space of its own belief into as many regions as robots it
  can reach: sub-networks do not know of each other, so their regions overlap
  and robots of different sub-networks may explore the same area (the central
  method degrades into one KME per sub-network). Lost reports only shrink a
  round (robots keep their targets); lost requests are re-sent after
  ``request_timeout``; lost assignments are re-requested the same way.
* **Unreliable communication** (ours; the paper assumes every message arrives).
  A robot that has needed a target for ``coordinator_timeout`` ticks without one
  it can follow runs KME for a team of one: :func:`kme_round` on its own belief
  with itself only (K = 1: one region, the unknown space; eq. (6) to its
  contour), without the targets of others. It goes on asking; an ``assign`` that
  arrives later replaces its target. The coordinator waits for reports at most
  ``round_timeout``. With lossless links an answer comes within one request
  period, so the rule does not fire.
* **Blocked targets** (ours). A target on which a robot was blocked
  ``block_limit`` times in a row (e.g. a failed robot stands on it) is
  unreachable for that robot (``delta = inf``) until it next arrives at a target;
  a robot left with no target at all forgets these and tries them again. See
  :mod:`mrexplore.strategies.fallback`.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numba
import numpy as np
import numpy.typing as npt
from scipy.optimize import linear_sum_assignment

from mrexplore.comm.bytes import BROADCAST
from mrexplore.comm.messages import STATUS, StatusItem, item_message
from mrexplore.grid.occupancy import OCCUPIED, UNKNOWN, BeliefGrid
from mrexplore.planning import distance_field, frontier_clusters, frontier_mask
from mrexplore.planning.distance import count_field, distance_field_kernel
from mrexplore.planning.visibility import is_visible_kernel
from mrexplore.strategies.base import Cell, Decision, Param, ReplanRules, RobotView, passable
from mrexplore.strategies.coordinated import CoordinatedWithFallback
from mrexplore.strategies.network import request_timeout, round_timeout

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]

# 4-neighbour offsets in a fixed order: N, S, W, E.
_NEIGHBOURS = ((-1, 0), (1, 0), (0, -1), (0, 1))


# ---------------------------------------------------------------- §IV.A K-Means
def map_diagonal(shape: tuple[int, ...]) -> float:
    """``l``: the diagonal of the map, in cells.

    >>> map_diagonal((3, 4))
    5.0
    """
    return math.hypot(shape[0], shape[1])


@numba.njit(cache=True, nogil=True)
def _nearest_kernel(
    points: npt.NDArray[np.float64], centroids: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64]]:
    """Nearest centroid of each point (ties to the lowest index) and its squared distance."""
    n = points.shape[0]
    k = centroids.shape[0]
    labels = np.empty(n, dtype=np.int64)
    best_d2 = np.empty(n, dtype=np.float64)
    for i in range(n):
        best = np.inf
        label = 0
        for j in range(k):
            dr = points[i, 0] - centroids[j, 0]
            dc = points[i, 1] - centroids[j, 1]
            d2 = dr * dr + dc * dc
            if d2 < best:
                best = d2
                label = j
        labels[i] = label
        best_d2[i] = best
    return labels, best_d2


@numba.njit(cache=True, nogil=True)
def _kmeans_kernel(
    points: npt.NDArray[np.float64], centroids: npt.NDArray[np.float64], max_iterations: int
) -> npt.NDArray[np.int64]:
    """Lloyd iterations, updating ``centroids`` in place; returns the labels."""
    n = points.shape[0]
    k = centroids.shape[0]
    labels = np.full(n, -1, dtype=np.int64)
    for _ in range(max(1, max_iterations)):
        new_labels, own = _nearest_kernel(points, centroids)
        counts = np.zeros(k, dtype=np.int64)
        for i in range(n):
            counts[new_labels[i]] += 1
        if n >= k:
            for j in range(k):
                if counts[j] == 0:  # re-seed an empty cluster at the farthest point
                    far = int(np.argmax(own))
                    counts[new_labels[far]] -= 1
                    new_labels[far] = j
                    counts[j] = 1
                    own[far] = -1.0
        same = True
        for i in range(n):
            if new_labels[i] != labels[i]:
                same = False
                break
        if same:
            break
        labels = new_labels
        sums = np.zeros((k, 2), dtype=np.float64)
        for i in range(n):
            sums[labels[i], 0] += points[i, 0]
            sums[labels[i], 1] += points[i, 1]
        for j in range(k):
            if counts[j] > 0:
                centroids[j, 0] = sums[j, 0] / counts[j]
                centroids[j, 1] = sums[j, 1] / counts[j]
    return labels


def nearest_centroid(points: FloatArray, centroids: FloatArray) -> IntArray:
    """Index of the nearest centroid (Euclidean; ties to the lowest index) of each point."""
    labels, _ = _nearest_kernel(
        np.ascontiguousarray(points, dtype=np.float64),
        np.ascontiguousarray(centroids, dtype=np.float64),
    )
    return np.asarray(labels)


def kmeans(
    points: FloatArray, centroids: FloatArray, max_iterations: int
) -> tuple[FloatArray, IntArray]:
    """Lloyd's K-Means from the given centroids; returns ``(centroids, labels)``.

    Stops when the labels no longer change or after ``max_iterations``. A cluster
    left empty is re-seeded at the point farthest from its own centroid, so every
    centroid keeps at least one point when there are at least ``K`` points.

    >>> pts = np.array([[0.0, 0.0], [0.0, 1.0], [9.0, 9.0], [9.0, 10.0]])
    >>> c, lab = kmeans(pts, np.array([[0.0, 0.0], [1.0, 1.0]]), 10)
    >>> c.tolist(), lab.tolist()
    ([[0.0, 0.5], [9.0, 9.5]], [0, 0, 1, 1])
    """
    out = np.array(centroids, dtype=np.float64, copy=True, order="C")
    labels = _kmeans_kernel(np.ascontiguousarray(points, dtype=np.float64), out, max_iterations)
    return out, np.asarray(labels)


def partition_unknown(
    belief: BeliefGrid,
    k: int,
    rng: np.random.Generator,
    previous: FloatArray | None,
    *,
    max_points: int,
    max_iterations: int,
) -> tuple[npt.NDArray[np.int16], FloatArray]:
    """§IV.A: the region label (``0..k-1``, ``-1`` = known) of every cell, and the centroids.

    K-Means runs on at most ``max_points`` unknown cells drawn from ``rng``,
    warm-started from ``previous`` when it has ``k`` rows, else from ``k``
    random unknown cells (§IV.D step 3).
    """
    grid = np.ascontiguousarray(belief)
    width = grid.shape[1]
    # Unknown cells in raster order, as flat indices (np.nonzero on the 2-D mask gives
    # the same cells in the same order, about ten times slower).
    unknown = np.flatnonzero(grid.reshape(-1) == UNKNOWN)
    if unknown.size == 0 or k <= 0:
        return np.full(belief.shape, -1, dtype=np.int16), np.zeros((max(k, 0), 2))
    picked = unknown
    if unknown.size > max_points:
        picked = unknown[rng.choice(unknown.size, size=max_points, replace=False)]
    sample = np.stack([picked // width, picked % width], axis=1).astype(np.float64)
    if previous is None or previous.shape != (k, 2):
        pick = rng.choice(sample.shape[0], size=k, replace=sample.shape[0] < k)
        previous = sample[pick]
    centroids, _ = kmeans(sample, previous, max_iterations)
    # Every unknown cell joins its nearest centroid (as nearest_centroid does, in one
    # pass over the grid instead of a list of every unknown cell).
    return _label_unknown_kernel(grid, np.ascontiguousarray(centroids)), centroids


@numba.njit(cache=True, nogil=True)
def _label_unknown_kernel(
    belief: npt.NDArray[np.int8], centroids: npt.NDArray[np.float64]
) -> npt.NDArray[np.int16]:  # pragma: no cover - compiled
    """The nearest centroid of every ``UNKNOWN`` cell (ties to the lowest index), -1 elsewhere.

    The arithmetic is that of :func:`_nearest_kernel` on the cell's ``(row, col)``
    as float64, so the labels are the same.
    """
    height, width = belief.shape
    k = centroids.shape[0]
    labels = np.full((height, width), -1, dtype=np.int16)
    for r in range(height):
        row = float(r)
        for c in range(width):
            if belief[r, c] != UNKNOWN:
                continue
            col = float(c)
            best = np.inf
            label = 0
            for j in range(k):
                dr = row - centroids[j, 0]
                dc = col - centroids[j, 1]
                d2 = dr * dr + dc * dc
                if d2 < best:
                    best = d2
                    label = j
            labels[r, c] = label
    return labels


# ---------------------------------------------------------------- §IV.B regions
def cells_of(mask: BoolArray) -> tuple[IntArray, IntArray]:
    """``np.nonzero(mask)`` of a 2-D mask as int64 ``(rows, cols)``, raster order.

    The same arrays, found through the flat mask (several times faster on a map).

    >>> [a.tolist() for a in cells_of(np.array([[False, True], [True, True]]))]
    [[0, 1, 1], [1, 0, 1]]
    """
    flat = np.flatnonzero(np.ascontiguousarray(mask).reshape(-1)).astype(np.int64)
    rows, cols = np.divmod(flat, mask.shape[1])
    return rows, cols


def region_frontier_pairs(
    labels: npt.NDArray[np.int16], frontier: BoolArray
) -> tuple[IntArray, IntArray, IntArray, IntArray, IntArray]:
    """Every (frontier cell ``f``, unknown 4-neighbour ``c``) pair: ``f in F_c``.

    Returns ``(f_rows, f_cols, c_rows, c_cols, region)`` with ``region`` the
    label of ``c``; pairs ordered by direction (N, S, W, E), then raster order.
    """
    height, width = labels.shape
    f_rows, f_cols = cells_of(frontier)
    parts: list[tuple[IntArray, ...]] = []
    for d_row, d_col in _NEIGHBOURS:
        c_rows, c_cols = f_rows + d_row, f_cols + d_col
        inside = (c_rows >= 0) & (c_rows < height) & (c_cols >= 0) & (c_cols < width)
        fr, fc, cr, cc = f_rows[inside], f_cols[inside], c_rows[inside], c_cols[inside]
        region = labels[cr, cc].astype(np.int64)
        keep = region >= 0
        parts.append((fr[keep], fc[keep], cr[keep], cc[keep], region[keep]))
    stacked = [np.concatenate([p[i] for p in parts]).astype(np.int64) for i in range(5)]
    return stacked[0], stacked[1], stacked[2], stacked[3], stacked[4]


def contour_cells(labels: npt.NDArray[np.int16]) -> tuple[IntArray, IntArray, IntArray]:
    """Unknown cells with a 4-neighbour inside the map of another label: ``(rows, cols, region)``.

    >>> lab = np.array([[0, 0, 0], [0, 0, 1], [-1, 1, 1]], dtype=np.int16)
    >>> [a.tolist() for a in contour_cells(lab)]
    [[0, 1, 1, 1, 2], [2, 0, 1, 2, 1], [0, 0, 0, 1, 1]]
    """
    rows, cols, region = _contour_kernel(np.ascontiguousarray(labels, dtype=np.int16))
    return rows, cols, region


@numba.njit(cache=True, nogil=True)
def _contour_kernel(
    labels: npt.NDArray[np.int16],
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.int64]]:  # pragma: no cover
    """:func:`contour_cells` in one raster pass (the map border never makes a contour)."""
    height, width = labels.shape
    n = 0
    found = np.empty(height * width, dtype=np.int64)
    for r in range(height):
        for c in range(width):
            own = labels[r, c]
            if own < 0:
                continue
            if (
                (r > 0 and labels[r - 1, c] != own)
                or (r < height - 1 and labels[r + 1, c] != own)
                or (c > 0 and labels[r, c - 1] != own)
                or (c < width - 1 and labels[r, c + 1] != own)
            ):
                found[n] = r * width + c
                n += 1
    rows = np.empty(n, dtype=np.int64)
    cols = np.empty(n, dtype=np.int64)
    region = np.empty(n, dtype=np.int64)
    for i in range(n):
        rows[i] = found[i] // width
        cols[i] = found[i] - rows[i] * width
        region[i] = labels[rows[i], cols[i]]
    return rows, cols, region


@numba.njit(cache=True, nogil=True)
def _blocked_kernel(
    occupied: npt.NDArray[np.bool_],
    from_rows: npt.NDArray[np.int64],
    from_cols: npt.NDArray[np.int64],
    to_rows: npt.NDArray[np.int64],
    to_cols: npt.NDArray[np.int64],
) -> npt.NDArray[np.bool_]:
    """For each pair, whether a known obstacle lies on the line (not line of sight)."""
    out = np.empty(from_rows.shape[0], dtype=np.bool_)
    for i in range(from_rows.shape[0]):
        out[i] = not is_visible_kernel(occupied, from_rows[i], from_cols[i], to_rows[i], to_cols[i])
    return out


@numba.njit(cache=True, nogil=True)
def _first_unblocked_kernel(
    occupied: npt.NDArray[np.bool_],
    row: int,
    col: int,
    to_rows: npt.NDArray[np.int64],
    to_cols: npt.NDArray[np.int64],
) -> int:
    """Index of the first target (in the given order) seen from ``(row, col)``, or -1."""
    for i in range(to_rows.shape[0]):
        if is_visible_kernel(occupied, row, col, to_rows[i], to_cols[i]):
            return i
    return -1


def obstacle_on_line(
    occupied: BoolArray,
    from_rows: npt.ArrayLike,
    from_cols: npt.ArrayLike,
    to_rows: npt.ArrayLike,
    to_cols: npt.ArrayLike,
) -> BoolArray:
    """Whether a known obstacle lies on each straight line ``from -> to`` (rho, rho1)."""
    n = np.broadcast(from_rows, to_rows).shape
    return np.asarray(
        _blocked_kernel(
            np.ascontiguousarray(occupied, dtype=np.bool_),
            np.broadcast_to(np.asarray(from_rows, dtype=np.int64), n).copy(),
            np.broadcast_to(np.asarray(from_cols, dtype=np.int64), n).copy(),
            np.broadcast_to(np.asarray(to_rows, dtype=np.int64), n).copy(),
            np.broadcast_to(np.asarray(to_cols, dtype=np.int64), n).copy(),
        )
    )


def accessible_contour_distance(
    delta: FloatArray, f_rows: IntArray, f_cols: IntArray
) -> FloatArray:
    """Eq. (1) for each pair ``(f, c)``: ``delta(r, f)``; the minimum over ``F_c`` is eq. (3).

    ``delta`` is the robot's real-path distance field (``inf`` where unreachable).
    A contour cell is accessible when one of its pairs is finite.
    """
    return np.asarray(delta[f_rows, f_cols], dtype=np.float64)


def inaccessible_contour_distance(
    robot: Cell, c_rows: IntArray, c_cols: IntArray, occupied: BoolArray, diagonal: float
) -> FloatArray:
    """Eq. (2): ``g(r, c) + rho`` for each contour cell ``c``; ``rho = l`` if the line is blocked.

    >>> occ = np.zeros((5, 5), dtype=bool); occ[2, 2] = True
    >>> rows, cols = np.array([2, 0]), np.array([4, 0])
    >>> inaccessible_contour_distance((2, 0), rows, cols, occ, 10.0).tolist()
    [14.0, 2.0]
    """
    g = np.hypot(c_rows - robot[0], c_cols - robot[1])
    blocked = obstacle_on_line(occupied, np.int64(robot[0]), np.int64(robot[1]), c_rows, c_cols)
    return np.asarray(g + np.where(blocked, diagonal, 0.0), dtype=np.float64)


def nearest_inaccessible_contour(
    robot: Cell, c_rows: IntArray, c_cols: IntArray, occupied: BoolArray, diagonal: float
) -> tuple[float, int]:
    """Eqs. (2)-(3) for one region: ``(min_c g + rho, index of that c)``; ``(inf, -1)`` if empty.

    Same result as ``min(inaccessible_contour_distance(...))`` (first index among
    ties, in order of ``g``) but tests lines in order of ``g`` and stops at the
    first clear one: every blocked cell costs at least ``l``, more than any ``g``.
    """
    if c_rows.size == 0:
        return math.inf, -1
    g = np.hypot(c_rows - robot[0], c_cols - robot[1])
    order = np.argsort(g, kind="stable")
    first = _first_unblocked_kernel(
        np.ascontiguousarray(occupied, dtype=np.bool_),
        int(robot[0]),
        int(robot[1]),
        np.ascontiguousarray(c_rows[order]),
        np.ascontiguousarray(c_cols[order]),
    )
    if first >= 0:
        index = int(order[first])
        return float(g[index]), index
    index = int(order[0])
    return float(g[index]) + diagonal, index


@dataclass(frozen=True)
class RegionDistances:
    """Eq. (3) for every robot (rows) and region (columns).

    Attributes:
        d: ``d(r_i, R_j)`` in cells.
        accessible: whether ``R_j`` is accessible for ``r_i``.
        closest: ``(N, K, 2)`` the contour cell attaining ``d`` (``-1`` if none).
    """

    d: FloatArray
    accessible: BoolArray
    closest: IntArray


def robot_region_distances(
    positions: Sequence[Cell],
    deltas: Sequence[FloatArray],
    labels: npt.NDArray[np.int16],
    frontier: BoolArray,
    occupied: BoolArray,
    k: int,
) -> RegionDistances:
    """Eqs. (1)-(3): the distance of each robot to each of the ``k`` regions.

    ``deltas[i]`` is robot ``i``'s real-path distance field over known-free cells
    (``inf`` where it cannot go); it must be exact on every frontier cell.
    """
    diagonal = map_diagonal(labels.shape)
    n = len(positions)
    d = np.full((n, k), math.inf)
    accessible = np.zeros((n, k), dtype=bool)
    closest = np.full((n, k, 2), -1, dtype=np.int64)
    f_rows, f_cols, pc_rows, pc_cols, pair_region = region_frontier_pairs(labels, frontier)
    c_rows, c_cols, c_region = contour_cells(labels)
    by_region = [np.flatnonzero(c_region == j) for j in range(k)]
    pairs_by_region = [np.flatnonzero(pair_region == j) for j in range(k)]
    for i, (position, delta) in enumerate(zip(positions, deltas, strict=True)):
        pair_d = accessible_contour_distance(delta, f_rows, f_cols)
        for j in range(k):
            pairs = pairs_by_region[j]
            if pairs.size:
                best = int(pairs[np.argmin(pair_d[pairs])])
                if np.isfinite(pair_d[best]):  # eq. (1), min over accessible c: eq. (3)
                    d[i, j] = pair_d[best]
                    accessible[i, j] = True
                    closest[i, j] = (pc_rows[best], pc_cols[best])
                    continue
            cells = by_region[j]
            value, index = nearest_inaccessible_contour(  # eqs. (2)-(3)
                position, c_rows[cells], c_cols[cells], occupied, diagonal
            )
            if index >= 0:
                d[i, j] = value
                closest[i, j] = (c_rows[cells[index]], c_cols[cells[index]])
    return RegionDistances(d, accessible, closest)


def assign_regions(d: FloatArray, infeasible: float | None = None) -> IntArray:
    """Eqs. (4)-(5): region index of each robot minimising ``sum a_ij d(r_i, R_j)``.

    Each robot gets one region and each region at most one robot (exactly one
    when the matrix is square, as in the paper). Infinite distances are replaced
    by ``infeasible`` (default ten times the largest finite one, or 1).

    >>> assign_regions(np.array([[1.0, 2.0], [1.5, 9.0]])).tolist()
    [1, 0]
    """
    if d.size == 0:
        return np.zeros(d.shape[0], dtype=np.int64)
    finite = d[np.isfinite(d)]
    if infeasible is None:
        infeasible = 10.0 * float(finite.max()) if finite.size else 1.0
    cost = np.where(np.isfinite(d), d, infeasible)
    rows, cols = linear_sum_assignment(cost)
    out = np.full(d.shape[0], -1, dtype=np.int64)
    out[rows] = cols
    return out


# ---------------------------------------------------------------- §IV.C targets
@numba.njit(cache=True, nogil=True)
def _spaced_kernel(
    rows: npt.NDArray[np.int64], cols: npt.NDArray[np.int64], spacing2: float
) -> npt.NDArray[np.int64]:
    kept = np.empty(rows.shape[0], dtype=np.int64)
    n = 0
    for i in range(rows.shape[0]):
        ok = True
        for k in range(n):
            dr = rows[i] - rows[kept[k]]
            dc = cols[i] - cols[kept[k]]
            if dr * dr + dc * dc < spacing2:
                ok = False
                break
        if ok:
            kept[n] = i
            n += 1
    return kept[:n].copy()


def spaced_subset(rows: IntArray, cols: IntArray, spacing: float) -> IntArray:
    """Indices of a greedy subset, in the given order, of cells at least ``spacing`` apart.

    >>> spaced_subset(np.array([0, 0, 0, 0]), np.array([0, 3, 5, 9]), 4.0).tolist()
    [0, 2, 3]
    """
    return np.asarray(
        _spaced_kernel(
            np.ascontiguousarray(rows, dtype=np.int64),
            np.ascontiguousarray(cols, dtype=np.int64),
            float(spacing) * float(spacing),  # inf, not OverflowError, past 1e154
        )
    )


FM_ORDERS = ("nearest", "clusters", "raster")
"""Orders of the greedy FM choice (parameter ``fm_order``)."""


def frontier_subset(
    frontier: BoolArray, spacing: float, nearest_robot: FloatArray | None = None
) -> tuple[IntArray, IntArray]:
    """FM: frontier cells at least ``spacing`` apart (§IV.C), as ``(rows, cols)``.

    Greedy: candidates in increasing order of ``nearest_robot`` (the path cost
    from the closest robot, ``H x W``; unreachable cells last, ties in raster
    order), each kept when it is at least ``spacing`` from every cell kept so
    far. Without ``nearest_robot``: the representatives of the frontier clusters
    by decreasing cluster size, then every frontier cell in raster order.

    >>> f = np.zeros((1, 10), dtype=bool); f[0, [0, 2, 9]] = True
    >>> [a.tolist() for a in frontier_subset(f, 3.0, np.arange(10.0)[::-1].reshape(1, 10))]
    [[0, 0], [9, 2]]
    """
    rows, cols = cells_of(frontier)
    if nearest_robot is not None:
        order = np.argsort(nearest_robot[rows, cols], kind="stable")
        rows, cols = rows[order], cols[order]
    else:
        clusters = sorted(frontier_clusters(frontier), key=lambda c: -c.size)
        rep = np.array([c.representative for c in clusters], dtype=np.int64).reshape(-1, 2)
        rows = np.concatenate([rep[:, 0], rows])
        cols = np.concatenate([rep[:, 1], cols])
    keep = spaced_subset(rows, cols, spacing)
    return rows[keep], cols[keep]


def target_distance(
    delta_f: FloatArray,
    fm_rows: IntArray,
    fm_cols: IntArray,
    closest_contour: Cell,
    occupied: BoolArray,
    diagonal: float,
    taken: BoolArray,
    v: float,
) -> FloatArray:
    """Eq. (6): ``delta(r, f_j) + g(f_j, cc) + rho1(f_j, cc) + rho2(f_j)`` for each ``f_j`` of FM.

    ``delta_f`` holds the robot's real-path cost to each ``f_j`` (``inf`` when
    unreachable: then ``d = inf``). ``rho1 = diagonal`` when a known obstacle lies
    on the line ``f_j -> cc``; ``rho2 = v`` where ``taken``.

    >>> occ = np.zeros((4, 6), dtype=bool)
    >>> target_distance(np.array([2.0, np.inf, 5.0]), np.array([0, 0, 3]),
    ...     np.array([0, 5, 5]), (3, 0), occ, 7.2, np.array([False, False, True]), 100.0).tolist()
    [5.0, inf, 110.0]
    """
    cc_row, cc_col = closest_contour
    g = np.hypot(fm_rows - cc_row, fm_cols - cc_col)
    rho1 = np.where(
        obstacle_on_line(occupied, fm_rows, fm_cols, np.int64(cc_row), np.int64(cc_col)),
        diagonal,
        0.0,
    )
    rho2 = np.where(taken, v, 0.0)
    d = delta_f + g + rho1 + rho2
    return np.asarray(np.where(np.isfinite(delta_f), d, math.inf), dtype=np.float64)


def choose_target(d: FloatArray) -> int:
    """Eq. (7): ``argmin_j d(r_i, f_j)`` (first among ties), or -1 when every ``d`` is infinite."""
    if d.size == 0 or not np.isfinite(d).any():
        return -1
    return int(np.argmin(d))


# ---------------------------------------------------------------- path costs
class _FieldBuffers:
    """The buffers of the distance fields of one round, kept for the next (one grid shape)."""

    def __init__(self, n_cells: int) -> None:
        self.n_cells = n_cells
        self.dists: list[FloatArray] = []
        self.state = np.zeros(n_cells, dtype=np.uint8)
        self.buckets = np.empty((3, n_cells), dtype=np.int32)


_local = threading.local()


def robot_fields(free: BoolArray, sources: Sequence[Cell], frontier: BoolArray) -> list[FloatArray]:
    """``distance_field(free, s, targets=frontier)`` for each source ``s``, bit for bit.

    The fields live in buffers kept (per thread) for the next call, so they are valid
    only until then: a round allocates no new ``H x W`` arrays, which at 685 x 744
    cost as much as a tenth of the searches (page faults on fresh memory).
    """
    height, width = free.shape
    n_cells = height * width
    buffers: _FieldBuffers | None = getattr(_local, "buffers", None)
    if buffers is None or buffers.n_cells != n_cells:
        buffers = _local.buffers = _FieldBuffers(n_cells)
    while len(buffers.dists) < len(sources):
        buffers.dists.append(np.empty(n_cells))
    flat = np.ascontiguousarray(free, dtype=np.bool_).reshape(-1)
    targets = np.ascontiguousarray(frontier, dtype=np.bool_).reshape(-1)
    n_targets = int(np.count_nonzero(targets & flat))
    fields = []
    for source, dist in zip(sources, buffers.dists, strict=False):
        row, col = int(source[0]), int(source[1])
        src = row * width + col
        grid = flat
        n = n_targets
        if not flat[src]:  # as distance_field: the source always counts as passable
            n += int(targets[src])
            grid = flat.copy()
            grid[src] = True
        dist.fill(np.inf)
        buffers.state.fill(0)
        count_field()
        distance_field_kernel(
            grid, height, width, src, targets, n, math.inf, dist, buffers.state, buffers.buckets
        )
        fields.append(dist.reshape(height, width))
    return fields


# ---------------------------------------------------------------- one round
@dataclass
class KmePlan:
    """The result of one KME round on the coordinator."""

    targets: dict[int, Cell] = field(default_factory=dict)
    regions: dict[int, int] = field(default_factory=dict)
    accessible: dict[int, bool] = field(default_factory=dict)
    centroids: FloatArray | None = None


def kme_round(
    belief: BeliefGrid,
    positions: Mapping[int, Cell],
    rng: np.random.Generator,
    previous_centroids: FloatArray | None,
    *,
    fm_spacing: float,
    v: float,
    max_points: int,
    max_iterations: int,
    taken: Iterable[Cell] = (),
    fm_order: str = "nearest",
    unreachable: Mapping[int, Iterable[Cell]] | None = None,
) -> KmePlan:
    """Steps 4-10 of §IV.D for the robots in ``positions`` on one belief map.

    ``taken`` are targets held by robots outside the round (they count for rho2).
    ``v <= 0`` means ``v = l``. ``fm_order`` is one of :data:`FM_ORDERS`.
    ``unreachable[r]`` are cells robot ``r`` cannot reach whatever the map says
    (``delta = inf`` there).
    """
    robots = sorted(positions)
    plan = KmePlan(centroids=previous_centroids)
    frontier = frontier_mask(belief)
    if not robots or not frontier.any():
        return plan
    k = len(robots)
    diagonal = map_diagonal(belief.shape)
    v = v if v > 0 else diagonal
    free = passable(belief)
    occupied = np.asarray(belief == OCCUPIED)
    labels, centroids = partition_unknown(
        belief, k, rng, previous_centroids, max_points=max_points, max_iterations=max_iterations
    )
    plan.centroids = centroids
    deltas = robot_fields(free, [positions[r] for r in robots], frontier)
    for delta, robot in zip(deltas, robots, strict=True):
        delta[positions[robot]] = math.inf  # a robot's own cell is no target
        for cell in (unreachable or {}).get(robot, ()):
            delta[cell] = math.inf
    distances = robot_region_distances(
        [positions[r] for r in robots], deltas, labels, frontier, occupied, k
    )
    region_of = assign_regions(distances.d, infeasible=10.0 * diagonal)
    if fm_order == "nearest":
        # frontier_subset reads the key at frontier cells only: take the minimum there.
        nearest_key = np.full(belief.shape, math.inf)
        f_rows, f_cols = cells_of(frontier)
        nearest_key[f_rows, f_cols] = np.minimum.reduce([d[f_rows, f_cols] for d in deltas])
        order_key: FloatArray | None = nearest_key
    elif fm_order == "raster":
        order_key = np.zeros(belief.shape)  # a stable sort keeps raster order
    else:
        order_key = None  # cluster representatives first
    fm_rows, fm_cols = frontier_subset(frontier, fm_spacing, order_key)
    chosen = np.zeros(fm_rows.size, dtype=bool)
    taken_set = set(taken)
    for j in range(fm_rows.size):
        chosen[j] = (int(fm_rows[j]), int(fm_cols[j])) in taken_set
    order = sorted(range(k), key=lambda i: (bool(distances.accessible[i, region_of[i]]), i))
    for i in order:
        robot = robots[i]
        region = int(region_of[i])
        plan.regions[robot] = region
        plan.accessible[robot] = bool(distances.accessible[i, region])
        cc = distances.closest[i, region]
        delta_f = deltas[i][fm_rows, fm_cols]
        if cc[0] >= 0:
            d = target_distance(
                delta_f, fm_rows, fm_cols, (int(cc[0]), int(cc[1])), occupied, diagonal, chosen, v
            )
        else:  # no unknown cell in the region: eq. (6) without the region terms
            d = delta_f + np.where(chosen, v, 0.0)
        best = choose_target(d)
        if best >= 0:
            plan.targets[robot] = (int(fm_rows[best]), int(fm_cols[best]))
            chosen[best] = True
            continue
        reachable = frontier & np.isfinite(deltas[i])
        if reachable.any():  # no cell of FM reachable: the nearest frontier cell
            f_rows, f_cols = cells_of(reachable)
            nearest = int(np.argmin(deltas[i][f_rows, f_cols]))
            plan.targets[robot] = (int(f_rows[nearest]), int(f_cols[nearest]))
    return plan


# ---------------------------------------------------------------- the strategy
class Kme(CoordinatedWithFallback):
    """Wu, Puig & Garcia's KME, run by the lowest-id robot of each sub-network."""

    id = "kme"
    summary = "Wu, Puig & Garcia: K-Means regions of unknown space, optimal region assignment"
    citation = (
        "L. Wu, D. Puig, M. A. Garcia, Balanced multi-robot exploration through a global "
        "optimization strategy (§IV, eqs. 1-7)"
    )
    v = Param(
        0.0,
        "cells",
        "penalty rho2 for a frontier chosen by another robot; 0 = l",
        "v",
        low=0,
        note="penalty rho2 for a frontier already chosen by another robot; 0 = `l`",
    )
    fm_spacing = Param(
        0.0,
        "cells",
        "least spacing of the frontiers in FM; 0 = sensor range",
        low=0,
        note=(
            "least distance between two frontiers of FM (paper: the sensor range); 0 = sensor range"
        ),
    )
    fm_order = Param(
        "nearest",
        "",
        "greedy FM order: nearest | clusters | raster",
        choices=FM_ORDERS,
        note=(
            "order of the greedy FM choice: `nearest` (path cost from the closest "
            "robot), `clusters` (cluster representatives by size, then raster), "
            "`raster`"
        ),
    )
    max_points = Param(
        3000,
        "cells",
        "unknown cells K-Means is run on (random subsample)",
        low=1,
        note="unknown cells K-Means runs on (random subsample)",
    )
    kmeans_iterations = Param(
        20,
        "",
        "most Lloyd iterations of K-Means per round",
        low=1,
        note="most Lloyd iterations per round (stops when labels settle)",
    )
    round_timeout = Param(
        0,
        "ticks",
        "decide with the reports at hand after this; 0 = auto",
        low=0,
        note=(
            "the coordinator decides with the positions it has after this; 0 = 2 x "
            "latency x hops + 1"
        ),
    )
    request_timeout = Param(
        0,
        "ticks",
        "re-send a request after this; 0 = auto",
        low=0,
        note="re-send a request that brought no target; 0 = 2 x round_timeout + 2",
    )
    # §IV.D step 11: "Robots move to their targets until one robot arrives at its
    # target": a round on arrival, not when a target got explored.
    replan_on_target_explored = ReplanRules.replan_on_target_explored.with_default(False)

    def __init__(self, robot_id: int, n_robots: int, **params: object) -> None:
        super().__init__(robot_id, n_robots, **params)
        # Coordinator state.
        self.reports: dict[int, tuple[Cell, int]] = {}  # robot -> (position, tick sent)
        self.round_since = -1  # tick the open round's first request was sent, -1 = none
        self.round_opened = -1  # tick the coordinator opened it
        self.requesters: set[int] = set()
        self.centroids: FloatArray | None = None
        self.rounds = 0
        # Member state.
        self.replied_at = -1
        self.alone_centroids: FloatArray | None = None

    # ------------------------------------------------------------ timing
    def _round_timeout(self, view: RobotView, coordinator: int) -> int:
        return round_timeout(self.round_timeout, view, coordinator)

    def _request_timeout(self, view: RobotView, coordinator: int) -> int:
        round_ticks = self._round_timeout(view, coordinator)
        return request_timeout(self.request_timeout, round_ticks)

    # ------------------------------------------------------------ decide
    def decide_coordinated(self, view: RobotView) -> Decision:
        coordinator = self.coordinator(view)
        is_coordinator = coordinator == self.robot_id
        assignment = self.assignment(view)
        heard_request = False
        for message in view.inbox:
            payload = message.payload
            if message.type == STATUS and isinstance(payload, StatusItem):
                heard_request |= payload.needs_goal and payload.robot != self.robot_id
                if is_coordinator:
                    self._record_report(payload, message.tick_sent, view.tick)
        needs_goal = self.needs_plan(view)
        if is_coordinator:
            self.watch.stop()
            return self._coordinate(view, needs_goal)

        decision = Decision()
        if assignment is not None:
            followed = self.follow(view, assignment)
            if followed.goal is not None:
                self.requested_at = -1
                decision = followed
                needs_goal = False
            elif assignment != view.position:
                needs_goal = True  # cannot reach it on my own map
        if not needs_goal:
            self.watch.stop()
        else:
            own = self.fall_back(view, self._request_timeout(view, coordinator))
            if own is not None:
                decision, needs_goal = own, False
        request = needs_goal and (
            self.requested_at < 0
            or view.tick - self.requested_at >= self._request_timeout(view, coordinator)
        )
        if request:
            self.requested_at = view.tick
        if request or (heard_request and self.replied_at != view.tick):
            # A request opens a round for everyone; a report answers one.
            self.replied_at = view.tick
            status = StatusItem(self.robot_id, view.position, request)
            dest = BROADCAST if request else coordinator
            decision.messages.append(item_message(STATUS, self.robot_id, dest, status))
        return decision

    def _record_report(self, status: StatusItem, tick_sent: int, now: int) -> None:
        self.reports[status.robot] = (status.position, tick_sent)
        if status.needs_goal:
            self.requesters.add(status.robot)
            if self.round_since < 0:
                self.round_since, self.round_opened = tick_sent, now
            else:
                self.round_since = min(self.round_since, tick_sent)

    def plan_alone(self, view: RobotView) -> Decision:
        """KME for a team of one: this robot, its own belief, no targets of others.

        The round draws from the robot's random stream (K-Means) only when the robot
        can reach a frontier cell, so an attempt that finds nothing changes nothing.
        """
        frontier = frontier_mask(view.belief)
        dist = distance_field(passable(view.belief), view.position, targets=frontier)
        dist[view.position] = math.inf
        reachable = frontier & np.isfinite(dist)
        if not reachable.any():
            return Decision()
        if self.blocked_targets.excluded:
            rows, cols = np.nonzero(reachable)
            cells = {(int(r), int(c)) for r, c in zip(rows, cols, strict=True)}
            if cells <= self.blocked_targets.excluded:
                self.blocked_targets.forget()  # nothing else to go to: try them again
        plan = self._round(view, {self.robot_id: view.position}, self.alone_centroids)
        self.alone_centroids = plan.centroids
        goal = plan.targets.get(self.robot_id)
        return Decision() if goal is None else self.follow(view, goal)

    def _round(
        self,
        view: RobotView,
        positions: Mapping[int, Cell],
        centroids: FloatArray | None,
        taken: Iterable[Cell] = (),
    ) -> KmePlan:
        """:func:`kme_round` on this robot's belief with the strategy's parameters."""
        return kme_round(
            view.belief,
            positions,
            view.rng,
            centroids,
            fm_spacing=self.fm_spacing or view.sensor_range,
            v=self.v,
            max_points=self.max_points,
            max_iterations=self.kmeans_iterations,
            taken=taken,
            fm_order=self.fm_order,
            unreachable={self.robot_id: self.blocked_targets.excluded},
        )

    def _coordinate(self, view: RobotView, needs_goal: bool) -> Decision:
        """Coordinator: open rounds, collect positions, decide when all reported."""
        members = view.subnetwork
        decision = Decision()
        self.reports[self.robot_id] = (view.position, view.tick)
        self.keep_members(members)
        if view.goal is not None:
            self.held_goals[self.robot_id] = view.goal
        may_request = self.requested_at < 0 or (
            view.tick - self.requested_at >= self._request_timeout(view, self.robot_id)
        )
        if needs_goal and self.robot_id not in self.requesters and may_request:
            self.requested_at = view.tick
            self.requesters.add(self.robot_id)
            if self.round_since < 0:
                self.round_since, self.round_opened = view.tick, view.tick
            if len(members) > 1:  # ask the others for their positions
                status = StatusItem(self.robot_id, view.position, True)
                decision.messages.append(item_message(STATUS, self.robot_id, BROADCAST, status))
        self.requesters &= members
        if self.round_since < 0 or not self.requesters:
            self.round_since = self.round_opened = -1
            return decision
        fresh = {r for r in members if r in self.reports and self.reports[r][1] >= self.round_since}
        waited = view.tick - self.round_opened
        if fresh != set(members) and waited < self._round_timeout(view, self.robot_id):
            return decision
        return self._run_round(view, fresh, decision)

    def _run_round(self, view: RobotView, robots: set[int], decision: Decision) -> Decision:
        positions = {r: self.reports[r][0] for r in robots}
        outside = [g for r, g in self.held_goals.items() if r not in robots]
        plan = self._round(view, positions, self.centroids, outside)
        self.centroids = plan.centroids
        self.rounds += 1
        self.last_plan_tick = view.tick
        for robot in sorted(robots):
            goal = plan.targets.get(robot)
            if goal is None:
                continue
            unchanged = self.held_goals.get(robot) == goal
            self.held_goals[robot] = goal
            if not unchanged or robot in self.requesters:
                self.hand_out(view, decision, robot, goal)
        if decision.goal is not None:  # the coordinator follows a goal of its own
            self.requested_at = -1
        if self.robot_id in self.requesters and decision.goal is None:
            decision.idle = True  # nothing reachable for the coordinator itself
            self.blocked_targets.forget()  # try the targets it gave up on again
        self.requesters.clear()
        self.round_since = self.round_opened = -1
        return decision
