"""Paths to one goal: the step every strategy takes once it knows where to go."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from mrexplore.planning.distance import distance_field, extract_path


def path_to(
    passable: npt.NDArray[np.bool_], start: tuple[int, int], goal: tuple[int, int]
) -> npt.NDArray[np.int32] | None:
    """Shortest 8-connected path from ``start`` to ``goal`` over ``passable`` cells, or
    ``None`` when ``goal`` cannot be reached.

    The search stops as soon as ``goal`` is settled, so a near goal is cheap.

    >>> free = np.ones((2, 3), dtype=bool)
    >>> path_to(free, (0, 0), (0, 2)).tolist()
    [[0, 0], [0, 1], [0, 2]]
    >>> free[:, 1] = False
    >>> path_to(free, (0, 0), (1, 2)) is None
    True
    """
    only_goal = np.zeros(passable.shape, dtype=bool)
    only_goal[goal] = True
    dist = distance_field(passable, start, targets=only_goal)
    if not np.isfinite(dist[goal]):
        return None
    return extract_path(dist, goal)
