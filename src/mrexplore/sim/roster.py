"""The roster of a run: every robot's simulator-side state, who is alive, who wakes
late (``start_delay``) and who fails (``fail``, ``failure_rate``).

The roster of all robots and the set still alive are separate: a failed robot keeps
its place (and its cell, an obstacle for the others) but stops moving, sensing and
communicating.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from mrexplore.comm import Message
from mrexplore.grid.occupancy import BeliefGrid, new_belief
from mrexplore.seeding import Streams
from mrexplore.sim.scenario import Cell, Scenario


@dataclass
class Robot:
    """Simulator-side state of one robot (the strategy never sees this object).

    ``position`` is where the robot is (the world's cell); ``believed`` is the cell
    it believes it is on, which its strategy sees and plans from. They differ only
    with odometry drift (:mod:`mrexplore.sim.noise`); without it, the motion phase
    keeps them equal.
    """

    id: int
    position: Cell
    belief: BeliefGrid
    sensed: npt.NDArray[np.bool_]
    alive: bool = True
    path: npt.NDArray[np.int32] | None = None
    path_index: int = 0
    goal: Cell | None = None
    budget: float = 0.0
    distance: float = 0.0
    arrived: bool = False
    blocked: bool = False
    blocked_ticks: int = 0
    new_cells: int = 0
    inbox: list[Message] = field(default_factory=list)
    believed: Cell = (-1, -1)

    def __post_init__(self) -> None:
        if self.believed == (-1, -1):
            self.believed = self.position

    @property
    def travelling(self) -> bool:
        return self.path is not None

    @property
    def path_remaining(self) -> int:
        return 0 if self.path is None else len(self.path) - 1 - self.path_index


class Roster:
    """The robots of a run, in id order, and the ticks at which they start or fail."""

    def __init__(
        self,
        scenario: Scenario,
        starts: tuple[Cell, ...],
        shape: tuple[int, int],
        streams: Streams,
    ) -> None:
        n = scenario.robots
        self.robots = [
            Robot(i, start, new_belief(shape), np.zeros(shape, dtype=bool))
            for i, start in enumerate(starts)
        ]
        self.failures: dict[int, list[int]] = {}
        """Robots failing at a tick (``fail``), by tick."""
        for robot_id, fail_tick in scenario.fail:
            self.failures.setdefault(fail_tick, []).append(robot_id)
        self.coverage_failures: list[tuple[int, float]] = []
        """Robots failing once the team's knowledge reaches a share (``fail_at_coverage``),
        ``any`` already drawn."""
        for robot_id, share in scenario.fail_at_coverage:
            if robot_id == -1:
                robot_id = int(streams.fail_choice.integers(n))
            self.coverage_failures.append((robot_id, share))
        self.failed: set[int] = set()
        self.failure_rate = scenario.failure_rate
        self._failure_draws = streams.failures
        # Robots that start later (``start_delay``) stand dormant until their tick.
        self.wakes: dict[int, list[int]] = {}
        """Dormant robots by the tick they start."""
        if scenario.start_delay > 0:
            first = streams.start_times.integers(0, scenario.start_delay + 1, n)
            for robot, tick in zip(self.robots, first - first.min(), strict=True):
                if tick > 0:
                    robot.alive = False
                    self.wakes.setdefault(int(tick), []).append(robot.id)

    def alive(self) -> frozenset[int]:
        """The ids of the robots alive now."""
        return frozenset(r.id for r in self.robots if r.alive)

    def wake(self, tick: int) -> None:
        """Dormant robots whose start tick is ``tick`` start (``start_delay``), unless
        they failed before."""
        for robot_id in self.wakes.pop(tick, []):
            self.robots[robot_id].alive = robot_id not in self.failed

    def fail(self, tick: int, coverage: float = 0.0) -> None:
        """Robots failing at ``tick`` stop moving, sensing and communicating.

        ``coverage`` is the share of explorable cells the team knew at the end of the
        last tick: robots of ``fail_at_coverage`` whose share it reached fail now.
        A failed robot stays where it is, an obstacle for the others; a dormant robot
        that fails never wakes.
        """
        failing = set(self.failures.get(tick, []))
        if self.coverage_failures:
            reached = [item for item in self.coverage_failures if coverage >= item[1]]
            failing |= {robot_id for robot_id, _ in reached}
            self.coverage_failures = [i for i in self.coverage_failures if i not in reached]
        if self.failure_rate > 0:
            draws = self._failure_draws.random(len(self.robots))
            failing |= {r.id for r in self.robots if r.alive and draws[r.id] < self.failure_rate}
        for robot_id in sorted(failing):
            self.failed.add(robot_id)
            robot = self.robots[robot_id]
            if robot.alive:
                robot.alive = False
                robot.path, robot.goal = None, None
                robot.inbox.clear()
