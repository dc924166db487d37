"""Line-of-sight disk sensor: what a robot sees from its cell.

A robot at cell ``s`` with sensor range ``R`` (cells) observes every cell ``t``
of the grid with ``(t_row - s_row)**2 + (t_col - s_col)**2 <= R**2`` that is
visible from ``s`` under the line-of-sight rule of
:mod:`mrexplore.planning.visibility` (summary: the grid line from ``s`` to ``t``
crosses no occupied cell before ``t`` and never squeezes diagonally between two
occupied cells; the blocking cell itself is seen). The simulator and trace
validation both call :func:`visible_cells`, so there is exactly one definition.

Example:
    >>> import numpy as np
    >>> from mrexplore.grid.occupancy import new_belief
    >>> world = np.zeros((5, 5), dtype=bool)
    >>> world[2, :] = True  # a wall across the middle
    >>> belief = new_belief(world.shape)
    >>> rows, cols, values = observe(belief, world, (0, 0), radius=4.0)
    >>> bool(belief[2, 0] == 100), bool(belief[3, 0] == -1)  # wall seen, not behind
    (True, True)
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, BeliefGrid, BoolGrid
from mrexplore.planning._validate import as_bool_grid, as_cell, as_radius
from mrexplore.planning.visibility import (
    clip_radius,
    is_visible_kernel,
    ray_table,
    visible_cells_kernel,
)

__all__ = ["is_visible", "observe", "visible_cells", "visible_cells_flat"]

IntArray = npt.NDArray[np.int64]


def _visible_flat(grid: BoolGrid, row: int, col: int, radius: float) -> IntArray:
    """Flat indices of the cells visible from ``(row, col)``; inputs already validated."""
    table = ray_table(clip_radius(radius, grid.shape))
    height, width = grid.shape
    out = np.empty(table.n_cells, dtype=np.int64)
    n_visible = visible_cells_kernel(
        grid.reshape(-1),
        height,
        width,
        row,
        col,
        table.flags,
        table.cell,
        table.parent,
        table.skip,
        table.reach,
        out,
    )
    return out[:n_visible]


def visible_cells_flat(occupied: BoolGrid, position: tuple[int, int], radius: float) -> IntArray:
    """:func:`visible_cells` as flat indices ``row * W + col`` (same cells, same order)."""
    grid = as_bool_grid(occupied, "occupied")
    row, col = as_cell(position, grid.shape, "position")
    return _visible_flat(grid, row, col, as_radius(radius, "radius"))


def visible_cells(
    occupied: BoolGrid, position: tuple[int, int], radius: float
) -> tuple[IntArray, IntArray]:
    """Cells seen by a robot at ``position`` with sensor range ``radius``.

    Args:
        occupied: ``H x W`` ground truth, ``True`` = occupied (blocks sight).
        position: robot cell ``(row, col)``, inside the grid.
        radius: sensor range in cells (float, ``>= 0``).

    Returns:
        ``(rows, cols)``, int64 arrays of equal length: every visible cell once,
        the robot's own cell first, then a fixed order (the ray table's, not
        sorted). Cells outside the grid are left out.

    Raises:
        MrexploreInputError: bad grid, position outside it, or a bad radius.
    """
    grid = as_bool_grid(occupied, "occupied")
    row, col = as_cell(position, grid.shape, "position")
    flat = _visible_flat(grid, row, col, as_radius(radius, "radius"))
    rows, cols = np.divmod(flat, grid.shape[1])
    return rows, cols


@numba.njit(cache=True, nogil=True)
def _observe_kernel(
    belief: npt.NDArray[np.int8],
    occupied: npt.NDArray[np.bool_],
    visible: IntArray,
    new_cells: IntArray,
    new_values: npt.NDArray[np.int8],
) -> int:
    """Write the truth of ``visible`` cells into flat ``belief``; list those that were unknown."""
    n_new = 0
    for index in visible:
        value = np.int8(OCCUPIED) if occupied[index] else np.int8(FREE)
        if belief[index] == UNKNOWN:
            new_cells[n_new] = index
            new_values[n_new] = value
            n_new += 1
        belief[index] = value
    return n_new


def observe(
    belief: BeliefGrid, occupied: BoolGrid, position: tuple[int, int], radius: float
) -> tuple[IntArray, IntArray, npt.NDArray[np.int8]]:
    """Sense from ``position``: write what is seen into ``belief`` and report what is new.

    Every visible cell (see :func:`visible_cells`) gets its true state, ``FREE``
    or ``OCCUPIED``, in ``belief`` (in place; a cell known before is overwritten
    with the truth too).

    Args:
        belief: ``H x W`` int8 belief map, C-contiguous, modified in place.
        occupied: ``H x W`` ground truth, ``True`` = occupied.
        position: robot cell ``(row, col)``.
        radius: sensor range in cells.

    Returns:
        ``(rows, cols, values)`` of the visible cells that were ``UNKNOWN`` in
        ``belief`` before the call (the new knowledge), in :func:`visible_cells`
        order; ``values`` is int8 (``FREE`` or ``OCCUPIED``).

    Raises:
        MrexploreInputError: mismatched shapes, a belief that is not a writable,
            C-contiguous int8 array, a position outside the grid, or a bad radius.
    """
    grid = as_bool_grid(occupied, "occupied")
    if not isinstance(belief, np.ndarray) or belief.dtype != np.int8:
        raise MrexploreInputError("belief must be an int8 numpy array (UNKNOWN=-1, FREE=0, ...)")
    if belief.shape != grid.shape:
        raise MrexploreInputError(f"belief has shape {belief.shape}, ground truth has {grid.shape}")
    if not (belief.flags.c_contiguous and belief.flags.writeable):
        raise MrexploreInputError(
            "belief must be writable and C-contiguous (it is updated in place)"
        )
    row, col = as_cell(position, grid.shape, "position")
    visible = _visible_flat(grid, row, col, as_radius(radius, "radius"))
    new_cells = np.empty(visible.shape[0], dtype=np.int64)
    new_values = np.empty(visible.shape[0], dtype=np.int8)
    n_new = _observe_kernel(belief.reshape(-1), grid.reshape(-1), visible, new_cells, new_values)
    rows, cols = np.divmod(new_cells[:n_new], grid.shape[1])
    return rows, cols, new_values[:n_new]


def is_visible(occupied: BoolGrid, viewer: tuple[int, int], target: tuple[int, int]) -> bool:
    """Whether ``target`` is in line of sight of ``viewer`` (range not considered).

    A robot at ``viewer`` with range ``R`` observes ``target`` exactly when this is
    true and the squared offset is ``<= R**2``. Walks the line directly instead of
    using the ray table, so tests can check one against the other.

    Raises:
        MrexploreInputError: bad grid, or a cell outside it.
    """
    grid = as_bool_grid(occupied, "occupied")
    row, col = as_cell(viewer, grid.shape, "viewer")
    target_row, target_col = as_cell(target, grid.shape, "target")
    return bool(is_visible_kernel(grid, row, col, target_row, target_col))
