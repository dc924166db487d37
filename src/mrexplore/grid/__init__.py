"""Occupancy grids, world generators and map file readers / writers.

Grids are indexed ``[row, col]`` with row 0 at the top; ground truth is a bool
array with ``True`` = occupied (see :mod:`mrexplore.grid.occupancy`).
"""

from mrexplore.grid.components import free_component_of, largest_free_component
from mrexplore.grid.generators import GENERATORS, GeneratorInfo, generate_map, list_generators
from mrexplore.grid.io import downsample, load_map, resample_to_cell_size, write_map
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, GridMap, new_belief

__all__ = [
    "FREE",
    "GENERATORS",
    "OCCUPIED",
    "UNKNOWN",
    "GeneratorInfo",
    "GridMap",
    "downsample",
    "free_component_of",
    "generate_map",
    "largest_free_component",
    "list_generators",
    "load_map",
    "new_belief",
    "resample_to_cell_size",
    "write_map",
]
