"""Gonzalez-Banos & Latombe (2002): go where ``gain * exp(-lambda * distance)`` is largest.

H. H. Gonzalez-Banos, J.-C. Latombe, "Navigation strategies for exploring indoor
environments", The International Journal of Robotics Research 21(10-11), 2002,
pp. 829-848. Their next-best-view rule scores a candidate position ``q`` by

    g(q) = A(q) * exp(-lambda * L(q))

where ``A(q)`` estimates the unexplored area visible from ``q`` and ``L(q)`` is the
length of the path to ``q``; the robot goes to the candidate of largest ``g``. A small
``lambda`` favours gain (the robot travels far for a large unknown area), a large one
favours nearness (``lambda -> inf`` is the nearest frontier).

Here, for each robot on its own belief (a third-party plugin of mrexplore, found
through the entry-point group ``mrexplore.strategies``):

* candidates ``q`` = the reachable frontier cells (known free, an unknown 4-neighbour);
* ``A(q)`` = unknown cells within the sensor range of ``q``
  (:func:`mrexplore.planning.information_gain`, one compiled pass for all candidates;
  with ``line_of_sight`` only those in line of sight in the belief);
* ``L(q)`` = shortest-path length (cells) over cells the robot knows to be free
  (:func:`mrexplore.planning.distance_field`, computed by
  :class:`~mrexplore.strategies.base.FrontierStrategy`).

Parameters (``UtilityFrontier.params``; ``--set NAME=VALUE`` on the command line):

==================  ======  =======  ======  =======================================================
name                symbol  default  unit    meaning
==================  ======  =======  ======  =======================================================
``distance_decay``  lambda  0.2      1/cell  decay of utility with path length, `gain * exp(-lambda
                                             * L)`; 0.2 is Gonzalez-Banos & Latombe's choice, here
                                             per cell of path
``line_of_sight``   -       false    -       count only unknown cells in line of sight (in the
                                             belief) in the gain
``block_limit``     -       2        -       a target the robot was blocked on this many times in a
                                             row counts as unreachable for it (ours, see below; 0 =
                                             never); from ``strategies.fallback``
ReplanRules         -                        shared: ``strategies.base``
==================  ======  =======  ======  =======================================================

Messages: none of its own; maps travel through the run's map-sharing mechanism.

Interpretations (where the paper and this grid world differ):

* **lambda = 0.2 and its unit.** 0.2 is the value commonly cited for Gonzalez-Banos &
  Latombe's experiments; the paper's text was not available to us to check it or
  its length unit, so treat it as an example's default, not a reproduction. Here
  ``L`` is measured in cells, so the default is 0.2 per cell:
  the utility halves every ``ln 2 / 0.2 = 3.5`` cells of path. Whether that weighs
  distance as their 0.2 did depends on how a cell compares with their length unit; on
  a 0.25 m grid it is a strong preference for nearby frontiers. Tune it with
  ``--set distance_decay=...``.
* **Candidates.** They sample candidate positions near the free edges of the explored
  region; we use every reachable frontier cell, the grid's counterpart.
* **Gain.** ``A(q)`` is their visible unexplored area (polygon visibility, bounded
  by the sensor range); our default counts the unknown cells of the sensor disk
  (``line_of_sight=true`` adds the visibility test through known obstacles).
* **Several robots.** The paper explores with one robot. Each robot here applies the
  rule on its own belief without coordination (like ``nearest-frontier``): maps are
  shared, goals are not, so two robots may choose the same frontier.
* **Blocked targets (ours).** A failed robot standing in a one-cell door is not in
  anyone's belief, so every plan through the door is blocked, and a literal version
  picks the same best cell again forever (seen in ``standard-v1-quick``, harsh regime).
  As the built-in coordinated strategies do, a target the robot was blocked on
  ``block_limit`` times in a row is left out until it next arrives somewhere
  (:class:`mrexplore.strategies.fallback.BlockedTargets`); with nothing else left it
  tries those targets again.
* **Numerics.** ``exp(-lambda L)`` underflows to 0 for long paths (``L > 3700``
  cells at 0.2), which would make every candidate tie; we maximise the equivalent
  ``ln A - lambda L`` instead. Ties go to the first cell in raster order.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.planning import information_gain
from mrexplore.strategies.base import (
    Cell,
    Decision,
    FrontierStrategy,
    Param,
    RobotView,
    reachable_frontier_cells,
)
from mrexplore.strategies.fallback import BlockedTargets, FallbackRules

__all__ = ["UtilityFrontier", "best_candidate"]


def best_candidate(
    gains: npt.NDArray[np.integer], distances: npt.NDArray[np.floating], distance_decay: float
) -> int:
    """Index of the candidate with the largest ``gain * exp(-distance_decay * distance)``.

    Compared as ``ln gain - distance_decay * distance``, so long paths do not underflow
    to a tie; a candidate with no gain never wins over one with some. Ties: the first.

    >>> best_candidate(np.array([10, 40]), np.array([2.0, 10.0]), 0.2)
    0
    >>> best_candidate(np.array([10, 40]), np.array([2.0, 10.0]), 0.1)
    1
    >>> best_candidate(np.array([5, 50]), np.array([4000.0, 4010.0]), 0.2)
    1
    """
    with np.errstate(divide="ignore"):  # ln 0 = -inf: no gain, last choice
        scores = np.log(gains.astype(np.float64)) - distance_decay * distances
    return int(np.argmax(scores))


class UtilityFrontier(FrontierStrategy):
    """Gonzalez-Banos & Latombe (2002): each robot picks the reachable frontier cell of
    largest ``gain * exp(-lambda * distance)`` on its own belief."""

    id = "utility-frontier"
    summary = "Gonzalez-Banos & Latombe 2002: frontier of largest gain * exp(-lambda * path)"
    citation = (
        "H. H. Gonzalez-Banos, J.-C. Latombe, Navigation strategies for exploring indoor "
        "environments, IJRR 21(10-11), 2002"
    )

    distance_decay = Param(
        0.2,
        "1/cell",
        "how fast utility decays with path length",
        "lambda",
        low=0,
        note=(
            "decay of utility with path length, `gain * exp(-lambda * L)`; 0.2 is "
            "Gonzalez-Banos & Latombe's choice, here per cell of path"
        ),
    )
    line_of_sight = Param(
        False, "", "count only unknown cells in line of sight (in the belief) in the gain"
    )
    block_limit = FallbackRules.block_limit

    def __init__(self, robot_id: int, n_robots: int, **params: Any) -> None:
        super().__init__(robot_id, n_robots, **params)
        self.blocked_targets = BlockedTargets(self.block_limit)

    def decide(self, view: RobotView) -> Decision:
        self.blocked_targets.observe(view)
        decision = super().decide(view)
        if decision.idle and self.blocked_targets.forget():
            decision = super().decide(view)  # nothing left but given-up targets: retry them
        self.blocked_targets.decided(view, decision)
        return decision

    def choose_goal(
        self, view: RobotView, frontier: npt.NDArray[np.bool_], dist: npt.NDArray[np.float64]
    ) -> Cell | None:
        rows, cols = reachable_frontier_cells(frontier, dist)
        if self.blocked_targets.excluded:  # targets given up on (blocked on them)
            given_up = np.zeros(frontier.shape, dtype=bool)
            given_up[tuple(np.array(sorted(self.blocked_targets.excluded)).T)] = True
            keep = ~given_up[rows, cols]
            rows, cols = rows[keep], cols[keep]
        if rows.size == 0:
            return None
        gains = information_gain(
            view.belief,
            np.column_stack((rows, cols)),
            view.sensor_range,
            line_of_sight=self.line_of_sight,
        )
        best = best_candidate(gains, dist[rows, cols], self.distance_decay)
        return int(rows[best]), int(cols[best])
