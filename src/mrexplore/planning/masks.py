"""Masks of the cells around a set of centres (areas that robots sense or will sense)."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import numpy.typing as npt

from mrexplore.planning.visibility import clip_radius, disk_offsets


def disk_mask(
    shape: tuple[int, int], centres: Iterable[tuple[int, int]], radius: float
) -> npt.NDArray[np.bool_]:
    """``H x W`` mask of the cells within ``radius`` (cells, Euclidean) of any of
    ``centres``, clipped at the border of the map.

    >>> disk_mask((3, 4), [(1, 1)], 1.0).astype(int).tolist()
    [[0, 1, 0, 0], [1, 1, 1, 0], [0, 1, 0, 0]]
    >>> disk_mask((2, 2), [], 5.0).any()
    np.False_
    """
    mask = np.zeros(shape, dtype=bool)
    offsets = disk_offsets(clip_radius(radius, shape))  # same cells, bounded table
    for row, col in centres:  # one disk at a time: a few centres, possibly a large disk
        rows = offsets[:, 0] + row
        cols = offsets[:, 1] + col
        inside = (rows >= 0) & (rows < shape[0]) & (cols >= 0) & (cols < shape[1])
        mask[rows[inside], cols[inside]] = True
    return mask
