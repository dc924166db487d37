"""Burgard et al. (2005): coordinated exploration by utility discounting.

W. Burgard, M. Moors, C. Stachniss, F. Schneider, "Coordinated multi-robot
exploration", IEEE Transactions on Robotics 21(3), 2005; as summarised in
Wu, Puig & Garcia §II and Meier, Stachniss & Burgard §4 (eq. 1, Algorithm 1).

A coordinator (the lowest live robot id in each sub-network) assigns goals.
Targets ``t`` are frontier cells of the coordinator's belief, each with
utility ``U_t = 1``. Goals already held by other robots discount the utility
of targets near them:

    U_t <- U_t - P(||t - t'||),   P(d) = 1 - d / max_range  if d < max_range else 0   (eq. 1)

Then, repeatedly, the pair (robot i, target t) maximising ``U_t - beta * V_t^i``
is assigned, where ``V_t^i`` is the cost (shortest-path length over cells known
to be free) of robot i reaching t, and the utilities of the targets in the
visibility area of t are discounted before the next robot is chosen, until every
robot has a target. Whenever a robot needs a target the whole team is assigned
again (Meier et al. §5.1: "Only a centralized coordination technique has the
ability to choose that robot-target tuple that provides the (globally) highest
expected utility").

Parameters (rendered from ``Burgard.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin burgard

===================  ======  =========  =====  =====================================================
name                 symbol  default    unit   meaning
===================  ======  =========  =====  =====================================================
``assign``           -       team       -      whenever a robot needs a goal, re-assign the whole
                                               team (`team`), or only the robots that asked
                                               (`requesting`, our earlier version)
``status_period``    -       1          ticks  with assign=team, each robot reports its position
                                               this often
``protocol``         -       positions  -      `positions`: the coordinator computes every cost on
                                               its map from reported positions (Burgard et al.);
                                               `bids`: every robot sends its costs to the frontier
                                               cells it can reach (the market paper's description of
                                               [3])
``request_timeout``  -       5          ticks  resend a goal request if no assignment came
UtilityDiscounting   -                         shared: ``strategies.utility``
ReplanRules          -                         shared: ``strategies.base``
FallbackRules        -                         shared: ``strategies.fallback``
===================  ======  =========  =====  =====================================================

.. params:end

Interpretations (where the sources are silent):

* Cost normalisation: the papers give ``U`` in [0, 1] and ``V`` as path cost
  with ``beta`` trading them off, but not the scale of ``V``. With raw path
  lengths in cells, ``beta = 1`` would make utility irrelevant beyond one cell
  of distance. We scale each robot's costs to [0, 1] by its largest finite cost
  over the current targets (``normalize_cost=True``); set it to False for raw
  costs.
* The visibility area of a target t (Meier et al. Algorithm 1 step 5, after
  Burgard et al.): the targets within ``max_range`` in line of sight of t on the
  coordinator's map, where known obstacles block sight and unknown cells do not
  (the sensor at t would see through them if they are free);
  ``visibility_discount=False`` discounts every target within ``max_range``.
* Whole-team assignment (``assign=team``): when a robot needs a goal, the loop
  runs over every robot of the sub-network the coordinator knows the position
  of, those on their way included, so the coordinator chooses the globally best
  robot-target tuple each time; a robot whose goal does not change hears
  nothing. It needs every robot's position: each robot sends a ``status``
  (position, flags) every ``status_period`` ticks (Burgard et al.'s robots share
  their poses with their sensor data). ``assign=requesting`` (our earlier
  version) re-assigns only the robots that asked, the goals of the others
  fixed and discounting first.
* The coordinator's inputs are messages: a robot needing a goal sends a
  ``status`` message (position, flags: 8 bytes + header) to the coordinator,
  which answers with an ``assign`` message (target: 6 bytes + header). The
  coordinator plans for itself without messages. Each message takes one tick,
  so a non-coordinator robot waits two ticks for a new goal.
* Bids (``protocol=bids``). The decentralised market paper (``market-occupancy``),
  whose centralised baseline is Burgard et al. (its [3]), describes the method as
  "centralized since every robot constructs its bids and sends them to a central
  executive, that tries to maximize the total expected utility ... by assigning them
  tasks, based on their bids". A robot that needs a goal sends a ``bid`` message:
  its status item and, for every frontier cell of its own map it can reach, a bid
  item (cell, path-length cost as float32; ``7 + 8 + 10 n`` bytes). The coordinator
  then calls the sub-network for bids (``bid_call``, a header, broadcast; with
  ``assign=team``), every member answers with its bids, and the coordinator assigns
  once every member has bid (or ``request_timeout`` ticks after the call) from the
  costs the robots sent: a cell a robot did not bid on is out of its reach. No
  ``status`` is sent. A robot that asked gets its goal four ticks later (two with
  ``positions``). ``positions`` (the default) is Burgard et al.'s own setting, where
  the robots share their maps and poses and the coordinator computes every cost on
  its map.
* Unreliable communication (ours; the papers assume every message arrives): a
  robot that has needed a goal for ``coordinator_timeout`` ticks without an
  assignment it can follow runs the method for a team of one (its own belief,
  itself only, no goals of others: :func:`assign_greedy` with one robot) and
  goes on asking; an assignment that arrives later replaces its goal. The
  coordinator never waits for its team. With lossless links an answer takes two
  ticks, so the rule does not fire.
* Blocked targets (ours): a target on which a robot was blocked ``block_limit``
  times in a row (e.g. a failed robot stands on it) has an infinite cost for that
  robot until it next arrives at a target; a robot left with no target at all
  forgets these and tries them again. See :mod:`mrexplore.strategies.fallback`.

Messages: ``status`` (robot -> coordinator), ``assign`` (coordinator -> robot); with
``protocol=bids``, ``bid`` (robot -> coordinator) and ``bid_call`` (coordinator -> all)
instead of ``status``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BID_BYTES, BROADCAST, STATUS_BYTES, fixed_size
from mrexplore.comm.messages import BID, STATUS, Message, StatusItem, item_message
from mrexplore.grid.occupancy import OCCUPIED
from mrexplore.planning import distance_field, frontier_mask
from mrexplore.planning.team_fields import team_costs
from mrexplore.strategies.base import Cell, Decision, Param, RobotView, passable
from mrexplore.strategies.coordinated import CoordinatedWithFallback
from mrexplore.strategies.utility import UtilityDiscounting, coverage_probability, discount

__all__ = [
    "BID_CALL",
    "BidsPayload",
    "Burgard",
    "assign_greedy",
    "bids_size",
    "coverage_probability",
    "discount",
]


@dataclass(frozen=True, slots=True)
class BidsPayload:
    """``protocol=bids``: a robot's position, whether it needs a goal, and its cost
    (path length on its own map) to each frontier cell it can reach."""

    robot: int
    position: Cell
    needs_goal: bool
    rows: npt.NDArray[np.int64]
    cols: npt.NDArray[np.int64]
    costs: npt.NDArray[np.float32]


BID_CALL = "bid_call"
"""``protocol=bids``: the coordinator asks every robot of its sub-network for bids."""


def bids_size(n_bids: int) -> int:
    """Bytes of a ``bid`` message of ``protocol=bids``: a status item (robot, position,
    flags) and ``n_bids`` bid items (robot, row, col, cost float32).

    >>> bids_size(0), bids_size(10)
    (15, 115)
    """
    return fixed_size(STATUS_BYTES) + n_bids * BID_BYTES


def assign_greedy(
    robots: list[int],
    positions: Mapping[int, Cell],
    held_goals: Mapping[int, Cell],
    belief_passable: npt.NDArray[np.bool_],
    frontier: npt.NDArray[np.bool_],
    *,
    beta: float,
    max_range: float,
    normalize_cost: bool,
    unreachable: Mapping[int, Iterable[Cell]] | None = None,
    occupied: npt.NDArray[np.bool_] | None = None,
    bids: Mapping[int, BidsPayload] | None = None,
) -> dict[int, Cell]:
    """Burgard's sequential assignment of frontier targets to ``robots``.

    ``held_goals`` are goals of robots not being re-assigned; they discount the
    utilities first. ``unreachable[i]`` are targets robot ``i`` cannot reach
    whatever its map says (cost infinite). ``occupied``: discount only in the
    visibility area of each goal (:func:`discount`). ``bids[i]``: robot ``i``'s
    costs as it sent them (a target it did not bid on is out of its reach); the
    others' costs are path lengths on ``belief_passable``. Returns a goal for every
    robot that can reach a target.
    """
    width = frontier.shape[1]
    flat = np.flatnonzero(frontier)  # row-major: sorted
    rows, cols = np.divmod(flat, width)
    utility = np.ones(rows.size, dtype=np.float64)
    for goal in held_goals.values():
        discount(utility, rows, cols, goal, max_range, occupied)
    # One field per robot that did not bid, all in one compiled pass (team_costs).
    planned = [r for r in robots if bids is None or r not in bids]
    fields = team_costs(belief_passable, [positions[r] for r in planned], flat)
    costs: dict[int, npt.NDArray[np.float64]] = {}
    for robot in robots:
        if bids is not None and robot in bids:
            cost = np.full(flat.size, np.inf)
            sent = bids[robot]
            where = np.searchsorted(flat, sent.rows * width + sent.cols)
            hit = where < flat.size
            hit[hit] = flat[where[hit]] == (sent.rows * width + sent.cols)[hit]
            cost[where[hit]] = sent.costs[hit]
        else:
            cost = fields[planned.index(robot)]
        cost[(rows == positions[robot][0]) & (cols == positions[robot][1])] = np.inf
        for cell in (unreachable or {}).get(robot, ()):
            cost[(rows == cell[0]) & (cols == cell[1])] = np.inf
        if normalize_cost:
            finite = cost[np.isfinite(cost)]
            if finite.size and finite.max() > 0:
                cost = cost / finite.max()
        costs[robot] = cost
    assigned: dict[int, Cell] = {}
    remaining = [r for r in robots if np.isfinite(costs[r]).any()]
    while remaining and rows.size:
        best_value = -np.inf
        best: tuple[int, int] | None = None
        for robot in remaining:  # robots in id order: ties go to the lowest id
            value = utility - beta * costs[robot]
            index = int(np.argmax(value))
            if np.isfinite(value[index]) and value[index] > best_value:
                best_value, best = float(value[index]), (robot, index)
        if best is None:
            break
        robot, index = best
        goal = (int(rows[index]), int(cols[index]))
        assigned[robot] = goal
        discount(utility, rows, cols, goal, max_range, occupied)
        remaining.remove(robot)
    return assigned


class Burgard(UtilityDiscounting, CoordinatedWithFallback):
    """Burgard et al. 2005, run by the lowest-id robot of each sub-network."""

    id = "burgard"
    summary = "Burgard et al. 2005: utility discounting, central greedy assignment"
    citation = "W. Burgard et al., Coordinated multi-robot exploration, IEEE T-RO 21(3), 2005"
    assign = Param(
        "team",
        "",
        "whenever a robot needs a goal, assign the whole team, or only those that asked",
        choices=("team", "requesting"),
        note=(
            "whenever a robot needs a goal, re-assign the whole team (`team`), or "
            "only the robots that asked (`requesting`, our earlier version)"
        ),
    )
    status_period = Param(
        1, "ticks", "with assign=team, each robot reports its position this often", low=1
    )
    protocol = Param(
        "positions",
        "",
        "positions: the coordinator plans on its map from reported positions; bids: "
        "every robot sends its costs to every frontier cell (the market paper's [3])",
        choices=("positions", "bids"),
        note=(
            "`positions`: the coordinator computes every cost on its map from "
            "reported positions (Burgard et al.); `bids`: every robot sends its "
            "costs to the frontier cells it can reach (the market paper's "
            "description of [3])"
        ),
    )
    request_timeout = Param(
        5,
        "ticks",
        "resend a goal request after this many ticks",
        low=1,
        note="resend a goal request if no assignment came",
    )

    def __init__(self, robot_id: int, n_robots: int, **params: object) -> None:
        super().__init__(robot_id, n_robots, **params)
        # Coordinator state: what it knows of the robots of its sub-network.
        self.known_positions: dict[int, Cell] = {}
        self.requests: set[int] = set()
        self.bids: dict[int, BidsPayload] = {}  # protocol=bids: this round's, by robot
        self.round_opened: int | None = None  # protocol=bids: tick the call went out
        # Member state: when the last report went out.
        self.reported_at = -(10**9)

    def decide_coordinated(self, view: RobotView) -> Decision:
        coordinator = self.coordinator(view)
        assignment = self.assignment(view)
        called = False
        for message in view.inbox:
            payload = message.payload
            if isinstance(payload, StatusItem | BidsPayload):
                self.known_positions[payload.robot] = payload.position
                if isinstance(payload, BidsPayload):
                    self.bids[payload.robot] = payload
                if payload.needs_goal:
                    self.requests.add(payload.robot)
                    self.held_goals.pop(payload.robot, None)
            elif message.type == BID_CALL:
                called = message.sender == coordinator

        needs_goal = self.needs_plan(view)
        if self.robot_id == coordinator:
            self.watch.stop()
            return self._coordinate(view, needs_goal)
        decision = Decision()
        if called:  # protocol=bids: the coordinator opened a round
            decision.messages.append(self._report(view, coordinator, needs_goal=needs_goal))
        if assignment is not None:
            decision = self.follow(view, assignment)
            if decision.goal is not None:
                self.requested_at = -1
                self.watch.stop()
                return decision
            needs_goal = True
        if not needs_goal:
            self.watch.stop()
            team = self.assign == "team" and self.protocol == "positions"
            if team and view.tick - self.reported_at >= self.status_period:
                decision.messages.append(self._status(view, coordinator, needs_goal=False))
            return decision
        own = self.fall_back(view, self.request_timeout)
        if own is not None:
            return own
        if self.requested_at < 0 or view.tick - self.requested_at >= self.request_timeout:
            self.requested_at = view.tick
            if not called:
                decision.messages.append(self._report(view, coordinator, needs_goal=True))
        return decision

    def _report(self, view: RobotView, coordinator: int, *, needs_goal: bool) -> Message:
        """``status`` (``protocol=positions``), or this robot's bids (``bids``)."""
        if self.protocol == "positions":
            return self._status(view, coordinator, needs_goal=needs_goal)
        frontier = frontier_mask(view.belief)
        dist = distance_field(passable(view.belief), view.position, targets=frontier)
        for cell in self.blocked_targets.excluded:
            dist[cell] = np.inf
        dist[view.position] = np.inf
        rows, cols = np.nonzero(frontier & np.isfinite(dist))
        costs = dist[rows, cols].astype(np.float32)  # float32 on the wire
        bids = BidsPayload(self.robot_id, view.position, needs_goal, rows, cols, costs)
        self.reported_at = view.tick
        return Message(BID, self.robot_id, coordinator, bids_size(rows.size), bids)

    def _status(self, view: RobotView, coordinator: int, *, needs_goal: bool) -> Message:
        """This robot's position for the coordinator, and whether it needs a goal."""
        self.reported_at = view.tick
        status = StatusItem(self.robot_id, view.position, needs_goal)
        return item_message(STATUS, self.robot_id, coordinator, status)

    def plan_alone(self, view: RobotView) -> Decision:
        """The method for a team of one: this robot, its own belief, no other goals."""
        frontier = frontier_mask(view.belief)
        while True:
            assigned = assign_greedy(
                [self.robot_id],
                {self.robot_id: view.position},
                {},
                passable(view.belief),
                frontier,
                beta=self.beta,
                max_range=self.max_range or view.sensor_range,
                normalize_cost=self.normalize_cost,
                unreachable={self.robot_id: self.blocked_targets.excluded},
                occupied=view.belief == OCCUPIED if self.visibility_discount else None,
            )
            goal = assigned.get(self.robot_id)
            if goal is not None:
                return self.follow(view, goal)
            if not self.blocked_targets.forget():
                return Decision()

    def _coordinate(self, view: RobotView, needs_goal: bool) -> Decision:
        """Coordinator: when a robot needs a goal (itself included), assign goals to the
        whole team it knows the positions of (``assign=team``), or only to the robots
        that asked (``requesting``)."""
        members = view.subnetwork
        self.known_positions[self.robot_id] = view.position
        self.requests &= members
        self.keep_members(members)
        if needs_goal:
            self.requests.add(self.robot_id)
            self.held_goals.pop(self.robot_id, None)
        elif view.goal is not None:
            self.held_goals[self.robot_id] = view.goal
        if not self.requests:
            return Decision()
        frontier = frontier_mask(view.belief)
        chosen = members if self.assign == "team" else self.requests
        robots = sorted(r for r in chosen if r in self.known_positions)
        bids: dict[int, BidsPayload] | None = None
        if self.protocol == "bids":
            # The market paper's [3]: "every robot constructs its bids and sends them to
            # a central executive". A round opens with a call to the team; it is decided
            # once every robot chosen has bid, or after request_timeout ticks.
            if self.round_opened is None:
                self.round_opened = view.tick
                self.bids = {r: b for r, b in self.bids.items() if r in self.requests}
                if self.assign == "team" and len(members) > 1:
                    call = Message(BID_CALL, self.robot_id, BROADCAST, fixed_size(0), None)
                    return Decision(messages=[call])
            late = view.tick - self.round_opened >= self.request_timeout
            if not late and any(r not in self.bids for r in chosen - {self.robot_id}):
                return Decision()
            bids = {r: b for r, b in self.bids.items() if r in chosen}
            robots = sorted({self.robot_id} & chosen | set(bids))
            self.round_opened, self.bids = None, {}
            self.requests -= set(bids)  # served or not, a robot still in need asks again
        max_range = self.max_range or view.sensor_range
        occupied = view.belief == OCCUPIED if self.visibility_discount else None
        assigned = assign_greedy(
            robots,
            self.known_positions,
            {r: g for r, g in self.held_goals.items() if r not in robots},
            passable(view.belief),
            frontier,
            beta=self.beta,
            max_range=max_range,
            normalize_cost=self.normalize_cost,
            unreachable={self.robot_id: self.blocked_targets.excluded},
            occupied=occupied,
            bids=bids,
        )
        decision = Decision()
        for robot, goal in assigned.items():
            unchanged = robot not in self.requests and self.held_goals.get(robot) == goal
            self.held_goals[robot] = goal
            self.requests.discard(robot)
            if unchanged:  # re-assigned the goal it holds: nothing to say
                continue
            self.hand_out(view, decision, robot, goal)
        if self.robot_id in self.requests:  # nothing reachable for the coordinator
            self.blocked_targets.forget()  # try the targets it gave up on again
            self.requests.discard(self.robot_id)
            decision.idle = decision.goal is None
        self.last_plan_tick = view.tick
        return decision
