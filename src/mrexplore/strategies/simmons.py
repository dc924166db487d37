"""Simmons et al. (2000): information-gain bids, central greedy assignment.

R. Simmons, D. Apfelbaum, W. Burgard, D. Fox, M. Moors, S. Thrun, H. Younes,
"Coordination for multi-robot exploration and mapping", Proc. AAAI Conference
on Artificial Intelligence (AAAI-2000), pp. 852-858; as summarised in Wu, Puig &
Garcia §II ("information gain ... subtracting the overlapped areas expected to
be found by other robots ... bids ... expected information gain minus the cost
... a center agent collects the bids and assigns the target to the robot which
offers the highest bid") and Vazquez & Malcolm §3.2 ("the utility ... counting
the number of unexplored cells that lie inside the circumference of the sensor
range ... each robot makes a bid for each frontier ... a robot is assigned a
frontier based on the best bid and the whole process repeated for unassigned
robots").

The method, step by step (``F`` = frontier cells, ``R`` = sensor range in cells):

1. Each robot ``i`` that needs a goal computes, on its own belief, for every
   reachable frontier cell ``f``:

   * the information gain ``I(f)`` = unknown cells within ``R`` of ``f``
     (:func:`~mrexplore.planning.information_gain`);
   * the cost ``C_i(f)`` = shortest-path length (cells) from its cell to ``f``
     over cells it knows to be free (:func:`~mrexplore.planning.distance_field`);
   * its bid ``B_i(f) = I(f) - w * C_i(f)`` (:func:`bid_value`).

   It sends its ``k`` best bids, spread at least ``bid_separation`` cells apart
   (:func:`select_bids`), to the coordinator.
2. The coordinator (the lowest live id of the sub-network) starts from the goals
   it has already assigned to robots that keep them, ``A``, and repeats until
   every bidding robot has a goal or no bid is left (:func:`assign_bids`):

   * overlap ``O(f)`` = unknown cells (in the coordinator's belief) within ``R`` of
     ``f`` and within ``R`` of some target in ``A`` (:func:`overlap`);
   * current bid ``B_i(f) - O(f)``, i.e. the bid with the information gain
     reduced by the area the assigned targets are expected to see;
   * assign the highest current bid ``(i, f)``, add ``f`` to ``A``, drop robot
     ``i`` and cell ``f`` from the remaining bids.
3. The coordinator sends each robot its goal; the robot plans a path to it on
   its own belief.

Parameters (rendered from ``Simmons.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin simmons

===================  ======  =======  =====  =======================================================
name                 symbol  default  unit   meaning
===================  ======  =======  =====  =======================================================
``cost_weight``      w       4.0      -      weight of the travel cost in `I - w C` (both in cells)
``bids_per_robot``   k       5        -      bids a robot sends per request
``bid_separation``   -       0.0      cells  least Euclidean distance between two bids of one robot;
                                             0 = `R`
``line_of_sight``    -       false    -      count only unknown cells in line of sight (in the
                                             belief) in `I` and `O`
``request_timeout``  -       5        ticks  resend bids if no assignment came back (at least `2 x
                                             latency + 1`)
ReplanRules          -                       shared: ``strategies.base``
===================  ======  =======  =====  =======================================================

.. params:end

Messages (sizes from :mod:`mrexplore.comm.bytes`):

=========  =====================  ============================  ===============================
type       direction              payload                       bytes
=========  =====================  ============================  ===============================
``bid``    robot -> coordinator   ``k`` bids (robot, row, col,  ``HEADER_BYTES + k * BID_BYTES``
                                  value float32)                = 7 + 10 k (57 for k = 5)
``assign`` coordinator -> robot   goal (robot, row, col)        ``HEADER_BYTES + TARGET_BYTES``
                                                                = 13
=========  =====================  ============================  ===============================

Interpretations (where the sources are silent):

* **Scale of gain and cost, and ``w``.** Simmons subtracts the travel cost
  from the information gain and gives no weight. We keep both in cells: ``I``
  is a count of cells (an area, up to about ``pi R^2``), ``C`` a path length.
  ``burgard`` instead uses a utility in [0, 1] and divides each robot's costs by
  its largest cost, because its utility has no unit; here the gain already has
  the scale of the map, so raw costs keep "gain minus cost" literal and the
  trade-off does not depend on how far the farthest frontier happens to be.
  With ``w = 1`` (the literal reading) one unknown cell pays for one cell of
  travel, and robots cross the map for large frontiers, leaving slivers behind:
  in a pilot (mean T99 of seeds 1-5, 4 robots, unlimited communication) it was
  the slowest setting on the 100 x 100 office (903 ticks), cityblock (497) and
  the Intel map (905), behind ``nearest-frontier``. ``w = 4`` was the best or
  within noise of the best on office, cityblock, unstructured and Intel with
  4 and 8 robots, so it is the default; ``w = 8`` suits a single robot better.
  The full table is in ``docs/strategies/simmons.md``.
* **Which bids.** A robot bids on frontier *cells*. To keep messages small it
  sends only its ``k`` best bids, chosen greedily (best first, then the best at
  least ``bid_separation`` away from every chosen one) so that the coordinator
  gets distinct alternatives rather than ``k`` neighbouring cells of one
  frontier.
* **Overlap.** The bid carries only the net value ``I - w C`` (the byte model's
  bid item has one value). The coordinator reduces it by the overlap ``O``,
  which it computes on its own belief as ``I(f) - I(f | cells within R of
  assigned targets excluded)``; with shared maps both beliefs agree.
* **Who is (re-)assigned.** Robots that need a goal (arrived, blocked, goal
  explored, or a re-planning rule fired) send bids; the goals held by the
  others count as assigned targets from the start. Bids that could not be
  served in a round (all their cells taken) are dropped; the robot resends
  after ``request_timeout``.
* **Coordinator.** The coordinator runs its own part of step 1 locally (no
  message). Under limited communication each sub-network has its own
  coordinator, which only knows the goals it assigned itself and the bids that
  reach it; a robot that loses its coordinator resends its bids to the new one
  after the timeout. Assignments take one message each way: a robot other than
  the coordinator waits ``2 x latency`` ticks for a goal, moving on towards its
  old goal meanwhile.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BID_BYTES, HEADER_BYTES, float32_on_wire
from mrexplore.comm.messages import BID, BidItem, Message
from mrexplore.grid.occupancy import BeliefGrid
from mrexplore.planning import disk_mask, distance_field, frontier_mask, information_gain
from mrexplore.strategies.base import (
    Cell,
    Decision,
    Param,
    RobotView,
    passable,
    reachable_frontier_cells,
)
from mrexplore.strategies.coordinated import CoordinatedStrategy

__all__ = [
    "Bid",
    "BidsPayload",
    "Simmons",
    "assign_bids",
    "bid_value",
    "bids_size",
    "overlap",
    "select_bids",
]

Bid = BidItem
"""One bid: robot ``robot`` offers ``value = I - w C`` for frontier cell ``cell``."""


@dataclass(frozen=True, slots=True)
class BidsPayload:
    """A robot's bids for its best frontier cells (possibly none)."""

    robot: int
    bids: tuple[Bid, ...]


def bids_size(n_bids: int) -> int:
    """Bytes of a ``bid`` message carrying ``n_bids`` bids.

    >>> bids_size(5)
    57
    """
    return HEADER_BYTES + BID_BYTES * n_bids


def bid_value(
    gain: npt.NDArray[np.integer] | npt.NDArray[np.floating],
    cost: npt.NDArray[np.floating],
    cost_weight: float,
) -> npt.NDArray[np.float64]:
    """Simmons' bid: information gain minus weighted travel cost, ``B = I - w C`` (cells).

    >>> bid_value(np.array([50, 20]), np.array([10.0, 2.0]), 1.0).tolist()
    [40.0, 18.0]
    """
    return np.asarray(gain, dtype=np.float64) - cost_weight * np.asarray(cost, dtype=np.float64)


def select_bids(
    rows: npt.NDArray[np.integer],
    cols: npt.NDArray[np.integer],
    values: npt.NDArray[np.floating],
    k: int,
    separation: float,
) -> npt.NDArray[np.int64]:
    """Indices of up to ``k`` best ``values``, each at least ``separation`` cells from the others.

    Greedy: the best value first (ties: the first index), then the best among the
    candidates farther than ``separation`` (Euclidean, cells) from every chosen one.

    >>> select_bids(np.array([0, 0, 0]), np.array([0, 1, 5]), np.array([3.0, 2.0, 1.0]), 2, 2.0)
    array([0, 2])
    """
    chosen: list[int] = []
    open_ = np.ones(len(values), dtype=bool)
    order_values = np.asarray(values, dtype=np.float64)
    while len(chosen) < k and open_.any():
        masked = np.where(open_, order_values, -np.inf)
        best = int(np.argmax(masked))
        chosen.append(best)
        near = np.hypot(rows - rows[best], cols - cols[best]) < separation
        open_ &= ~near
        open_[best] = False
    return np.asarray(chosen, dtype=np.int64)


def overlap(
    belief: BeliefGrid,
    cells: npt.NDArray[np.integer],
    radius: float,
    assigned: npt.NDArray[np.bool_],
    *,
    line_of_sight: bool = False,
) -> npt.NDArray[np.int64]:
    """``O(f)``: unknown cells within ``radius`` of each cell ``f`` that ``assigned`` also covers.

    ``assigned`` is the mask of the disks around the targets already assigned
    (:func:`disk_mask`); the result is ``I(f) - I(f | assigned excluded)``.
    """
    full = information_gain(belief, cells, radius, line_of_sight=line_of_sight)
    if not assigned.any():
        return np.zeros_like(full)
    rest = information_gain(belief, cells, radius, line_of_sight=line_of_sight, exclude=assigned)
    return full - rest


def assign_bids(
    bids: Mapping[int, Sequence[Bid]],
    belief: BeliefGrid,
    radius: float,
    assigned_targets: Iterable[Cell] = (),
    *,
    line_of_sight: bool = False,
) -> dict[int, Cell]:
    """Simmons' central assignment: repeatedly give the highest overlap-reduced bid its cell.

    Args:
        bids: each bidding robot's bids.
        belief: the coordinator's belief (the overlap is counted on it).
        radius: sensor range ``R`` in cells.
        assigned_targets: goals already held by robots that are not re-assigned.
        line_of_sight: count only cells in line of sight in ``I`` and ``O``.

    Returns:
        A goal for every robot that could be served, ``{robot: cell}``. Ties go
        to the robot with the lowest id, then to its earlier bid.
    """
    entries = [(robot, bid) for robot in sorted(bids) for bid in bids[robot]]
    if not entries:
        return {}
    cells = np.array([bid.cell for _, bid in entries], dtype=np.int64)
    values = np.array([bid.value for _, bid in entries], dtype=np.float64)
    owners = np.array([robot for robot, _ in entries], dtype=np.int64)
    shape = (int(belief.shape[0]), int(belief.shape[1]))
    covered = disk_mask(shape, assigned_targets, radius)
    open_ = np.ones(len(entries), dtype=bool)
    result: dict[int, Cell] = {}
    while open_.any():
        current = values - overlap(belief, cells, radius, covered, line_of_sight=line_of_sight)
        best = int(np.argmax(np.where(open_, current, -np.inf)))
        robot = int(owners[best])
        goal = (int(cells[best, 0]), int(cells[best, 1]))
        result[robot] = goal
        open_ &= (owners != robot) & ~((cells[:, 0] == goal[0]) & (cells[:, 1] == goal[1]))
        covered |= disk_mask(shape, [goal], radius)
    return result


class Simmons(CoordinatedStrategy):
    """Simmons et al. 2000, coordinated by the lowest-id robot of each sub-network."""

    id = "simmons"
    summary = "Simmons et al. 2000: information-gain bids, central greedy assignment"
    citation = "R. Simmons et al., Coordination for multi-robot exploration and mapping, AAAI 2000"
    cost_weight = Param(
        4.0,
        "",
        "weight w of travel cost in the bid I - w C",
        "w",
        low=0,
        note="weight of the travel cost in `I - w C` (both in cells)",
    )
    bids_per_robot = Param(5, "", "bids a robot sends per request", "k", low=1)
    bid_separation = Param(
        0.0,
        "cells",
        "least distance between two bids of a robot; 0 = sensor range",
        low=0,
        note="least Euclidean distance between two bids of one robot; 0 = `R`",
    )
    line_of_sight = Param(
        False,
        "",
        "count only unknown cells in line of sight",
        note=("count only unknown cells in line of sight (in the belief) in `I` and `O`"),
    )
    request_timeout = Param(
        5,
        "ticks",
        "resend bids after this many ticks",
        low=1,
        note="resend bids if no assignment came back (at least `2 x latency + 1`)",
    )

    def __init__(self, robot_id: int, n_robots: int, **params: object) -> None:
        super().__init__(robot_id, n_robots, **params)
        # Coordinator state: bids waiting for a round (and the goals it has assigned).
        self.pending_bids: dict[int, tuple[Bid, ...]] = {}

    # ------------------------------------------------------------------ step 1
    def make_bids(self, view: RobotView) -> tuple[Bid, ...]:
        """This robot's ``k`` best spread bids ``I(f) - w C(f)`` over its reachable frontier."""
        frontier = frontier_mask(view.belief)
        if not frontier.any():
            return ()
        dist = distance_field(passable(view.belief), view.position, targets=frontier)
        rows, cols = reachable_frontier_cells(frontier, dist)
        if rows.size == 0:
            return ()
        gains = information_gain(
            view.belief,
            np.column_stack((rows, cols)),
            view.sensor_range,
            line_of_sight=self.line_of_sight,
        )
        values = bid_value(gains, dist[rows, cols], self.cost_weight)
        separation = self.bid_separation or view.sensor_range
        chosen = select_bids(rows, cols, values, self.bids_per_robot, separation)
        sent = float32_on_wire(values[chosen])
        return tuple(
            Bid(self.robot_id, (int(rows[i]), int(cols[i])), float(value))
            for i, value in zip(chosen, sent, strict=True)
        )

    # ------------------------------------------------------------------ tick
    def decide(self, view: RobotView) -> Decision:
        coordinator = self.coordinator(view)
        assignment = self.assignment(view)
        for message in view.inbox:
            payload = message.payload
            if message.type == BID and isinstance(payload, BidsPayload):
                self.pending_bids[payload.robot] = payload.bids
                self.held_goals.pop(payload.robot, None)

        needs_goal = self.needs_plan(view)
        if self.robot_id == coordinator:
            return self._coordinate(view, needs_goal)
        self.pending_bids.clear()
        self.held_goals.clear()
        decision = Decision()
        if assignment is not None:
            decision = self.follow(view, assignment)
            if decision.goal is not None:
                self.requested_at = -1
                return decision
            needs_goal, self.requested_at = True, -1
        if needs_goal and self._request_due(view):
            self.requested_at = view.tick
            bids = self.make_bids(view)
            if not bids and view.goal is not None:
                decision.idle = True  # nothing left to explore from here
            payload = BidsPayload(self.robot_id, bids)
            decision.messages.append(
                Message(BID, self.robot_id, coordinator, bids_size(len(bids)), payload)
            )
        return decision

    def _request_due(self, view: RobotView) -> bool:
        timeout = max(self.request_timeout, 2 * view.comm_latency + 1)
        return self.requested_at < 0 or view.tick - self.requested_at >= timeout

    # ------------------------------------------------------------------ step 2
    def _coordinate(self, view: RobotView, needs_goal: bool) -> Decision:
        """Coordinator: serve the pending bids (its own included) by :func:`assign_bids`."""
        members = view.subnetwork
        self.pending_bids = {r: b for r, b in self.pending_bids.items() if r in members}
        self.keep_members(members)
        if needs_goal and self._request_due(view):
            self.requested_at = view.tick
            self.pending_bids[self.robot_id] = self.make_bids(view)
            self.held_goals.pop(self.robot_id, None)
        elif not needs_goal and view.goal is not None:
            self.held_goals[self.robot_id] = view.goal
        if not self.pending_bids:
            return Decision()
        assigned = assign_bids(
            {r: b for r, b in self.pending_bids.items() if b},
            view.belief,
            view.sensor_range,
            [g for r, g in self.held_goals.items() if r not in self.pending_bids],
            line_of_sight=self.line_of_sight,
        )
        decision = Decision()
        own_bids = self.pending_bids.get(self.robot_id)
        for robot, goal in assigned.items():
            self.held_goals[robot] = goal
            self.hand_out(view, decision, robot, goal)
        if own_bids is not None:
            if decision.goal is None:
                # Nothing reachable to assign itself: stop, and try again after the timeout.
                self.held_goals.pop(self.robot_id, None)
                decision.idle = view.goal is not None
            else:
                self.requested_at = -1
        self.pending_bids.clear()
        return decision
