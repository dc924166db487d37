"""When a run ends, and why: its ``status``.

- ``complete``: the team's union of beliefs holds ``coverage_threshold`` of the
  explorable cells (``complete_when="team"``), or some robot's own belief holds
  every explorable cell (``complete_when="robot"``);
- ``stalled``: no progress for ``stall_ticks`` ticks, no robot left to explore, or
  ``idle_ticks`` ticks with every robot idle (no path, no move, nothing learned by the
  team that tick) and nothing in flight;
- ``max_ticks``: the run reached its limit.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.comm import CommModel
from mrexplore.sim.roster import Robot, Roster
from mrexplore.sim.scenario import Scenario
from mrexplore.sim.sensing import Sensing
from mrexplore.sim.world import World


@numba.njit(cache=True, nogil=True)
def _first_unknown(
    belief: npt.NDArray[np.int8], cells: npt.NDArray[np.int64], start: int
) -> int:  # pragma: no cover - compiled
    """The first position ``k >= start`` with ``belief[cells[k]]`` unknown, or
    ``len(cells)`` when there is none."""
    k = start
    while k < cells.shape[0] and belief[cells[k]] != -1:
        k += 1
    return k


class EndCondition:
    """The end conditions of a run, checked at the end of every tick."""

    def __init__(
        self,
        scenario: Scenario,
        world: World,
        roster: Roster,
        sensing: Sensing,
        network: CommModel,
    ) -> None:
        self.roster = roster
        self.robots: Sequence[Robot] = roster.robots
        self.sensing = sensing
        self.network = network
        self.by_robot = scenario.complete_when == "robot"
        self.idle_ticks = scenario.idle_ticks
        self.n_explorable = world.n_explorable
        self.target = math.ceil(scenario.coverage_threshold * self.n_explorable - 1e-9)
        """Known explorable cells that complete the run (``complete_when="team"``)."""
        self.stall_ticks = (
            scenario.stall_ticks
            if scenario.stall_ticks is not None
            else math.ceil(1.5 * self.n_explorable / scenario.speed) + 100
        )
        self.max_ticks = (
            scenario.max_ticks
            if scenario.max_ticks is not None
            else max(1000, math.ceil(20 * self.n_explorable / scenario.speed))
        )
        # Per robot: the first tick its own belief held every explorable cell (-1: not
        # yet), found by a scan over the explorable cells that resumes where it stopped.
        self._explorable_cells = np.flatnonzero(world.explorable.reshape(-1)).astype(np.int64)
        self._robot_scan = np.zeros(len(self.robots), dtype=np.int64)
        self.robot_complete = np.full(len(self.robots), -1, dtype=np.int32)
        self._last_progress_tick = 0
        self._last_known = 0
        self._last_travelled = 0.0
        self._idle_streak = 0

    def start(self) -> str | None:
        """The status at tick 0 (``None``: the run goes on)."""
        self._check_robots_complete(0)
        self._last_progress_tick, self._last_known = 0, self._progress()
        self._last_travelled = sum(r.distance for r in self.robots)
        self._idle_streak = 0
        if self._complete():
            return "complete"
        if self.max_ticks <= 0:
            return "max_ticks"
        return None

    def check(self, tick: int) -> str | None:
        """The status at the end of ``tick`` (``None``: the run goes on)."""
        self._check_robots_complete(tick)
        if self._complete():
            return "complete"
        progress = self._progress()
        learned = progress > self._last_known
        if learned:
            self._last_known, self._last_progress_tick = progress, tick
        elif tick - self._last_progress_tick >= self.stall_ticks:
            return "stalled"
        travelled = sum(r.distance for r in self.robots)
        moved, self._last_travelled = travelled > self._last_travelled, travelled
        waiting = bool(self.roster.wakes)  # dormant robots will start later
        if not any(r.alive for r in self.robots) and not waiting:
            return "stalled"  # nobody left to explore
        # Idle: no robot has a path, none moved and the team learned nothing this tick,
        # and nothing is in flight. A robot whose goal is always the next cell has no
        # path after each move, but it moves and learns: it is not idle.
        all_idle = not waiting and all(r.path is None for r in self.robots if r.alive)
        idle = all_idle and not learned and not moved and self.network.in_flight() == 0
        self._idle_streak = self._idle_streak + 1 if idle else 0
        if self._idle_streak >= self.idle_ticks:
            return "stalled"
        if tick >= self.max_ticks:
            return "max_ticks"
        return None

    def _check_robots_complete(self, tick: int) -> None:
        """Stamp :attr:`robot_complete` for robots whose belief now holds every
        explorable cell. Beliefs mostly only gain cells, so each robot's scan resumes
        at the first cell it found unknown; a scan that reaches the end is checked
        over every cell (a mechanism such as ``polygon`` may forget cells)."""
        cells = self._explorable_cells
        for robot in self.robots:
            i = robot.id
            if self.robot_complete[i] >= 0 or not robot.alive:
                continue
            belief = robot.belief.reshape(-1)
            self._robot_scan[i] = _first_unknown(belief, cells, int(self._robot_scan[i]))
            if self._robot_scan[i] < cells.size:
                continue
            self._robot_scan[i] = _first_unknown(belief, cells, 0)
            if self._robot_scan[i] == cells.size:
                self.robot_complete[i] = tick

    def _complete(self) -> bool:
        if self.by_robot:
            return bool((self.robot_complete >= 0).any())
        return self.sensing.known_explorable >= self.target

    def _progress(self) -> int:
        """What must grow for the run not to stall: the team's known explorable cells
        (and, when a robot's map completes the run, how far the robots' scans got)."""
        if self.by_robot:
            return self.sensing.known_explorable + int(self._robot_scan.sum())
        return self.sensing.known_explorable
