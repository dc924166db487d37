"""The tick loop, scenarios and run records."""

from mrexplore.sim.engine import Simulation, check_path, simulate
from mrexplore.sim.record import RunRecord
from mrexplore.sim.scenario import Scenario, parse_cells, parse_length, parse_size
from mrexplore.sim.world import World, build_world

__all__ = [
    "RunRecord",
    "Scenario",
    "Simulation",
    "World",
    "build_world",
    "check_path",
    "parse_cells",
    "parse_length",
    "parse_size",
    "simulate",
]
