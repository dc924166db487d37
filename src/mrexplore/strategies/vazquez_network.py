"""Vazquez & Malcolm: decentralised exploration that keeps a mobile ad hoc network.

J. Vazquez, C. Malcolm, "Distributed multirobot exploration maintaining a mobile
network", Proc. 2nd IEEE International Conference on Intelligent Systems (IS'04),
Varna, 2004, vol. 3, pp. 113-118.

What is implemented (paper section -> code):

* §3: every robot broadcasts its position and its current heading (the frontier it
  selected) to its sub-network (messages ``position`` every ``position_period``
  ticks and ``target`` on every new choice); maps travel through the run's
  map-sharing mechanism ("sensorial information"; by default ``broadcast``, §4:
  "The information arrives by multi hops to all the members of the team", with no
  exchange of whole maps when sub-networks join). "Based on
  this periodic information the robots are able to identify the topology": here
  the topology of the sub-network is ``view.links``.
* §3.1.1 bridge detection: the graph of the sub-network (vertices = robots,
  edges = links) and its bridges, ``networkx.bridges`` (:func:`network_roles`).
* §3.1.2 constraints: ``g(q_i, q_k) = (x_i - x_k)^2 + (y_i - y_k)^2`` (:func:`g`),
  signal strength decaying with the square of distance, ``1 / g``
  (:func:`signal_strength`); the link breaks beyond ``d3``; the comfort zone
  ``d1 < distance < d2`` with ``d2 = 0.9 d3`` and ``d1 = 3/2`` of the sensor
  diameter (:func:`comfort_distances`, :func:`in_comfort_zone`).
* §3.2 exploration (after Simmons et al. 2000): frontier cells; the travel cost
  ``C(f)`` of every frontier from one flood fill (:func:`~mrexplore.planning.distance_field`);
  the utility ``U(f)`` = unknown cells within the sensor range of ``f``, lessened
  "if there are any robots near that destination": cells within ``R`` of other
  robots' announced destinations and reported positions are not counted
  (:func:`utility`, :func:`exclusion_mask`); ``U`` in ticks of sensing,
  ``U / (2R + 1)``, so that it compares with ``C`` in ticks; each robot takes the
  frontier of best ``U(f) - w C(f)`` (:func:`net_value`) for itself
  (decentralised); the path walks the cost field downhill
  (:func:`~mrexplore.planning.extract_path`). A frontier given up for a constraint
  is left to the others ("the frontier may be selected by another robot").
* §3.1 and §3.3, Figure 2, behaviour selection (:func:`select_behaviour`). A bridge
  neighbour constrains only while its signal strength is below ``1 / d2^2`` (it is
  farther than ``d2``; §3.1: "only if they constitute a solitary bridge connection
  ... and if the signal strength ... falls below a threshold"), and for
  ``constraint_memory`` ticks after the two are back within ``d2`` (§3.3.1: "once
  the robot achieves the connection status it constrains future plans").

  - **achieve-connectivity** when a constraining neighbour is farther than ``d2``
    or was lost altogether: search frontiers inside the comfort zone, else move
    towards the neighbour (§3.3.1), or back to where it was last heard of;
  - **avoid-collision** when a robot is closer than the collision distance ``d1``:
    robots that close are static obstacles in the planning space (the paper's
    potential-field planner after Warren 1990, §3.3.2); a moving robot re-plans
    its path to the same goal when one of them stands on the path ahead
    (:func:`route_around`);
  - **maintain-connectivity** otherwise: explore as in §3.2 ("otherwise the
    algorithm is executed as explained in Section 3.2").

  A change of behaviour makes the robot re-evaluate its plan (Figure 2: "when a
  change in behaviour is detected the robot will reevaluate its current plan"): a
  new plan, but for a change into or out of avoid-collision, which re-evaluates the
  path to the current goal (§3.3.2: "The avoid-collision behaviour causes a
  re-evaluation of paths to the current goal"; the section's rule for its behaviour
  refines the caption's general one; ``replan_on_behaviour=any`` reads the caption
  alone); otherwise it plans on arriving (``P(x, y) = f(x, y)``), when blocked, or by the
  re-planning rules of :data:`REPLAN_PARAMS` (re-planning when the frontier has
  been explored is off by default: the paper re-plans on arrival).

Parameters (rendered from ``VazquezNetwork.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin vazquez-network

=============================  ======  =================  =====  ===================================
name                           symbol  default            unit   meaning
=============================  ======  =================  =====  ===================================
``comm_range``                 d3      0.0                cells  communication range; 0 = the run's
                                                                 `--comm-range` (cells); inf = no
                                                                 constraints
``d2_fraction``                d2      0.9                -      `d2 = 0.9 d3` (paper)
``d1_sensor_diameters``        d1      1.5                -      `d1 = 1.5 x 2 R` (paper: 3/2 of the
                                                                 sensor diameter)
``d1_max_fraction``            -       0.75               -      cap `d1 <= 0.75 d2` so the comfort
                                                                 zone is never empty
``cost_weight``                w       1.0                -      weight of travel cost in `U - w C`
``line_of_sight``              -       false              -      count only unknown cells in line of
                                                                 sight (in the belief) in `U`
``position_period``            k       2                  ticks  broadcast the position every k
                                                                 ticks
``follow_distance``            -       2.0                cells  how close a `convoy` follower, or a
                                                                 robot returning to a lost
                                                                 neighbour, gets
``reconnect_timeout``          -       0                  ticks  give up going back to a lost
                                                                 neighbour; 0 = `4 d3 / speed`, at
                                                                 least 50
``zone_includes_targets``      -       false              -      also require the comfort zone
                                                                 around each constraining
                                                                 neighbour's announced destination
                                                                 (ours)
``constraint_memory``          -       0                  ticks  keep a neighbour constraining after
                                                                 the pair is back within `d2`
                                                                 (`always`: after its link stopped
                                                                 being a bridge); 0 = `memory_ranges
                                                                 x d3 / speed`, at least 10
``memory_ranges``              -       1.0                d3     the default memory in ranges of
                                                                 travel
``resolve_conflicts``          -       true               -      re-plan when a lower id announces a
                                                                 destination within `R` of one's own
``abort_memory``               -       0                  ticks  leave a frontier given up for a
                                                                 constraint to the others; 0 = `4 d3
                                                                 / speed`, at least 50
``constrain_bridges``          -       stretched          -      a bridge neighbour constrains when
                                                                 beyond `d2` (`stretched`) or
                                                                 `always`
``broken_bridge_frontier``     -       lower-keeps        -      a bridge link broke: both go back,
                                                                 the lower id keeps its frontier and
                                                                 resumes it once reconnected, the
                                                                 higher leaves its own to the
                                                                 others; `both-leave`: both leave
                                                                 theirs
``zone_between_pair``          -       true               -      a stretched pair searches within
                                                                 `d2` of both robots
``no_frontier_rule``           -       approach           -      no frontier in the zone: `approach`
                                                                 the stretched neighbour (else the
                                                                 end nearer the root explores and
                                                                 the others go with it) or `convoy`
``discount_around``            -       both               -      `U` leaves out cells near other
                                                                 robots' `destinations`,
                                                                 `positions`, or `both`
``utility_unit``               -       ticks              -      `U` as `U / (2R + 1)` ticks of
                                                                 sensing, or `cells`
``replan_on_behaviour``        -       reroute-collision  -      re-plan on any change of behaviour
                                                                 but into or out of avoid-collision,
                                                                 which re-routes to the current goal
                                                                 (§3.3.2); `any`: a new plan on
                                                                 every change; `connectivity`: only
                                                                 into and out of achieve-
                                                                 connectivity
``replan_on_target_explored``  -       false              -      re-plan when the goal is no longer
                                                                 a frontier cell
ReplanRules                    -                                 shared: ``strategies.base``
=============================  ======  =================  =====  ===================================

.. params:end

Messages (sizes from :mod:`mrexplore.comm.bytes`, each a broadcast to the sub-network):

============  ==========================================  ==================================
type          payload                                     bytes
============  ==========================================  ==================================
``position``  robot, row, col (:class:`PositionPayload`)  ``HEADER_BYTES + POSITION_BYTES``
                                                          = 7 + 6 = 13
``target``    robot, row, col of the selected frontier,   ``HEADER_BYTES + TARGET_BYTES``
              or none (row = col = 0xFFFF on the wire)    = 7 + 6 = 13
              (:class:`TargetPayload`)
============  ==========================================  ==================================

``position`` goes out every ``position_period`` ticks and at once when robots join
the sub-network; ``target`` on every change of destination and again when robots
join. A lone robot transmits nothing (the simulator drops broadcasts to nobody).

Interpretations (where the paper is silent or does not fit a grid world):

* **g and its thresholds.** The paper defines ``g`` as the *squared* distance but
  compares it with ``d1, d2, d3``, which are distances (ranges in metres,
  ``d2 = 0.9 d3``). We compare ``g`` with the squared thresholds:
  ``d1^2 < g < d2^2``; the link is gone when ``g > d3^2``.
* **Signal strength** is not part of a robot's view. As the paper assumes no
  interference by walls and ``1/d^2`` decay, a robot computes it as ``1 / g`` from
  the positions it has heard; "below the threshold" means ``1 / g < 1 / d2^2``, i.e.
  farther than ``d2``.
* **d3 is the robot's radio range.** By default (``comm_range = 0``) it is the
  run's ``--comm-range`` in cells, which every robot knows as the specification of
  its own radio (:attr:`RobotView.comm_range`); ``--set comm_range=R`` plans with a
  different assumed range. With an unlimited range the network cannot break, so
  bridges impose nothing and the method is decentralised Simmons exploration with
  shared destinations and collision avoidance.
* **d1 = 3/2 of the sensor diameter** assumes a sensor small against the radio
  (Khepera: 45 cm against 1-2 m, ``d1 / d2 = 0.675 / 0.9 = 0.75`` at the shortest
  range). On grids the sensor is often large against the radio (``R = 8``,
  ``d3 = 25``: ``d1 = 24 > d2 = 22.5``, an empty comfort zone), so ``d1`` is capped
  at ``d1_max_fraction x d2`` with the paper's own ratio 0.75 as default.
* **Collision distance** = ``d1`` (the paper calls ``d1`` the collision constraint).
  Robots closer than ``d1`` at their last reported cells are obstacles when the
  robot searches for a frontier or a path, unless they box it in (then it plans
  as if they were gone). Re-routing an ongoing path happens when such a robot
  stands on the next ``d1`` cells of it; if they cut the goal off, the robot keeps
  its path (the simulator still keeps two robots out of one cell).
* **Which neighbours constrain.** §3.1 sets two conditions: the link is a bridge
  *and* the signal is below the threshold. ``constrain_bridges=stretched`` (default)
  reads them together: a bridge neighbour constrains while it is farther than
  ``d2``, and for ``constraint_memory`` ticks after the pair is back within ``d2``
  or reconnected (§3.3.1 "constrains future plans"). ``always`` (the earlier
  reading) constrains every bridge neighbour all the time, and keeps a neighbour
  constraining for ``constraint_memory`` ticks after its link stopped being a
  bridge. The memory is not given in the paper; by default it lasts the time to
  travel one range (``memory_ranges = 1``), the scale at which the pair could be
  stretched again.
* **The constrained search.** For a constrained robot, the frontier search and
  its paths are limited to cells within ``d2`` of every constraining neighbour's
  reported position (the comfort zone as a configuration space, Figure 1), and
  the chosen frontier must lie in each neighbour's comfort zone (beyond ``d1``).
  ``zone_includes_targets`` (ours, off by default) also requires the comfort zone
  of each neighbour's announced destination. While the pair is stretched the search
  is "constrained to the comfort zone between the pair of robots" (§3.3.1): the
  cells within ``d2`` of both (``zone_between_pair``, default); searching around the
  other robot only (the earlier reading) lets the two take the frontiers near each
  other and swap sides forever when their last frontiers lie farther apart than
  ``d3``.
* **No frontier inside the comfort zone.** §3.3.1: "When no frontier cells are
  found the robot computes a path to the current position of the other robot in
  the bridge connection" (``no_frontier_rule=approach``, default): towards the
  farthest constraining neighbour beyond ``d2``, stopping in mid-zone
  ``(d1 + d2) / 2``. When every constraining neighbour is within ``d2`` (only the
  memory, or ``always``), the paper gives no rule; the robot nearer the root of the
  sub-network (:func:`orient`) explores the best frontier it reaches without leaving
  ``d2`` of the others (else its best frontier, the path cut there), and the others
  go with it (to mid-zone from it). (Choosing the best frontier first and cutting
  the path after left a chain of six, every link a bridge under ``always``, holding
  forever: every end's best frontier lay beyond ``d2``, measured.) ``convoy`` (the earlier
  reading) orients each constraint towards the lowest id of the sub-network (the
  *root*, by hop distance, then id; :func:`orient`): the endpoint nearer the root
  *leads*. A
  robot with no frontier in its zone

  - moves towards a leading neighbour that is farther than ``d2``
    (achieve-connectivity), stopping in mid-zone ``(d1 + d2) / 2``;
  - else holds if a following neighbour is farther than ``d2`` (it comes back);
  - else follows its leader (to within ``follow_distance`` of it);
  - else (it leads all its constraints) heads for its best frontier anyway, but
    only as far as its path stays within ``d2`` of every follower; if it cannot
    move it holds until the next position update.
* **Who turns back.** "The pair of robots that are out of the comfort zone in a bridge
  connection are encouraged to return" (§3.3.1). When a pair becomes stretched, the
  robot with the lower id keeps the frontier it is heading for and the other one
  returns (searches the zone between them, or moves towards it). If both turned at
  once, two robots whose frontiers lie farther apart than ``d3`` swapped frontiers
  forever. The same rule holds for every change of behaviour that makes a robot
  choose again (under ``replan_on_behaviour=any`` also into and out of
  avoid-collision): the robot whose id is lower than that of every partner
  constraining it keeps its frontier, the others choose again (all choosing at once
  chased each other's comfort zones or cycled at ``d1`` forever: the chase and the
  chatter, measured).
* **Aborted frontiers.** A robot that gives up its frontier because a constraint
  starts (into achieve-connectivity, or a neighbour lost) or because a robot blocks
  its way (the simulator stopped it: avoid-collision's constraint) leaves that frontier,
  and the cells within ``R`` of it, to the others for ``abort_memory`` ticks (§3.2:
  "robots may abort the plan to explore a frontier due to constraints, in such
  case the frontier may be selected by another robot"). Without it two
  constrained robots can pick, abort and pick again the same two frontiers
  forever (a livelock we observed with every combination of the rules above), and
  two robots that took each other's side of a corridor keep blocking each other.
* **Disconnection.** A robot whose former direct neighbour is no longer in its
  sub-network (their link was a bridge and broke) switches to achieve-connectivity
  and goes back to that neighbour's last reported cell, reconnecting on the way if
  the neighbour comes back too. It gives up (and explores) when it gets there
  without reconnecting or after ``reconnect_timeout`` ticks (a failed robot never
  answers). Robots that lost a far part of the team through someone else's bridge
  go on exploring: only the pair of the broken link returns (§3.3.1 "the pair of
  robots ... are encouraged to return"). A broken bridge is a stretched one seen
  late (the positions heard are up to ``k`` ticks plus a hop old, and ``d3 - d2``
  is a tenth of the range), so the rule of a stretched pair, the lower id keeps its
  frontier, applies to it too (``broken_bridge_frontier=lower-keeps``): both go back,
  the higher id leaves its frontier to the others, the lower resumes its own once
  reconnected. If both left theirs (``both-leave``, the earlier reading), two robots
  whose frontiers lie farther apart than ``d3`` took each other's on reconnecting,
  crossed and broke the link again, forever (measured under
  ``replan_on_behaviour=connectivity`` and ``reroute-collision``). A frontier is kept
  once: if the link breaks again on the way to it, the lower id leaves it too (else
  three robots in a chain whose links flicker at the range took the same frontiers
  back every tick, measured). Keeping it again for progress only (a shorter path
  left than ever before) also ends the flicker, but slowly: 10 robots at 1 m on the
  large office took 5345 and 4629 ticks (seeds 3, 5) against 2103 and 3025 when kept
  once, measured; it would end the one swap that keeping once leaves
  (``utility_unit=cells``, 2 robots). (Only the higher one going back, the lower
  waiting, would split a chain whose middle robot has the highest id: it cannot
  return to both ends at once, measured.)
* **Utility reduction.** "The utility expected by a robot considering moving to a
  particular frontier is lessened if there are any robots near that destination":
  unknown cells within ``R`` of another robot's announced destination (Simmons et
  al.) and of another robot's reported cell (the sentence's "any robots near") are
  not counted (``discount_around=both``; ``destinations`` is the earlier reading).
  Robots that follow, approach, return or hold announce "no destination".
* **Scale of U and C.** ``U`` counts cells and ``C`` is a path length. To compare
  them in one unit, ``U`` is read as the ticks a moving sensor needs to sense that
  many new cells, ``U / (2R + 1)`` (a step senses at most a strip ``2R + 1`` cells
  wide); ``w = 1`` then trades a tick of sensing for a tick of travel.
  ``utility_unit=cells`` (the earlier reading) trades one unknown cell for one cell
  of travel, which sends robots to large unknown areas far away.
* **Simultaneous choices.** Each robot chooses for itself, so two robots planning
  in the same tick can pick the same frontier before they hear of each other.
  With ``resolve_conflicts`` the robot with the higher id re-plans when a lower id
  announces a destination within ``R`` of its own (§3.2: an aborted frontier "may
  be selected by another robot").
* **k.** The paper broadcasts every half second, in which a Khepera covers one to
  two body lengths; at one cell per tick we broadcast positions every ``k = 2``
  ticks.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import networkx as nx
import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, TARGET_BYTES, fixed_size
from mrexplore.comm.messages import TARGET, CellItem, Message, item_message
from mrexplore.grid.occupancy import BeliefGrid, BoolGrid
from mrexplore.planning import (
    extract_path,
    frontier_mask,
    information_gain,
    path_to,
)
from mrexplore.planning.multi_disks import disks_mask
from mrexplore.planning.multi_fields import (
    FieldWorkspace,
    raster_cells,
    shared_workspace,
)
from mrexplore.strategies.base import (
    Cell,
    Decision,
    Param,
    Path,
    ReplanRules,
    RobotView,
    Strategy,
    frontier_at,
    passable,
    reachable_frontier_cells,
)

POSITION = "position"
"""Message type of the periodic position broadcast."""

ACHIEVE_CONNECTIVITY = "achieve-connectivity"
MAINTAIN_CONNECTIVITY = "maintain-connectivity"
AVOID_COLLISION = "avoid-collision"

# What the robot's current goal is (for re-planning rules and announcements).
EXPLORE = "explore"  # a frontier chosen by U - w C (inside the comfort zone if constrained)
LEAD = "lead"  # towards a frontier, path cut to keep the followers within d2
FOLLOW = "follow"  # towards the bridge neighbour on the root side
APPROACH = "approach"  # achieve-connectivity: towards a bridge neighbour beyond d2
RETURN = "return"  # disconnected: towards a lost neighbour's last known position
HOLD = "hold"  # staying put until the next position update

_FOREVER = 2**62
"""Ticks of a default duration that ``4 d3`` makes endless (an infinite ``d3``)."""


PositionPayload = CellItem
"""A robot and its cell (``POSITION_BYTES``: robot, row, col)."""


@dataclass(frozen=True, slots=True)
class TargetPayload:
    """A robot's selected frontier, or ``None`` for none (``TARGET_BYTES``)."""

    robot: int
    goal: Cell | None


@dataclass(frozen=True)
class NetworkRoles:
    """A robot's place in its sub-network's communication graph (§3.1.1).

    ``bridges``: its neighbours over bridge links; ``neighbours``: every direct
    neighbour; ``hops``: hop distance of every robot of the sub-network from the
    root, its lowest id.
    """

    bridges: frozenset[int]
    neighbours: frozenset[int]
    hops: Mapping[int, int]


# ---------------------------------------------------------------------- equations
def g(q_i: Sequence[float], q_k: Sequence[float]) -> float:
    """§3.1.2: ``g(q_i, q_k) = (x_i - x_k)^2 + (y_i - y_k)^2`` (cells squared).

    >>> g((0, 0), (3, 4))
    25.0
    """
    return float((q_i[0] - q_k[0]) ** 2 + (q_i[1] - q_k[1]) ** 2)


def signal_strength(q_i: Sequence[float], q_k: Sequence[float]) -> float:
    """§3.1.2: signal strength decays with the square of distance, ``1 / g`` (inf at 0).

    >>> signal_strength((0, 0), (3, 4))
    0.04
    """
    squared = g(q_i, q_k)
    return math.inf if squared == 0 else 1.0 / squared


def comfort_distances(
    comm_range: float,
    sensor_range: float,
    *,
    d2_fraction: float = 0.9,
    d1_sensor_diameters: float = 1.5,
    d1_max_fraction: float = 0.75,
) -> tuple[float, float, float]:
    """``(d1, d2, d3)`` in cells: §3.1.2 with ``d1`` capped at ``d1_max_fraction x d2``.

    ``d3`` is the communication range, ``d2 = d2_fraction x d3`` and
    ``d1 = d1_sensor_diameters x 2 x sensor_range``.

    >>> comfort_distances(100.0, 8.0)
    (24.0, 90.0, 100.0)
    >>> comfort_distances(25.0, 8.0)  # 24 > 0.75 x 22.5: capped
    (16.875, 22.5, 25.0)
    >>> comfort_distances(math.inf, 8.0)
    (24.0, inf, inf)
    """
    d3 = float(comm_range)
    d2 = d2_fraction * d3
    d1 = d1_sensor_diameters * 2.0 * float(sensor_range)
    if math.isfinite(d2):
        d1 = min(d1, d1_max_fraction * d2)
    return d1, d2, d3


def in_comfort_zone(
    cells: npt.NDArray[np.integer], anchor: Sequence[float], d1: float, d2: float
) -> npt.NDArray[np.bool_]:
    """§3.1.2: which ``(K, 2)`` cells lie in the comfort zone ``d1^2 < g < d2^2`` of ``anchor``.

    >>> in_comfort_zone(np.array([[0, 1], [0, 3], [0, 6]]), (0, 0), 2.0, 5.0).tolist()
    [False, True, False]
    """
    squared = (cells[:, 0] - anchor[0]) ** 2 + (cells[:, 1] - anchor[1]) ** 2
    return np.asarray((squared > d1 * d1) & (squared < d2 * d2))


def exclusion_mask(
    shape: tuple[int, int], centres: Iterable[Cell], radius: float
) -> BoolGrid | None:
    """Cells within ``radius`` of any centre (the area other robots will sense), or None.

    >>> exclusion_mask((3, 4), [(1, 1)], 1.0).astype(int).tolist()
    [[0, 1, 0, 0], [1, 1, 1, 0], [0, 1, 0, 0]]
    """
    cells = list(centres)
    return disks_mask(shape, cells, radius) if cells else None


def utility(
    belief: BeliefGrid,
    candidates: npt.NDArray[np.integer],
    sensor_range: float,
    other_destinations: Iterable[Cell] = (),
    *,
    line_of_sight: bool = False,
) -> npt.NDArray[np.int64]:
    """§3.2: ``U(f)``, unknown cells within ``sensor_range`` of each frontier ``f``,
    not counting cells within ``sensor_range`` of another robot's destination.

    >>> belief = np.full((1, 7), -1, dtype=np.int8)
    >>> belief[0, 0] = 0
    >>> utility(belief, np.array([[0, 0]]), 2.0).tolist()  # cells 1, 2 unknown
    [2]
    >>> utility(belief, np.array([[0, 0]]), 2.0, [(0, 4)]).tolist()  # cell 2 excluded
    [1]
    """
    exclude = exclusion_mask(belief.shape, other_destinations, sensor_range)
    return information_gain(
        belief, candidates, sensor_range, line_of_sight=line_of_sight, exclude=exclude
    )


def net_value(
    gain: npt.NDArray[np.number], cost: npt.NDArray[np.floating], cost_weight: float
) -> npt.NDArray[np.float64]:
    """§3.2 after Simmons: ``U(f) - w C(f)`` (``U`` in cells or ticks, ``C`` in cells).

    >>> net_value(np.array([10, 30]), np.array([4.0, 25.0]), 1.0).tolist()
    [6.0, 5.0]
    """
    return np.asarray(gain, dtype=np.float64) - cost_weight * np.asarray(cost, dtype=np.float64)


def select_behaviour(
    position: Cell,
    bridge_positions: Iterable[Cell],
    other_positions: Iterable[Cell],
    *,
    d2: float,
    collision_distance: float,
    disconnected: bool = False,
) -> str:
    """Figure 2: the behaviour for the current network conditions.

    achieve-connectivity if a bridge neighbour was lost (``disconnected``) or its
    signal strength ``1 / g`` is below ``1 / d2^2``; else avoid-collision if a robot
    is closer than ``collision_distance``; else maintain-connectivity.

    >>> select_behaviour((0, 0), [(0, 10)], [(0, 10)], d2=9.0, collision_distance=3.0)
    'achieve-connectivity'
    >>> select_behaviour((0, 0), [(0, 8)], [(0, 8), (2, 0)], d2=9.0, collision_distance=3.0)
    'avoid-collision'
    >>> select_behaviour((0, 0), [(0, 8)], [(0, 8)], d2=9.0, collision_distance=3.0)
    'maintain-connectivity'
    """
    if disconnected:
        return ACHIEVE_CONNECTIVITY
    squared = d2 * d2  # 0 for a range of about 1e-160 cells or less: every link is weak
    threshold = (1.0 / squared if math.isfinite(squared) else 0.0) if squared > 0 else math.inf
    if any(signal_strength(position, other) < threshold for other in bridge_positions):
        return ACHIEVE_CONNECTIVITY
    limit = collision_distance * collision_distance
    if any(g(position, other) < limit for other in other_positions):
        return AVOID_COLLISION
    return MAINTAIN_CONNECTIVITY


def network_roles(
    robot: int, nodes: Iterable[int], links: Iterable[tuple[int, int]]
) -> NetworkRoles:
    """§3.1.1: the bridges at ``robot`` in the graph (vertices = robots, edges = links)
    and every robot's hop distance from the root (the lowest id).

    >>> roles = network_roles(1, [0, 1, 2, 3], [(0, 1), (1, 2), (2, 3), (1, 3)])
    >>> sorted(roles.bridges), sorted(roles.neighbours), dict(sorted(roles.hops.items()))
    ([0], [0, 2, 3], {0: 0, 1: 1, 2: 2, 3: 2})
    """
    node_set = frozenset(nodes)
    if robot not in node_set:
        return NetworkRoles(frozenset(), frozenset(), {robot: 0})
    link_set = frozenset((min(a, b), max(a, b)) for a, b in links)
    bridges, components_hops = _graph_facts(node_set, link_set)
    neighbours = frozenset(b if a == robot else a for a, b in link_set if robot in (a, b))
    bridged = frozenset(b if a == robot else a for a, b in bridges if robot in (a, b))
    hops = next(h for h in components_hops if robot in h)
    return NetworkRoles(bridged, neighbours, hops)


@functools.lru_cache(maxsize=256)
def _graph_facts(
    nodes: frozenset[int], links: frozenset[tuple[int, int]]
) -> tuple[frozenset[tuple[int, int]], tuple[Mapping[int, int], ...]]:
    """Bridges of the graph (``networkx.bridges``) and, per connected component, the
    hop distance of each robot from the component's lowest id.

    Every robot of a sub-network sees the same topology, so the answer is shared
    (a pure function of its arguments, cached).
    """
    graph = nx.Graph()
    graph.add_nodes_from(sorted(nodes))
    graph.add_edges_from(sorted(links))
    bridges = frozenset((min(a, b), max(a, b)) for a, b in nx.bridges(graph))
    hops = tuple(
        MappingProxyType(dict(nx.single_source_shortest_path_length(graph, min(component))))
        for component in nx.connected_components(graph)
    )
    return bridges, hops


def orient(
    robot: int, partners: Iterable[int], hops: Mapping[int, int]
) -> tuple[list[int], list[int]]:
    """Split constraint partners into leaders (nearer the root) and followers.

    A partner leads if its ``(hops, id)`` is smaller than the robot's; leaders come
    nearest the root first. Across a bridge the root side is always the leader.

    >>> orient(2, [1, 3], {0: 0, 1: 1, 2: 2, 3: 3})
    ([1], [3])
    >>> orient(2, [1, 3], {0: 0, 1: 1, 2: 1, 3: 1})  # same hops: lower id leads
    ([1], [3])
    """
    mine = (hops.get(robot, 0), robot)
    keyed = sorted(((hops.get(p, 0), p), p) for p in partners if p != robot)
    return [p for key, p in keyed if key < mine], [p for key, p in keyed if key > mine]


def within_distance(shape: tuple[int, int], centres: Sequence[Cell], radius: float) -> BoolGrid:
    """Cells closer than ``radius`` to every centre (the comfort zone's outer disks).

    >>> within_distance((1, 5), [(0, 0), (0, 4)], 3.0).astype(int).tolist()
    [[0, 0, 1, 0, 0]]
    """
    rows = np.arange(shape[0])[:, None]
    cols = np.arange(shape[1])[None, :]
    inside = np.ones(shape, dtype=bool)
    for row, col in centres:
        inside &= (rows - row) ** 2 + (cols - col) ** 2 < radius * radius
    return inside


def cut_path_to_zone(path: Path, anchors: Sequence[Cell], d2: float) -> Path:
    """The longest prefix of ``path`` whose cells are all within ``d2`` of every anchor.

    The first cell (the robot's own) is always kept.

    >>> cut_path_to_zone(np.array([[0, 0], [0, 1], [0, 2], [0, 3]]), [(0, -1)], 3.5).tolist()
    [[0, 0], [0, 1], [0, 2]]
    """
    if len(path) == 0 or not anchors:
        return path
    points = np.asarray(anchors, dtype=np.float64)
    squared = ((path[:, None, :] - points[None, :, :]) ** 2).sum(axis=-1)
    inside = (squared < d2 * d2).all(axis=1)
    inside[0] = True
    outside = np.flatnonzero(~inside)
    return path if outside.size == 0 else path[: int(outside[0])]


def cut_path_near(path: Path, point: Cell, radius: float) -> Path:
    """``path`` up to its first cell within ``radius`` of ``point``.

    >>> cut_path_near(np.array([[0, 0], [0, 1], [0, 2], [0, 3]]), (0, 4), 2.0).tolist()
    [[0, 0], [0, 1], [0, 2]]
    """
    if len(path) == 0:
        return path
    squared = (path[:, 0] - point[0]) ** 2 + (path[:, 1] - point[1]) ** 2
    close = np.flatnonzero(squared <= radius * radius)
    return path if close.size == 0 else path[: int(close[0]) + 1]


def approach_cell(dist: npt.NDArray[np.float64], point: Cell) -> Cell | None:
    """The reachable cell (finite ``dist``) nearest to ``point`` (Euclidean), then cheapest.

    >>> field = np.array([[0.0, 1.0, np.inf], [1.0, 1.4, np.inf]])
    >>> approach_cell(field, (0, 2))
    (0, 1)
    """
    _, rows, cols = raster_cells(np.isfinite(dist))
    if rows.size == 0:
        return None
    squared = (rows - point[0]) ** 2 + (cols - point[1]) ** 2
    nearest = np.flatnonzero(squared == squared.min())
    best = int(nearest[np.argmin(dist[rows[nearest], cols[nearest]])])
    return int(rows[best]), int(cols[best])


def route_around(
    free: BoolGrid,
    start: Cell,
    goal: Cell,
    obstacles: Sequence[Cell],
    fields: FieldWorkspace | None = None,
) -> Path | None:
    """§3.3.2: shortest path from ``start`` to ``goal`` with ``obstacles`` (robots closer
    than the collision distance) as static obstacles; None if they cut the goal off.

    >>> free = np.ones((3, 3), dtype=bool)
    >>> route_around(free, (1, 0), (1, 2), [(1, 1)]).tolist()  # no corner cutting
    [[1, 0], [0, 0], [0, 1], [0, 2], [1, 2]]
    >>> route_around(np.ones((1, 3), dtype=bool), (0, 0), (0, 2), [(0, 1)]) is None
    True
    """
    grid = free.copy()
    if obstacles:
        rows, cols = np.asarray(obstacles).T
        grid[rows, cols] = False
    grid[goal] = free[goal]  # a robot on the goal itself does not make it unreachable
    if fields is None:
        return path_to(grid, start, goal)
    field = fields.search(grid, start, target_cells=np.array([goal[0] * grid.shape[1] + goal[1]]))
    return extract_path(field, goal) if np.isfinite(field[goal]) else None


# ---------------------------------------------------------------------- strategy
class VazquezNetwork(Strategy, ReplanRules):
    """Vazquez & Malcolm: behaviour-based exploration keeping the mobile network."""

    id = "vazquez-network"
    default_sharing = "broadcast"
    summary = (
        "Vazquez & Malcolm 2004: decentralised information-gain exploration; bridge "
        "links keep a comfort zone (behaviours of Fig. 2)"
    )
    citation = (
        "J. Vazquez, C. Malcolm, Distributed multirobot exploration maintaining a "
        "mobile network, IEEE Intelligent Systems (IS'04), 2004"
    )
    comm_range = Param(
        0.0,
        "cells",
        "communication range d3; 0 = the run's --comm-range, inf = unlimited",
        "d3",
        low=0,
        finite=False,
        note=("communication range; 0 = the run's `--comm-range` (cells); inf = no constraints"),
    )
    d2_fraction = Param(
        0.9,
        "",
        "preventive constraint d2 = d2_fraction x d3",
        "d2",
        low=0,
        high=1,
        low_open=True,
        note="`d2 = 0.9 d3` (paper)",
    )
    d1_sensor_diameters = Param(
        1.5,
        "",
        "collision constraint d1 in sensor diameters",
        "d1",
        low=0,
        note="`d1 = 1.5 x 2 R` (paper: 3/2 of the sensor diameter)",
    )
    d1_max_fraction = Param(
        0.75,
        "",
        "cap d1 at this fraction of d2",
        low=0,
        high=1,
        note="cap `d1 <= 0.75 d2` so the comfort zone is never empty",
    )
    cost_weight = Param(
        1.0,
        "",
        "weight w of travel cost in U - w C",
        "w",
        low=0,
        note="weight of travel cost in `U - w C`",
    )
    line_of_sight = Param(
        False,
        "",
        "count only unknown cells in line of sight in U",
        note="count only unknown cells in line of sight (in the belief) in `U`",
    )
    position_period = Param(2, "ticks", "broadcast the position every k ticks", "k", low=1)
    follow_distance = Param(
        2.0,
        "cells",
        "how close a robot moving towards a neighbour gets",
        low=0,
        note=("how close a `convoy` follower, or a robot returning to a lost neighbour, gets"),
    )
    reconnect_timeout = Param(
        0,
        "ticks",
        "give up returning to a lost neighbour; 0 = 4 d3 (at least 50)",
        low=0,
        note=("give up going back to a lost neighbour; 0 = `4 d3 / speed`, at least 50"),
    )
    zone_includes_targets = Param(
        False,
        "",
        "keep the zone around bridge neighbours' destinations too (ours)",
        note=(
            "also require the comfort zone around each constraining neighbour's "
            "announced destination (ours)"
        ),
    )
    constraint_memory = Param(
        0,
        "ticks",
        "keep a neighbour's comfort zone after reconnecting with it (and, with "
        "constrain_bridges=always, after its link stops being a bridge); 0 = "
        "memory_ranges x d3 of travel (at least 10 ticks)",
        low=0,
        note=(
            "keep a neighbour constraining after the pair is back within `d2` "
            "(`always`: after its link stopped being a bridge); 0 = `memory_ranges "
            "x d3 / speed`, at least 10"
        ),
    )
    memory_ranges = Param(
        1.0,
        "d3",
        "default constraint_memory in ranges of travel (d3 / speed ticks)",
        low=0,
        note="the default memory in ranges of travel",
    )
    resolve_conflicts = Param(
        True,
        "",
        "re-plan when a lower id announces a destination within R of ours",
        note=("re-plan when a lower id announces a destination within `R` of one's own"),
    )
    abort_memory = Param(
        0,
        "ticks",
        "leave a frontier given up for a constraint to the others this long; 0 = 4 d3 "
        "of travel (at least 50)",
        low=0,
        note=(
            "leave a frontier given up for a constraint to the others; 0 = `4 d3 / "
            "speed`, at least 50"
        ),
    )
    constrain_bridges = Param(
        "stretched",
        "",
        "which bridge links constrain: stretched (signal below threshold, beyond d2, "
        "§3.1) or always (every bridge)",
        choices=("stretched", "always"),
        note=("a bridge neighbour constrains when beyond `d2` (`stretched`) or `always`"),
    )
    broken_bridge_frontier = Param(
        "lower-keeps",
        "",
        "a broken bridge link: both go back, the lower id keeping its frontier to "
        "resume (lower-keeps), or both leave theirs to the others (both-leave)",
        choices=("lower-keeps", "both-leave"),
        note=(
            "a bridge link broke: both go back, the lower id keeps its frontier and "
            "resumes it once reconnected, the higher leaves its own to the others; "
            "`both-leave`: both leave theirs"
        ),
    )
    zone_between_pair = Param(
        True,
        "",
        "a stretched pair searches the comfort zone between the two (within d2 of "
        "both, §3.3.1), not around the other robot only",
        note="a stretched pair searches within `d2` of both robots",
    )
    no_frontier_rule = Param(
        "approach",
        "",
        "no frontier in the comfort zone: approach (move towards the stretched "
        "partner, §3.3.1) or convoy (lead / follow / hold by distance to the root)",
        choices=("approach", "convoy"),
        note=(
            "no frontier in the zone: `approach` the stretched neighbour (else the "
            "end nearer the root explores and the others go with it) or `convoy`"
        ),
    )
    discount_around = Param(
        "both",
        "",
        "U leaves out cells within R of other robots' destinations, positions or both",
        choices=("both", "destinations", "positions"),
        note=("`U` leaves out cells near other robots' `destinations`, `positions`, or `both`"),
    )
    utility_unit = Param(
        "ticks",
        "",
        "U in ticks of sensing, U / (2R + 1) (ticks, like C) or in cells",
        choices=("ticks", "cells"),
        note="`U` as `U / (2R + 1)` ticks of sensing, or `cells`",
    )
    replan_on_behaviour = Param(
        "reroute-collision",
        "",
        "re-evaluate the plan on any change of behaviour but into or out of "
        "avoid-collision, which re-routes to the goal (§3.3.2), on any change (Fig. 2), "
        "or only into and out of achieve-connectivity",
        choices=("any", "reroute-collision", "connectivity"),
        note=(
            "re-plan on any change of behaviour but into or out of avoid-collision, "
            "which re-routes to the current goal (§3.3.2); `any`: a new plan on "
            "every change; `connectivity`: only into and out of "
            "achieve-connectivity"
        ),
    )
    # "If the robot arrives at the current frontier the exploration algorithm its
    # executed" (Fig. 2): a plan ends on arrival, not when its frontier is explored.
    replan_on_target_explored = ReplanRules.replan_on_target_explored.with_default(False)

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        # What this robot knows of the others, from messages: (value, tick sent).
        self.positions: dict[int, tuple[Cell, int]] = {}
        self.destinations: dict[int, tuple[Cell, int]] = {}
        # Its own plan.
        self.mode = HOLD
        self.destination: Cell | None = None  # the frontier it heads for (announced)
        self.announced: Cell | None = None
        self.path: Path | None = None
        self.hold_until = -1
        self.last_plan_tick = -1
        self.last_position_tick = -(10**9)
        self.behaviour = MAINTAIN_CONNECTIVITY
        self.avoided: frozenset[Cell] = frozenset()
        # Network state.
        self.previous_subnetwork: frozenset[int] = frozenset({robot_id})
        self.previous_neighbours: frozenset[int] = frozenset()
        self.lost: dict[int, tuple[Cell, int]] = {}  # neighbour -> (last cell, tick lost)
        self.kept: Cell | None = None  # the frontier kept while going back to the lost
        self.resumed: Cell | None = None  # the last kept frontier resumed (kept once only)
        self.remembered: dict[int, int] = {}  # partner -> constrained until this tick
        self.stretched: frozenset[int] = frozenset()  # bridge partners beyond d2 last tick
        self.aborted: dict[Cell, int] = {}  # frontier given up for a constraint -> until tick
        self._roles_key: tuple[frozenset[int], frozenset[tuple[int, int]]] | None = None
        self._roles = NetworkRoles(frozenset(), frozenset(), {robot_id: 0})

    # ------------------------------------------------------------------ knowledge
    def _d3(self, view: RobotView) -> float:
        """The communication range d3 in cells: the parameter, or the run's range."""
        given = self.comm_range
        return given if given > 0 else view.comm_range

    def _radii(self, view: RobotView) -> tuple[float, float]:
        d1, d2, _d3 = comfort_distances(
            self._d3(view),
            view.sensor_range,
            d2_fraction=self.d2_fraction,
            d1_sensor_diameters=self.d1_sensor_diameters,
            d1_max_fraction=self.d1_max_fraction,
        )
        return d1, d2

    def _constrained(self, view: RobotView) -> bool:
        """Whether the network can break at all (finite ``d3``)."""
        return math.isfinite(self._d3(view))

    def _memory(self, view: RobotView, name: str) -> int:
        """A duration parameter in ticks; 0 = its default in ranges of travel:
        ``reconnect_timeout`` and ``abort_memory`` 4 d3 (at least 50 ticks),
        ``constraint_memory`` ``memory_ranges x d3`` (at least 10)."""
        ticks = int(self.p[name])
        if ticks > 0:
            return ticks
        ranges, least = (self.memory_ranges, 10) if name == "constraint_memory" else (4.0, 50)
        travel = ranges * self._d3(view) / view.speed  # inf for a range of about 1e308 cells
        return max(least, math.ceil(travel)) if math.isfinite(travel) else _FOREVER

    def _roles_of(self, view: RobotView) -> NetworkRoles:
        key = (view.subnetwork, view.links)
        if key != self._roles_key:
            self._roles_key = key
            self._roles = network_roles(self.robot_id, view.subnetwork, view.links)
        return self._roles

    def _position(self, robot: int) -> Cell | None:
        known = self.positions.get(robot)
        return None if known is None else known[0]

    def _cells_in_order(self, robots: Sequence[int]) -> list[Cell]:
        """Last reported cells of ``robots`` (those heard of), in the given order."""
        return [c for c in (self._position(r) for r in robots) if c is not None]

    def _cells(self, robots: Iterable[int]) -> list[Cell]:
        """Last reported cells of ``robots`` (those heard of), in id order."""
        return [c for c in (self._position(r) for r in sorted(robots)) if c is not None]

    def _read_inbox(self, view: RobotView) -> bool:
        """Update positions and destinations; True if a conflict asks for a new plan."""
        conflict = False
        radius2 = view.sensor_range * view.sensor_range
        for message in view.inbox:
            payload = message.payload
            if isinstance(payload, PositionPayload):
                old = self.positions.get(payload.robot)
                if old is None or old[1] <= message.tick_sent:
                    self.positions[payload.robot] = (payload.cell, message.tick_sent)
            elif isinstance(payload, TargetPayload):
                old_target = self.destinations.get(payload.robot)
                if old_target is not None and old_target[1] > message.tick_sent:
                    continue
                if payload.goal is None:
                    self.destinations.pop(payload.robot, None)
                    continue
                self.destinations[payload.robot] = (payload.goal, message.tick_sent)
                if (
                    self.resolve_conflicts
                    and payload.robot < self.robot_id
                    and self.mode in (EXPLORE, LEAD)
                    and self.destination is not None
                    and g(payload.goal, self.destination) <= radius2
                ):
                    conflict = True
        return conflict

    def _track_lost(self, view: RobotView, roles: NetworkRoles) -> bool:
        """Note direct neighbours that left the sub-network (their link was a bridge) and
        those that came back; True if either set changed."""
        changed = False
        if self._constrained(view):
            for robot in sorted(self.previous_neighbours - view.subnetwork):
                cell = self._position(robot)
                if cell is not None and robot not in self.lost:
                    self.lost[robot] = (cell, view.tick)
                    changed = True
            timeout = self._memory(view, "reconnect_timeout")
            for robot in sorted(self.lost):
                if robot in view.subnetwork:  # connection achieved: constrain future plans
                    self.remembered[robot] = view.tick + self._memory(view, "constraint_memory")
                    del self.lost[robot]
                    changed = True
                elif view.tick - self.lost[robot][1] > timeout:
                    del self.lost[robot]
                    changed = True
            for robot in [r for r, until in self.remembered.items() if until < view.tick]:
                del self.remembered[robot]
        self.previous_neighbours = roles.neighbours
        return changed

    def _partners(self, view: RobotView, roles: NetworkRoles, d2: float) -> frozenset[int]:
        """Robots whose comfort zone constrains this one.

        §3.1: "A pair of robots impose mutual motion constraints only if they constitute
        a solitary bridge connection ... and if the signal strength among the pair of
        robots falls below a threshold": bridge neighbours farther than ``d2``
        (``constrain_bridges=stretched``), and for ``constraint_memory`` ticks those it
        got back within ``d2`` of or reconnected with (§3.3.1: "once the robot achieves
        the connection status it constrains future plans"). With
        ``constrain_bridges=always`` every bridge neighbour constrains, and keeps
        constraining for ``constraint_memory`` ticks after its link stopped being a
        bridge."""
        if not self._constrained(view):
            return frozenset()
        until = view.tick + self._memory(view, "constraint_memory")
        stretched = frozenset(
            robot
            for robot in roles.bridges
            if (cell := self._position(robot)) is not None and g(view.position, cell) >= d2 * d2
        )
        if self.constrain_bridges == "always":
            self.stretched = stretched
            for robot in roles.bridges:
                self.remembered[robot] = until
            return frozenset(r for r in self.remembered if r in view.subnetwork)
        for robot in self.stretched - stretched:
            if robot in view.subnetwork:  # back in the comfort zone: connection achieved
                self.remembered[robot] = until
        self.stretched = stretched
        return stretched | frozenset(r for r in self.remembered if r in view.subnetwork)

    def _others_close(self, view: RobotView, collision_distance: float) -> list[Cell]:
        """Last reported cells of robots of the sub-network closer than the collision distance."""
        limit = collision_distance * collision_distance
        cells = self._cells(view.subnetwork - {self.robot_id})
        return [cell for cell in cells if g(view.position, cell) < limit]

    @property
    def _fields(self) -> FieldWorkspace:
        """The thread's search buffers, shared by the robots: a field is read within the
        decision that searched it, and valid until the next search."""
        return shared_workspace("vazquez-network")

    # ------------------------------------------------------------------ protocol
    def decide(self, view: RobotView) -> Decision:
        tick = view.tick
        conflict = self._read_inbox(view)
        roles = self._roles_of(view) if self._constrained(view) else self._roles
        lost_changed = self._track_lost(view, roles)
        d1, d2 = self._radii(view)

        messages: list[Message] = []
        joined = bool(view.subnetwork - self.previous_subnetwork)
        self.previous_subnetwork = view.subnetwork
        if joined or tick - self.last_position_tick >= self.position_period:
            self.last_position_tick = tick
            payload = PositionPayload(self.robot_id, view.position)
            messages.append(item_message(POSITION, self.robot_id, BROADCAST, payload))
        if joined and self.announced is not None:
            messages.append(self._target_message(self.announced))

        partners = self._partners(view, roles, d2)
        close = self._others_close(view, d1)
        behaviour = select_behaviour(
            view.position,
            self._cells(partners),
            close,
            d2=d2,
            collision_distance=d1,
            disconnected=bool(self.lost),
        )
        replan = self.replan_on_behaviour
        changed = {behaviour, self.behaviour}
        switched = behaviour != self.behaviour and (
            replan == "any"
            or ACHIEVE_CONNECTIVITY in changed
            or (replan == "reroute-collision" and AVOID_COLLISION not in changed)
        )
        self.behaviour = behaviour
        pair = self.stretched | partners
        if (
            switched
            and not self.lost
            and self.mode in (EXPLORE, LEAD)
            and pair
            and self.robot_id < min(pair)
        ):
            # The lower id of a constrained pair keeps its frontier on any change of
            # behaviour, as the pair stretches and as it comes back; the other returns to
            # it (two robots turning at once swap frontiers, or chase each other's comfort
            # zones, forever).
            switched = False

        if conflict or lost_changed or switched or self._needs_plan(view):
            # A plan given up to a constraint: the network's, or a robot in the way.
            constrained_now = switched and behaviour == ACHIEVE_CONNECTIVITY
            gave_up = constrained_now or (lost_changed and not self._keeps(view)) or view.blocked
            if gave_up and self.mode in (EXPLORE, LEAD) and not view.arrived:
                self._abort(view)
            decision = self._plan(view, roles, partners, close, d1, d2)
            announce = self.destination if self.mode in (EXPLORE, LEAD) else None
            if announce != self.announced:
                self.announced = announce
                decision.messages.append(self._target_message(announce))
        elif behaviour == AVOID_COLLISION:
            decision = self._avoid_collision(view, close, d1)
        else:
            decision = Decision()
        decision.messages[:0] = messages
        return decision

    def _target_message(self, goal: Cell | None) -> Message:
        payload = TargetPayload(self.robot_id, goal)
        return Message(TARGET, self.robot_id, BROADCAST, fixed_size(TARGET_BYTES), payload)

    def _needs_plan(self, view: RobotView) -> bool:
        """Arrived (``P(x, y) = f(x, y)``), blocked, lost the goal, or a re-planning rule."""
        if view.arrived or view.blocked:
            return True
        if view.goal is None:
            return view.tick >= self.hold_until
        every = self.replan_every
        if every > 0 and view.tick - self.last_plan_tick >= every:
            return True
        if self.replan_on_new_info and view.new_cells > 0:
            return True
        if self.mode in (EXPLORE, LEAD) and self.replan_on_target_explored:
            assert self.destination is not None
            return not frontier_at(view.belief, *self.destination)
        if self.mode == RETURN:
            return not self.lost
        return False

    # ------------------------------------------------------------------ planning
    def _go(
        self,
        view: RobotView,
        mode: str,
        path: Path,
        destination: Cell | None,
    ) -> Decision:
        """Follow ``path`` (or hold if it does not leave the robot's cell)."""
        if len(path) < 2:
            return self._hold(view)
        goal = (int(path[-1, 0]), int(path[-1, 1]))
        self.mode = mode
        self.destination = destination
        self.path = path
        self.avoided = frozenset()
        return Decision(goal=goal, path=path)

    @staticmethod
    def _grid(view: RobotView, close: Sequence[Cell]) -> BoolGrid:
        """Cells to plan over: known free, minus robots closer than the collision distance."""
        grid = passable(view.belief)
        if close:
            rows, cols = np.asarray(close).T
            grid[rows, cols] = False
            grid[view.position] = True
        return grid

    def _hold(self, view: RobotView) -> Decision:
        """Stay until the next position update (or an event) asks for a new plan."""
        self.mode = HOLD
        self.destination = None
        self.path = None
        self.hold_until = view.tick + self.position_period
        return Decision(idle=True) if view.goal is not None else Decision()

    def _plan(
        self,
        view: RobotView,
        roles: NetworkRoles,
        partners: frozenset[int],
        close: list[Cell],
        d1: float,
        d2: float,
    ) -> Decision:
        """The exploration algorithm (§3.2) under the current behaviour's constraints."""
        self.last_plan_tick = view.tick
        if self.lost:  # achieve-connectivity after a disconnection: go back
            if self._keeps(view):
                self.kept = self.kept or self.destination
            return self._return(view, roles, partners, close, d1, d2)
        kept, self.kept = self.kept, None
        if kept is not None and frontier_at(view.belief, *kept):  # back: resume it
            # Stopped at the frontier: the same length and path as a full field.
            width = view.belief.shape[1]
            kept_cell = np.array([kept[0] * width + kept[1]], dtype=np.int64)
            dist = self._fields.search(
                self._grid(view, close), view.position, target_cells=kept_cell
            )
            if 0 < dist[kept] < math.inf:
                self.resumed = kept
                return self._go(view, EXPLORE, extract_path(dist, kept), kept)
        frontier = frontier_mask(view.belief)
        if not frontier.any():
            return self._hold(view)
        partner_cells = self._cells(partners)
        if partner_cells:
            # Constrained search (§3.3.1): paths stay within d2 of every partner, and
            # the destination lies in the comfort zone of each partner's position (and
            # announced destination). Stretched, "the search of frontier cells is
            # constrained to the comfort zone between the pair": within d2 of the
            # robot's own cell too.
            # A robot beyond d2 of a partner plans paths that never take it farther away.
            between = self.zone_between_pair and bool(self.stretched & partners)
            region = within_distance(view.belief.shape, [view.position], d2) if between else None
            for cell in partner_cells:
                reach = max(d2, math.sqrt(g(view.position, cell)) + 0.5)
                near = within_distance(view.belief.shape, [cell], reach)
                region = near if region is None else region & near
            anchors = list(partner_cells)
            if self.zone_includes_targets:
                anchors += [
                    self.destinations[r][0] for r in sorted(partners) if r in self.destinations
                ]
            found = self._evaluate(view, frontier, close, region)
            if found is not None:
                dist, cells, value = found
                zone = np.ones(len(cells), dtype=bool)
                for anchor in anchors:
                    zone &= in_comfort_zone(cells, anchor, d1, d2)
                if zone.any():
                    best = int(np.argmax(np.where(zone, value, -np.inf)))
                    goal = (int(cells[best, 0]), int(cells[best, 1]))
                    return self._go(view, EXPLORE, extract_path(dist, goal), goal)
            return self._outside_zone(view, roles, partners, frontier, close, d1, d2)
        found = self._evaluate(view, frontier, close)
        if found is None:
            return self._hold(view)
        dist, cells, value = found
        best = int(np.argmax(value))  # first in raster order among ties
        goal = (int(cells[best, 0]), int(cells[best, 1]))
        return self._go(view, EXPLORE, extract_path(dist, goal), goal)

    def _abort(self, view: RobotView) -> None:
        """§3.2: "In some occasions robots may abort the plan to explore a frontier due
        to constraints, in such case the frontier may be selected by another robot":
        the robot leaves the frontier it gave up to the others for ``abort_memory``
        ticks (it would otherwise pick it again and abort again, forever)."""
        if self.destination is not None:
            self.aborted[self.destination] = view.tick + self._memory(view, "abort_memory")

    def _left_to_others(self, view: RobotView, targets: BoolGrid) -> BoolGrid:
        """``targets`` without the cells within ``R`` of the frontiers this robot aborted
        (unless that leaves none)."""
        self.aborted = {cell: until for cell, until in self.aborted.items() if until >= view.tick}
        if not self.aborted:
            return targets
        mask = exclusion_mask(targets.shape, sorted(self.aborted), view.sensor_range)
        kept = targets & ~mask if mask is not None else targets
        return kept if kept.any() else targets

    def _evaluate(
        self,
        view: RobotView,
        frontier: BoolGrid,
        close: Sequence[Cell],
        region: BoolGrid | None = None,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.float64]] | None:
        """§3.2: flood-fill costs ``C`` from the robot, utilities ``U`` and ``U - w C`` of
        every reachable frontier cell (inside ``region`` if given), or None if none.

        Robots closer than the collision distance are static obstacles
        (avoid-collision), unless they box the robot in.
        """
        free = passable(view.belief)
        if region is not None:
            free &= region
        targets = self._left_to_others(view, frontier if region is None else frontier & region)
        for obstacles in (close, ()) if close else ((),):
            grid = free
            if obstacles:
                grid = free.copy()
                rows, cols = np.asarray(obstacles).T
                grid[rows, cols] = False
            dist = self._fields.search(grid, view.position, targets=targets)
            rows, cols = reachable_frontier_cells(targets, dist)
            if rows.size:
                break
        if rows.size == 0:
            return None
        cells = np.stack([rows, cols], axis=1)
        cells_gained = utility(
            view.belief,
            cells,
            view.sensor_range,
            self._discount_centres(view),
            line_of_sight=self.line_of_sight,
        )
        gain = cells_gained.astype(np.float64)
        if self.utility_unit == "ticks":  # the ticks a moving sensor needs to gain U
            gain /= 2 * view.sensor_range + 1
        return dist, cells, net_value(gain, dist[rows, cols], self.cost_weight)

    def _discount_centres(self, view: RobotView) -> list[Cell]:
        """§3.2: "The utility expected by a robot considering moving to a particular
        frontier is lessened if there are any robots near that destination": the cells
        around other robots' announced destinations and (``discount_around``) around
        the last reported cells of the other robots of the sub-network."""
        around = self.discount_around
        centres: list[Cell] = []
        if around in ("both", "destinations"):
            centres += [cell for _robot, (cell, _tick) in sorted(self.destinations.items())]
        if around in ("both", "positions"):
            centres += self._cells(view.subnetwork - {self.robot_id})
        return centres

    def _outside_zone(
        self,
        view: RobotView,
        roles: NetworkRoles,
        partners: frozenset[int],
        frontier: BoolGrid,
        close: list[Cell],
        d1: float,
        d2: float,
    ) -> Decision:
        """No frontier in the comfort zone. ``no_frontier_rule=approach`` (§3.3.1: "When
        no frontier cells are found the robot computes a path to the current position
        of the other robot in the bridge connection"): move towards the farthest partner
        beyond ``d2`` until mid-zone; a robot constrained only by memory explores
        unconstrained. ``convoy``: approach, wait, follow or lead (see interpretations)."""
        position = view.position
        if self.no_frontier_rule == "approach":
            far = [(g(position, c), c) for c in self._cells(partners) if g(position, c) >= d2 * d2]
            if far:
                return self._towards(view, APPROACH, max(far)[1], (d1 + d2) / 2, close)
            # Partners within d2 (remembered, or every bridge): the end nearer the root
            # of the sub-network explores, keeping the others within d2; they go with
            # it, to mid-zone.
            leaders, followers = orient(self.robot_id, partners, roles.hops)
            ahead = self._cells_in_order(leaders)
            if ahead:
                return self._towards(view, FOLLOW, ahead[0], (d1 + d2) / 2, close)
            leaders = []
        else:
            leaders, followers = orient(self.robot_id, partners, roles.hops)
        stretched = [
            (g(position, cell), cell)
            for cell in self._cells(leaders)
            if g(position, cell) >= d2 * d2
        ]
        if stretched:  # achieve-connectivity towards the farthest leader
            return self._towards(view, APPROACH, max(stretched)[1], (d1 + d2) / 2, close)
        follower_cells = self._cells(followers)
        if any(g(position, cell) >= d2 * d2 for cell in follower_cells):
            return self._hold(view)  # a stretched follower comes back to us
        leader_cells = self._cells_in_order(leaders)
        if leader_cells:
            radius = self.follow_distance
            return self._towards(view, FOLLOW, leader_cells[0], radius, close)
        found = None
        if self.no_frontier_rule == "approach" and follower_cells:
            # The end explores "its path kept within d2 of the others": a frontier it can
            # reach without leaving d2 of any of them, if there is one (choosing first and
            # cutting the path after left a chain whose best frontiers lay beyond d2
            # holding forever, measured: constrain_bridges=always, 6 robots).
            reach = within_distance(view.belief.shape, follower_cells, d2)
            found = self._evaluate(view, frontier, close, reach)
        found = found or self._evaluate(view, frontier, close)
        if found is None:
            return self._hold(view)
        dist, cells, value = found
        best = int(np.argmax(value))
        goal = (int(cells[best, 0]), int(cells[best, 1]))
        path = cut_path_to_zone(extract_path(dist, goal), follower_cells, d2)
        return self._go(view, LEAD, path, goal)

    def _towards(
        self, view: RobotView, mode: str, point: Cell, radius: float, close: Sequence[Cell]
    ) -> Decision:
        """Move along a shortest path towards ``point`` until within ``radius`` of it
        (around robots closer than the collision distance when possible)."""
        dist = self._fields.search(self._grid(view, close), view.position)
        cell = approach_cell(dist, point)
        if close and (cell is None or g(cell, point) > radius * radius):
            close = []
            dist = self._fields.search(passable(view.belief), view.position)
            cell = approach_cell(dist, point)
        if cell is None:
            return self._hold(view)
        path = cut_path_near(extract_path(dist, cell), point, radius)
        return self._go(view, mode, path, None)

    def _keeps(self, view: RobotView) -> bool:
        """Disconnected, and the lower id of every broken link
        (``broken_bridge_frontier=lower-keeps``): it goes back keeping its frontier, to
        resume it once reconnected, unless it is already heading for a frontier it
        resumed (kept once: a link that breaks again on the way gives it up)."""
        lower = self.broken_bridge_frontier == "lower-keeps"
        again = self.destination is not None and self.destination == self.resumed
        return lower and bool(self.lost) and self.robot_id < min(self.lost) and not again

    def _return(
        self,
        view: RobotView,
        roles: NetworkRoles,
        partners: frozenset[int],
        close: list[Cell],
        d1: float,
        d2: float,
    ) -> Decision:
        """Disconnected: head back to the nearest lost neighbour's last known position."""
        robot = min(self.lost, key=lambda r: (g(view.position, self.lost[r][0]), r))
        cell = self.lost[robot][0]
        decision = self._towards(view, RETURN, cell, self.follow_distance, close)
        if decision.goal is None:  # it is there (or cannot get closer): give up on it
            del self.lost[robot]
            self.behaviour = MAINTAIN_CONNECTIVITY
            return self._plan(view, roles, partners, close, d1, d2)
        return decision

    def _avoid_collision(self, view: RobotView, close: list[Cell], d1: float) -> Decision:
        """§3.3.2: re-plan the path to the current goal around robots standing on it."""
        path = self.path
        if path is None or view.goal is None or not close:
            return Decision()
        index = len(path) - 1 - view.path_remaining
        if not (0 <= index < len(path)) or tuple(path[index]) != view.position:
            return Decision()  # the simulator detoured: its path is not ours
        blocked = frozenset(close)
        if blocked == self.avoided:
            return Decision()
        ahead = path[index + 1 : index + 1 + math.ceil(min(d1, len(path)))]
        if not {(r, c) for r, c in ahead.tolist()} & blocked:
            return Decision()
        self.avoided = blocked
        new_path = route_around(
            passable(view.belief), view.position, view.goal, close, self._fields
        )
        if new_path is None:
            return Decision()  # cut off: keep the path, the simulator handles contact
        self.path = new_path
        return Decision(goal=view.goal, path=new_path)
