"""Planning primitives on occupancy grids: pure functions, no simulator state.

- :mod:`~mrexplore.planning.distance`: exact 8-connected distance fields
  (straight step 1, diagonal sqrt(2), no corner cutting) and path extraction.
- :mod:`~mrexplore.planning.frontiers`: frontier cells and clusters.
- :mod:`~mrexplore.planning.gain`: information gain of candidate cells, and the
  information-gain filter of frontier points.
- :mod:`~mrexplore.planning.paths`: the path to one goal (:func:`path_to`).
- :mod:`~mrexplore.planning.masks`: cells within a radius of a set of centres.
- :mod:`~mrexplore.planning.visibility`: the line-of-sight rule shared with
  :mod:`mrexplore.sensing`.

Compiled kernels (numba) are built on first call and cached on disk, so importing
this package compiles nothing.
"""

from mrexplore.planning.distance import (
    SQRT2,
    UnreachableTargetError,
    distance_field,
    extract_path,
    path_length,
)
from mrexplore.planning.frontiers import FrontierCluster, frontier_clusters, frontier_mask
from mrexplore.planning.gain import filter_by_gain, information_gain
from mrexplore.planning.masks import disk_mask
from mrexplore.planning.paths import path_to
from mrexplore.planning.visibility import bresenham_line, clip_radius, disk_offsets, ray_table

__all__ = [
    "SQRT2",
    "FrontierCluster",
    "UnreachableTargetError",
    "bresenham_line",
    "clip_radius",
    "disk_mask",
    "disk_offsets",
    "distance_field",
    "extract_path",
    "filter_by_gain",
    "frontier_clusters",
    "frontier_mask",
    "information_gain",
    "path_length",
    "path_to",
    "ray_table",
]
