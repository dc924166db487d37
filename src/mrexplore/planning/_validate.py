"""Input checks shared by the public planning and sensing functions.

Kernels trust their arguments; these helpers run once per public call, at the
edge, and raise :class:`mrexplore.errors.MrexploreInputError` with a message
that says what was wrong.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError


def as_bool_grid(grid: npt.ArrayLike, name: str) -> npt.NDArray[np.bool_]:
    """Return ``grid`` as a C-contiguous 2-D boolean array (no copy when it already is)."""
    array = np.asarray(grid)
    if array.ndim != 2:
        raise MrexploreInputError(f"{name} must be a 2-D grid, got shape {array.shape}")
    if array.dtype != np.bool_:
        if not (np.issubdtype(array.dtype, np.integer) or np.issubdtype(array.dtype, np.bool_)):
            raise MrexploreInputError(
                f"{name} must be a boolean (or 0/1 integer) grid, got dtype {array.dtype}"
            )
        array = array != 0
    return np.ascontiguousarray(array)


def as_belief_grid(belief: npt.ArrayLike, name: str = "belief") -> npt.NDArray[np.int8]:
    """Return ``belief`` as a C-contiguous 2-D ``int8`` array (no copy when it already is)."""
    array = np.asarray(belief)
    if array.ndim != 2:
        raise MrexploreInputError(f"{name} must be a 2-D grid, got shape {array.shape}")
    if array.dtype != np.int8:
        raise MrexploreInputError(
            f"{name} must be an int8 belief map (UNKNOWN=-1, FREE=0, OCCUPIED=100), "
            f"got dtype {array.dtype}"
        )
    return np.ascontiguousarray(array)


def as_cell(cell: object, shape: tuple[int, ...], name: str) -> tuple[int, int]:
    """Return ``cell`` as a ``(row, col)`` pair of Python ints inside a grid of ``shape``."""
    try:
        row, col = (int(v) for v in cell)  # type: ignore[attr-defined]  # any 2-sequence
    except (TypeError, ValueError):
        raise MrexploreInputError(f"{name} must be a (row, col) pair, got {cell!r}") from None
    if not (0 <= row < shape[0] and 0 <= col < shape[1]):
        raise MrexploreInputError(
            f"{name} {(row, col)} lies outside the {shape[0]} x {shape[1]} grid"
        )
    return row, col


def as_cells(cells: npt.ArrayLike, shape: tuple[int, ...], name: str) -> npt.NDArray[np.int64]:
    """Return ``cells`` as a C-contiguous ``(K, 2)`` int64 array of in-grid ``(row, col)``."""
    array = np.asarray(cells)
    if array.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if array.ndim != 2 or array.shape[1] != 2:
        raise MrexploreInputError(f"{name} must have shape (K, 2), got {array.shape}")
    if not np.issubdtype(array.dtype, np.integer):
        raise MrexploreInputError(f"{name} must hold integer (row, col), got dtype {array.dtype}")
    array = np.ascontiguousarray(array, dtype=np.int64)
    outside = (
        (array[:, 0] < 0)
        | (array[:, 0] >= shape[0])
        | (array[:, 1] < 0)
        | (array[:, 1] >= shape[1])
    )
    if outside.any():
        first = int(np.flatnonzero(outside)[0])
        raise MrexploreInputError(
            f"{name}[{first}] = {tuple(int(v) for v in array[first])} lies outside the "
            f"{shape[0]} x {shape[1]} grid"
        )
    return array


def as_radius(radius: object, name: str = "radius") -> float:
    """Return ``radius`` (cells) as a finite, non-negative float."""
    try:
        value = float(radius)  # type: ignore[arg-type]  # validated just below
    except (TypeError, ValueError):
        raise MrexploreInputError(f"{name} must be a number of cells, got {radius!r}") from None
    if not np.isfinite(value) or value < 0:
        raise MrexploreInputError(f"{name} must be finite and >= 0 cells, got {radius!r}")
    return value
