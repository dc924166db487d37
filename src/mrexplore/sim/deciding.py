"""The decide phase: each live robot's strategy sees its :class:`RobotView` and
returns a :class:`Decision`, which is checked and applied to the robot.

Also counts what deciding cost (time, decide calls, plans, distance fields) for the
run record: the distance fields are counted by a
:class:`~mrexplore.planning.distance.FieldCounter` this phase owns and activates
around each decide call.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from typing import Any

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.errors import StrategyError
from mrexplore.grid.occupancy import FREE, BeliefGrid
from mrexplore.planning.distance import FieldCounter
from mrexplore.seeding import Streams
from mrexplore.sim.comms import Comms, Links
from mrexplore.sim.roster import Robot
from mrexplore.sim.scenario import Cell, Scenario
from mrexplore.strategies.base import Decision, RobotView, Strategy

Decider = Callable[[int, RobotView], Decision]
"""``decide(robot_id, view) -> Decision``: replaces the strategies in :meth:`Simulation.step`."""


class Deciding:
    """The strategies of a run, the views they see and the decisions they return."""

    def __init__(
        self,
        scenario: Scenario,
        strategies: Sequence[Strategy],
        robots: Sequence[Robot],
        comms: Comms,
        streams: Streams,
        *,
        comm_range_cells: float,
        sensor_range_cells: float,
    ) -> None:
        self.strategy_id = scenario.strategy
        self.strategies = strategies
        self.robots = robots
        self.comms = comms
        self.streams = streams
        # What every view holds whatever the robot and the tick.
        self._view_constants: dict[str, Any] = {
            "n_robots": len(robots),
            "comm_latency": scenario.latency,
            "comm_range": comm_range_cells,
            "sensor_range": sensor_range_cells,
            "speed": scenario.speed,
        }
        self.decide_seconds = 0.0
        self.decisions = 0
        """Decide calls (one per live robot per tick)."""
        self.plans = 0
        """Decide calls that set a new goal or idled the robot."""
        self.field_decisions = 0
        """Decide calls that computed at least one distance field."""
        self.field_counter = FieldCounter()
        """Counts the distance fields computed inside decide calls."""

    def view_of(self, robot_id: int, tick: int, all_links: Links | None = None) -> RobotView:
        """What robot ``robot_id`` knows at ``tick``: the view its strategy gets."""
        robot = self.robots[robot_id]
        network = self.comms.network
        if all_links is None:
            all_links = frozenset(network.links())
        subnetwork = network.subnetwork_of(robot.id)
        belief_view = robot.belief.view()
        belief_view.flags.writeable = False
        return RobotView(
            robot_id=robot.id,
            tick=tick,
            position=robot.believed,
            belief=belief_view,
            goal=robot.goal,
            path_remaining=robot.path_remaining,
            arrived=robot.arrived,
            blocked=robot.blocked,
            inbox=tuple(robot.inbox),
            subnetwork=subnetwork,
            links=self.comms.subnetwork_links(tick, subnetwork, all_links),
            rng=self.streams.robots[robot.id],
            new_cells=robot.new_cells,
            **self._view_constants,
        )

    def decide(self, tick: int, decide: Decider | None = None) -> None:
        """Every live robot, in id order, decides (``decide`` replaces the strategies
        when given) and its decision is applied."""
        all_links = frozenset(self.comms.network.links())
        fields = self.field_counter
        for robot in self.robots:
            if not robot.alive:
                continue
            view = self.view_of(robot.id, tick, all_links)
            fields_before = fields.count
            started = time.perf_counter()
            with fields:
                if decide is None:
                    decision = self.strategies[robot.id].decide(view)
                else:
                    decision = decide(robot.id, view)
            self.decide_seconds += time.perf_counter() - started
            self.decisions += 1
            if fields.count > fields_before:
                self.field_decisions += 1
            robot.inbox.clear()
            self._apply(robot, decision, tick)

    def _apply(self, robot: Robot, decision: Decision, tick: int) -> None:
        if not isinstance(decision, Decision):
            raise StrategyError(
                f"strategy {self.strategy_id!r} returned {type(decision).__name__}, not a Decision"
            )
        for message in decision.messages:
            if message.sender != robot.id:
                raise StrategyError(f"robot {robot.id} sent a message as robot {message.sender}")
            self.comms.send(dataclasses.replace(message, tick_sent=tick), tick)
        if decision.idle:
            self.plans += 1
            robot.path, robot.goal = None, None
        elif decision.goal is not None:
            self.plans += 1
            path = decision.path
            if path is None:
                raise StrategyError(f"robot {robot.id}: a goal without a path")
            check_path(path, robot.believed, decision.goal, robot.belief)
            robot.goal = (int(decision.goal[0]), int(decision.goal[1]))
            robot.path = np.asarray(path, dtype=np.int32)
            robot.path_index = 0
            robot.blocked_ticks = 0
            if len(robot.path) == 1:  # already there
                robot.path, robot.goal = None, None
        else:
            return
        robot.arrived = False
        robot.blocked = False
        robot.new_cells = 0


_PATH_PROBLEMS = {
    1: "path leaves the map",
    2: "path crosses a cell its robot does not know to be free",
    3: "path has a step that is not to an 8-neighbour",
    4: "path cuts a corner",
}


@numba.njit(cache=True, nogil=True)
def _path_problem(
    cells: npt.NDArray[np.int32], belief: npt.NDArray[np.int8]
) -> int:  # pragma: no cover - compiled
    """The first failing check of :func:`check_path` (a key of ``_PATH_PROBLEMS``), or 0.

    One pass per check, in :func:`check_path`'s order, so that a path with several
    faults gets the same message."""
    height, width = belief.shape
    n = cells.shape[0]
    for k in range(n):
        if cells[k, 0] < 0 or cells[k, 1] < 0 or cells[k, 0] >= height or cells[k, 1] >= width:
            return 1
    for k in range(1, n):
        if belief[cells[k, 0], cells[k, 1]] != 0:
            return 2
    for k in range(1, n):
        step = max(abs(cells[k, 0] - cells[k - 1, 0]), abs(cells[k, 1] - cells[k - 1, 1]))
        if step != 1:
            return 3
    for k in range(1, n):
        d_row = cells[k, 0] - cells[k - 1, 0]
        d_col = cells[k, 1] - cells[k - 1, 1]
        if d_row != 0 and d_col != 0:
            r0, c0 = cells[k - 1, 0], cells[k - 1, 1]
            if belief[r0 + d_row, c0] != 0 or belief[r0, c0 + d_col] != 0:
                return 4
    return 0


def check_path(path: npt.NDArray[np.integer], start: Cell, goal: Cell, belief: BeliefGrid) -> None:
    """Raise :class:`StrategyError` unless ``path`` is a legal route over known-free cells."""
    cells = np.asarray(path)
    if cells.ndim != 2 or cells.shape[1] != 2 or len(cells) == 0:
        raise StrategyError(f"path must be a (K, 2) array of cells, got shape {cells.shape}")
    if tuple(cells[0]) != tuple(start) or tuple(cells[-1]) != tuple(goal):
        raise StrategyError(f"path must run from {start} to {goal}")
    if cells.dtype == np.int32 and cells.flags.c_contiguous and belief.dtype == np.int8:
        problem = _path_problem(cells, belief)  # the checks below, compiled
        if problem:
            raise StrategyError(_PATH_PROBLEMS[problem])
        return
    height, width = belief.shape
    if (cells < 0).any() or (cells[:, 0] >= height).any() or (cells[:, 1] >= width).any():
        raise StrategyError("path leaves the map")
    rows, cols = cells[:, 0], cells[:, 1]
    if (belief[rows[1:], cols[1:]] != FREE).any():
        raise StrategyError("path crosses a cell its robot does not know to be free")
    steps = np.diff(cells, axis=0)
    if (np.abs(steps).max(axis=1, initial=0) != 1).any():
        raise StrategyError("path has a step that is not to an 8-neighbour")
    diagonal = (steps[:, 0] != 0) & (steps[:, 1] != 0)
    if diagonal.any():
        r0, c0 = rows[:-1][diagonal], cols[:-1][diagonal]
        dr, dc = steps[diagonal, 0], steps[diagonal, 1]
        if (belief[r0 + dr, c0] != FREE).any() or (belief[r0, c0 + dc] != FREE).any():
            raise StrategyError("path cuts a corner")
