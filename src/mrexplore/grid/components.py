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

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError, ScenarioError

BoolGrid = npt.NDArray[np.bool_]

#: 4-connectivity structuring element, for :func:`scipy.ndimage.label` (which
#: :func:`label_free` matches label for label; the tests compare them).
FOUR_CONNECTED: npt.NDArray[np.bool_] = np.array(
    [[False, True, False], [True, True, True], [False, True, False]]
)


@numba.njit(cache=True, nogil=True)
def _root(parent: npt.NDArray[np.int32], label: int) -> int:
    """The root of ``label`` in the union-find forest ``parent`` (halving the path)."""
    while parent[label] != label:
        parent[label] = parent[parent[label]]
        label = parent[label]
    return label


@numba.njit(cache=True, nogil=True)
def _label_free_kernel(
    occupied: npt.NDArray[np.bool_], labels: npt.NDArray[np.int32], parent: npt.NDArray[np.int32]
) -> int:
    """Fill ``labels`` (zeros on entry) and return the number of components.

    Two passes: the first gives each free cell its upper or left neighbour's
    provisional label (a new one when both are occupied) and joins the two
    labels' sets when they differ; the second renumbers the sets ``1..count`` in
    raster order of their first cell. ``parent`` has room for every provisional
    label (at most ``H * W // 2 + 1``, a checkerboard).
    """
    height, width = occupied.shape
    provisional = 0
    for row in range(height):
        for col in range(width):
            if occupied[row, col]:
                continue
            up = labels[row - 1, col] if row > 0 else 0
            left = labels[row, col - 1] if col > 0 else 0
            if up == 0 and left == 0:
                provisional += 1
                parent[provisional] = provisional
                labels[row, col] = provisional
            elif up == 0:
                labels[row, col] = left
            else:
                labels[row, col] = up
                if left != 0 and left != up:
                    up_root, left_root = _root(parent, up), _root(parent, left)
                    parent[max(up_root, left_root)] = min(up_root, left_root)
    final = np.zeros(provisional + 1, dtype=np.int32)
    count = 0
    for row in range(height):
        for col in range(width):
            if labels[row, col] == 0:
                continue
            root = _root(parent, labels[row, col])
            if final[root] == 0:
                count += 1
                final[root] = count
            labels[row, col] = final[root]
    return count


def label_free(occupied: npt.ArrayLike) -> tuple[npt.NDArray[np.int32], int]:
    """Label the 4-connected free components.

    The same labels as ``scipy.ndimage.label(free, structure=FOUR_CONNECTED)``, by a
    compiled two-pass union-find about as fast as scipy's (importing scipy.ndimage
    would cost a run of a small map more time than the simulation itself).

    Args:
        occupied: ``H x W`` array, truthy = occupied.

    Returns:
        ``(labels, count)``: ``labels`` is an ``H x W`` ``int32`` array, 0 on
        occupied cells and ``1..count`` on free cells; labels are numbered in
        raster order of each component's first cell.

    >>> labels, count = label_free(np.array([[0, 1, 0], [1, 1, 0], [0, 0, 1]]))
    >>> labels.tolist(), count
    ([[1, 0, 2], [0, 0, 2], [3, 3, 0]], 3)
    """
    grid = np.ascontiguousarray(occupied, dtype=bool)
    if grid.ndim != 2:
        raise MrexploreInputError(f"occupied has shape {grid.shape}; a grid is 2-D")
    labels = np.zeros(grid.shape, dtype=np.int32)
    parent = np.empty(grid.size // 2 + 2, dtype=np.int32)
    count = _label_free_kernel(grid, labels, parent)
    return labels, int(count)


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
