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

Parameters:

===================  ======  =======  ======  ============================================
name                 symbol  default  unit    meaning
===================  ======  =======  ======  ============================================
``distance_decay``   lambda  0.2      1/cell  how fast utility decays with path length
``line_of_sight``    -       false    -       count only unknown cells in line of sight
ReplanRules          -                        shared: ``mrexplore.strategies.base``
===================  ======  =======  ======  ============================================

Messages: none of its own; maps travel through the run's map-sharing mechanism.

Interpretations (where the paper and this grid world differ):

* **lambda = 0.2 and its unit.** 0.2 is the value Gonzalez-Banos & Latombe chose in
  their experiments. Here ``L`` is measured in cells, so the default is 0.2 per cell:
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
* **Numerics.** ``exp(-lambda L)`` underflows to 0 for long paths (``L > 3700``
  cells at 0.2), which would make every candidate tie; we maximise the equivalent
  ``ln A - lambda L`` instead. Ties go to the first cell in raster order.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from mrexplore.planning import information_gain
from mrexplore.strategies.base import (
    Cell,
    FrontierStrategy,
    Param,
    RobotView,
    reachable_frontier_cells,
)

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

    def choose_goal(
        self, view: RobotView, frontier: npt.NDArray[np.bool_], dist: npt.NDArray[np.float64]
    ) -> Cell | None:
        rows, cols = reachable_frontier_cells(frontier, dist)
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
