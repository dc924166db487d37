"""The union of many equal disks on a grid, painted through one stamp per radius.

:func:`~mrexplore.planning.masks.disk_mask` scatters the ``K`` cells of each disk
through fancy indexing (about 1 ms per call for a few robots at a 40-cell sensor
range). :func:`disks_mask` gives the same mask by OR-ing one precomputed
``(2k + 1) x (2k + 1)`` stamp, built from the very same
:func:`~mrexplore.planning.visibility.disk_offsets` table, into the window around each
centre (clipped at the border).
"""

from __future__ import annotations

import functools
from collections.abc import Iterable

import numpy as np
import numpy.typing as npt

from mrexplore.planning.visibility import clip_radius, disk_offsets

__all__ = ["disk_stamp", "disks_mask"]


@functools.lru_cache(maxsize=16)
def disk_stamp(radius: float) -> npt.NDArray[np.bool_]:
    """Read-only ``(2k + 1) x (2k + 1)`` mask of :func:`disk_offsets` ``(radius)`` shifted by
    ``k``, the largest offset.

    >>> disk_stamp(1.0).astype(int).tolist()
    [[0, 1, 0], [1, 1, 1], [0, 1, 0]]
    """
    offsets = disk_offsets(radius)
    reach = int(np.abs(offsets).max())
    stamp = np.zeros((2 * reach + 1, 2 * reach + 1), dtype=bool)
    stamp[offsets[:, 0] + reach, offsets[:, 1] + reach] = True
    stamp.flags.writeable = False
    return stamp


def disks_mask(
    shape: tuple[int, int], centres: Iterable[tuple[int, int]], radius: float
) -> npt.NDArray[np.bool_]:
    """``H x W`` mask of the cells within ``radius`` (cells, Euclidean) of any of
    ``centres``: exactly :func:`~mrexplore.planning.masks.disk_mask`.

    >>> disks_mask((3, 4), [(1, 1)], 1.0).astype(int).tolist()
    [[0, 1, 0, 0], [1, 1, 1, 0], [0, 1, 0, 0]]
    """
    height, width = shape
    mask = np.zeros(shape, dtype=bool)
    stamp = disk_stamp(clip_radius(radius, shape))
    reach = stamp.shape[0] // 2
    for row, col in centres:
        top, bottom = max(row - reach, 0), min(row + reach + 1, height)
        left, right = max(col - reach, 0), min(col + reach + 1, width)
        if top >= bottom or left >= right:
            continue
        window = mask[top:bottom, left:right]
        window |= stamp[
            top - row + reach : bottom - row + reach, left - col + reach : right - col + reach
        ]
    return mask
