"""The tick loop.

Each tick ``t >= 1`` runs these phases, robots always in id order:

1. **deliver**: the communication model hands over the messages due at ``t``;
   map messages are merged into beliefs by the sharing mechanism, the rest go to
   the strategy's inbox;
2. **decide**: every live robot's strategy sees its :class:`RobotView` and returns
   a :class:`Decision` (a goal with a path, idle, or keep going) and messages;
3. **move**: each robot advances up to its budget of ``speed`` cells of path
   (a diagonal step costs sqrt 2; an unused budget carries over up to
   ``speed + sqrt 2``); a robot never enters a cell another robot holds: it waits,
   after ``patience`` ticks detours around the robots it can see, else gives up
   its goal (the strategy is told it was ``blocked``);
4. **sense**: each live robot observes its line-of-sight disk (every tick, or
   with ``sensing="arrival"`` only when it is not travelling); new cells go into
   its belief and, through the sharing mechanism, into messages sent at ``t``;
5. **record** positions, knowledge and bytes, and check the end conditions.

Tick 0 is only phases 4-5 at the start cells. Only this module and
:mod:`mrexplore.metrics` see ground truth.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.comm import (
    CommModel,
    CommSetup,
    MapSharing,
    Message,
    make_comm_model,
    make_sharing,
)
from mrexplore.comm.sharing import (
    BroadcastSharing,
    CellUpdates,
    FullSharing,
    NoSharing,
    Observation,
)
from mrexplore.errors import StrategyError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, BeliefGrid, new_belief
from mrexplore.planning import distance_field, extract_path
from mrexplore.planning.distance import fields_computed
from mrexplore.planning.visibility import clip_radius, ray_table, visible_cells_kernel
from mrexplore.seeding import make_streams
from mrexplore.sim.record import BELIEF_CELLS_AUTO, RunRecord, mark_known_changed
from mrexplore.sim.scenario import Cell, Scenario
from mrexplore.sim.world import World, build_world, cells_from_length
from mrexplore.strategies.base import Decision, RobotView, Strategy
from mrexplore.strategies.registry import get_strategy, make_strategy
from mrexplore.trace import component_labels, pack_links

logger = logging.getLogger(__name__)

SQRT2 = math.sqrt(2.0)
DETOUR_LOOKAHEAD = 3


@dataclass
class Robot:
    """Simulator-side state of one robot (the strategy never sees this object)."""

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

    @property
    def travelling(self) -> bool:
        return self.path is not None

    @property
    def path_remaining(self) -> int:
        return 0 if self.path is None else len(self.path) - 1 - self.path_index


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


@numba.njit(cache=True, nogil=True)
def _stamp_cells(
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
    width: int,
    belief: npt.NDArray[np.int8],
    robot_known: npt.NDArray[np.int32],
    tick: int,
) -> None:  # pragma: no cover - compiled
    """Stamp ``tick`` on the listed cells that are known in ``belief`` and not stamped."""
    for k in range(rows.shape[0]):
        i = rows[k] * width + cols[k]
        if robot_known[i] < 0 and belief[i] != -1:
            robot_known[i] = tick


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


Decider = Callable[[int, RobotView], Decision]
"""``decide(robot_id, view) -> Decision``: replaces the strategies in :meth:`Simulation.step`."""


class Simulation:
    """One run of one scenario; call :meth:`run` once."""

    def __init__(self, scenario: Scenario, *, record_beliefs: bool | None = None) -> None:
        """Prepare a run of ``scenario``.

        ``record_beliefs`` records every robot's own ``robot_first_known`` in the
        run record (``None``: only when robots x cells <= ``BELIEF_CELLS_AUTO``);
        it changes nothing else in the run.
        """
        scenario.validate()
        get_strategy(scenario.strategy)  # fail early on an unknown id
        self.scenario = scenario
        self.streams = make_streams(scenario.seed, scenario.robots)
        self.world: World = build_world(
            scenario, self.streams.starts, record_beliefs=record_beliefs
        )
        self.truth = self.world.grid.occupied
        self.truth_state = np.where(self.truth, OCCUPIED, FREE).astype(np.int8)
        shape = self.world.grid.shape
        n = scenario.robots
        self.robots = [
            Robot(i, start, new_belief(shape), np.zeros(shape, dtype=bool))
            for i, start in enumerate(self.world.starts)
        ]
        self.strategies: list[Strategy] = [
            make_strategy(scenario.strategy, i, n, dict(scenario.params)) for i in range(n)
        ]
        comm_range = (
            math.inf
            if isinstance(scenario.comm_range, float) and math.isinf(scenario.comm_range)
            else cells_from_length(scenario.comm_range, self.world.grid, "--comm-range")
        )
        self.comm_range_cells = comm_range
        self.comm: CommModel = make_comm_model(
            scenario.comm_model,
            CommSetup(
                n_robots=n,
                occupied=self.truth,
                rng=self.streams.comm,
                comm_range=comm_range,
                comm_los=scenario.comm_los,
                bandwidth=scenario.bandwidth,
                latency=scenario.latency,
                loss=scenario.loss,
                metres_per_cell=self.world.grid.resolution_m,
            ),
            scenario.comm_params,
        )
        self.failures: dict[int, list[int]] = {}
        for robot_id, fail_tick in scenario.fail:
            self.failures.setdefault(fail_tick, []).append(robot_id)
        self.failed: set[int] = set()
        # Robots that start later (``start_delay``) stand dormant until their tick.
        self.wakes: dict[int, list[int]] = {}
        if scenario.start_delay > 0:
            first = self.streams.start_times.integers(0, scenario.start_delay + 1, n)
            for robot, tick in zip(self.robots, first - first.min(), strict=True):
                if tick > 0:
                    robot.alive = False
                    self.wakes.setdefault(int(tick), []).append(robot.id)
        self.sharing_id = scenario.sharing or get_strategy(scenario.strategy).default_sharing
        self.sharing: MapSharing = make_sharing(self.sharing_id, **scenario.sharing_params)
        self.sharing.bind(n, shape)
        self.occupant = np.full(shape, -1, dtype=np.int32)
        for robot in self.robots:
            self.occupant[robot.position] = robot.id
        self.first_known = np.full(shape, -1, dtype=np.int32)
        if record_beliefs is None:
            record_beliefs = n * shape[0] * shape[1] <= BELIEF_CELLS_AUTO
        self.robot_first_known = (
            np.full((n, *shape), -1, dtype=np.int32) if record_beliefs else None
        )
        # How robot_first_known is kept up to date. With the built-in full / none
        # sharing a belief changes only where the robot senses, bumps or merges the
        # cells of a CellUpdates payload, so those cells are stamped as they change
        # (the tick is the same as at the record). Any other mechanism may write
        # anywhere: then each record compares the belief with a copy of it from the
        # previous record, eight cells at a time.
        self._stamp_direct = record_beliefs and type(self.sharing) in (
            BroadcastSharing,
            FullSharing,
            NoSharing,
        )
        self._belief_shadow = (
            # rows padded to whole 8-byte words so that every row is word-aligned
            np.full((n, -(-shape[0] * shape[1] // 8) * 8), UNKNOWN, dtype=np.int8)
            if record_beliefs and not self._stamp_direct
            else None
        )
        self._no_stamps = np.zeros(0, dtype=np.int32)
        self.sense_count = np.zeros(shape, dtype=np.uint16)
        self._explorable_flat = np.ascontiguousarray(self.world.explorable).reshape(-1)
        self._truth_flat = np.ascontiguousarray(self.truth, dtype=np.bool_).reshape(-1)
        self._rays = ray_table(clip_radius(self.world.sensor_range_cells, shape))
        # Each robot's last sensor footprint: the ground truth never changes, so a robot
        # that has not moved sees the same cells (the ray walk is skipped).
        self._last_visible: list[tuple[Cell, npt.NDArray[np.int64]] | None] = [None] * n
        self.n_explorable = self.world.n_explorable
        self.known_explorable = 0
        # Per robot: the first tick its own belief held every explorable cell (-1: not
        # yet), found by a scan over the explorable cells that resumes where it stopped.
        self._explorable_cells = np.flatnonzero(self._explorable_flat).astype(np.int64)
        self._robot_scan = np.zeros(n, dtype=np.int64)
        self.robot_complete = np.full(n, -1, dtype=np.int32)
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
        self.decide_seconds = 0.0
        self.decisions = 0
        self.plans = 0
        self.field_decisions = 0
        """Decide calls that computed at least one distance field."""
        self.fields = 0
        """Distance fields computed inside decide calls."""
        # Stepping state (see start/step/finish).
        self.tick = -1
        self.status: str | None = None
        self._started = 0.0
        self._target = 0
        self._last_progress_tick = 0
        self._last_known = 0
        self._idle_streak = 0
        self._positions: list[npt.NDArray[np.int32]] = []
        self._alive_log: list[npt.NDArray[np.bool_]] = []
        self._distance_log: list[npt.NDArray[np.float64]] = []
        self._goals_log: list[npt.NDArray[np.int32]] = []
        self._known_log: list[int] = []
        self._component_log: list[npt.NDArray[np.int16]] = []
        self._last_subnetworks: list[frozenset[int]] | None = None
        self._links_log: list[npt.NDArray[np.uint8]] = []
        self._last_links: list[frozenset[tuple[int, int]]] = []
        self._group_links: tuple[object, dict[frozenset[int], frozenset[tuple[int, int]]]] = (
            None,
            {},
        )

    # ------------------------------------------------------------------ phases
    def _alive(self) -> frozenset[int]:
        return frozenset(r.id for r in self.robots if r.alive)

    def _wake(self, tick: int) -> None:
        """Dormant robots whose start tick is ``tick`` start (``start_delay``), unless
        they failed before."""
        for robot_id in self.wakes.pop(tick, []):
            self.robots[robot_id].alive = robot_id not in self.failed

    def _fail(self, tick: int) -> None:
        """Robots failing at ``tick`` stop moving, sensing and communicating.

        A failed robot stays where it is, an obstacle for the others; a dormant robot
        that fails never wakes.
        """
        failing = set(self.failures.get(tick, []))
        rate = self.scenario.failure_rate
        if rate > 0:
            draws = self.streams.failures.random(len(self.robots))
            failing |= {r.id for r in self.robots if r.alive and draws[r.id] < rate}
        for robot_id in sorted(failing):
            self.failed.add(robot_id)
            robot = self.robots[robot_id]
            if robot.alive:
                robot.alive = False
                robot.path, robot.goal = None, None
                robot.inbox.clear()

    def _update_links(self, tick: int) -> None:
        """Let the communication model see where the robots are; let sharing react."""
        self.comm.update(tick, {r.id: r.position for r in self.robots}, self._alive())
        beliefs = [r.belief for r in self.robots]
        subnetworks = self.comm.subnetworks()
        for message in self.sharing.on_topology(tick, subnetworks, self.comm.links(), beliefs):
            self._send(message, tick)

    def _deliver(self, tick: int) -> None:
        for robot_id, messages in self.comm.deliver(tick).items():
            robot = self.robots[robot_id]
            if not robot.alive:
                continue
            map_messages = [m for m in messages if m.type in self.sharing.message_types]
            if map_messages:
                robot.new_cells += self.sharing.on_receive_all(robot_id, robot.belief, map_messages)
                if self._stamp_direct:
                    self._stamp_received(robot, map_messages)
            robot.inbox.extend(m for m in messages if m.type not in self.sharing.message_types)
        for message in self.sharing.drain():
            self._send(dataclasses.replace(message, tick_sent=tick), tick)

    def _stamp_received(self, robot: Robot, messages: list[Message]) -> None:
        """robot_first_known of the cells the merged ``messages`` made known."""
        assert self.robot_first_known is not None
        belief = robot.belief.reshape(-1)
        known = self.robot_first_known[robot.id].reshape(-1)
        width = belief.size // robot.belief.shape[0]
        for message in messages:
            payload = message.payload
            assert isinstance(payload, CellUpdates)
            _stamp_cells(payload.rows, payload.cols, width, belief, known, self.tick)

    def view_of(
        self, robot_id: int, all_links: frozenset[tuple[int, int]] | None = None
    ) -> RobotView:
        """What robot ``robot_id`` knows at the current tick: the view its strategy gets."""
        robot = self.robots[robot_id]
        if all_links is None:
            all_links = frozenset(self.comm.links())
        subnetwork = self.comm.subnetwork_of(robot.id)
        # The links of a sub-network, shared by its members within one tick.
        key = (self.tick, all_links)
        if self._group_links[0] != key:
            self._group_links = (key, {})
        links = self._group_links[1].get(subnetwork)
        if links is None:
            links = frozenset(link for link in all_links if link[0] in subnetwork)
            self._group_links[1][subnetwork] = links
        belief_view = robot.belief.view()
        belief_view.flags.writeable = False
        return RobotView(
            robot_id=robot.id,
            n_robots=len(self.robots),
            tick=self.tick,
            position=robot.position,
            belief=belief_view,
            goal=robot.goal,
            path_remaining=robot.path_remaining,
            arrived=robot.arrived,
            blocked=robot.blocked,
            inbox=tuple(robot.inbox),
            subnetwork=subnetwork,
            links=links,
            comm_latency=self.scenario.latency,
            comm_range=self.comm_range_cells,
            sensor_range=self.world.sensor_range_cells,
            speed=self.scenario.speed,
            rng=self.streams.robots[robot.id],
            new_cells=robot.new_cells,
        )

    def _decide(self, tick: int, decide: Decider | None = None) -> None:
        all_links = frozenset(self.comm.links())
        for robot in self.robots:
            if not robot.alive:
                continue
            view = self.view_of(robot.id, all_links)
            fields_before = fields_computed()
            started = time.perf_counter()
            if decide is None:
                decision = self.strategies[robot.id].decide(view)
            else:
                decision = decide(robot.id, view)
            self.decide_seconds += time.perf_counter() - started
            self.decisions += 1
            fields = fields_computed() - fields_before
            if fields:
                self.fields += fields
                self.field_decisions += 1
            robot.inbox.clear()
            self._apply(robot, decision, tick)

    def _apply(self, robot: Robot, decision: Decision, tick: int) -> None:
        if not isinstance(decision, Decision):
            raise StrategyError(
                f"strategy {self.scenario.strategy!r} returned {type(decision).__name__}, "
                "not a Decision"
            )
        for message in decision.messages:
            if message.sender != robot.id:
                raise StrategyError(f"robot {robot.id} sent a message as robot {message.sender}")
            self._send(dataclasses.replace(message, tick_sent=tick), tick)
        if decision.idle:
            self.plans += 1
            robot.path, robot.goal = None, None
        elif decision.goal is not None:
            self.plans += 1
            path = decision.path
            if path is None:
                raise StrategyError(f"robot {robot.id}: a goal without a path")
            check_path(path, robot.position, decision.goal, robot.belief)
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

    def _move(self) -> None:
        speed = self.scenario.speed
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
                if self._bumps(robot, nxt):
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
                patience = self.scenario.patience
                if blocker.id > robot.id and blocker.path is not None:
                    patience *= 4
                if robot.blocked_ticks >= patience:
                    self._detour(robot)
            elif moved:
                robot.blocked_ticks = 0

    def _bumps(self, robot: Robot, nxt: Cell) -> bool:
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
        if self._stamp_direct:
            assert self.robot_first_known is not None
            for cell in step_cells:
                if self.robot_first_known[robot.id][cell] < 0:
                    self.robot_first_known[robot.id][cell] = self.tick
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
        radius2 = self.world.sensor_range_cells * self.world.sensor_range_cells
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

    def _sense(self, tick: int) -> None:
        arrival_only = self.scenario.sensing == "arrival"
        width = self.truth.shape[1]
        truth_state = self.truth_state.reshape(-1)
        sense_count = self.sense_count.reshape(-1)
        first_known = self.first_known.reshape(-1)
        explorable = self._explorable_flat
        for robot in self.robots:
            if not robot.alive or (arrival_only and robot.travelling and tick > 0):
                continue
            visible = self._visible(robot)
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
                self.robot_first_known[robot.id].reshape(-1)
                if self._stamp_direct and self.robot_first_known is not None
                else self._no_stamps,
            )
            robot.new_cells += changed
            if n_fresh == 0:
                continue
            self.known_explorable += explorable_new
            observation = Observation(
                rows[:n_fresh], cols[:n_fresh], values[:n_fresh], was_unknown[:n_fresh]
            )
            for message in self.sharing.on_observe(robot.id, tick, observation, robot.belief):
                self._send(message, tick)

    def _visible(self, robot: Robot) -> npt.NDArray[np.int64]:
        """Flat indices of the cells ``robot`` sees: :func:`mrexplore.sensing.visible_cells`
        (same cells, same order) from the table built once per run."""
        last = self._last_visible[robot.id]
        if last is not None and last[0] == robot.position:
            return last[1]
        height, width = self.truth.shape
        rays = self._rays
        out = np.empty(rays.n_cells, dtype=np.int64)
        n_visible = visible_cells_kernel(
            self._truth_flat,
            height,
            width,
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

    def _send(self, message: Message, tick: int) -> None:
        """Hand a message to the communication model.

        A robot knows its sub-network, so it does not transmit a broadcast when it
        has nobody to reach (a lone robot sends nothing).
        """
        if message.is_broadcast and len(self.comm.subnetwork_of(message.sender)) < 2:
            return
        self.comm.send(message, tick)

    # ------------------------------------------------------------------ loop
    def start(self) -> None:
        """Tick 0: links, first sensing, first flush, first record. Called by
        :meth:`run`; callers that drive the run tick by tick (the RL environment)
        call it once, then :meth:`step` until :attr:`status` is set."""
        if self.tick >= 0:
            raise RuntimeError("Simulation.start() called twice")
        self._started = time.perf_counter()
        self.tick = 0
        self._target = math.ceil(self.scenario.coverage_threshold * self.n_explorable - 1e-9)
        self._update_links(0)
        self._sense(0)
        self.comm.flush(0)
        self._record(0)
        self._last_progress_tick, self._last_known = 0, self._progress()
        self._idle_streak = 0
        if self._complete():
            self.status = "complete"
        elif self.max_ticks <= 0:
            self.status = "max_ticks"

    def step(self, decide: Decider | None = None) -> str | None:
        """One tick: starts, failures, links, delivery, decisions, moves, sensing, flush.

        ``decide(robot_id, view)`` replaces the strategies' decisions when given
        (it is called for every live robot, in id order, exactly where the strategy
        would be). Returns the run's status once it is over (``complete``,
        ``max_ticks``, ``stalled``), else ``None``.
        """
        if self.tick < 0:
            raise RuntimeError("call Simulation.start() before step()")
        if self.status is not None:
            raise RuntimeError(f"the run is over ({self.status})")
        self.tick += 1
        tick = self.tick
        self._wake(tick)
        self._fail(tick)
        self._update_links(tick)
        self._deliver(tick)
        self._decide(tick, decide)
        self._move()
        self._sense(tick)
        self.comm.flush(tick)
        self._record(tick)
        self.status = self._check_end(tick)
        return self.status

    def _check_end(self, tick: int) -> str | None:
        if self._complete():
            return "complete"
        progress = self._progress()
        if progress > self._last_known:
            self._last_known, self._last_progress_tick = progress, tick
        elif tick - self._last_progress_tick >= self.stall_ticks:
            return "stalled"
        if not any(r.alive for r in self.robots) and not self.wakes:
            return "stalled"  # nobody left to explore
        all_idle = not self.wakes and all(r.path is None for r in self.robots if r.alive)
        idle = all_idle and self.comm.in_flight() == 0
        self._idle_streak = self._idle_streak + 1 if idle else 0
        if self._idle_streak >= self.scenario.idle_ticks:
            return "stalled"
        if tick >= self.max_ticks:
            return "max_ticks"
        return None

    def _record(self, tick: int) -> None:
        n_robots = len(self.robots)
        subnetworks = self.comm.subnetworks()
        if self._last_subnetworks is not None and subnetworks == self._last_subnetworks:
            self._component_log.append(self._component_log[-1])  # stacked (copied) at finish
        else:
            self._component_log.append(component_labels(subnetworks, n_robots))
            self._last_subnetworks = subnetworks
        links = self.comm.links()
        if self._last_links and links == self._last_links[0]:  # most ticks: no link changed
            self._links_log.append(self._links_log[-1])
        else:
            self._links_log.append(pack_links(links, n_robots))
            self._last_links[:] = [links]
        if self.robot_first_known is not None and self._belief_shadow is not None:
            n_cells = self.first_known.size
            n_words = n_cells // 8
            for robot in self.robots:
                belief = robot.belief.reshape(-1)
                shadow = self._belief_shadow[robot.id, :n_cells]
                mark_known_changed(
                    belief,
                    shadow,
                    belief[: 8 * n_words].view(np.uint64),
                    shadow[: 8 * n_words].view(np.uint64),
                    self.robot_first_known[robot.id].reshape(-1),
                    tick,
                    UNKNOWN,
                )
        self._positions.append(np.array([r.position for r in self.robots], dtype=np.int32))
        self._alive_log.append(np.array([r.alive for r in self.robots], dtype=bool))
        self._distance_log.append(np.array([r.distance for r in self.robots], dtype=np.float64))
        self._goals_log.append(
            np.array([r.goal if r.goal else (-1, -1) for r in self.robots], dtype=np.int32)
        )
        self._known_log.append(self.known_explorable)
        self._check_robots_complete(tick)

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
        if self.scenario.complete_when == "robot":
            return bool((self.robot_complete >= 0).any())
        return self.known_explorable >= self._target

    def _progress(self) -> int:
        """What must grow for the run not to stall: the team's known explorable cells
        (and, when a robot's map completes the run, how far the robots' scans got)."""
        if self.scenario.complete_when == "robot":
            return self.known_explorable + int(self._robot_scan.sum())
        return self.known_explorable

    def run(self, progress: Callable[[int, float], None] | None = None) -> RunRecord:
        """Run to completion, ``max_ticks`` or a stall; return the run record."""
        self.start()
        while self.status is None:
            self.step()
            if progress is not None:
                progress(self.tick, self.known_explorable / self.n_explorable)
        return self.finish()

    def finish(self) -> RunRecord:
        """The run record of the ticks run so far (the status ``max_ticks`` if the
        run was stopped before it ended by itself)."""
        if self.tick < 0:
            raise RuntimeError("call Simulation.start() before finish()")
        scenario = self.scenario
        tick = self.tick
        status = self.status or "max_ticks"
        wall_time = time.perf_counter() - self._started
        ledger = self.comm.ledger
        comm_stats = self.comm.stats()
        return RunRecord(
            scenario=scenario,
            world=self.world,
            status=status,
            ticks=tick,
            positions=np.stack(self._positions),
            alive=np.stack(self._alive_log),
            distance=np.stack(self._distance_log),
            goals=np.stack(self._goals_log),
            known_explorable=np.asarray(self._known_log, dtype=np.int64),
            robot_complete=self.robot_complete.copy(),
            first_known=self.first_known,
            sense_count=self.sense_count,
            sensed_by_robot=np.array([int(r.sensed.sum()) for r in self.robots], dtype=np.int64),
            bytes_per_tick=ledger.bytes_per_tick(tick + 1),
            bytes_by_type=dict(sorted(ledger.bytes_by_type.items())),
            messages_by_type=dict(sorted(ledger.messages_by_type.items())),
            bytes_by_robot=ledger.bytes_by_robot.copy(),
            wall_time_s=wall_time,
            decide_seconds=self.decide_seconds,
            decisions=self.decisions,
            plans=self.plans,
            field_decisions=self.field_decisions,
            fields=self.fields,
            strategy_params=dict(self.strategies[0].p),
            comm_range_cells=self.comm_range_cells,
            comm_description=self.comm.describe(),
            subnetworks=np.asarray(comm_stats.subnetwork_counts, dtype=np.int64),
            partition_events=int(comm_stats.partition_events),
            merge_events=int(comm_stats.merge_events),
            messages_lost=ledger.lost,
            lost_by_type=dict(sorted(ledger.lost_by_type.items())),
            hops_by_type=dict(sorted(ledger.hops_by_type.items())),
            queue_delay_mean=float(comm_stats.queue_delay_mean),
            sharing_metrics=self.sharing.metrics(),
            sharing=self.sharing_id,
            max_ticks=self.max_ticks,
            component=np.stack(self._component_log),
            link_bits=np.stack(self._links_log),
            robot_first_known=self.robot_first_known,
        )


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


def simulate(scenario: Scenario) -> RunRecord:
    """Run one scenario and return its record."""
    return Simulation(scenario).run()
