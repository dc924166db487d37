"""Two uncoordinated frontier baselines.

``random-frontier``
    Each robot picks a uniformly random reachable frontier cell of its own
    belief. Sheng et al. (2006), §5, case (1): "all the robots randomly pick
    frontier cells as next targets".

``nearest-frontier``
    B. Yamauchi, "Frontier-based exploration using multiple robots", Agents
    1998: each robot independently travels to the closest reachable frontier
    (shortest path over cells it knows to be free). No coordination: robots
    only share their maps.

Parameters (rendered from the classes' ``params`` by :mod:`mrexplore.strategies.doc`):

``nearest-frontier``:

.. params:begin nearest-frontier

=====================  ======  =======  =====  =====================================================
name                   symbol  default  unit   meaning
=====================  ======  =======  =====  =====================================================
``min_frontier_size``  -       1        cells  ignore 8-connected frontier clusters smaller than
                                               this (Yamauchi's minimum region size); all frontier
                                               cells are used if none is big enough
ReplanRules            -                       shared: ``strategies.base``
=====================  ======  =======  =====  =====================================================

.. params:end

``random-frontier``:

.. params:begin random-frontier

=============================  ======  =======  =====  =============================================
name                           symbol  default  unit   meaning
=============================  ======  =======  =====  =============================================
``replan_on_target_explored``  -       false    -      re-plan when the goal is no longer a frontier
                                                       cell
``min_frontier_size``          -       1        cells  ignore 8-connected frontier clusters smaller
                                                       than this (Yamauchi's minimum region size);
                                                       all frontier cells are used if none is big
                                                       enough
ReplanRules                    -                       shared: ``strategies.base``
=============================  ======  =======  =====  =============================================

.. params:end

Messages: none of their own; maps travel through the run's map-sharing mechanism.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.planning import frontier_clusters
from mrexplore.planning.frontier_search import nearest_frontier
from mrexplore.strategies.base import (
    Cell,
    Decision,
    FrontierStrategy,
    Param,
    ReplanRules,
    RobotView,
    reachable_frontier_cells,
)


def _large_clusters_only(frontier: npt.NDArray[np.bool_], min_size: int) -> npt.NDArray[np.bool_]:
    """Frontier cells of clusters with at least ``min_size`` cells (all if none qualifies)."""
    if min_size <= 1:
        return frontier
    kept = np.zeros_like(frontier)
    for cluster in frontier_clusters(frontier):
        if cluster.size >= min_size:
            kept[cluster.cells[:, 0], cluster.cells[:, 1]] = True
    return kept if kept.any() else frontier


class _FrontierBaseline(FrontierStrategy):
    """What both baselines share: the candidates, the reachable frontier cells of
    clusters of at least ``min_frontier_size`` cells (every reachable frontier cell if
    none of those is reachable); each baseline picks one of them by :meth:`pick`."""

    min_frontier_size = Param(
        1,
        "cells",
        "ignore frontier clusters smaller than this",
        low=1,
        note=(
            "ignore 8-connected frontier clusters smaller than this (Yamauchi's minimum "
            "region size); all frontier cells are used if none is big enough"
        ),
    )

    def choose_goal(
        self, view: RobotView, frontier: npt.NDArray[np.bool_], dist: npt.NDArray[np.float64]
    ) -> Cell | None:
        targets = _large_clusters_only(frontier, self.min_frontier_size)
        rows, cols = reachable_frontier_cells(targets, dist)
        if rows.size == 0 and targets is not frontier:
            rows, cols = reachable_frontier_cells(frontier, dist)
        if rows.size == 0:
            return None
        index = self.pick(view, dist[rows, cols])
        return int(rows[index]), int(cols[index])

    def pick(self, view: RobotView, costs: npt.NDArray[np.float64]) -> int:
        """Index of the chosen candidate, given their path costs (cells) in raster order."""
        raise NotImplementedError


class NearestFrontier(_FrontierBaseline):
    """Yamauchi (1998): go to the closest reachable frontier cell."""

    id = "nearest-frontier"
    summary = "Yamauchi 1998: each robot goes to its closest frontier, no coordination"
    citation = "B. Yamauchi, Frontier-based exploration using multiple robots, Agents 1998"

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.nearest_only = self.min_frontier_size <= 1

    def decide(self, view: RobotView) -> Decision:
        if not self.nearest_only:
            return super().decide(view)
        # Same goal and path as FrontierStrategy.decide + choose_goal, from one compiled
        # search that touches only the cells nearer than the nearest frontier.
        if not self.needs_plan(view):
            return Decision()
        self.last_plan_tick = view.tick
        found = nearest_frontier(view.belief, view.position)
        if found is None:
            return Decision(idle=True)
        goal, path = found
        return Decision(goal=goal, path=path)

    def pick(self, view: RobotView, costs: npt.NDArray[np.float64]) -> int:
        return int(np.argmin(costs))  # first in raster order among ties


class RandomFrontier(_FrontierBaseline):
    """Sheng et al. (2006) case (1): a uniformly random reachable frontier cell.

    Unlike ``nearest-frontier``, a robot keeps its random goal until it arrives
    (``replan_on_target_explored=False`` by default): re-drawing a random goal
    whenever the current one is seen from afar turns the robot into a random
    walker that hardly ever reaches anything.
    """

    id = "random-frontier"
    summary = "each robot picks a random reachable frontier cell (Sheng 2006 §5 case 1)"
    citation = "W. Sheng et al., Robotics and Autonomous Systems 54 (2006), §5 case (1)"
    replan_on_target_explored = ReplanRules.replan_on_target_explored.with_default(False)

    def pick(self, view: RobotView, costs: npt.NDArray[np.float64]) -> int:
        return int(view.rng.integers(costs.size))
