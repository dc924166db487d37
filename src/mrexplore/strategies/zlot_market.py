"""Zlot, Stentz, Dias & Thayer (2002): exploration controlled by a market economy.

R. Zlot, A. Stentz, M. B. Dias, S. Thayer, "Multi-robot exploration controlled by
a market economy", Proc. IEEE International Conference on Robotics and
Automation (ICRA), vol. 3, 2002, pp. 3016-3023; as summarised in Wu, Puig &
Garcia §II: "each robot selects some targets from the unexplored workspace so
that they form a representative subset ... Targets are auctioned by robots
(auctioneers) to other robots (bidders) with proposed prices. Bidders calculate
their bids as the expected benefit, which is the expected revenue (utility)
minus the expected cost. If the bid ... is lower than the proposed price, the bid
will not be submitted ... the auctioneer will choose the bidder with the highest
bid. If no bid is submitted ... the auctioneer will keep the job for itself ...
If a robot wins the auction of a target, it adds this target to its route list
... targets are auctioned again in future decision steps ... when robots change
their positions."

The market, per robot (``R`` = sensor range in cells, ``I(g)`` = unknown cells
within ``R`` of goal ``g`` in the robot's belief, ``d`` = shortest-path length in
cells over cells the robot knows to be free):

1. **Goal generation** (:meth:`ZlotMarket.generate_goals`). When its tour holds
   fewer than ``min_tour`` goals, a robot draws ``goals_per_round`` goal points
   at random among the reachable frontier cells (:func:`spread_goals`), at least
   ``goal_spacing`` cells from each other and from every goal it knows to be held
   (its own, and those announced or awarded by the robots it can reach), and no
   farther than ``generation_radius`` beyond the nearest such cell. It inserts
   them into its tour by cheapest insertion and puts each one up for auction.
2. **Tour and cost.** A tour is the robot's position ``p_0`` followed by its
   goals ``p_1 .. p_m``, visited in order (open path). The cost of adding goal
   ``x`` is the cheapest insertion (:func:`insertion_cost`)::

       c(x) = min( min_i d(p_i, x) + d(x, p_{i+1}) - d(p_i, p_{i+1}),  d(p_m, x) )

   and the cost a goal ``p_j`` carries in the tour is what removing it saves
   (:func:`removal_savings`)::

       s_j = d(p_{j-1}, p_j) + d(p_j, p_{j+1}) - d(p_{j-1}, p_{j+1})   (s_m = d(p_{m-1}, p_m))

3. **Revenue and profit.** ``r(g) = w_r * I(g)`` (:func:`revenue`); a bidder's
   bid is ``r(x) - c(x)``, an owner's value of a goal it holds is ``r(p_j) - s_j``.
4. **Auction** (single item, first price, sealed bid). The auctioneer
   broadcasts the goal with a reserve price equal to its own value of it. Every
   other robot that can reach the goal answers with its bid if the bid exceeds
   the reserve. After ``auction_ticks`` (at least two message trips to the
   farthest robot of the sub-network) the auctioneer closes the auction: the
   highest bid above the reserve wins (:func:`winning_bid`); the auctioneer drops
   the goal and broadcasts the award, and the winner inserts the goal into its
   tour. Without such a bid the auctioneer keeps the goal.
5. **Re-auction.** Every ``reauction_every`` ticks a robot auctions again the
   goal of its tour it values least (reserve = that value).
6. **Execution.** The robot drives to the first goal of its tour; goals that are
   reached or no longer frontier cells (explored, by anyone) are dropped.

Parameters (rendered from ``ZlotMarket.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin zlot-market

=====================  ======  =======  =====  =====================================================
name                   symbol  default  unit   meaning
=====================  ======  =======  =====  =====================================================
``revenue_weight``     w_r     1.0      -      revenue per unknown cell expected to be seen, in
                                               cells of travel
``goals_per_round``    -       3        -      goal points drawn per generation
``goal_spacing``       -       0.0      cells  least Euclidean distance between goal points; 0 = `R`
``generation_radius``  -       1.0      cells  draw goals at most this far (path) beyond the nearest
                                               unclaimed frontier cell
``min_tour``           -       1        -      generate goals when the tour holds fewer goals
``auction_ticks``      -       2        ticks  auction duration, raised to `2 x latency x hops`
``reauction_every``    -       10       ticks  re-auction the least valued goal of the tour (0 =
                                               never)
``line_of_sight``      -       false    -      count only unknown cells in line of sight (in the
                                               belief) in `I`
=====================  ======  =======  =====  =====================================================

.. params:end

Messages (sizes from :mod:`mrexplore.comm.bytes`):

===========  =====================  ================================  =====================
type         direction              payload                           bytes
===========  =====================  ================================  =====================
``auction``  auctioneer -> all      auctioneer, goal row, col,        ``7 + BID_BYTES`` = 17
             (broadcast)            reserve float32
``bid``      bidder -> auctioneer   bidder, goal row, col, bid        ``7 + BID_BYTES`` = 17
                                    float32
``award``    auctioneer -> all      winner, goal row, col             ``7 + TARGET_BYTES``
             (broadcast)                                              = 13
===========  =====================  ================================  =====================

Interpretations (where the sources are silent):

* **Goal points are frontier cells.** Zlot places goals in unexplored space and
  plans through unknown space optimistically. Our motion contract only allows
  paths over cells the robot knows to be free, so a goal point is a reachable
  frontier cell: the nearest place from which that piece of unexplored space is
  observed. A goal is "explored" (and dropped) when it stops being a frontier
  cell.
* **Random generation, in the robot's vicinity.** Of the paper's goal
  generators we use the random one, drawn with the robot's own random stream
  and spread by ``goal_spacing`` (dart throwing), restricted to the frontier
  cells at most ``generation_radius`` cells (path) farther than the nearest
  unclaimed one. Frontier cells within ``goal_spacing`` of goals held by
  reachable robots are avoided while unclaimed ones exist. The default radius
  of 1 cell makes the draw a random choice among the nearest unclaimed frontier
  cells, so a round usually yields one goal; wider radii spread goals over the
  unexplored space as the paper's random generator does, but a robot then
  skips the nearest frontier and comes back for it later: in a pilot (mean T99
  of seeds 1-5, 4 robots) a radius of ``R / 2`` took 1015 ticks on the Intel
  map against 792 for 1 cell, 512 against 411 on the 100 x 100 cityblock and
  924 against 880 on the 100 x 100 office (see ``docs/strategies/zlot-market.md``).
* **Tour.** Goals are visited in tour order; new goals go in by cheapest
  insertion (no full TSP re-optimisation); the tour is an open path from the
  robot's current cell.
* **Reserve price.** The auctioneer's own value of the goal, so a goal changes
  hands only when another robot values it more; bids must be strictly above it
  (ties stay with the auctioneer; equal bids go to the lowest id).
* **Lost messages.** Bids that arrive after the close are ignored. A lost award
  loses the goal (the auctioneer has dropped it): the area stays a frontier and
  is drawn again later. Goals held by robots out of reach are not avoided.
* **Revenue weight.** With shared maps every robot counts nearly the same
  ``I(g)``, so revenue cancels between bid and reserve and the market allocates
  by marginal travel cost; ``w_r`` matters where beliefs differ (limited
  communication).
* A robot whose belief has no reachable frontier cell retries generating goals
  every ``GENERATION_RETRY_TICKS`` ticks.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, float32_on_wire
from mrexplore.comm.messages import BID, BidItem, CellItem, Message, item_message
from mrexplore.planning import SQRT2, extract_path, frontier_mask, information_gain
from mrexplore.planning.multi_fields import FieldWorkspace, raster_cells, shared_workspace
from mrexplore.strategies.base import (
    Cell,
    Decision,
    Param,
    RobotView,
    Strategy,
    frontier_at,
    passable,
)
from mrexplore.strategies.network import hop_distances

__all__ = [
    "AUCTION",
    "AWARD",
    "AuctionPayload",
    "AwardPayload",
    "BidPayload",
    "TickDistances",
    "ZlotMarket",
    "hops_to_farthest",
    "insertion_cost",
    "removal_savings",
    "revenue",
    "spread_goals",
    "winning_bid",
]

AUCTION = "auction"
AWARD = "award"

GENERATION_RETRY_TICKS = 5
"""Ticks between two attempts to generate goals when the last one found no frontier."""

# The three messages carry items of the byte model (mrexplore.comm.messages).
AuctionPayload = BidItem
"""An auction announcement, a bid item: the auctioneer, the goal for sale, the reserve."""
BidPayload = BidItem
"""A sealed bid (sent to the auctioneer only): the bidder, the goal, its value."""
AwardPayload = CellItem
"""The auctioneer sold the goal (``cell``) to the winner (``robot``)."""


@dataclass
class OpenAuction:
    """An auction this robot runs: the best bid so far and when it closes."""

    reserve: float
    closes_at: int
    best_value: float = -np.inf
    best_bidder: int = -1


# ---------------------------------------------------------------------- equations
def revenue(
    gain: npt.NDArray[np.integer] | npt.NDArray[np.floating], revenue_weight: float
) -> npt.NDArray[np.float64]:
    """Expected revenue of goals: ``r = w_r * I`` (cells of travel).

    >>> revenue(np.array([10, 0]), 2.0).tolist()
    [20.0, 0.0]
    """
    return revenue_weight * np.asarray(gain, dtype=np.float64)


def insertion_cost(
    to_new: npt.NDArray[np.floating], legs: npt.NDArray[np.floating]
) -> tuple[float, int]:
    """Cheapest insertion of a goal ``x`` into an open tour ``p_0 .. p_m``.

    Args:
        to_new: ``(m + 1,)`` path lengths ``d(p_i, x)``, ``p_0`` = the robot.
        legs: ``(m,)`` path lengths ``d(p_i, p_{i+1})``.

    Returns:
        ``(cost, index)``: the least increase of the tour length, and the index of
        the goal list (``p_1 ..`` at 0) at which ``x`` goes; ``(inf, m)`` when
        ``x`` is unreachable.

    >>> insertion_cost(np.array([5.0, 3.0]), np.array([4.0]))  # after p_1: +3
    (3.0, 1)
    >>> insertion_cost(np.array([1.0, 1.0]), np.array([2.0]))  # between p_0, p_1: 1+1-2
    (0.0, 0)
    """
    m = len(legs)
    costs = np.empty(m + 1, dtype=np.float64)
    costs[:m] = to_new[:m] + to_new[1:] - legs
    costs[m] = to_new[m]
    index = int(np.argmin(costs))
    return float(costs[index]), index


def removal_savings(
    legs: npt.NDArray[np.floating], skips: npt.NDArray[np.floating]
) -> npt.NDArray[np.float64]:
    """What removing each goal ``p_j`` (j = 1..m) saves on the open tour ``p_0 .. p_m``.

    Args:
        legs: ``(m,)`` path lengths ``d(p_i, p_{i+1})``.
        skips: ``(m - 1,)`` path lengths ``d(p_i, p_{i+2})``.

    ``s_j = d(p_{j-1}, p_j) + d(p_j, p_{j+1}) - d(p_{j-1}, p_{j+1})`` and
    ``s_m = d(p_{m-1}, p_m)``.

    >>> removal_savings(np.array([3.0, 4.0]), np.array([7.0])).tolist()  # 3 + 4 - 7, 4
    [0.0, 4.0]
    """
    savings = np.asarray(legs, dtype=np.float64).copy()
    savings[:-1] += legs[1:] - skips
    return savings


def winning_bid(bids: Mapping[int, float], reserve: float) -> tuple[int, float] | None:
    """The highest bid strictly above ``reserve`` (ties: lowest bidder id), or ``None``.

    >>> winning_bid({1: 5.0, 2: 7.0, 3: 7.0}, 6.0)
    (2, 7.0)
    >>> winning_bid({1: 5.0}, 5.0) is None
    True
    """
    best: tuple[int, float] | None = None
    for bidder in sorted(bids):
        value = bids[bidder]
        if value > reserve and (best is None or value > best[1]):
            best = (bidder, value)
    return best


def spread_goals(
    rows: npt.NDArray[np.integer],
    cols: npt.NDArray[np.integer],
    k: int,
    spacing: float,
    rng: np.random.Generator,
) -> npt.NDArray[np.int64]:
    """Indices of up to ``k`` random candidates, pairwise more than ``spacing`` cells apart.

    Dart throwing: draw a candidate uniformly among those still open, close every
    candidate within ``spacing`` (Euclidean) of it, repeat.
    """
    chosen: list[int] = []
    open_ = np.ones(len(rows), dtype=bool)
    while len(chosen) < k and open_.any():
        candidates = np.flatnonzero(open_)
        pick = int(candidates[rng.integers(candidates.size)])
        chosen.append(pick)
        open_ &= np.hypot(rows - rows[pick], cols - cols[pick]) > spacing
    return np.asarray(chosen, dtype=np.int64)


def hops_to_farthest(robot: int, links: Iterable[tuple[int, int]]) -> int:
    """Hops from ``robot`` to the farthest robot it can reach over ``links`` (0 if alone).

    >>> hops_to_farthest(0, [(0, 1), (1, 2)])
    2
    """
    return max(hop_distances(robot, links).values())


def octile_distances(cell: Cell, others: Sequence[Cell]) -> npt.NDArray[np.float64]:
    """Octile distances (cells) from ``cell`` to each of ``others``: the length of an
    8-connected path without obstacles, a lower bound of every path length.

    >>> octile_distances((0, 0), [(3, 1), (0, 2)]).round(3).tolist()
    [3.414, 2.0]
    """
    offsets = np.abs(np.asarray(others, dtype=np.float64).reshape(-1, 2) - np.asarray(cell))
    return offsets.max(axis=1) + (SQRT2 - 1.0) * offsets.min(axis=1)


@functools.lru_cache(maxsize=8)
def _disk(radius: float) -> npt.NDArray[np.bool_]:
    """``(2k + 1) x (2k + 1)`` mask of the offsets within ``radius`` cells, ``k = floor(radius)``
    (read-only, shared)."""
    reach = int(radius)
    offsets = np.arange(-reach, reach + 1, dtype=np.int64)
    disk = np.hypot(offsets[:, None], offsets[None, :]) <= radius
    disk.flags.writeable = False
    return disk


def clear_disk(mask: npt.NDArray[np.bool_], row: int, col: int, radius: float) -> None:
    """Set ``mask`` to ``False`` at every cell within ``radius`` (Euclidean, cells) of
    ``(row, col)``, in place.

    >>> mask = np.ones((3, 4), dtype=bool)
    >>> clear_disk(mask, 1, 1, 1.0)
    >>> mask.astype(int).tolist()
    [[1, 0, 1, 1], [0, 0, 0, 1], [1, 0, 1, 1]]
    """
    height, width = mask.shape
    # A larger disk holds the same cells of the grid (bounds the stamp's size).
    radius = min(radius, float(height + width + abs(row) + abs(col)))
    disk = _disk(radius)
    reach = disk.shape[0] // 2
    top, bottom = max(row - reach, 0), min(row + reach + 1, height)
    left, right = max(col - reach, 0), min(col + reach + 1, width)
    if top >= bottom or left >= right:
        return
    inside = disk[
        top - row + reach : bottom - row + reach, left - col + reach : right - col + reach
    ]
    mask[top:bottom, left:right] &= ~inside


def cells_within(
    field: npt.NDArray[np.float64], mask: npt.NDArray[np.bool_], source: Cell, bound: float
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """Rows and cols (raster order) of the cells of ``mask`` with ``field <= bound``, for a
    field from ``source``: only the square within ``bound`` of it is read (a path is
    never shorter than the Chebyshev distance).

    >>> field = np.array([[0.0, 1.0, 2.0]])
    >>> cells_within(field, np.array([[True, False, True]]), (0, 0), 1.5)
    (array([0]), array([0]))
    """
    height, width = field.shape
    reach = int(min(bound, height + width))
    top, left = max(source[0] - reach, 0), max(source[1] - reach, 0)
    bottom, right = min(source[0] + reach + 1, height), min(source[1] + reach + 1, width)
    window = (slice(top, bottom), slice(left, right))
    _, rows, cols = raster_cells(mask[window] & (field[window] <= bound))
    return rows + top, cols + left


class TickDistances:
    """Shortest-path lengths (cells) between cells over one tick's belief.

    Each query runs one distance field from its source, stopped once every
    target is settled or beyond ``max_distance``. Within a tick the belief does
    not change (nor, often, from one tick to the next), so a pair found by one query
    is reused by the next while the free cells stay the same, and paths are
    symmetric (8-connected, no corner cutting): ``d(a, b) = d(b, a)``. The
    searches run in a :class:`~mrexplore.planning.multi_fields.FieldWorkspace`
    kept across queries, ticks and robots: a query costs only the cells it touches.
    """

    def __init__(self) -> None:
        self.tick = -1
        self.free = np.zeros((0, 0), dtype=bool)
        self._known: dict[tuple[Cell, Cell], float] = {}

    @property
    def fields(self) -> FieldWorkspace:
        """The thread's search buffers (shared by every robot's market; each query
        releases them before it returns)."""
        return shared_workspace("zlot-market")

    def reset(self, tick: int, free: npt.NDArray[np.bool_]) -> None:
        """Start a new tick over the belief's free cells ``free``; the lengths found so far
        are kept when the free cells are those of the last tick."""
        if not np.array_equal(free, self.free):
            self._known.clear()
            self.free = free
        self.tick = tick

    def between(
        self, source: Cell, targets: Sequence[Cell], max_distance: float = np.inf
    ) -> npt.NDArray[np.float64]:
        """``d(source, t)`` for each target; ``inf`` if unreachable or beyond ``max_distance``."""
        missing = [t for t in targets if (source, t) not in self._known]
        if missing:
            width = self.free.shape[1]
            index = np.array([r * width + c for r, c in missing], dtype=np.int64)
            field = self.fields.search(
                self.free, source, target_cells=index, max_distance=max_distance
            )
            lengths = field.reshape(-1)[index].tolist()
            self.fields.release()
            for target, length in zip(missing, lengths, strict=True):
                if np.isfinite(length) or np.isinf(max_distance):  # a bounded miss is not final
                    self._known[source, target] = self._known[target, source] = length
        return np.array([self._known.get((source, t), np.inf) for t in targets], dtype=np.float64)

    def path(self, source: Cell, goal: Cell) -> npt.NDArray[np.int32] | None:
        """The path :func:`~mrexplore.planning.paths.path_to` gives over this tick's belief."""
        width = self.free.shape[1]
        index = np.array([goal[0] * width + goal[1]], dtype=np.int64)
        field = self.fields.search(self.free, source, target_cells=index)
        path = extract_path(field, goal) if np.isfinite(field[goal]) else None
        self.fields.release()
        return path


class ZlotMarket(Strategy):
    """Zlot et al. 2002: goal points traded in single-item auctions among the robots."""

    id = "zlot-market"
    summary = "Zlot et al. 2002: market economy, goal points traded in auctions"
    citation = (
        "R. Zlot, A. Stentz, M. B. Dias, S. Thayer, Multi-robot exploration controlled "
        "by a market economy, ICRA 2002"
    )
    revenue_weight = Param(
        1.0,
        "",
        "revenue per unknown cell, in cells of travel",
        "w_r",
        low=0,
        note="revenue per unknown cell expected to be seen, in cells of travel",
    )
    goals_per_round = Param(3, "", "goal points drawn per generation", low=1)
    goal_spacing = Param(
        0.0,
        "cells",
        "least distance between goals; 0 = sensor range",
        low=0,
        note="least Euclidean distance between goal points; 0 = `R`",
    )
    generation_radius = Param(
        1.0,
        "cells",
        "draw goals at most this far (path) beyond the nearest candidate",
        low=0,
        note=("draw goals at most this far (path) beyond the nearest unclaimed frontier cell"),
    )
    min_tour = Param(
        1,
        "",
        "generate new goals when the tour is shorter than this",
        low=1,
        note="generate goals when the tour holds fewer goals",
    )
    auction_ticks = Param(
        2,
        "ticks",
        "auction duration (at least 2 x latency x hops)",
        low=1,
        note="auction duration, raised to `2 x latency x hops`",
    )
    reauction_every = Param(
        10,
        "ticks",
        "re-auction the least valued goal (0 = never)",
        low=0,
        note="re-auction the least valued goal of the tour (0 = never)",
    )
    line_of_sight = Param(
        False,
        "",
        "count only unknown cells in line of sight",
        note="count only unknown cells in line of sight (in the belief) in `I`",
    )

    def __init__(self, robot_id: int, n_robots: int, **params: object) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.tour: list[Cell] = []
        self.auctions: dict[Cell, OpenAuction] = {}
        self.foreign_goals: dict[Cell, int] = {}
        self.last_reauction = 0
        self.next_generation = 0
        self._distances = TickDistances()

    # ------------------------------------------------------------------ helpers
    def _revenues(self, view: RobotView, goals: Sequence[Cell]) -> npt.NDArray[np.float64]:
        gain = information_gain(
            view.belief,
            np.array(goals, dtype=np.int64).reshape(-1, 2),
            view.sensor_range,
            line_of_sight=self.line_of_sight,
        )
        return revenue(gain, self.revenue_weight)

    def _tour_points(self, view: RobotView) -> list[Cell]:
        return [view.position, *self.tour]

    def distances(self, view: RobotView) -> TickDistances:
        """Path lengths over this tick's belief, each pair computed once while the known
        free cells stay the same."""
        if self._distances.tick != view.tick:
            self._distances.reset(view.tick, passable(view.belief))
        return self._distances

    def legs(self, view: RobotView) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """``d(p_i, p_{i+1})`` and ``d(p_i, p_{i+2})`` along the tour.

        Each comes from a field around ``p_i`` that stops at ``p_{i+2}``: tours
        are local, so these fields are small. Goals the robot cannot reach are
        dropped from the tour on the way.
        """
        distances = self.distances(view)
        while True:
            points = self._tour_points(view)
            m = len(self.tour)
            legs, skips = np.zeros(m), np.zeros(max(m - 1, 0))
            for i in range(m):
                ahead = distances.between(points[i], points[i + 1 : i + 3])
                legs[i] = ahead[0]
                if i < m - 1:
                    skips[i] = ahead[1]
            unreachable = np.flatnonzero(~np.isfinite(legs))
            if unreachable.size == 0:
                return legs, skips
            del self.tour[int(unreachable[0])]  # the graph is undirected: nobody reaches it

    def tour_values(self, view: RobotView) -> npt.NDArray[np.float64]:
        """The robot's value ``r(p_j) - s_j`` of each goal of its tour."""
        if not self.tour:
            return np.zeros(0)
        legs, skips = self.legs(view)
        return self._revenues(view, self.tour) - removal_savings(legs, skips)

    def insert(self, view: RobotView, goals: Sequence[Cell]) -> list[Cell]:
        """Add ``goals`` to the tour one by one by cheapest insertion; return those added."""
        distances = self.distances(view)
        added: list[Cell] = []
        for goal in goals:
            if goal in self.tour or goal == view.position:
                continue
            legs, _ = self.legs(view)
            cost, index = insertion_cost(distances.between(goal, self._tour_points(view)), legs)
            if np.isfinite(cost):
                self.tour.insert(index, goal)
                added.append(goal)
        return added

    def bids_for(
        self, view: RobotView, goals: Sequence[Cell], reserves: Sequence[float]
    ) -> npt.NDArray[np.float64]:
        """This robot's bids ``r(x) - c(x)`` for each goal; ``-inf`` where no bid can beat its
        reserve (the field from ``x`` stops at ``r(x) - reserve + max leg``, beyond which no
        insertion is cheap enough)."""
        revenues = self._revenues(view, goals)
        bids = np.full(len(goals), -np.inf)
        budgets = revenues - np.asarray(reserves, dtype=np.float64)
        if not (budgets > 0).any():
            return bids
        legs, _ = self.legs(view)
        longest = float(legs.max()) if legs.size else 0.0
        points = self._tour_points(view)
        for k, goal in enumerate(goals):
            # Octile distances never exceed path lengths: a cheap lower bound of c(x).
            if budgets[k] <= insertion_cost(octile_distances(goal, points), legs)[0]:
                continue
            to_new = self.distances(view).between(goal, points, budgets[k] + longest)
            cost, _ = insertion_cost(to_new, legs)
            if np.isfinite(cost):
                bids[k] = revenues[k] - cost
        return bids

    def generate_goals(self, view: RobotView) -> list[Cell]:
        """Step 1: random goal points among the reachable frontier cells near the robot.

        The candidates are the reachable frontier cells (not the robot's own) farther
        than the spacing from every held goal, or all of them when none is; of those,
        the ones at most ``generation_radius`` beyond the nearest. Two searches find
        them: one stopped at the nearest candidate, one bounded just beyond it.
        """
        frontier = frontier_mask(view.belief)
        if not frontier.any():
            return []
        distances = self.distances(view)
        fields, free = distances.fields, distances.free
        foreign_goals = {g: r for g, r in self.foreign_goals.items() if frontier[g]}
        spacing = self.goal_spacing or view.sensor_range
        held = self.tour + [g for g, r in foreign_goals.items() if r in view.subnetwork]
        candidates = frontier.copy()
        candidates[view.position] = False
        unclaimed = candidates.copy()
        for row, col in held:
            clear_disk(unclaimed, row, col, spacing)
        complete = False  # whether the field in the workspace covers the whole component
        if unclaimed.any():
            field = fields.search(free, view.position, targets=unclaimed, stop_after=1)
            mask, nearest = unclaimed, fields.nearest(unclaimed)
            if not np.isfinite(nearest):  # none reachable: the search went everywhere
                complete = True
                mask, nearest = candidates, fields.nearest(candidates)
        else:
            field = fields.search(free, view.position, targets=candidates, stop_after=1)
            mask, nearest = candidates, fields.nearest(candidates)
        if not np.isfinite(nearest):
            fields.release()
            return []
        self.foreign_goals = foreign_goals
        bound = nearest + self.generation_radius
        if not complete:
            field = fields.search(free, view.position, max_distance=bound)
        rows, cols = cells_within(field, mask, view.position, bound)
        fields.release()
        chosen = spread_goals(rows, cols, self.goals_per_round, spacing, view.rng)
        return [(int(rows[i]), int(cols[i])) for i in chosen]

    def _auction_duration(self, view: RobotView) -> int:
        hops = hops_to_farthest(self.robot_id, view.links)
        return max(self.auction_ticks, 2 * view.comm_latency * max(hops, 1))

    def _announce(
        self, view: RobotView, goals: Sequence[Cell], reserves: Sequence[float]
    ) -> list[Message]:
        closes_at = view.tick + self._auction_duration(view)
        messages = []
        for goal, reserve in zip(goals, reserves, strict=True):
            reserve = float(float32_on_wire(reserve))
            self.auctions[goal] = OpenAuction(reserve, closes_at)
            payload = AuctionPayload(self.robot_id, goal, reserve)
            messages.append(item_message(AUCTION, self.robot_id, BROADCAST, payload))
        return messages

    # ------------------------------------------------------------------ tick
    def decide(self, view: RobotView) -> Decision:
        decision = Decision()
        announcements: list[AuctionPayload] = []
        won: list[Cell] = []
        for message in view.inbox:
            payload = message.payload
            if message.type == AUCTION and isinstance(payload, AuctionPayload):
                if payload.robot != self.robot_id:  # the auctioneer
                    self.foreign_goals[payload.cell] = payload.robot
                    announcements.append(payload)
            elif message.type == BID and isinstance(payload, BidPayload):
                auction = self.auctions.get(payload.cell)
                if auction is not None and (
                    payload.value > auction.best_value
                    or (payload.value == auction.best_value and payload.robot < auction.best_bidder)
                ):
                    auction.best_value, auction.best_bidder = payload.value, payload.robot
            elif message.type == AWARD and isinstance(payload, AwardPayload):
                if payload.robot == self.robot_id:  # the winner
                    won.append(payload.cell)
                else:
                    self.foreign_goals[payload.cell] = payload.robot

        # Step 6 bookkeeping: drop goals reached, explored or that blocked the robot.
        if view.blocked and self.tour and view.goal is None:
            self.tour.pop(0)
        self.tour = [
            g for g in self.tour if g != view.position and frontier_at(view.belief, g[0], g[1])
        ]
        if won:
            self.insert(view, [g for g in won if frontier_at(view.belief, g[0], g[1])])

        # Step 4, bidder side: answer announcements with bids above the reserve.
        wanted = [
            a
            for a in announcements
            if a.cell not in self.tour and frontier_at(view.belief, a.cell[0], a.cell[1])
        ]
        if wanted:
            bids = self.bids_for(view, [a.cell for a in wanted], [a.value for a in wanted])
            for announcement, value in zip(wanted, bids, strict=True):
                value = float(float32_on_wire(value))
                if np.isfinite(value) and value > announcement.value:  # above the reserve
                    bid = BidPayload(self.robot_id, announcement.cell, value)
                    auctioneer = announcement.robot
                    decision.messages.append(item_message(BID, self.robot_id, auctioneer, bid))

        # Step 4, auctioneer side: close due auctions.
        for goal in [g for g, a in self.auctions.items() if view.tick >= a.closes_at]:
            auction = self.auctions.pop(goal)
            if goal not in self.tour or auction.best_bidder < 0:
                continue
            if winning_bid({auction.best_bidder: auction.best_value}, auction.reserve) is None:
                continue
            self.tour.remove(goal)
            award = AwardPayload(auction.best_bidder, goal)
            decision.messages.append(item_message(AWARD, self.robot_id, BROADCAST, award))

        alone = len(view.subnetwork) < 2
        # Step 1: generate goals when the tour runs short; auction them.
        if len(self.tour) < self.min_tour and view.tick >= self.next_generation:
            added = self.insert(view, self.generate_goals(view))
            if not added:
                self.next_generation = view.tick + GENERATION_RETRY_TICKS
            elif not alone:
                value_of = dict(zip(self.tour, self.tour_values(view).tolist(), strict=True))
                added = [g for g in added if g in value_of]
                decision.messages += self._announce(view, added, [value_of[g] for g in added])

        # Step 5: re-auction the least valued goal.
        every = self.reauction_every
        if every > 0 and not alone and view.tick - self.last_reauction >= every:
            self.last_reauction = view.tick
            values = self.tour_values(view)
            candidates = [i for i, g in enumerate(self.tour) if g not in self.auctions]
            if candidates:
                least = min(candidates, key=lambda i: (values[i], i))
                decision.messages += self._announce(
                    view, [self.tour[least]], [float(values[least])]
                )

        self._navigate(view, decision)
        return decision

    def _navigate(self, view: RobotView, decision: Decision) -> None:
        """Step 6: drive to the first goal of the tour (dropping unreachable ones)."""
        while self.tour:
            goal = self.tour[0]
            if view.goal == goal:
                return
            path = self.distances(view).path(view.position, goal)
            if path is not None:
                decision.goal, decision.path = goal, path
                return
            self.tour.pop(0)
        if view.goal is not None:
            decision.idle = True
