"""Utility discounting around goals: Burgard et al.'s step, shared by ``burgard``
(central assignment) and ``meier-polygon`` (each robot around the targets it heard of).

Meier, Stachniss & Burgard §4, eq. (1) and Algorithm 1 step 5; Burgard et al. 2005.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.planning._validate import as_bool_grid, as_cell, as_radius
from mrexplore.planning.visibility import in_sight_kernel
from mrexplore.strategies.base import Cell, Param, declared_params


class UtilityDiscounting:
    """The parameters of utility discounting (a parameter group): the trade-off
    ``U - beta V``, the radius of ``P(d)``, the scale of ``V`` and where the discount
    applies.
    """

    beta = Param(
        1.0,
        "",
        "weight of travel cost against utility",
        "beta",
        low=0,
        note="weight of cost against utility",
    )
    max_range = Param(
        0.0,
        "cells",
        "discount radius of P(d); 0 = sensor range",
        "max_range",
        low=0,
        note="radius of P(d); 0 = sensor range",
    )
    normalize_cost = Param(True, "", "scale each robot's costs to [0, 1]")
    visibility_discount = Param(
        True,
        "",
        "discount only targets in line of sight of a goal (its visibility area)",
        note=(
            "discount only the targets in line of sight of a goal (its visibility "
            "area); false: every target within `max_range`"
        ),
    )


DISCOUNT_PARAMS: dict[str, Param[Any]] = declared_params(UtilityDiscounting)
"""The parameters of utility discounting by name (:class:`UtilityDiscounting`)."""


def coverage_probability(distance: npt.NDArray[np.float64], max_range: float) -> np.ndarray:
    """Meier et al. eq. (1): P(d) = 1 - d / max_range for d < max_range, else 0."""
    return np.where(distance < max_range, 1.0 - distance / max_range, 0.0)


def discount(
    utility: npt.NDArray[np.float64],
    target_rows: npt.NDArray[np.int64],
    target_cols: npt.NDArray[np.int64],
    goal: Cell,
    max_range: float,
    occupied: npt.NDArray[np.bool_] | None = None,
) -> None:
    """Reduce the utility of every target near ``goal`` by P(||t - goal||), in place.

    With ``occupied`` (the planner's map, ``True`` where a cell is known to block
    sight) only the targets in the visibility area of ``goal`` are reduced (Meier et
    al. Algorithm 1 step 5: "Reduce the utility of each target point t' in the
    visibility area"): those in line of sight of ``goal`` within ``max_range``
    (:mod:`mrexplore.planning.visibility`; unknown cells do not block sight).
    """
    d = np.hypot(target_rows - goal[0], target_cols - goal[1])
    reduction = coverage_probability(d, max_range)
    if occupied is not None and reduction.any():
        # One line of sight per target the discount reaches (those within max_range,
        # all inside the goal's disk), not the goal's whole disk: the same cells.
        grid = as_bool_grid(occupied, "occupied")
        row, col = as_cell(goal, grid.shape, "goal")
        as_radius(max_range, "max_range")
        rows = np.ascontiguousarray(target_rows, dtype=np.int64)
        cols = np.ascontiguousarray(target_cols, dtype=np.int64)
        seen = np.empty(rows.shape[0], dtype=np.bool_)
        in_sight_kernel(grid, row, col, rows, cols, reduction > 0, seen)
        reduction = np.where(seen, reduction, 0.0)
    utility -= reduction
