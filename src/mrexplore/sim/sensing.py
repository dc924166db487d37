"""The sense phase, and what the team knows.

Each live robot observes its line-of-sight disk (every tick, or with
``sensing="arrival"`` only when it is not travelling): the same cells, in the same
order, as :func:`mrexplore.sensing.visible_cells`, from a ray table built once per
run. Own sensing is the truth and overrides anything received before. New cells go
into the robot's belief and, through the sharing mechanism, into messages sent at
the same tick; the team's first tick of knowing each cell (``first_known``) and
how often each cell was sensed (``sense_count``) are kept here.
"""

from __future__ import annotations

from collections.abc import Sequence

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.comm.sharing import Observation
from mrexplore.grid.occupancy import FREE, OCCUPIED
from mrexplore.planning.visibility import clip_radius, ray_table, visible_cells_kernel
from mrexplore.sim.comms import Comms
from mrexplore.sim.noise import Odometry, SensorModel, noisy_sense_kernel
from mrexplore.sim.roster import Robot
from mrexplore.sim.scenario import Cell
from mrexplore.sim.stamps import BeliefStamps
from mrexplore.sim.world import World


@numba.njit(cache=True, nogil=True)
def _sense_kernel(
    visible: npt.NDArray[np.int64],
    width: int,
    truth_state: npt.NDArray[np.int8],
    belief: npt.NDArray[np.int8],
    sensed: npt.NDArray[np.bool_],
    sense_count: npt.NDArray[np.uint16],
    first_known: npt.NDArray[np.int32],
    explorable: npt.NDArray[np.bool_],
    tick: int,
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
    values: npt.NDArray[np.int8],
    was_unknown: npt.NDArray[np.bool_],
    robot_known: npt.NDArray[np.int32],
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """One robot's sensing of the flat cells ``visible`` (each once), on flat arrays.

    Counts the visible cells whose belief differs from the truth; for the cells the
    robot senses for the first time (``fresh``), in the order of ``visible``: writes
    their row, col, true value and whether the belief held them unknown to the
    outputs, writes the truth into ``belief``, sets ``sensed``, counts ``sense_count``
    and stamps ``first_known`` where the team did not know the cell yet (and
    ``robot_known``, the robot's own first_known, unless it is empty, where the
    robot did not know it).

    Returns ``(changed, fresh, newly known explorable cells)``.
    """
    changed = 0
    fresh = 0
    explorable_new = 0
    stamp = robot_known.shape[0] > 0
    for k in range(visible.shape[0]):
        i = visible[k]
        value = truth_state[i]
        if belief[i] != value:
            changed += 1
        if sensed[i]:
            continue
        rows[fresh] = i // width
        cols[fresh] = i % width
        values[fresh] = value
        was_unknown[fresh] = belief[i] == -1
        if stamp and robot_known[i] < 0:
            robot_known[i] = tick  # the truth written below is never unknown
        fresh += 1
        belief[i] = value
        sensed[i] = True
        sense_count[i] += 1
        if first_known[i] < 0:
            first_known[i] = tick
            if explorable[i]:
                explorable_new += 1
    return changed, fresh, explorable_new


class Sensing:
    """The robots' sensors over the ground truth, and the team's knowledge."""

    def __init__(
        self,
        world: World,
        robots: Sequence[Robot],
        comms: Comms,
        stamps: BeliefStamps,
        *,
        arrival_only: bool,
        sensor: SensorModel | None = None,
        odometry: Odometry | None = None,
        sensor_rngs: Sequence[np.random.Generator] = (),
    ) -> None:
        self.robots = robots
        self.comms = comms
        self.stamps = stamps
        self.arrival_only = arrival_only
        truth = world.grid.occupied
        shape = truth.shape
        self.truth_state = np.where(truth, OCCUPIED, FREE).astype(np.int8)
        """The truth as belief values (free / occupied)."""
        self.first_known = np.full(shape, -1, dtype=np.int32)
        """The first tick at which any robot knew each cell (-1: never)."""
        self.sense_count = np.zeros(shape, dtype=np.uint16)
        """How many robots sensed each cell."""
        self.known_explorable = 0
        """Explorable cells the team knows."""
        self._height, self._width = shape
        self._explorable_flat = np.ascontiguousarray(world.explorable).reshape(-1)
        self._truth_flat = np.ascontiguousarray(truth, dtype=np.bool_).reshape(-1)
        self._rays = ray_table(clip_radius(world.sensor_range_cells, shape))
        # Each robot's last sensor footprint: the ground truth never changes, so a robot
        # that has not moved sees the same cells (the ray walk is skipped).
        self._last_visible: list[tuple[Cell, npt.NDArray[np.int64]] | None] = [None] * len(robots)
        # Imperfect robots (mrexplore.sim.noise): readings fused as log-odds, written at
        # the believed pose. None: perfect sensing and localisation.
        self.noisy = sensor is not None
        if sensor is not None:
            self.sensor = sensor
            self.odometry = odometry
            self.sensor_rngs = sensor_rngs
            self.sensor_range = max(float(world.sensor_range_cells), 1e-12)
            n_cells = shape[0] * shape[1]
            self.log_odds = [np.zeros(n_cells, dtype=np.float32) for _ in robots]
            """Each robot's own evidence per cell (log-odds, 0: none)."""
            self._world_sensed = [np.zeros(n_cells, dtype=np.bool_) for _ in robots]
            self._listed = np.zeros(n_cells, dtype=np.int64)
            self._calls = 0

    def sense(self, tick: int) -> None:
        """Every live robot that senses at ``tick`` observes its disk (in id order)."""
        width = self._width
        truth_state = self.truth_state.reshape(-1)
        sense_count = self.sense_count.reshape(-1)
        first_known = self.first_known.reshape(-1)
        explorable = self._explorable_flat
        sharing = self.comms.sharing
        for robot in self.robots:
            if not robot.alive or (self.arrival_only and robot.travelling and tick > 0):
                continue
            visible = self._visible(robot)
            if self.noisy:
                self._sense_noisy(robot, visible, tick)
                continue
            n = visible.size
            rows = np.empty(n, dtype=np.int64)
            cols = np.empty(n, dtype=np.int64)
            values = np.empty(n, dtype=np.int8)
            was_unknown = np.empty(n, dtype=np.bool_)
            # Own sensing is the truth: it overrides anything received before.
            changed, n_fresh, explorable_new = _sense_kernel(
                visible,
                width,
                truth_state,
                robot.belief.reshape(-1),
                robot.sensed.reshape(-1),
                sense_count,
                first_known,
                explorable,
                tick,
                rows,
                cols,
                values,
                was_unknown,
                self.stamps.sensed_cells(robot.id),
            )
            robot.new_cells += changed
            if n_fresh == 0:
                continue
            self.known_explorable += explorable_new
            observation = Observation(
                rows[:n_fresh], cols[:n_fresh], values[:n_fresh], was_unknown[:n_fresh]
            )
            for message in sharing.on_observe(robot.id, tick, observation, robot.belief):
                self.comms.send(message, tick)

    def _sense_noisy(self, robot: Robot, visible: npt.NDArray[np.int64], tick: int) -> None:
        """Noisy readings of ``visible``, written at the robot's believed pose."""
        sensor = self.sensor
        n = visible.size + 1  # and the believed cell
        rows = np.empty(n, dtype=np.int64)
        cols = np.empty(n, dtype=np.int64)
        values = np.empty(n, dtype=np.int8)
        was_unknown = np.empty(n, dtype=np.bool_)
        draws = self.sensor_rngs[robot.id].random(visible.size)
        if self.odometry is not None:
            est_row, est_col = (float(v) for v in self.odometry.estimate[robot.id])
            heading = float(self.odometry.heading[robot.id])
        else:
            est_row, est_col, heading = float(robot.position[0]), float(robot.position[1]), 0.0
        self._calls += 1
        changed, n_listed, explorable_new = noisy_sense_kernel(
            visible,
            self._width,
            self._height,
            robot.position[0],
            robot.position[1],
            est_row,
            est_col,
            np.cos(heading),
            np.sin(heading),
            robot.believed[0] * self._width + robot.believed[1],
            self.truth_state.reshape(-1),
            draws,
            self.sensor_range,
            sensor.false_occupied,
            sensor.false_free,
            sensor.range_growth,
            sensor.clamp_low,
            sensor.clamp_high,
            sensor.occupied_above,
            sensor.free_below,
            self.log_odds[robot.id],
            robot.belief.reshape(-1),
            robot.sensed.reshape(-1),
            self._world_sensed[robot.id],
            self.sense_count.reshape(-1),
            self.first_known.reshape(-1),
            self._explorable_flat,
            tick,
            self._listed,
            self._calls,
            rows,
            cols,
            values,
            was_unknown,
            self.stamps.sensed_cells(robot.id),
        )
        robot.new_cells += changed
        if n_listed == 0:
            return
        self.known_explorable += explorable_new
        observation = Observation(
            rows[:n_listed], cols[:n_listed], values[:n_listed], was_unknown[:n_listed]
        )
        for message in self.comms.sharing.on_observe(robot.id, tick, observation, robot.belief):
            self.comms.send(message, tick)

    def bumped(self, robot: Robot, flat_cells: Sequence[int]) -> None:
        """The robot bumped into walls at these belief cells: it is certain of them."""
        if self.noisy:
            for j in flat_cells:
                self.log_odds[robot.id][j] = self.sensor.clamp_high

    def _visible(self, robot: Robot) -> npt.NDArray[np.int64]:
        """Flat indices of the cells ``robot`` sees: :func:`mrexplore.sensing.visible_cells`
        (same cells, same order) from the table built once per run."""
        last = self._last_visible[robot.id]
        if last is not None and last[0] == robot.position:
            return last[1]
        rays = self._rays
        out = np.empty(rays.n_cells, dtype=np.int64)
        n_visible = visible_cells_kernel(
            self._truth_flat,
            self._height,
            self._width,
            robot.position[0],
            robot.position[1],
            rays.flags,
            rays.cell,
            rays.parent,
            rays.skip,
            rays.reach,
            out,
        )
        visible = out[:n_visible]
        self._last_visible[robot.id] = (robot.position, visible)
        return visible
