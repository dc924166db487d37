"""Meier, Stachniss & Burgard: decentralised coordination over polygonal maps.

D. Meier, C. Stachniss, W. Burgard, "Coordinating multiple robots during
exploration under communication with limited bandwidth", Proc. European
Conference on Mobile Robots (ECMR), 2005, §4, eq. (1) and Algorithm 1. Its
default map sharing is ``polygon`` (§3).

Algorithm 1, per robot, whenever it needs a new target:

1. its map = the union of the polygonal maps received from the others, combined
   with its own observations (done by the ``polygon`` sharing mechanism, which
   never overwrites cells the robot observed itself);
2. the potential targets are the frontier cells of that map;
3. ``U_t = 1`` for every target;
4-6. for every target t' received from another robot, "Reduce the utility of each
   target point t' in the visibility area": ``U_t <- U_t - P(||t - t'||)`` for the
   targets in line of sight of t' (known obstacles block sight, unknown cells do not),
   with ``P(d) = 1 - d / max_range`` for ``d < max_range``, else 0 (eq. 1);
7. ``t = argmax_t U_t - beta * V_t``, ``V_t`` the cost of reaching t;
8. broadcast t (a target point transmission, ``TPT``).

Parameters (rendered from ``MeierPolygon.params`` by :mod:`mrexplore.strategies.doc`):

.. params:begin meier-polygon

=============================  ======  =======  ====  ==============================================
name                           symbol  default  unit  meaning
=============================  ======  =======  ====  ==============================================
``respect_priority``           -       true     -     only targets of robots with a lower id
                                                      discount
``replan_on_target_explored``  -       false    -     re-plan when the goal is no longer a frontier
                                                      cell
UtilityDiscounting             -                      shared: ``strategies.utility``
ReplanRules                    -                      shared: ``strategies.base``
=============================  ======  =======  ====  ==============================================

.. params:end

Messages: ``TPT`` (target point transmission), broadcast: the target as one
polygon point (x int32, y int32, id uint32 = 12 bytes) plus the header.

Interpretations: §5 says target points are published "to robots with lower
priority"; we read that as a fixed priority by robot id, so robot i discounts
only around the latest targets of robots j < i (``respect_priority=False``
discounts around everyone's). A target stays in force until its robot sends a
new one. The cost scale follows ``burgard`` (see its doc page).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, POLYGON_POINT_BYTES, fixed_size
from mrexplore.comm.messages import Message
from mrexplore.grid.occupancy import OCCUPIED
from mrexplore.strategies.base import (
    Cell,
    Decision,
    FrontierStrategy,
    Param,
    ReplanRules,
    RobotView,
    reachable_frontier_cells,
)
from mrexplore.strategies.utility import UtilityDiscounting, discount

TPT = "TPT"


class MeierPolygon(UtilityDiscounting, FrontierStrategy):
    """Meier et al. Algorithm 1: decentralised utility discounting."""

    id = "meier-polygon"
    summary = "Meier et al. 2005: decentralised discounting over polygon maps (Alg. 1)"
    citation = "D. Meier, C. Stachniss, W. Burgard, ECMR 2005, §4 and Algorithm 1"
    default_sharing = "polygon"
    respect_priority = Param(
        True,
        "",
        "only lower ids' targets discount",
        note="only targets of robots with a lower id discount",
    )
    # Algorithm 1 runs "whenever a robot selects a new target location": when it
    # reached its target (or cannot reach it), not when the target got explored.
    replan_on_target_explored = ReplanRules.replan_on_target_explored.with_default(False)

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.received_targets: dict[int, Cell] = {}

    def decide(self, view: RobotView) -> Decision:
        for message in view.inbox:
            if message.type == TPT and isinstance(message.payload, tuple):
                self.received_targets[message.sender] = message.payload
        decision = super().decide(view)
        if decision.goal is not None:
            decision.messages.append(
                Message(
                    TPT,
                    self.robot_id,
                    BROADCAST,
                    fixed_size(POLYGON_POINT_BYTES),
                    decision.goal,
                )
            )
        return decision

    def choose_goal(
        self, view: RobotView, frontier: npt.NDArray[np.bool_], dist: npt.NDArray[np.float64]
    ) -> Cell | None:
        rows, cols = reachable_frontier_cells(frontier, dist)
        if rows.size == 0:
            return None
        cost = dist[rows, cols]  # V_t
        if self.normalize_cost and cost.max() > 0:
            cost = cost / cost.max()
        utility = np.ones(rows.size, dtype=np.float64)  # step 3
        max_range = self.max_range or view.sensor_range
        occupied = view.belief == OCCUPIED if self.visibility_discount else None
        for robot, target in sorted(self.received_targets.items()):  # steps 4-6
            if robot == self.robot_id or (self.respect_priority and robot > self.robot_id):
                continue
            discount(utility, rows, cols, target, max_range, occupied)  # "in the visibility area"
        best = int(np.argmax(utility - self.beta * cost))  # step 7
        return int(rows[best]), int(cols[best])
