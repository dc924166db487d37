"""Sheng, Yang, Tan & Xi (2006): distributed bidding with a nearness measure.

W. Sheng, Q. Yang, J. Tan, N. Xi, "Distributed multi-robot coordination in area
exploration", Robotics and Autonomous Systems 54 (2006) 945-955; §2-3 (the
method) and §5 (the defaults). Its map synchronisation (§4) is the ``sheng-sync`` sharing
mechanism, this strategy's default sharing.

Every robot runs the same program, asynchronously, with no central agent. A
robot is always in one of three states (§3.1, Fig. 3): **sensing and mapping**
(it has just arrived and sensed), **bidding** (it computes a bid over the
frontier cells of its own map and competes with the other bidders of its
sub-network) and **travelling** (it won a session and drives to its target).

§3.2, for every frontier cell ``i`` of the robot's own map:

* ``I_i``: the unknown cells within ``r_s`` of ``i`` that are not within ``r_s`` of
  the position of another sensing-and-mapping robot nor of the target of another
  travelling robot of the sub-network (:func:`~mrexplore.planning.disk_mask`,
  :func:`information_gains`);
* ``D_i``: the shortest travel distance from the robot to ``i`` over the cells it
  knows to be free (Dijkstra, 8-connected, no corner cutting);
* ``lambda_i``, eq. (1), :func:`nearness`: with ``d_1 <= d_2 <= ... <= d_(n_k-1)``
  the travel distances from ``i`` to the other robots of the sub-network (their
  positions, or their targets when they travel)::

      lambda_i = e^(-d_1/r_c) + alpha e^(-d_2/r_c) + ... + alpha^(n_k-2) e^(-d_(n_k-1)/r_c)

* the net gain, eq. (2), :func:`net_gain`: ``g_i = w1 I_i - w2 D_i + w3 lambda_i``,
  with ``lambda_i`` in units of ``r_c`` cells by default (``eq2_units``, below);
* the bid ``B = max_i g_i`` (:func:`compute_bid`).

§3.3 and Fig. 5, the bidding session (:class:`ShengBidding`): the bidder
broadcasts ``B`` and waits ``t_bid``; it wins if it heard no better bid (higher
value; equal values go to the lower id), declares itself the winner with its
target and travels. A bidder that heard a better bid waits for a winner to
declare; every declaration ends the session: the others recompute their bids
with the winner's target known and bid again. §3.4: a robot that finishes
sensing when the best current session began more than ``T_win`` ago (less than
``T_grace`` before it closes) stays out of it and waits for the next one.

Parameters (rendered from ``ShengBidding.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin sheng-bidding

=============================  ======  ==========  ======  =========================================
name                           symbol  default     unit    meaning
=============================  ======  ==========  ======  =========================================
``w1``                         ω1      1.0         1/cell  weight of the information gain `I_i` (§5)
``w2``                         ω2      1.0         1/cell  weight of the travel distance `D_i` (§5)
``w3``                         ω3      1.5         -       weight of the nearness `lambda_i` (§5;
                                                           `0` = "without nearness")
``alpha``                      α       0.5         -       fading factor of eq. (1), in [0, 1]; the
                                                           paper says only "positive, smaller than
                                                           1"
``nearness_over``              -       subnetwork  -       the robots eq. (1) measures to: the `n_k`
                                                           of the sub-network, or `known`, every
                                                           robot last heard of (Fig. 2's example)
``eq2_units``                  -       cells       -       units of eq. (2)'s terms: `cells`
                                                           (`lambda_i` in units of `r_c` cells),
                                                           `raw` (the literal sum) or `unit-free`
                                                           (see Interpretations)
``comm_range``                 r_c     0.0         cells   communication range in eq. (1); 0 = the
                                                           run's `--comm-range`, or 16 (section 5)
                                                           when unlimited; `inf` makes every term 1:
                                                           no pull
``bid_time``                   t_bid   1           ticks   bidding time (paper: 1.5 s); the session
                                                           lasts `max(bid_time, T_grace)`
``session_floor``              -       grace       -       the least `t_bid`: `grace` (`T_grace`, so
                                                           `T_win >= 0`) or `delay` (`t_d`, the
                                                           earlier reading; `T_win` can be -1)
``declare_timeout``            -       0           ticks   longest wait past `t_bid` for a winner's
                                                           declaration; 0 = `t_bid + 2 t_d`
``replan_on_target_explored``  -       false       -       stop and bid again when the target is no
                                                           longer a frontier cell
=============================  ======  ==========  ======  =========================================

.. params:end

Time windows (§3.4, Fig. 6), from the sub-network at the start of each session
(:func:`session_timing`): ``t_d = comm_latency x hop diameter`` of the
sub-network (the largest delay of a message in it; 0 for a lone robot),
``T_grace = t_d + 1`` (Proposition 1: ``T_grace > t_d``), ``t_bid = max(bid_time,
T_grace)`` and the send-map window ``T_win = t_bid - T_grace >= 0`` (Fig. 6 draws
``T_win`` and ``T_grace`` as the two parts of ``t_bid``; ``session_floor=delay`` is
the earlier reading ``t_bid = max(bid_time, t_d)``, where ``T_win`` can be -1).

Messages (all broadcast to the sub-network; sizes from :mod:`mrexplore.comm.bytes`,
header 7 bytes):

============  ===================================  =====  ===============================
type          payload                              bytes  sent
============  ===================================  =====  ===============================
``bid``       robot, target cell, value (float32)  17     a bid or a re-bid
``winner``    robot, target cell                   13     the winner's declaration
``position``  robot, cell                          13     on entering sensing-and-mapping
``target``    robot, target cell                   13     a travelling robot's target,
                                                          again when new robots join its
                                                          sub-network
============  ===================================  =====  ===============================

Interpretations (where the paper is silent):

* **Time.** Everything is in ticks. A bid sent at tick ``s`` is read by robots
  ``h`` hops away at ``s + h * comm_latency``; ``t_bid = max(bid_time, T_grace)``
  with ``bid_time = 1`` is the shortest session with a send-map window (the paper's
  1.5 s was long against a LAN's delay). One robot wins per session, so a
  sub-network sends out at most one robot every ``t_bid + t_d`` ticks (3 with one
  hop). When a tick is one cell of travel that queue can bind; the ``sheng2006``
  reproduction runs at a speed of 0.25 cells a tick, so a session is short
  against travel as in the paper.
* **The timer does not restart on re-bids.** Fig. 5 restarts it whenever a bid is
  recomputed; with sensing while moving, map updates arrive every tick and a
  restarting timer would never expire. A session lasts ``t_bid`` from the robot's
  first bid in it; re-bids (new map cells, a new bidder) happen only inside the
  send-map window and do not extend the session. With the defaults ``T_win = 0``:
  a robot re-bids or joins only in the tick a session began; a longer ``bid_time``
  widens the window.
* **Holding the map.** Map updates are sent by the run's sharing mechanism when
  cells are sensed; a strategy cannot hold them back. The late robot only stays out
  of the closing session, and updates arriving late in a session are used in the
  next one.
* **Session start times** travel with no timestamp (a bid is 10 bytes): a robot
  estimates a bid's start as its arrival tick minus ``comm_latency`` times the
  hops from the bidder, and keeps each robot's earliest bid of the session.
* **Timeouts.** A loser waits at most ``declare_timeout`` ticks past its own
  ``t_bid`` for a declaration, then forgets the better bids and bids again; a late
  robot waits at most ``t_bid + declare_timeout`` for the open session to end.
  No robot waits forever, whatever the network loses.
* **Who counts.** Only robots of the current sub-network enter ``I_i`` and eq. (1)
  (the paper: "within the same subnetwork", ``n_k``; ``nearness_over=known`` lets
  eq. (1) measure to every robot last heard of, as Fig. 2's example of robot 6, far
  from all the others, suggests); a robot whose position or target was
  never received is left out. A robot that is bidding, waiting or done counts as
  sensing-and-mapping at the position it announced.
* **Travel distances in eq. (1)** are shortest paths over the bidder's own map
  from the other robot's cell; an unreachable one gives ``e^(-inf) = 0``.
* **I_i** counts unknown cells of the disk without line of sight, as the paper
  defines it; the robot's own cell is never a candidate.
* **Units of eq. (2)** (``eq2_units``). The paper defines ``I_i`` as a number of
  cells and ``D_i`` as a travel distance, and gives no unit for the sum; ``lambda_i``
  is a pure number below ``1 / (1 - alpha)``. Added raw (``raw``), the nearness term
  is worth at most 3 cells against gains of up to 49 cells and distances of tens:
  at the paper's ``w3 = 1.5`` the team spreads as without it (group diameter 33.1
  against 31.4 cells, ``benchmarks/sheng_units_sweep.py``), unlike the paper's
  Figs. 10-11. Principle (stated before measuring): give each term a unit of
  cells, keeping the paper's definitions of ``I_i`` and ``D_i``; eq. (1) measures
  distance in units of ``r_c`` (``e^(-d/r_c)``), so one unit of ``lambda_i`` is ``r_c``
  cells. Then near another robot (``d << r_c``) one cell farther from it costs
  ``w3`` of gain, as one cell of travel costs ``w2``: the paper's weights 1, 1 and
  1.5 compare per cell. ``unit-free`` is the other consistent reading: ``I_i`` over
  the cells of the sensor disk, ``D_i`` over ``r_c``, ``lambda_i`` as it is.
* **Winning with a stale target.** If the bid's target is no longer a reachable
  frontier cell when the robot wins, it recomputes its bid and goes to the new
  best cell.
* **Travelling** goes to the target cell, as in the paper ("the winning robot then
  moves to its target frontier cell"), even when, sensing while moving, the robot
  sees the target's surroundings before it arrives. ``replan_on_target_explored``
  stops it where it is (it announces its position and bids again) once the target
  is no longer a frontier cell; stopping short makes more, shorter trips and so
  more sessions, which costs time in a team.
* **Completion.** A robot with no reachable frontier cell stays where it is and
  bids again as soon as its map gains cells.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, float32_on_wire
from mrexplore.comm.messages import BID, TARGET, BidItem, CellItem, Message, item_message
from mrexplore.grid.occupancy import BeliefGrid
from mrexplore.planning import (
    disk_offsets,
    distance_field,
    extract_path,
    frontier_mask,
    information_gain,
)
from mrexplore.planning.multi_disks import disks_mask
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
from mrexplore.strategies.network import hop_diameter, hop_distances

WINNER = "winner"
"""Message type of a winner declaration (robot id and target)."""
EQ2_UNITS = ("cells", "raw", "unit-free")
"""Readings of the units of eq. (2): ``cells`` (default), I_i and D_i in cells and
lambda_i in units of r_c cells, the length its eq. (1) measures distance in;
``raw``, the literal sum, lambda_i unscaled (at most 1 / (1 - alpha)); ``unit-free``,
I_i over the cells of the sensor disk, D_i over r_c, lambda_i unscaled."""
PAPER_R_C = 16.0
"""r_c of the paper's section 5, in cells: eq. (1)'s length scale when the run's
communication range is unlimited (an infinite r_c would make every nearness term 1)."""
POSITION = "position"
"""Message type of a sensing-and-mapping robot's position."""

# Robot states (§3.1, Fig. 3), plus the two waits of Fig. 5 made explicit.
SENSING = "sensing-mapping"
BIDDING = "bidding"
WAITING = "waiting"  # finished sensing inside a closing session: waits for the next
TRAVELLING = "travelling"
DONE = "done"  # no reachable frontier cell in its map


# ----------------------------------------------------------------------------- messages
# A bid is a bid item (the bidder, the frontier cell it bids for, ``B`` as float32); a
# winner declaration or a target re-announcement, and a sensing-and-mapping robot's
# position, are cell items (robot, cell).


# ----------------------------------------------------------------------------- equations
def nearness(distances: npt.ArrayLike, r_c: float, alpha: float) -> Any:
    """Eq. (1): ``lambda = sum_k alpha^k exp(-d_(k) / r_c)`` over the sorted distances.

    ``distances`` holds the travel distances (cells) to the other robots of the
    sub-network along its last axis, in any order (``inf`` = unreachable, adds 0);
    a 2-D array gives one value per row. ``r_c`` is the communication range (cells).

    >>> round(float(nearness([8.0, 4.0], 16.0, 0.5)), 6)  # e^-0.25 + 0.5 e^-0.5
    1.082066
    >>> float(nearness([], 16.0, 0.5))
    0.0
    """
    d = np.sort(np.asarray(distances, dtype=np.float64), axis=-1)
    fading = alpha ** np.arange(d.shape[-1], dtype=np.float64)
    with np.errstate(over="ignore"):
        terms = np.exp(-d / r_c)
    return np.sum(fading * terms, axis=-1)


def net_gain(
    information: npt.ArrayLike,
    distance: npt.ArrayLike,
    lam: npt.ArrayLike,
    w1: float,
    w2: float,
    w3: float,
) -> Any:
    """Eq. (2): ``g = w1 I - w2 D + w3 lambda`` (elementwise).

    >>> float(net_gain(20, 7.5, 1.0, 1.0, 1.0, 1.5))
    14.0
    """
    return (
        w1 * np.asarray(information, dtype=np.float64)
        - w2 * np.asarray(distance, dtype=np.float64)
        + w3 * np.asarray(lam, dtype=np.float64)
    )


def information_gains(
    belief: BeliefGrid,
    candidates: npt.NDArray[np.integer],
    sensor_range: float,
    others: Iterable[Cell],
) -> npt.NDArray[np.int64]:
    """``I_i`` of §3.2: unknown cells within ``sensor_range`` of each candidate, not
    counting those within ``sensor_range`` of any cell of ``others`` (positions of
    the other sensing-and-mapping robots, targets of the travelling ones)."""
    centres = list(others)
    exclude = disks_mask(belief.shape, centres, sensor_range) if centres else None
    return information_gain(belief, candidates, sensor_range, exclude=exclude)


# ----------------------------------------------------------------------------- the bid
@dataclass(frozen=True, slots=True)
class Bid:
    """The best frontier cell and its terms; ``value`` is ``B`` rounded to float32."""

    target: Cell
    value: float
    information: float
    distance: float
    nearness: float


def compute_bid(
    belief: BeliefGrid,
    position: Cell,
    sensing_positions: Sequence[Cell],
    travel_targets: Sequence[Cell],
    *,
    sensor_range: float,
    comm_range: float,
    alpha: float,
    w1: float,
    w2: float,
    w3: float,
    units: str = "cells",
    nearness_cells: Sequence[Cell] | None = None,
    own_fields: FieldWorkspace | None = None,
    other_fields: FieldWorkspace | None = None,
) -> tuple[Bid, npt.NDArray[np.float64]] | None:
    """§3.2: the bid ``B = max_i g_i`` of a robot at ``position`` over its frontier cells.

    ``sensing_positions`` and ``travel_targets`` describe the *other* robots of the
    sub-network; ``nearness_cells``, where eq. (1) measures to (default: the same
    robots). ``units`` puts the three terms of eq. (2) in one unit
    (:data:`EQ2_UNITS`). Returns the bid and the robot's distance field (for its
    path), or ``None`` when no frontier cell is reachable. Ties go to the first cell
    in raster order.

    The searches run in ``own_fields`` (the robot's field, then valid until that
    workspace's next search) and ``other_fields`` when given, in fresh arrays
    otherwise; the results are the same.
    """
    frontier = frontier_mask(belief)
    if not frontier.any():
        return None
    free = passable(belief)
    if own_fields is None:
        own = distance_field(free, position, targets=frontier)
    else:
        own = own_fields.search(free, position, targets=frontier)
    flat_index, rows, cols = raster_cells(frontier)
    at = own.reshape(-1)[flat_index]
    reachable = np.isfinite(at) & (at > 0)  # not the robot's own cell
    flat_index, rows, cols = flat_index[reachable], rows[reachable], cols[reachable]
    if rows.size == 0:
        return None
    cells = np.stack([rows, cols], axis=1)
    others = [*sensing_positions, *travel_targets]
    gain = information_gains(belief, cells, sensor_range, others)
    distance = own[rows, cols]
    near = others if nearness_cells is None else list(nearness_cells)
    if w3 != 0.0 and near:
        to_others = np.empty((rows.size, len(near)), dtype=np.float64)
        column_of: dict[Cell, int] = {}  # a cell met twice needs one field
        for k, cell in enumerate(near):
            if cell in column_of:
                to_others[:, k] = to_others[:, column_of[cell]]
                continue
            column_of[cell] = k
            if other_fields is None:
                candidates = np.zeros(frontier.shape, dtype=bool)
                candidates[rows, cols] = True
                to_others[:, k] = distance_field(free, cell, targets=candidates)[rows, cols]
            else:
                field = other_fields.search(free, cell, target_cells=flat_index)
                to_others[:, k] = field.reshape(-1)[flat_index]
                other_fields.release()
        lam = nearness(to_others, comm_range, alpha)
    else:
        lam = np.zeros(rows.size, dtype=np.float64)
    information = gain.astype(np.float64)
    if units == "raw":
        g = net_gain(information, distance, lam, w1, w2, w3)
    elif units == "unit-free":
        disk = len(disk_offsets(sensor_range))
        g = net_gain(information / disk, distance / comm_range, lam, w1, w2, w3)
    else:  # "cells": lambda in units of r_c cells
        g = net_gain(information, distance, lam * comm_range, w1, w2, w3)
    best = int(np.argmax(g))
    bid = Bid(
        target=(int(rows[best]), int(cols[best])),
        value=float(float32_on_wire(g[best])),
        information=float(gain[best]),
        distance=float(distance[best]),
        nearness=float(lam[best]),
    )
    return bid, own


# ----------------------------------------------------------------------------- timing
@dataclass(frozen=True, slots=True)
class SessionTiming:
    """The time parameters of §3.4 (Fig. 6), in ticks."""

    max_delay: int
    """``t_d``: the largest delay of a message inside the sub-network."""
    grace: int
    """``T_grace = t_d + 1`` (Proposition 1: ``T_grace > t_d``)."""
    bid: int
    """``t_bid = max(bid_time, T_grace)`` (``session_floor=delay``: ``max(bid_time, t_d)``)."""
    send_map_window: int
    """``T_win = t_bid - T_grace``."""
    declare_timeout: int
    """Ticks past ``t_bid`` a loser waits for a winner to declare."""


def session_timing(
    max_delay: int, bid_time: int, declare_timeout: int = 0, floor: str = "grace"
) -> SessionTiming:
    """§3.4's windows from the largest delay ``max_delay`` (ticks) of the sub-network;
    ``floor``: the least ``t_bid``, ``T_grace`` (Fig. 6's ``T_win >= 0``) or ``t_d``.

    >>> session_timing(1, 1)
    SessionTiming(max_delay=1, grace=2, bid=2, send_map_window=0, declare_timeout=4)
    >>> session_timing(1, 1, floor="delay").send_map_window  # the earlier reading
    -1
    >>> session_timing(0, 3).send_map_window  # a lone robot
    2
    """
    grace = max_delay + 1
    bid = max(bid_time, grace if floor == "grace" else max_delay)
    timeout = declare_timeout if declare_timeout > 0 else bid + 2 * max_delay
    return SessionTiming(max_delay, grace, bid, bid - grace, timeout)


@dataclass(slots=True)
class _HeardBid:
    value: float
    target: Cell
    begin: int  # estimated tick at which the bidder's session began


def _beats(value_a: float, robot_a: int, value_b: float, robot_b: int) -> bool:
    """Whether bid a is better than bid b: higher value, ties to the lower id."""
    return value_a > value_b or (value_a == value_b and robot_a < robot_b)


# ----------------------------------------------------------------------------- strategy
class ShengBidding(Strategy):
    """Sheng et al. 2006: every robot bids ``max_i g_i`` in sessions of its sub-network."""

    id = "sheng-bidding"
    summary = "Sheng et al. 2006: distributed bidding with a nearness measure"
    citation = (
        "W. Sheng, Q. Yang, J. Tan, N. Xi, Distributed multi-robot coordination in area "
        "exploration, Robotics and Autonomous Systems 54 (2006), §2-3"
    )
    default_sharing: ClassVar[str] = "sheng-sync"
    w1 = Param(
        1.0,
        "1/cell",
        "weight of the information gain I_i",
        "ω1",
        low=0,
        note="weight of the information gain `I_i` (§5)",
    )
    w2 = Param(
        1.0,
        "1/cell",
        "weight of the travel distance D_i",
        "ω2",
        low=0,
        note="weight of the travel distance `D_i` (§5)",
    )
    w3 = Param(
        1.5,
        "",
        "weight of the nearness measure lambda_i",
        "ω3",
        low=0,
        note='weight of the nearness `lambda_i` (§5; `0` = "without nearness")',
    )
    alpha = Param(
        0.5,
        "",
        "fading factor of eq. (1)",
        "α",
        low=0,
        high=1,
        note=(
            'fading factor of eq. (1), in [0, 1]; the paper says only "positive, smaller than 1"'
        ),
    )
    nearness_over = Param(
        "subnetwork",
        "",
        "robots eq. (1) measures to: subnetwork (its n_k) or known (all last heard of)",
        choices=("subnetwork", "known"),
        note=(
            "the robots eq. (1) measures to: the `n_k` of the sub-network, or "
            "`known`, every robot last heard of (Fig. 2's example)"
        ),
    )
    eq2_units = Param(
        "cells",
        "",
        "units of eq. (2)'s terms: cells, raw or unit-free",
        choices=EQ2_UNITS,
        note=(
            "units of eq. (2)'s terms: `cells` (`lambda_i` in units of `r_c` "
            "cells), `raw` (the literal sum) or `unit-free` (see Interpretations)"
        ),
    )
    comm_range = Param(
        0.0,
        "cells",
        "r_c of eq. (1); 0 = the run's --comm-range (16 if unlimited)",
        "r_c",
        low=0,
        note=(
            "communication range in eq. (1); 0 = the run's `--comm-range`, or 16 "
            "(section 5) when unlimited; `inf` makes every term 1: no pull"
        ),
    )
    bid_time = Param(
        1,
        "ticks",
        "bidding time (at least T_grace is used)",
        "t_bid",
        low=1,
        note=("bidding time (paper: 1.5 s); the session lasts `max(bid_time, T_grace)`"),
    )
    session_floor = Param(
        "grace",
        "",
        "least t_bid: grace (T_grace, so T_win >= 0) or delay (t_d)",
        choices=("grace", "delay"),
        note=(
            "the least `t_bid`: `grace` (`T_grace`, so `T_win >= 0`) or `delay` "
            "(`t_d`, the earlier reading; `T_win` can be -1)"
        ),
    )
    declare_timeout = Param(
        0,
        "ticks",
        "wait for a winner past t_bid at most this long; 0 = t_bid + 2 t_d",
        low=0,
        note=("longest wait past `t_bid` for a winner's declaration; 0 = `t_bid + 2 t_d`"),
    )
    replan_on_target_explored = Param(
        False, "", "stop and bid again when the target is no longer a frontier cell"
    )

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.state = SENSING
        # What this robot knows of the others, from messages only.
        self.positions: dict[int, Cell] = {}  # sensing-and-mapping robots
        self.targets: dict[int, Cell] = {}  # travelling robots
        self.bids: dict[int, _HeardBid] = {}  # bids of the current session
        # Its own session.
        self.my_bid: Bid | None = None
        self.session_start = -1
        self.expiry = -1
        self.timing = self._session_timing(0)
        self.wait_deadline = -1
        self.cells_seen = 0
        self.previous_subnetwork: frozenset[int] | None = None
        self._topology: tuple[frozenset[tuple[int, int]], int, dict[int, int]] | None = None

    # ------------------------------------------------------------------ decide
    def decide(self, view: RobotView) -> Decision:
        decision = self._step(view)
        if decision.replans:  # the simulator restarts its count of new cells
            self.cells_seen = 0
        return decision

    def _step(self, view: RobotView) -> Decision:
        out: list[Message] = []
        declared, new_bidder = self._absorb(view)
        info_changed = view.new_cells > self.cells_seen
        self.cells_seen = view.new_cells
        announced = False
        previous = self.previous_subnetwork
        self.previous_subnetwork = view.subnetwork
        if previous is not None and view.subnetwork - previous:
            out.append(self._announce(view))  # tell the robots that just joined
            announced = True

        if self.state == TRAVELLING:
            if view.goal is not None:
                explored = self.replan_on_target_explored and not frontier_at(
                    view.belief, *view.goal
                )
                if not explored:
                    return Decision(messages=out)
                decision = self._sense(view, out, announced)
                if decision.goal is None:
                    decision.idle = True
                return decision
            return self._sense(view, out, announced)
        if self.state == SENSING:
            return self._sense(view, out, announced)
        if self.state == DONE:
            if info_changed:
                return self._sense(view, out, announced=True)
            return Decision(messages=out)
        if self.state == WAITING:
            if declared or not self._live_bids(view) or view.tick >= self.wait_deadline:
                return self._start_session(view, out)
            return Decision(messages=out)
        # BIDDING
        if declared:
            return self._start_session(view, out)
        if (
            (info_changed or new_bidder)
            and view.tick - self.session_start <= self.timing.send_map_window
            and view.tick > self.session_start
        ):
            rebid = self._bid(view)
            if rebid is None:
                self.state = DONE
                return Decision(messages=out)
            self.my_bid = rebid
            out.append(self._bid_message(rebid))
        elif announced:  # the newcomers join the session, the others keep the bid live
            assert self.my_bid is not None
            out.append(self._bid_message(self.my_bid))
        if view.tick < self.expiry:
            return Decision(messages=out)
        assert self.my_bid is not None
        better = [
            robot
            for robot, heard in self._live_bids(view).items()
            if _beats(heard.value, robot, self.my_bid.value, self.robot_id)
        ]
        if not better:
            return self._win(view, out)
        if view.tick >= self.expiry + self.timing.declare_timeout:
            for robot in better:  # they never declared: forget them, bid again
                del self.bids[robot]
            return self._start_session(view, out)
        return Decision(messages=out)

    # ------------------------------------------------------------------ messages in
    def _absorb(self, view: RobotView) -> tuple[bool, bool]:
        """Update the tables from the inbox; return (a winner declared, a new bidder)."""
        declared = new_bidder = False
        bids = [m.payload for m in view.inbox if m.type == BID and isinstance(m.payload, BidItem)]
        bidding = {bid.robot for bid in bids}
        for message in view.inbox:
            payload = message.payload
            if message.type == POSITION and isinstance(payload, CellItem):
                self.positions[payload.robot] = payload.cell
                self.targets.pop(payload.robot, None)
                if payload.robot not in bidding:  # not bidding: its earlier bid is over
                    self.bids.pop(payload.robot, None)
            elif message.type in (WINNER, TARGET) and isinstance(payload, CellItem):
                self.targets[payload.robot] = payload.cell
                self.positions.pop(payload.robot, None)
                if message.type == WINNER:
                    declared = True
                    self.bids.clear()  # the session is over; its losers bid again
        for bid in bids:
            heard = self.bids.get(bid.robot)
            if heard is None:
                new_bidder = True
                begin = view.tick - view.comm_latency * self._hops(view).get(bid.robot, 1)
                self.bids[bid.robot] = _HeardBid(bid.value, bid.cell, begin)
            else:
                heard.value, heard.target = bid.value, bid.cell
        return declared, new_bidder

    def _hops(self, view: RobotView) -> dict[int, int]:
        if self._topology is None or self._topology[0] != view.links:
            hops = hop_distances(self.robot_id, view.links)
            diameter = hop_diameter(view.subnetwork, view.links) if len(hops) > 1 else 0
            self._topology = (view.links, diameter, hops)
        return self._topology[2]

    def _current_timing(self, view: RobotView) -> SessionTiming:
        self._hops(view)
        assert self._topology is not None
        max_delay = view.comm_latency * self._topology[1] if len(view.subnetwork) > 1 else 0
        return self._session_timing(max_delay)

    def _session_timing(self, max_delay: int) -> SessionTiming:
        p = self.p
        floor = str(p["session_floor"])
        return session_timing(max_delay, int(p["bid_time"]), int(p["declare_timeout"]), floor)

    def _live_bids(self, view: RobotView) -> dict[int, _HeardBid]:
        """Bids of the current session from robots still in the sub-network."""
        for robot in [r for r in self.bids if r not in view.subnetwork]:
            del self.bids[robot]
        return self.bids

    # ------------------------------------------------------------------ messages out
    def _announce(self, view: RobotView) -> Message:
        if self.state == TRAVELLING and view.goal is not None:
            return item_message(
                TARGET, self.robot_id, BROADCAST, CellItem(self.robot_id, view.goal)
            )
        return self._position_message(view)

    def _position_message(self, view: RobotView) -> Message:
        position = CellItem(self.robot_id, view.position)
        return item_message(POSITION, self.robot_id, BROADCAST, position)

    def _bid_message(self, bid: Bid) -> Message:
        payload = BidItem(self.robot_id, bid.target, bid.value)
        return item_message(BID, self.robot_id, BROADCAST, payload)

    # ------------------------------------------------------------------ states
    def _sense(self, view: RobotView, out: list[Message], announced: bool) -> Decision:
        """Sensing and mapping is over (the simulator sensed): announce, then bid or wait."""
        self.state = SENSING
        if not announced:
            out.append(self._position_message(view))
        self.timing = self._current_timing(view)
        live = self._live_bids(view)
        if live:
            begin = max(live.items(), key=lambda item: (item[1].value, -item[0]))[1].begin
            if view.tick - begin > self.timing.send_map_window:  # the session is closing
                self.state = WAITING
                self.wait_deadline = view.tick + self.timing.bid + self.timing.declare_timeout
                return Decision(messages=out)
        return self._start_session(view, out)

    def _start_session(self, view: RobotView, out: list[Message]) -> Decision:
        self.timing = self._current_timing(view)
        bid = self._bid(view)
        if bid is None:
            self.state = DONE
            self.my_bid = None
            return Decision(messages=out)
        self.state = BIDDING
        self.my_bid = bid
        self.session_start = view.tick
        self.expiry = view.tick + self.timing.bid
        out.append(self._bid_message(bid))
        return Decision(messages=out)

    def _r_c(self, view: RobotView) -> float:
        """r_c of eq. (1): the parameter, else the run's range, else the paper's 16."""
        given = self.comm_range
        if given > 0:
            return given
        return view.comm_range if math.isfinite(view.comm_range) else PAPER_R_C

    def _bid(self, view: RobotView) -> Bid | None:
        result = self._evaluate(view)
        return None if result is None else result[0]

    def _evaluate(self, view: RobotView) -> tuple[Bid, npt.NDArray[np.float64]] | None:
        others = view.subnetwork - {self.robot_id}
        near: list[Cell] | None = None
        if self.nearness_over == "known":  # eq. (1) over every robot last heard of
            known = {**self.positions, **self.targets}
            near = [cell for robot, cell in sorted(known.items()) if robot != self.robot_id]
        return compute_bid(
            view.belief,
            view.position,
            [cell for robot, cell in sorted(self.positions.items()) if robot in others],
            [cell for robot, cell in sorted(self.targets.items()) if robot in others],
            sensor_range=view.sensor_range,
            comm_range=self._r_c(view),
            alpha=self.alpha,
            w1=self.w1,
            w2=self.w2,
            w3=self.w3,
            units=self.eq2_units,
            nearness_cells=near,
            own_fields=shared_workspace("sheng-bidding own"),
            other_fields=shared_workspace("sheng-bidding others"),
        )

    def _path_to(self, view: RobotView, goal: Cell) -> npt.NDArray[np.int32] | None:
        """:func:`~mrexplore.planning.path_to` over the belief, in the bid's buffers."""
        width = view.belief.shape[1]
        index = np.array([goal[0] * width + goal[1]], dtype=np.int64)
        fields = shared_workspace("sheng-bidding own")
        field = fields.search(passable(view.belief), view.position, target_cells=index)
        return extract_path(field, goal) if np.isfinite(field[goal]) else None

    def _win(self, view: RobotView, out: list[Message]) -> Decision:
        """No better bid: declare (Fig. 5 ``broadcast(my_ID)``) and travel."""
        assert self.my_bid is not None
        goal = self.my_bid.target
        path = None
        if goal != view.position and frontier_at(view.belief, *goal):
            path = self._path_to(view, goal)
        if path is None:  # the target went stale during the session: recompute
            result = self._evaluate(view)
            if result is None:
                self.state = DONE
                return Decision(messages=out)
            self.my_bid, field = result
            goal = self.my_bid.target
            path = extract_path(field, goal)
        self.state = TRAVELLING
        self.bids.clear()
        declaration = CellItem(self.robot_id, goal)
        out.append(item_message(WINNER, self.robot_id, BROADCAST, declaration))
        return Decision(goal=goal, path=path, messages=out)
