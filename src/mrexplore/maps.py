"""The real maps that ship with mrexplore, loaded by short name.

Like ``networkx``'s and ``scikit-image``'s data modules: the files are package
data, so a plain ``pip install mrexplore`` has them and nothing outside the
package is read. Seven ROS ``map_server`` maps (Intel Research Lab, Willow
Garage twice, the AWS small house, the Nav2 depot and warehouse, the LSE arena)
and nine MovingAI grid benchmark maps, each with its source, licence and credit
line (:mod:`mrexplore.grid.catalogue` holds the table).

>>> import mrexplore.maps
>>> "intel" in mrexplore.maps.names()
True
>>> grid = mrexplore.maps.load("intel", cell_size_m=0.2)
>>> grid.name, grid.resolution_m, grid.shape
('intel', 0.2, (186, 172))
>>> mrexplore.maps.info("intel").licence
'CC-BY-1.0'

Names match without regard to case and with ``_`` for ``-`` (``lse_arena``).
The same names work on the command line: ``mrexplore run --map intel``. Folders
of your own maps can be named in ``$MREXPLORE_MAPS`` (see
:func:`~mrexplore.grid.catalogue.user_maps`); their files then load by stem.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mrexplore.errors import UnknownIdError
from mrexplore.grid.catalogue import CATALOGUE, MapEntry, lookup
from mrexplore.grid.components import largest_free_component
from mrexplore.grid.io import load_map
from mrexplore.grid.occupancy import GridMap

__all__ = ["MapEntry", "MapSummary", "info", "load", "names", "path", "summaries"]


def names() -> list[str]:
    """The names of every shipped map, ROS maps first, in catalogue order."""
    return [entry.name for entry in CATALOGUE]


def info(name: str) -> MapEntry:
    """The catalogue entry of a shipped map: file, source, licence, credit.

    Raises:
        UnknownIdError: no shipped map has this name.
    """
    entry = lookup(name)
    if entry is None:
        raise UnknownIdError("catalogue map", name, names())
    return entry


def path(name: str) -> Path:
    """The installed file of a shipped map (the YAML of a ROS map)."""
    return info(name).path


def load(name: str, *, cell_size_m: float | None = None) -> GridMap:
    """Load a shipped map as ground truth, optionally pooled to coarser cells.

    See :func:`~mrexplore.grid.io.load_map` for ``cell_size_m`` and the
    conventions of the returned grid (row 0 at the top, ``True`` = occupied).
    """
    return load_map(info(name).path, cell_size_m=cell_size_m)


@dataclass(frozen=True)
class MapSummary:
    """What ``mrexplore maps`` shows of a shipped map, measured on its file."""

    entry: MapEntry
    width: int
    height: int
    resolution_m: float | None
    explorable_cells: int
    """Cells of the largest 4-connected free region (where robots start)."""


def summaries() -> list[MapSummary]:
    """Size, resolution and explorable cells of every shipped map, at native resolution."""
    out = []
    for entry in CATALOGUE:
        grid = load_map(entry.path)
        height, width = grid.shape
        explorable = int(np.count_nonzero(largest_free_component(grid.occupied)))
        out.append(MapSummary(entry, width, height, grid.resolution_m, explorable))
    return out
