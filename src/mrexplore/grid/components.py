"""Connected components of the free space of a ground-truth grid.

Free cells are connected **4-ways** (edge neighbours). That is exactly the
reachability of a robot that moves 8-ways without cutting corners: a diagonal
step is only allowed when both edge neighbours it passes are free, so any path
of such moves can be rewritten as a 4-connected path, and vice versa.

Grids follow :mod:`mrexplore.grid.occupancy`: indexed ``[row, col]``, row 0 at the
top, ``True`` = occupied.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from mrexplore.errors import ScenarioError

BoolGrid = npt.NDArray[np.bool_]

#: 4-connectivity structuring element for :func:`scipy.ndimage.label`.
FOUR_CONNECTED: npt.NDArray[np.bool_] = np.array(
    [[False, True, False], [True, True, True], [False, True, False]]
)


def label_free(occupied: npt.ArrayLike) -> tuple[npt.NDArray[np.int32], int]:
    """Label the 4-connected free components.

    Args:
        occupied: ``H x W`` array, truthy = occupied.

    Returns:
        ``(labels, count)``: ``labels`` is an ``H x W`` ``int32`` array, 0 on
        occupied cells and ``1..count`` on free cells; labels are numbered in
        raster order of each component's first cell.
    """
    free = ~np.asarray(occupied, dtype=bool)
    labels, count = ndimage.label(free, structure=FOUR_CONNECTED)
    return labels.astype(np.int32, copy=False), int(count)


def largest_free_component(occupied: npt.ArrayLike) -> BoolGrid:
    """Mask of the largest 4-connected free component.

    Ties are broken by the lowest label, i.e. the component whose first cell
    comes first in raster order (row by row from the top).

    Args:
        occupied: ``H x W`` array, truthy = occupied.

    Returns:
        ``H x W`` bool mask, ``True`` on the cells of the largest free component;
        all ``False`` if there is no free cell.

    >>> import numpy as np
    >>> occ = np.array([[0, 1, 0, 0]], dtype=bool)
    >>> largest_free_component(occ).tolist()
    [[False, False, True, True]]
    """
    labels, count = label_free(occupied)
    if count == 0:
        return np.zeros(labels.shape, dtype=bool)
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    sizes[0] = 0  # label 0 is the occupied cells
    best = int(np.argmax(sizes))  # argmax returns the first maximum: lowest label
    return labels == best


def free_component_of(occupied: npt.ArrayLike, cells: Iterable[tuple[int, int]]) -> BoolGrid:
    """Union of the 4-connected free components that contain any of ``cells``.

    Args:
        occupied: ``H x W`` array, truthy = occupied.
        cells: ``(row, col)`` pairs. An occupied cell belongs to no component
            and adds nothing.

    Returns:
        ``H x W`` bool mask.

    Raises:
        ScenarioError: a cell lies outside the grid.
    """
    labels, _count = label_free(occupied)
    height, width = labels.shape
    wanted: set[int] = set()
    for cell in cells:
        row, col = (int(v) for v in cell)
        if not (0 <= row < height and 0 <= col < width):
            raise ScenarioError(f"cell ({row}, {col}) is outside the {width}x{height} grid")
        label = int(labels[row, col])
        if label:
            wanted.add(label)
    if not wanted:
        return np.zeros(labels.shape, dtype=bool)
    return np.isin(labels, np.fromiter(wanted, dtype=np.int32))
