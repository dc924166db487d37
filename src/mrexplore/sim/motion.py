"""The move phase: robots advance along their paths, one cell of a grid each.

Each robot advances up to its budget of ``speed`` cells of path (a diagonal step
costs sqrt 2; an unused budget carries over up to ``speed + sqrt 2``); a robot never
enters a cell another robot holds: it waits, after ``patience`` ticks detours around
the robots it can see, else gives up its goal (the strategy is told it was
``blocked``). A step into a wall that the robot's map did not show stops it too.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from mrexplore.grid.occupancy import FREE
from mrexplore.planning import distance_field, extract_path
from mrexplore.sim.roster import Robot
from mrexplore.sim.scenario import Cell, Scenario
from mrexplore.sim.stamps import BeliefStamps

SQRT2 = math.sqrt(2.0)
DETOUR_LOOKAHEAD = 3
"""Cells of a right-of-way robot's path that a detour keeps clear."""


class Motion:
    """Who stands where (``occupant``) and how robots move, wait and detour."""

    def __init__(
        self,
        scenario: Scenario,
        robots: Sequence[Robot],
        truth: npt.NDArray[np.bool_],
        truth_state: npt.NDArray[np.int8],
        sensor_range_cells: float,
        stamps: BeliefStamps,
    ) -> None:
        self.robots = robots
        self.speed = scenario.speed
        self.patience = scenario.patience
        self.truth = truth
        self.truth_state = truth_state
        self.sensor_range_cells = sensor_range_cells
        self.stamps = stamps
        self.occupant = np.full(truth.shape, -1, dtype=np.int32)
        """The id of the robot on each cell, -1 where none stands."""
        for robot in robots:
            self.occupant[robot.position] = robot.id

    def move(self, tick: int) -> None:
        """Every live robot with a path advances (in id order)."""
        speed = self.speed
        for robot in self.robots:
            if not robot.alive or robot.path is None:
                robot.budget = 0.0
                continue
            robot.budget = min(robot.budget + speed, speed + SQRT2)
            path = robot.path
            blocker: Robot | None = None
            moved = False
            while robot.path_index < len(path) - 1:
                nxt = (int(path[robot.path_index + 1, 0]), int(path[robot.path_index + 1, 1]))
                diagonal = nxt[0] != robot.position[0] and nxt[1] != robot.position[1]
                step = SQRT2 if diagonal else 1.0
                if step > robot.budget + 1e-9:
                    break
                if self._bumps(robot, nxt, tick):
                    break
                if self.occupant[nxt] >= 0:
                    blocker = self.robots[int(self.occupant[nxt])]
                    break
                self.occupant[robot.position] = -1
                self.occupant[nxt] = robot.id
                robot.position = nxt
                robot.budget -= step
                robot.distance += step
                robot.path_index += 1
                moved = True
            if robot.path is None:  # it bumped into a wall its map did not show
                continue
            if robot.path_index >= len(path) - 1:
                robot.path, robot.goal = None, None
                robot.arrived = True
                robot.budget = 0.0
                robot.blocked_ticks = 0
            elif blocker is not None:
                robot.blocked_ticks += 1
                # Right of way: a robot blocked by a travelling robot with a higher id
                # waits for it to swerve, and only detours itself after a long wait.
                patience = self.patience
                if blocker.id > robot.id and blocker.path is not None:
                    patience *= 4
                if robot.blocked_ticks >= patience:
                    self._detour(robot)
            elif moved:
                robot.blocked_ticks = 0

    def _bumps(self, robot: Robot, nxt: Cell, tick: int) -> bool:
        """Whether the step to ``nxt`` hits a wall (or cuts a wall corner).

        A path is planned on the robot's belief, which received maps (e.g. polygon
        approximations) can get wrong. The robot's short-range sensing stops it in
        front of the wall: it learns the cells of the step, drops its goal and is
        told it was ``blocked``. With exact maps this never happens.
        """
        row, col = robot.position
        step_cells = [nxt]
        if nxt[0] != row and nxt[1] != col:
            step_cells += [(nxt[0], col), (row, nxt[1])]
        if not any(self.truth[cell] for cell in step_cells):
            return False
        for cell in step_cells:
            robot.belief[cell] = self.truth_state[cell]
        self.stamps.bumped(robot.id, step_cells, tick)
        robot.path, robot.goal = None, None
        robot.blocked = True
        robot.budget = 0.0
        return True

    def _detour(self, robot: Robot) -> None:
        """Re-route around the robots this one can see; give up the goal if impossible.

        Robots with a lower id have right of way: the detour also avoids the next
        ``DETOUR_LOOKAHEAD`` cells of their paths, so two robots meeting head-on in
        a corridor do not both swerve into the same lane.
        """
        assert robot.goal is not None
        passable = robot.belief == FREE
        radius2 = self.sensor_range_cells * self.sensor_range_cells
        for other in self.robots:
            if other.id == robot.id:  # a failed robot still blocks its cell
                continue
            d_row = other.position[0] - robot.position[0]
            d_col = other.position[1] - robot.position[1]
            if d_row * d_row + d_col * d_col > radius2:
                continue
            passable[other.position] = False
            if other.alive and other.id < robot.id and other.path is not None:
                ahead = other.path[other.path_index + 1 : other.path_index + 1 + DETOUR_LOOKAHEAD]
                passable[ahead[:, 0], ahead[:, 1]] = False
        passable[robot.position] = True
        goal = robot.goal
        dist = distance_field(passable, robot.position)
        robot.blocked_ticks = 0
        if goal != robot.position and np.isfinite(dist[goal]):
            robot.path = extract_path(dist, goal)
            robot.path_index = 0
            return
        robot.path, robot.goal = None, None
        robot.blocked = True
