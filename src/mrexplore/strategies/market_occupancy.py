"""Decentralised market-based exploration with a frontier occupancy function.

"Decentralised market-based strategy for cooperative multi-robot exploration"
(authors, venue and year not named in our copy of the paper), §III.B,
eqs. (1)-(8) and Algorithm 1; frontier points from the RRT-based detector of
H. Umari, S. Mukhopadhyay, "Autonomous robotic exploration based on multiple
rapidly-exploring randomized trees", IROS 2017
(:mod:`mrexplore.planning.rrt_frontiers`). Doc page:
``docs/strategies/market-occupancy.md``.

Every robot ``i`` weighs every frontier point ``q_j`` of a list ``y`` (eqs. 1-2):

    C_ij = || p_i - q_j ||                                  Euclidean cost     (3)
    U_ij = lambda_u * c_j                                   utility            (4)
    F_ij = lambda_f * exp(-||q_j - q_a||^2 / (2 sigma^2))   frontier occupancy (5)
    W_ij = C_ij - U_ij + F_ij                                                   (6)

with ``c_j`` the unknown cells of robot ``i``'s map within ``r`` of ``q_j``,
``sigma = r_f / 3`` (``3 sigma = r_f``), and ``F_ij`` non-zero only when ``q_j``
lies within ``r_f`` of ``q_a``, the point assigned to another robot ``a``
(summed over the other robots). The weights of all robots form ``W`` (N x M,
eq. 7), and every robot solves the same assignment problem (eq. 8)

    min sum_i sum_j W_ij X_ij

with the Hungarian algorithm (:func:`scipy.optimize.linear_sum_assignment`),
then takes its own row's point (Algorithm 1, lines 5-7).

Event-based rounds (§III.B, Fig. 4): when a robot reaches its goal it broadcasts
a ``weight_request`` carrying its frontier list ``y``, and its own row. Every
robot that hears the request computes its row over ``y`` and broadcasts it
(Algorithm 1, lines 1-4). A robot decides a round as soon as it holds the rows
of every robot of its sub-network, or ``round_timeout`` ticks after it heard of
the round; the matrix then holds the rows that arrived in time.

Parameters (rendered from ``MarketOccupancy.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin market-occupancy

=============================  ========  ==========  ======================  =======================
name                           symbol    default     unit                    meaning
=============================  ========  ==========  ======================  =======================
``lambda_u``                   lambda_u  0.1         cells/cell              weight of the utility
                                                                             (eq. 4)
``lambda_f``                   lambda_f  0.0         cells                   peak of the frontier
                                                                             occupancy (eq. 5); 0 =
                                                                             `r_f`
``r``                          r         0.0         cells                   radius of the utility
                                                                             disk (eq. 4); 0 =
                                                                             sensor range
``r_f``                        r_f       0.0         cells                   occupancy radius 3
                                                                             sigma (eq. 5); 0 = 2 x
                                                                             sensor range
``cost``                       C_ij      euclidean   -                       eq. (3): Euclidean
                                                                             distance (the paper);
                                                                             `path`: shortest-path
                                                                             length on the robot's
                                                                             map
``frontier_detector``          -         grid        -                       `grid` or `rrt`
``rrt_eta``                    eta       5.0         cells                   RRT growth step of both
                                                                             trees; Umari's launch
                                                                             files: 1 m (5 cells at
                                                                             0.2 m per cell); 0 =
                                                                             sensor range, the
                                                                             earlier default
``rrt_global_eta``             eta       0.0         cells                   growth step of the
                                                                             global tree; Umari: 1 m
                                                                             with three robots on
                                                                             the merged map
                                                                             (`three_robots.launch`),
                                                                             15 m with one robot (75
                                                                             cells); 0 = `rrt_eta`
``rrt_samples``                -         0           samples/tick            RRT iterations per tree
                                                                             per tick; 0 = from
                                                                             `rrt_sample_density`;
                                                                             the earlier default was
                                                                             20
``rrt_sample_density``         -         1.0         samples/tick/footprint  the budget:
                                                                             `ceil(density H W / (pi
                                                                             r^2))` samples per tree
                                                                             per tick (Intel at 0.2
                                                                             m: 46; office 120 x 80
                                                                             with a 15-cell sensor:
                                                                             14; 100 x 100 with 8
                                                                             cells: 50)
``rrt_vertex_spacing``         -         1.0         cells                   a free edge shorter
                                                                             than this adds no
                                                                             vertex
``rrt_burst``                  -         50          batches                 extra RRT batches (one
                                                                             tick's budget each)
                                                                             when a goal is needed
                                                                             and no reachable point
                                                                             is stored
``rrt_clustering``             -         mean-shift  -                       how stored RRT points
                                                                             are merged: `mean-
                                                                             shift` (Umari's filter)
                                                                             or `greedy` (the
                                                                             earlier version)
``rrt_bandwidth``              -         1.5         cells                   mean-shift bandwidth;
                                                                             Umari's filter:
                                                                             `MeanShift(bandwidth=0.3)`,
                                                                             0.3 m
``rrt_cluster_radius``         -         0.0         cells                   `greedy`: stored RRT
                                                                             points closer than this
                                                                             are merged; 0 = sensor
                                                                             range / 2
``rrt_filter_radius``          -         2.5         cells                   RRT points: radius of
                                                                             the information-gain
                                                                             test (Umari:
                                                                             `info_radius * 0.5` =
                                                                             0.5 m); 0 = no test
``rrt_filter_min_gain``        -         5.0         cells                   RRT points with fewer
                                                                             unknown cells within
                                                                             `rrt_filter_radius` are
                                                                             dropped (Umari: 0.2 m²
                                                                             = 5 cells of 0.04 m²)
``filter_radius``              -         0.0         cells                   every detector's
                                                                             points: radius of the
                                                                             same test; 0 = no
                                                                             filter
``filter_min_gain``            -         0.0         cells                   every detector's points
                                                                             with fewer unknown
                                                                             cells within
                                                                             `filter_radius` are
                                                                             dropped
``round_timeout``              -         0           ticks                   decide with the rows at
                                                                             hand after this; 0 = 2
                                                                             x latency x hops + 1
``request_timeout``            -         0           ticks                   least time between two
                                                                             requests of a robot; 0
                                                                             = 2 x round_timeout + 2
``event_based``                -         true        -                       rounds open on events
                                                                             (goal reached, blocked,
                                                                             no goal); `false`: only
                                                                             every `replan_every`
                                                                             ticks (time-triggered,
                                                                             an ablation)
``idle_until_clock``           -         true        -                       with
                                                                             `event_based=false`, a
                                                                             robot that needs a goal
                                                                             waits for its clock;
                                                                             `false`: it also opens
                                                                             a round at once
``replan_on_target_explored``  -         false       -                       re-plan when the goal
                                                                             is no longer a frontier
                                                                             cell
ReplanRules                    -                                             shared:
                                                                             ``strategies.base``
=============================  ========  ==========  ======================  =======================

.. params:end

Messages (sizes: header of :mod:`mrexplore.comm.bytes` plus the payload below):

==================  ================================================  ================
type                payload                                           bytes
==================  ================================================  ================
``weight_request``  requester uint16, round uint16, M uint16,         7 + 6 + 8 M
                    M frontier points (x float32, y float32)
``weights``         robot uint16, requester uint16, round uint16,     7 + 6 + 4 M
                    M weights float32
==================  ================================================  ================

Both are broadcasts to the sub-network. A frontier point is two float32 (the
paper's points are continuous ``x, y, z``; in 2-D the ``z`` is dropped), as
:data:`FRONTIER_POINT_BYTES`; weights travel as float32, and each robot uses
its own row rounded to float32 too, so every robot solves the same matrix.

Interpretations (where the paper is silent):

* **lambda_u, lambda_f, r, r_f** are "experimentally determined" in the paper,
  without values. Defaults: ``r`` = the sensor range (the robot senses the
  unknown cells around the point, as the paper assumes), ``r_f`` = twice the
  sensor range (two robots at points closer than that sense overlapping
  disks), ``lambda_f = r_f`` (a point next to another robot's point costs as
  much as ``r_f`` cells more travel), ``lambda_u = 0.1`` (ten unknown cells
  are worth one cell of travel). We chose them by a small comparison of
  T99 on generated maps, documented in the doc page.
* **Several other robots.** ``F_ij`` sums the Gaussian over every other robot's
  assigned point within ``r_f``. The assigned points are those of the last
  round this robot decided.
* **Unreachable points.** A point that robot ``i`` cannot reach over cells it
  knows to be free, or its own cell, gets the weight :data:`INFEASIBLE`
  (``1e6``) so the assignment avoids it; a robot assigned such a point gets no
  goal from the round.
* **Fewer points than robots.** The Hungarian algorithm assigns ``min(N, M)``
  robots; each robot left over takes the point of its row with the least
  weight (robots then share points).
* **Who is re-assigned.** Every robot that answers a round gets the point the
  assignment gives it (Algorithm 1 runs on every robot). Rounds that end in the
  same tick are applied in the order of (tick of the request, requester id), so
  robots that saw the same rows agree.
* **Events.** A round starts when a robot reaches its goal (§III.B), or has no
  goal, or was blocked (our simulator's events); ``replan_on_target_explored``
  is off by default, so robots keep going to points they see explored on the way.
* **Without event-based communication** (``event_based=false``, our ablation
  of the paper's claim that event-based communication saves traffic and time):
  the events above no longer open rounds; each robot opens one every
  ``replan_every`` ticks from its previous one (its first at once), and a
  robot that reached its goal waits for its clock or another robot's round
  (``idle_until_clock=true``). Then "event-based is faster" is partly built in:
  the waiting robot is idle. With ``idle_until_clock=false`` a robot that needs a
  goal opens a round at once as well, so the ablation differs from the paper's
  method only by the periodic rounds it adds.
* **Frontier points.** ``grid``: the representative (the cell nearest the
  centroid) of every 8-connected cluster of the frontier cells the requester
  can reach over cells it knows to be free (a frontier cell seen across a
  corner can be cut off from known-free space; a point there would be
  infeasible for every robot and the round would give nobody a goal).
  ``rrt``: the requester's RRT detector store (each robot grows a global and a
  local tree every tick, see :mod:`mrexplore.planning.rrt_frontiers`), keeping
  the points it can reach, then dropping those under ``rrt_filter_min_gain``
  unknown cells within ``rrt_filter_radius`` (the information-gain test of Umari's
  filter node, the same test as ``filter_radius`` below); when it has none, the
  requester first grows its trees by up to ``rrt_burst`` more batches (the
  paper's detector runs much faster than the robots decide); if the trees still
  hold no reachable point
  while the grid shows reachable frontier cells, that request lists the grid's
  points instead (RRTs pass narrow doors rarely; without this fallback a lone
  robot on room-64-64-8 idled until the run stalled at 86% explored).
* **RRT defaults** (the principles in :mod:`mrexplore.planning.rrt_frontiers`).
  Umari's values are in metres and the strategy knows no cell size: they are
  converted at 0.2 m per cell, the robot-sized cell of the project's real-map runs.
  Budget: ``rrt_sample_density`` = 1 sample per tree per tick per sensor footprint
  ``pi r^2`` of the map (a uniform sampler finds a frontier of a given size later the
  bigger the map unless the budget grows with its area; Umari's detectors iterate at
  100 Hz while the robots drive at up to 0.3 m/s: 67 iterations per 0.2 m cell;
  the density gives 46 on the Intel map at 0.2 m); ``rrt_samples`` > 0 sets a fixed
  count (the earlier default 20). ``rrt_eta`` = 5 cells: Umari's launch files set 1
  m for the local trees, and 1 m for the global tree with three robots
  (``three_robots.launch``, 15 m in the single-robot files, ``rrt_global_eta`` = 75).
  ``rrt_bandwidth`` = 1.5 cells: Umari's filter clusters with
  ``MeanShift(bandwidth=0.3)``. ``rrt_filter_radius`` = 2.5 cells and
  ``rrt_filter_min_gain`` = 5 cells: the filter drops points whose
  ``informationGain`` within ``info_radius*0.5`` (``info_radius`` = 1 m) is under
  0.2 m².
* **One global tree per robot.** Umari runs one global detector on the merged map
  ("In multi-robot configuration, it is intended to have only a single instance of
  this node running"), and one local detector per robot. Here a robot's map is its
  merged map (its scans and whatever communication delivered), so each robot grows
  its own global tree on it: with unlimited communication every robot's map is the
  merged map and its tree a copy of Umari's one tree; under limited communication
  each grows it on what it knows. A team-shared tree would need shared memory or
  messages the paper's byte model does not count, so there is no parameter for it.
* **Frontier filter.** The paper takes its frontier points from Umari &
  Mukhopadhyay's pipeline, whose filter drops a point when the unknown area within
  half its ``info_radius`` (1 m by default, so 0.5 m) is under 0.2 m² (its
  ``informationGain`` counts unknown cells times the squared resolution). Here: a
  point of either detector with fewer than ``filter_min_gain`` unknown cells within
  ``filter_radius`` cells is dropped. These two default to 0 (no filter), so the
  grid detector's defaults are those of our earlier version; ``mrexplore reproduce
  market2018`` sets them from Umari's metres and its 0.2 m cells (2.5 cells, 5
  cells). The RRT detector is Umari's pipeline, whose filter belongs to it: its
  points pass the same test with ``rrt_filter_radius`` and ``rrt_filter_min_gain``
  first (on by default, the same values), then this one. When the filter would
  drop every reachable point, the request keeps them all (ours: Umari's system stops
  when no point is left, which here would end the run before the coverage
  threshold).
* **Limited communication.** A robot waits for the rows of the robots in its
  sub-network when it heard the request; a row that is lost or arrives late is
  left out after ``round_timeout``. Robots that hold different sets of rows may
  solve different matrices and pick the same point: the method degrades into
  less coordinated greedy choices, but never waits for ever.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt
from scipy.optimize import linear_sum_assignment

from mrexplore.comm.bytes import (
    BROADCAST,
    FRONTIER_POINT_BYTES,
    HEADER_BYTES,
    WEIGHT_BYTES,
    float32_on_wire,
)
from mrexplore.comm.messages import Message
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import BeliefGrid
from mrexplore.planning import (
    filter_by_gain,
    frontier_clusters,
    frontier_mask,
    information_gain,
)
from mrexplore.planning.rrt_frontiers import (
    CLUSTERINGS,
    RrtFrontierDetector,
    samples_per_tick,
)
from mrexplore.planning.team_fields import Components, team_costs, workspace_path
from mrexplore.strategies.base import (
    Cell,
    Decision,
    FrontierStrategy,
    Param,
    ReplanRules,
    RobotView,
    passable,
)
from mrexplore.strategies.network import request_timeout, round_timeout

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]

# ---------------------------------------------------------------- byte model
WEIGHT_REQUEST = "weight_request"
WEIGHTS = "weights"
ROUND_BYTES = 6
"""Round header of both messages: three uint16 (robot / requester, round, count)."""

INFEASIBLE = 1e6
"""Weight of a point a robot cannot reach (a float32 holds it exactly)."""

DETECTORS = ("grid", "rrt")


def request_size(n_points: int) -> int:
    """Bytes of a ``weight_request`` carrying ``n_points`` frontier points.

    >>> request_size(10)
    93
    """
    return HEADER_BYTES + ROUND_BYTES + FRONTIER_POINT_BYTES * n_points


def weights_size(n_points: int) -> int:
    """Bytes of a ``weights`` message with one row of ``n_points`` weights.

    >>> weights_size(10)
    53
    """
    return HEADER_BYTES + ROUND_BYTES + WEIGHT_BYTES * n_points


RoundKey = tuple[int, int, int]
"""(tick the request was sent, requester id, requester's round number)."""


@dataclass(frozen=True, slots=True)
class RequestPayload:
    """A round's opening: the requester's frontier list ``y`` (eqs. 1-2)."""

    key: RoundKey
    points: npt.NDArray[np.int64]


@dataclass(frozen=True, slots=True)
class WeightsPayload:
    """One robot's row ``W_i.`` over the round's frontier list."""

    key: RoundKey
    robot: int
    row: npt.NDArray[np.float32]


@dataclass(frozen=True, slots=True)
class FrontierReach:
    """Which frontier ``cells`` (sorted flat indices) of a robot's map at ``tick`` it can
    reach from ``position``, and with ``cost=path`` their path lengths (cells): what a
    frontier detection found, kept so that the row the robot computes over the points
    it just detected reads it instead of searching again (same map, same source)."""

    tick: int
    position: Cell
    cells: IntArray
    reachable: npt.NDArray[np.bool_]
    lengths: FloatArray | None

    def holds(self, view: RobotView, flat: IntArray) -> bool:
        """Whether this is ``view``'s tick and position and every cell of ``flat`` is here."""
        if self.tick != view.tick or self.position != view.position or not self.cells.size:
            return False
        where = np.minimum(np.searchsorted(self.cells, flat), self.cells.size - 1)
        return bool(np.array_equal(self.cells[where], flat))

    def lookup(self, flat: IntArray) -> tuple[npt.NDArray[np.bool_], FloatArray | None]:
        """Reachability and path lengths of ``flat`` (cells :meth:`holds`)."""
        where = np.searchsorted(self.cells, flat)
        return self.reachable[where], None if self.lengths is None else self.lengths[where]


# ---------------------------------------------------------------- eqs. 3-6
def cost(position: Cell, points: IntArray) -> FloatArray:
    """Eq. (3): ``C_ij``, the Euclidean distance (cells) from the robot to each point.

    >>> cost((0, 0), np.array([[3, 4], [0, 2]])).tolist()
    [5.0, 2.0]
    """
    return np.asarray(np.hypot(points[:, 0] - position[0], points[:, 1] - position[1]))


def utility(belief: BeliefGrid, points: IntArray, radius: float, lambda_u: float) -> FloatArray:
    """Eq. (4): ``U_ij = lambda_u * c``, ``c`` = unknown cells within ``radius`` of each point.

    >>> b = np.full((3, 3), -1, dtype=np.int8); b[1, 1] = 0
    >>> utility(b, np.array([[1, 1]]), 1.0, 0.5).tolist()
    [2.0]
    """
    if points.shape[0] == 0:
        return np.zeros(0)
    return np.asarray(lambda_u * information_gain(belief, points, radius), dtype=np.float64)


def occupancy(
    points: IntArray, others: Sequence[Cell] | IntArray, r_f: float, lambda_f: float
) -> FloatArray:
    """Eq. (5): ``F_ij``, a Gaussian (``3 sigma = r_f``) around other robots' assigned points.

    Zero beyond ``r_f`` of a point ``q_a``; summed over the other robots.

    >>> occupancy(np.array([[0, 0], [0, 3], [0, 7]]), [(0, 0)], 6.0, 2.0).round(4).tolist()
    [2.0, 0.6493, 0.0]
    """
    out = np.zeros(points.shape[0])
    others_arr = np.asarray(others, dtype=np.float64).reshape(-1, 2)
    if others_arr.shape[0] == 0 or points.shape[0] == 0 or r_f <= 0:
        return out
    sigma = r_f / 3.0
    d2 = (points[:, None, 0] - others_arr[None, :, 0]) ** 2
    d2 += (points[:, None, 1] - others_arr[None, :, 1]) ** 2
    with np.errstate(over="ignore"):  # (d / sigma)^2 = inf for a tiny sigma: exp -> 0
        gauss = np.exp(-0.5 * np.square(np.sqrt(d2) / sigma))
    gauss[d2 > r_f * r_f] = 0.0
    return np.asarray(lambda_f * gauss.sum(axis=1))


def weight(c: FloatArray, u: FloatArray, f: FloatArray) -> FloatArray:
    """Eq. (6): ``W_ij = C_ij - U_ij + F_ij``.

    >>> weight(np.array([5.0]), np.array([2.0]), np.array([0.5])).tolist()
    [3.5]
    """
    return np.asarray(c - u + f)


def assign(w: FloatArray) -> IntArray:
    """Eq. (8): the point (column) of each robot (row) minimising ``sum W_ij X_ij``.

    Robots left over when there are fewer points than robots take their row's
    least weight (first among ties).

    >>> assign(np.array([[1.0, 2.0], [1.5, 9.0], [0.0, 5.0]])).tolist()
    [1, 0, 0]
    """
    n, m = w.shape
    out = np.full(n, -1, dtype=np.int64)
    if m == 0:
        return out
    rows, cols = linear_sum_assignment(w)
    out[rows] = cols
    left = out < 0
    out[left] = np.argmin(w[left], axis=1)
    return out


# ---------------------------------------------------------------- the strategy
@dataclass
class Round:
    """One negotiation as seen by one robot."""

    key: RoundKey
    opened: int
    expected: frozenset[int]
    points: IntArray | None = None
    rows: dict[int, npt.NDArray[np.float32]] = field(default_factory=dict)


class MarketOccupancy(FrontierStrategy):
    """Decentralised market: weights with frontier occupancy, Hungarian on every robot."""

    id = "market-occupancy"
    summary = "decentralised market: cost - utility + frontier occupancy, Hungarian on every robot"
    citation = (
        "Decentralised market-based strategy for cooperative multi-robot exploration "
        "(§III, eqs. 1-8, Algorithm 1); frontiers: H. Umari, S. Mukhopadhyay, IROS 2017"
    )
    lambda_u = Param(
        0.1,
        "cells/cell",
        "weight of one unknown cell in U (eq. 4)",
        "lambda_u",
        low=0,
        note="weight of the utility (eq. 4)",
    )
    lambda_f = Param(
        0.0,
        "cells",
        "peak of the occupancy F (eq. 5); 0 = r_f",
        "lambda_f",
        low=0,
        note="peak of the frontier occupancy (eq. 5); 0 = `r_f`",
    )
    r = Param(
        0.0,
        "cells",
        "utility radius (eq. 4); 0 = sensor range",
        "r",
        low=0,
        note="radius of the utility disk (eq. 4); 0 = sensor range",
    )
    r_f = Param(
        0.0, "cells", "occupancy radius 3 sigma (eq. 5); 0 = 2 x sensor range", "r_f", low=0
    )
    cost = Param(
        "euclidean",
        "",
        "C_ij of eq. (3): euclidean | path",
        choices=("euclidean", "path"),
        note=(
            "eq. (3): Euclidean distance (the paper); `path`: shortest-path length "
            "on the robot's map"
        ),
        symbol="C_ij",
    )
    frontier_detector = Param(
        "grid", "", "frontier points: grid | rrt", choices=DETECTORS, note="`grid` or `rrt`"
    )
    rrt_eta = Param(
        5.0,
        "cells",
        "RRT growth step (Umari: 1 m); 0 = sensor range",
        "eta",
        low=0,
        note=(
            "RRT growth step of both trees; Umari's launch files: 1 m (5 cells at "
            "0.2 m per cell); 0 = sensor range, the earlier default"
        ),
    )
    rrt_global_eta = Param(
        0.0,
        "cells",
        "growth step of the global RRT; 0 = rrt_eta",
        "eta",
        low=0,
        note=(
            "growth step of the global tree; Umari: 1 m with three robots on the "
            "merged map (`three_robots.launch`), 15 m with one robot (75 cells); 0 "
            "= `rrt_eta`"
        ),
    )
    rrt_samples = Param(
        0,
        "samples/tick",
        "RRT samples per tree per tick; 0 = rrt_sample_density",
        low=0,
        note=(
            "RRT iterations per tree per tick; 0 = from `rrt_sample_density`; the "
            "earlier default was 20"
        ),
    )
    rrt_sample_density = Param(
        1.0,
        "samples/tick/footprint",
        "RRT samples per tree per tick per pi r^2 of the map",
        low=0,
        low_open=True,
        note=(
            "the budget: `ceil(density H W / (pi r^2))` samples per tree per tick "
            "(Intel at 0.2 m: 46; office 120 x 80 with a 15-cell sensor: 14; 100 x "
            "100 with 8 cells: 50)"
        ),
    )
    rrt_vertex_spacing = Param(
        1.0,
        "cells",
        "a free RRT edge shorter than this adds no vertex",
        low=0,
        note="a free edge shorter than this adds no vertex",
    )
    rrt_burst = Param(
        50,
        "batches",
        "extra RRT batches when a goal is needed and no point",
        low=0,
        note=(
            "extra RRT batches (one tick's budget each) when a goal is needed and "
            "no reachable point is stored"
        ),
    )
    rrt_clustering = Param(
        "mean-shift",
        "",
        "merge RRT points: mean-shift | greedy",
        choices=CLUSTERINGS,
        note=(
            "how stored RRT points are merged: `mean-shift` (Umari's filter) or "
            "`greedy` (the earlier version)"
        ),
    )
    rrt_bandwidth = Param(
        1.5,
        "cells",
        "mean-shift bandwidth (Umari: 0.3 m)",
        low=0,
        low_open=True,
        note=("mean-shift bandwidth; Umari's filter: `MeanShift(bandwidth=0.3)`, 0.3 m"),
    )
    rrt_cluster_radius = Param(
        0.0,
        "cells",
        "greedy: merge RRT points closer; 0 = sensor range/2",
        low=0,
        note=("`greedy`: stored RRT points closer than this are merged; 0 = sensor range / 2"),
    )
    rrt_filter_radius = Param(
        2.5,
        "cells",
        "RRT points: information-gain radius (Umari: 0.5 m); 0 = none",
        low=0,
        note=(
            "RRT points: radius of the information-gain test (Umari: `info_radius * "
            "0.5` = 0.5 m); 0 = no test"
        ),
    )
    rrt_filter_min_gain = Param(
        5.0,
        "cells",
        "RRT points: drop those with fewer unknown cells (Umari: 0.2 m2)",
        low=0,
        note=(
            "RRT points with fewer unknown cells within `rrt_filter_radius` are "
            "dropped (Umari: 0.2 m² = 5 cells of 0.04 m²)"
        ),
    )
    filter_radius = Param(
        0.0,
        "cells",
        "information-gain radius of the frontier filter; 0 = none",
        low=0,
        note="every detector's points: radius of the same test; 0 = no filter",
    )
    filter_min_gain = Param(
        0.0,
        "cells",
        "drop frontier points with fewer unknown cells within it",
        low=0,
        note=(
            "every detector's points with fewer unknown cells within `filter_radius` are dropped"
        ),
    )
    round_timeout = Param(
        0,
        "ticks",
        "decide with the rows at hand after this; 0 = auto",
        low=0,
        note="decide with the rows at hand after this; 0 = 2 x latency x hops + 1",
    )
    request_timeout = Param(
        0,
        "ticks",
        "re-send a request after this; 0 = auto",
        low=0,
        note="least time between two requests of a robot; 0 = 2 x round_timeout + 2",
    )
    event_based = Param(
        True,
        "",
        "rounds open on events (goal reached); false: every replan_every ticks",
        note=(
            "rounds open on events (goal reached, blocked, no goal); `false`: only "
            "every `replan_every` ticks (time-triggered, an ablation)"
        ),
    )
    idle_until_clock = Param(
        True,
        "",
        "with event_based=false, a robot needing a goal waits for its clock",
        note=(
            "with `event_based=false`, a robot that needs a goal waits for its "
            "clock; `false`: it also opens a round at once"
        ),
    )
    replan_on_target_explored = ReplanRules.replan_on_target_explored.with_default(False)

    def __init__(self, robot_id: int, n_robots: int, **params: object) -> None:
        super().__init__(robot_id, n_robots, **params)
        if not self.event_based and self.replan_every <= 0:
            raise ScenarioError(
                "--set event_based=false: time-triggered rounds need a period, "
                "e.g. --set replan_every=10"
            )
        self.rounds: dict[RoundKey, Round] = {}
        self.assigned: dict[int, Cell] = {}  # q_a: each robot's point, from decided rounds
        self.round_number = 0
        self.own_round: RoundKey | None = None
        self.requested_at = -1
        self.clock_at = -1  # tick of this robot's last round (time-triggered mode)
        self.detector: RrtFrontierDetector | None = None
        self.rounds_decided = 0
        self.grid_fallbacks = 0  # requests where the RRT found no point and the grid did
        self.frontier_reach: FrontierReach | None = None  # the last detection's field
        self.components = Components()  # of this robot's known-free cells (cost=euclidean)
        self.timeout_for: tuple[tuple[object, ...], int] | None = None  # (topology, ticks)

    # ------------------------------------------------------------ helpers
    def _round_timeout(self, view: RobotView) -> int:
        # The same topology gives the same wait: hop counts only when it changed.
        topology = (view.subnetwork, view.links, view.comm_latency)
        if self.timeout_for is None or self.timeout_for[0] != topology:
            self.timeout_for = (topology, round_timeout(self.round_timeout, view, self.robot_id))
        return self.timeout_for[1]

    def _request_timeout(self, view: RobotView) -> int:
        return request_timeout(self.request_timeout, self._round_timeout(view))

    def frontier_points(self, view: RobotView) -> IntArray:
        """The frontier list ``y`` (eqs. 1-2) of this robot's map, ``(M, 2)`` cells.

        Only points this robot can reach over cells it knows to be free: a point
        seen across a corner may be cut off from known-free space, and no robot
        could be sent there. Then the frontier filter (:meth:`_filtered`).
        """
        return self._filtered(view, self._detected(view))

    def _filtered(self, view: RobotView, points: IntArray, prefix: str = "") -> IntArray:
        """Points with at least ``filter_min_gain`` unknown cells within ``filter_radius``
        (Umari & Mukhopadhyay's filter), or all of them if none has; ``prefix="rrt_"``:
        the RRT detector's own values of the same test."""
        radius = float(getattr(self, prefix + "filter_radius"))
        kept = filter_by_gain(
            view.belief, points, radius, float(getattr(self, prefix + "filter_min_gain"))
        )
        return kept if kept.shape[0] else points

    def _detected(self, view: RobotView) -> IntArray:
        """The detector's reachable frontier points."""
        frontier = frontier_mask(view.belief)
        cells = np.flatnonzero(frontier)  # sorted
        can_reach, lengths = self._reach(view, cells)
        self.frontier_reach = FrontierReach(view.tick, view.position, cells, can_reach, lengths)
        in_reach = np.zeros(frontier.shape, dtype=np.bool_)
        in_reach.reshape(-1)[cells[can_reach]] = True
        if self.detector is not None:
            points = self.detector.points(view.belief)
            for _ in range(self.rrt_burst):
                if in_reach[points[:, 0], points[:, 1]].any():
                    break
                self.detector.step(view.belief, view.position, view.rng)
                points = self.detector.points(view.belief)
            points = points[in_reach[points[:, 0], points[:, 1]]]
            if points.shape[0] or not in_reach.any():
                return self._filtered(view, points, "rrt_")  # Umari's filter node
            self.grid_fallbacks += 1  # the trees missed every frontier: use the grid's
        clusters = frontier_clusters(in_reach)
        return np.array([c.representative for c in clusters], dtype=np.int64).reshape(-1, 2)

    def _reach(
        self, view: RobotView, cells: IntArray
    ) -> tuple[npt.NDArray[np.bool_], FloatArray | None]:
        """Whether this robot can reach each of ``cells`` (distinct flat indices) over
        cells it knows to be free, and with ``cost=path`` the path lengths (cells).

        With the Euclidean cost (eq. 3) a point's path length only decides whether it
        is feasible (reachable, and not the robot's own cell), so no distance field is
        computed: the robot's components tell the same (kept across calls and brought
        up to date with the cells its map added:
        :class:`~mrexplore.planning.team_fields.Components`).
        """
        if self.cost == "path":
            lengths = team_costs(passable(view.belief), [view.position], cells)[0]
            return np.isfinite(lengths), lengths
        return self.components.reachable(passable(view.belief), view.position, cells), None

    def row(self, view: RobotView, points: IntArray) -> npt.NDArray[np.float32]:
        """Eqs. (3)-(6): this robot's weights over ``points``, as sent (float32)."""
        r = self.r or view.sensor_range
        r_f = self.r_f or 2.0 * view.sensor_range
        lambda_f = self.lambda_f or r_f
        others = [q for robot, q in sorted(self.assigned.items()) if robot != self.robot_id]
        flat = points[:, 0].astype(np.int64) * view.belief.shape[1] + points[:, 1]
        can_reach = np.zeros(points.shape[0], dtype=np.bool_)
        reach = np.zeros(points.shape[0])  # path lengths, cells (cost=path)
        if points.shape[0]:
            known = self.frontier_reach
            if known is not None and known.holds(view, flat):
                can_reach, lengths = known.lookup(flat)  # this tick's, from here
            else:
                cells, inverse = np.unique(flat, return_inverse=True)
                can_reach, lengths = self._reach(view, cells)
                can_reach = can_reach[inverse]
                lengths = None if lengths is None else lengths[inverse]
            if lengths is not None:
                reach = lengths
        c = np.where(np.isfinite(reach), reach, 0.0) if self.cost == "path" else None
        w = weight(
            cost(view.position, points) if c is None else c,
            utility(view.belief, points, r, self.lambda_u),
            occupancy(points, others, r_f, lambda_f),
        )
        if points.shape[0]:
            if self.cost == "path":
                feasible = np.isfinite(reach) & (reach > 0)
            else:  # reachable and not here: the path length is finite and > 0
                feasible = can_reach & (
                    flat != view.position[0] * view.belief.shape[1] + view.position[1]
                )
            w = np.where(feasible, w, INFEASIBLE)
        return float32_on_wire(np.minimum(w, INFEASIBLE))

    def _weights_message(self, key: RoundKey, row: npt.NDArray[np.float32]) -> Message:
        payload = WeightsPayload(key, self.robot_id, row)
        return Message(WEIGHTS, self.robot_id, BROADCAST, weights_size(row.size), payload)

    # ------------------------------------------------------------ decide
    def decide(self, view: RobotView) -> Decision:
        if self.frontier_detector == "rrt":
            if self.detector is None:
                samples = self.rrt_samples or samples_per_tick(
                    view.belief.shape, view.sensor_range, self.rrt_sample_density
                )
                self.detector = RrtFrontierDetector(
                    eta=self.rrt_eta or view.sensor_range,
                    samples=samples,
                    global_eta=self.rrt_global_eta,
                    clustering=self.rrt_clustering,
                    bandwidth=self.rrt_bandwidth,
                    cluster_radius=self.rrt_cluster_radius or view.sensor_range / 2,
                    vertex_spacing=self.rrt_vertex_spacing,
                )
            self.detector.step(view.belief, view.position, view.rng)
        decision = Decision()
        for message in view.inbox:
            payload = message.payload
            if message.type == WEIGHT_REQUEST and isinstance(payload, RequestPayload):
                known = self.rounds.get(payload.key)
                if known is not None and known.points is not None:
                    continue
                state = Round(payload.key, view.tick, view.subnetwork) if known is None else known
                state.points = payload.points
                own = self.row(view, payload.points)  # Algorithm 1, lines 1-3
                state.rows[self.robot_id] = own
                self.rounds[payload.key] = state
                decision.messages.append(self._weights_message(payload.key, own))
            elif message.type == WEIGHTS and isinstance(payload, WeightsPayload):
                pending = self.rounds.get(payload.key)
                if pending is None:  # the row came before the request: keep it
                    pending = Round(payload.key, view.tick, view.subnetwork)
                    self.rounds[payload.key] = pending
                pending.rows[payload.robot] = payload.row  # line 4

        if self.own_round is None and self._round_due(view):
            self._open_round(view, decision)
        goal = self._decide_rounds(view)
        if goal is not None:
            followed = self._follow(view, goal)
            decision.goal, decision.path = followed.goal, followed.path
        return decision

    def _round_due(self, view: RobotView) -> bool:
        """Whether this robot opens a round now.

        Event-based (the paper, §III.B): when the re-planning rules fire (goal
        reached, blocked, no goal), at most once per ``request_timeout``.
        Time-triggered (``event_based=false``, the ablation): every
        ``replan_every`` ticks from this robot's last round, whatever happened;
        a robot that reached its goal waits for its clock (or another robot's round),
        unless ``idle_until_clock=false``: then the events open a round too.
        """
        if not self.event_based:
            clock = self.clock_at < 0 or view.tick - self.clock_at >= self.replan_every
            if clock or self.idle_until_clock:
                return clock
        if not self.needs_plan(view):
            return False
        return self.requested_at < 0 or (
            view.tick - self.requested_at >= self._request_timeout(view)
        )

    def _open_round(self, view: RobotView, decision: Decision) -> None:
        """Event: this robot needs a goal; send ``y`` and its row (§III.B, Fig. 4)."""
        self.requested_at = view.tick
        self.clock_at = view.tick
        points = self.frontier_points(view)
        if points.shape[0] == 0:
            return
        self.round_number = (self.round_number + 1) % 0x10000
        key: RoundKey = (view.tick, self.robot_id, self.round_number)
        state = Round(key, view.tick, view.subnetwork, points)
        state.rows[self.robot_id] = self.row(view, points)
        self.rounds[key] = state
        self.own_round = key
        if len(view.subnetwork) > 1:
            payload = RequestPayload(key, points)
            decision.messages.append(
                Message(
                    WEIGHT_REQUEST, self.robot_id, BROADCAST, request_size(len(points)), payload
                )
            )
            decision.messages.append(self._weights_message(key, state.rows[self.robot_id]))

    def _decide_rounds(self, view: RobotView) -> Cell | None:
        """Algorithm 1, lines 5-7, for every round that is complete or timed out."""
        goal: Cell | None = None
        if not self.rounds:
            return goal
        timeout = self._round_timeout(view)
        for key in sorted(self.rounds):
            state = self.rounds[key]
            waiting = state.expected & view.subnetwork
            complete = state.points is not None and waiting <= set(state.rows)
            if not complete and view.tick - state.opened < timeout:
                continue
            del self.rounds[key]
            if key == self.own_round:
                self.own_round = None
            if state.points is None or self.robot_id not in state.rows:
                continue  # the request never came: nothing to decide
            robots = sorted(state.rows)
            w = np.stack([state.rows[r].astype(np.float64) for r in robots])
            columns = assign(w)  # line 6
            self.rounds_decided += 1
            for index, robot in enumerate(robots):
                if w[index, columns[index]] < INFEASIBLE:
                    q = state.points[columns[index]]
                    self.assigned[robot] = (int(q[0]), int(q[1]))
            mine = robots.index(self.robot_id)
            if w[mine, columns[mine]] < INFEASIBLE:  # line 7
                q = state.points[columns[mine]]
                goal = (int(q[0]), int(q[1]))
        return goal

    def _follow(self, view: RobotView, goal: Cell) -> Decision:
        """Head for an assigned point, planning over this robot's known-free cells."""
        if goal in (view.goal, view.position):
            return Decision()
        path = workspace_path(passable(view.belief), view.position, goal)
        if path is None:
            return Decision()
        self.last_plan_tick = view.tick
        self.requested_at = -1
        return Decision(goal=goal, path=path)


__all__ = [
    "FRONTIER_POINT_BYTES",
    "INFEASIBLE",
    "WEIGHTS",
    "WEIGHT_BYTES",
    "WEIGHT_REQUEST",
    "MarketOccupancy",
    "assign",
    "cost",
    "occupancy",
    "request_size",
    "utility",
    "weight",
    "weights_size",
]
