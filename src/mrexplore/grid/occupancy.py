"""Occupancy grids: ground truth and belief maps.

Conventions used everywhere in mrexplore:

* A grid is indexed ``[row, col]``; row 0 is the top of the picture (the first
  image row of a PGM, the first text line of a MovingAI map). Positions are
  ``(row, col)`` integer pairs.
* Ground truth is a boolean (or uint8) array, ``True``/``1`` = occupied.
* A belief map is an ``int8`` array with ``UNKNOWN = -1``, ``FREE = 0`` and
  ``OCCUPIED = 100``, as in ROS ``nav_msgs/OccupancyGrid``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

UNKNOWN: int = -1
FREE: int = 0
OCCUPIED: int = 100

BoolGrid = npt.NDArray[np.bool_]
BeliefGrid = npt.NDArray[np.int8]


@dataclass(frozen=True)
class GridMap:
    """A ground-truth world: which cells are occupied, and where it came from.

    Attributes:
        occupied: ``H x W`` boolean array, ``True`` where a cell blocks motion and sight.
        name: generator id or file name, for reports.
        resolution_m: metres per cell when the source says so, else ``None``.
        source: the path or generator call the map was built from.
        credit: attribution line for maps made by others.
    """

    occupied: BoolGrid
    name: str = "map"
    resolution_m: float | None = None
    source: str = ""
    credit: str = ""
    meta: dict[str, object] = field(default_factory=dict)

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.occupied.shape[0]), int(self.occupied.shape[1]))

    @property
    def free(self) -> BoolGrid:
        return ~self.occupied

    def truth_uint8(self) -> npt.NDArray[np.uint8]:
        """Ground truth as stored in ``trace.npz``: ``uint8``, 1 = occupied."""
        return self.occupied.astype(np.uint8)


def new_belief(shape: tuple[int, int]) -> BeliefGrid:
    """An all-unknown belief map of the given shape."""
    return np.full(shape, UNKNOWN, dtype=np.int8)
