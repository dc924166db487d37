"""The tick loop, scenarios and run records.

:class:`Scenario` (``scenario.py``) is what the user asked for, checked in one place
by :meth:`Scenario.check`; :func:`build_world` (``world.py``) resolves it against its
map. :class:`Simulation` (``engine.py``) assembles one part per phase of a tick and
runs them in order: ``roster.py`` (robots, starts and failures), ``comms.py`` (links,
delivery, sending), ``deciding.py`` (views and decisions), ``motion.py`` (moves),
``sensing.py`` (sensing and the team's knowledge), ``stamps.py`` (each robot's own
first-known ticks), ``recorder.py`` (per-tick logs and the :class:`RunRecord` of
``record.py``) and ``end.py`` (the run's status).
"""

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
