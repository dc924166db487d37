"""The move phase: robots advance along their paths, one cell of a grid each.

Each robot advances up to its budget of ``speed`` cells of path (a diagonal step
costs sqrt 2; an unused budget carries over up to ``speed + sqrt 2``); a robot never
enters a cell another robot holds: it waits, after ``patience`` ticks detours around
the robots it can see, else gives up its goal (the strategy is told it was
``blocked``). A step into a wall that the robot's map did not show stops it too.

Paths are planned in the robot's belief, from the cell it believes it is on; the
robot executes their steps in the world from where it is. Without odometry drift
the two cells are the same; with it (:mod:`mrexplore.sim.noise`) each step moves the
robot's estimate too, and a wall its map puts elsewhere can be bumped into.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from mrexplore.grid.occupancy import FREE, OCCUPIED
from mrexplore.planning import distance_field, extract_path
from mrexplore.planning.visibility import is_visible_kernel
from mrexplore.sim.noise import Odometry
from mrexplore.sim.roster import Robot
from mrexplore.sim.scenario import Cell, Scenario
from mrexplore.sim.sensing import Sensing
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
        *,
        odometry: Odometry | None = None,
        sensing: Sensing | None = None,
    ) -> None:
        self.robots = robots
        self.speed = scenario.speed
        self.patience = scenario.patience
        self.truth = truth
        self.truth_state = truth_state
        self.sensor_range_cells = sensor_range_cells
        self.stamps = stamps
        self.odometry = odometry
        self.sensing = sensing
        self.meeting = odometry is not None and odometry.model.reset == "meeting"
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
                # the planned step, made from where the robot is (with drift, not where
                # it believes it is)
                k = robot.path_index
                d_row = int(path[k + 1, 0]) - int(path[k, 0])
                d_col = int(path[k + 1, 1]) - int(path[k, 1])
                nxt = (robot.position[0] + d_row, robot.position[1] + d_col)
                step = SQRT2 if d_row != 0 and d_col != 0 else 1.0
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
                if self.odometry is None:
                    robot.believed = nxt
                else:
                    self.odometry.moved(robot.id, d_row, d_col)
                    robot.believed = self.odometry.believed_cell(robot.id)
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
        if self.meeting:
            self._meet()

    def _meet(self) -> None:
        """``reset = meeting``: robots that see each other correct their estimates."""
        assert self.odometry is not None
        radius2 = self.sensor_range_cells * self.sensor_range_cells
        live = [r for r in self.robots if r.alive]
        pairs = []
        for a_index, a in enumerate(live):
            for b in live[a_index + 1 :]:
                d_row = a.position[0] - b.position[0]
                d_col = a.position[1] - b.position[1]
                if d_row * d_row + d_col * d_col > radius2:
                    continue
                if is_visible_kernel(self.truth, *a.position, *b.position):
                    pairs.append((a.id, b.id))
        if not pairs:
            return
        self.odometry.meet(pairs, [r.position for r in self.robots])
        for robot in live:
            robot.believed = self.odometry.believed_cell(robot.id)

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
        height, width = self.truth.shape
        if all(0 <= r < height and 0 <= c < width for r, c in step_cells) and not any(
            self.truth[cell] for cell in step_cells
        ):
            return False
        # What the robot learns, where it believes the cells are (without drift, there).
        b_row, b_col = robot.believed[0] - row, robot.believed[1] - col
        learned = []
        for cell in step_cells:
            at = (cell[0] + b_row, cell[1] + b_col)
            if at == robot.believed or not (0 <= at[0] < height and 0 <= at[1] < width):
                continue
            inside = 0 <= cell[0] < height and 0 <= cell[1] < width
            robot.belief[at] = self.truth_state[cell] if inside else OCCUPIED
            learned.append(at)
        if self.sensing is not None:
            self.sensing.bumped(
                robot, [r * width + c for r, c in learned if robot.belief[r, c] == OCCUPIED]
            )
        self.stamps.bumped(robot.id, learned, tick)
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
        height, width = passable.shape
        radius2 = self.sensor_range_cells * self.sensor_range_cells
        for other in self.robots:
            if other.id == robot.id:  # a failed robot still blocks its cell
                continue
            d_row = other.position[0] - robot.position[0]
            d_col = other.position[1] - robot.position[1]
            if d_row * d_row + d_col * d_col > radius2:
                continue
            # where this robot sees the other, in its own belief (the same cell without
            # drift)
            seen = (robot.believed[0] + d_row, robot.believed[1] + d_col)
            if 0 <= seen[0] < height and 0 <= seen[1] < width:
                passable[seen] = False
            if other.alive and other.id < robot.id and other.path is not None:
                ahead = other.path[other.path_index + 1 : other.path_index + 1 + DETOUR_LOOKAHEAD]
                # the other's next steps, from where this robot sees it
                ahead = ahead - other.path[other.path_index] + np.asarray(seen)
                inside = (
                    (ahead[:, 0] >= 0)
                    & (ahead[:, 0] < height)
                    & (ahead[:, 1] >= 0)
                    & (ahead[:, 1] < width)
                )
                passable[ahead[inside, 0], ahead[inside, 1]] = False
        passable[robot.believed] = True
        goal = robot.goal
        dist = distance_field(passable, robot.believed)
        robot.blocked_ticks = 0
        if goal != robot.believed and np.isfinite(dist[goal]):
            robot.path = extract_path(dist, goal)
            robot.path_index = 0
            return
        robot.path, robot.goal = None, None
        robot.blocked = True
