"""The tick loop.

Each tick ``t >= 1`` runs these phases, robots always in id order:

0. **wake and fail** (:class:`~mrexplore.sim.roster.Roster`): dormant robots whose
   start tick it is start; robots failing at ``t`` stop; the communication model
   sees where the robots are and the sharing mechanism reacts to new links
   (:class:`~mrexplore.sim.comms.Comms`);
1. **deliver** (:class:`~mrexplore.sim.comms.Comms`): the communication model hands
   over the messages due at ``t``; map messages are merged into beliefs by the
   sharing mechanism, the rest go to the strategy's inbox;
2. **decide** (:class:`~mrexplore.sim.deciding.Deciding`): every live robot's
   strategy sees its :class:`RobotView` and returns a :class:`Decision` (a goal with
   a path, idle, or keep going) and messages;
3. **move** (:class:`~mrexplore.sim.motion.Motion`): each robot advances up to its
   budget of ``speed`` cells of path (a diagonal step costs sqrt 2; an unused budget
   carries over up to ``speed + sqrt 2``); a robot never enters a cell another
   robot holds: it waits, after ``patience`` ticks detours around the robots it can
   see, else gives up its goal (the strategy is told it was ``blocked``);
4. **sense** (:class:`~mrexplore.sim.sensing.Sensing`): each live robot observes
   its line-of-sight disk (every tick, or with ``sensing="arrival"`` only when it is
   not travelling); new cells go into its belief and, through the sharing
   mechanism, into messages sent at ``t``, which the network transmits;
5. **record** (:class:`~mrexplore.sim.recorder.Recorder`) positions, knowledge and
   links, and check the end conditions (:class:`~mrexplore.sim.end.EndCondition`).

Tick 0 is only the links and phases 4-5 at the start cells. Every robot's own
``robot_first_known``, when recorded, is kept by the way of
:mod:`mrexplore.sim.stamps` chosen for the run. Only :mod:`mrexplore.sim` and
:mod:`mrexplore.metrics` see ground truth.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from mrexplore.comm import CommModel, CommSetup, MapSharing, make_comm_model, make_sharing
from mrexplore.seeding import make_streams
from mrexplore.sim.comms import Comms, Links
from mrexplore.sim.deciding import Decider, Deciding, check_path
from mrexplore.sim.end import EndCondition
from mrexplore.sim.motion import Motion
from mrexplore.sim.noise import Odometry, odometry_model, sensor_model
from mrexplore.sim.record import BELIEF_CELLS_AUTO, RunRecord
from mrexplore.sim.recorder import Recorder
from mrexplore.sim.roster import Robot, Roster
from mrexplore.sim.scenario import Scenario, is_unlimited
from mrexplore.sim.sensing import Sensing
from mrexplore.sim.stamps import make_belief_stamps
from mrexplore.sim.world import World, build_world, cells_from_length
from mrexplore.strategies.base import RobotView, Strategy
from mrexplore.strategies.registry import get_strategy, make_strategy

__all__ = ["Decider", "Robot", "Simulation", "check_path", "simulate"]


class Simulation:
    """One run of one scenario; call :meth:`run` once."""

    def __init__(self, scenario: Scenario, *, record_beliefs: bool | None = None) -> None:
        """Prepare a run of ``scenario``.

        ``record_beliefs`` records every robot's own ``robot_first_known`` in the
        run record (``None``: only when robots x cells <= ``BELIEF_CELLS_AUTO``);
        it changes nothing else in the run.
        """
        scenario.check()
        self.scenario = scenario
        self.streams = make_streams(scenario.seed, scenario.robots)
        self.world: World = build_world(
            scenario, self.streams.starts, record_beliefs=record_beliefs
        )
        self.truth = self.world.grid.occupied
        shape = self.world.grid.shape
        n = scenario.robots
        self.roster = Roster(scenario, self.world.starts, shape, self.streams)
        self.robots = self.roster.robots
        self.strategies: list[Strategy] = [
            make_strategy(scenario.strategy, i, n, dict(scenario.params)) for i in range(n)
        ]
        comm_range = (
            math.inf
            if is_unlimited(scenario.comm_range)
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
        self.sharing_id = scenario.sharing or get_strategy(scenario.strategy).default_sharing
        self.sharing: MapSharing = make_sharing(self.sharing_id, **scenario.sharing_params)
        self.sharing.bind(n, shape)
        if record_beliefs is None:
            record_beliefs = n * shape[0] * shape[1] <= BELIEF_CELLS_AUTO
        self.stamps = make_belief_stamps(record_beliefs, self.sharing, n, shape)
        # The parts of a tick, in the order they run.
        self.comms = Comms(self.comm, self.sharing, self.sharing_id, self.robots, self.stamps)
        self.deciding = Deciding(
            scenario,
            self.strategies,
            self.robots,
            self.comms,
            self.streams,
            comm_range_cells=comm_range,
            sensor_range_cells=self.world.sensor_range_cells,
        )
        # Imperfect robots (off unless a noise is above 0: then nothing changes).
        sensor, self.odometry = None, None
        if scenario.noisy:
            sensor = sensor_model(scenario.sensor_noise, scenario.sensor_params)
            odometry = odometry_model(scenario.odometry_noise, scenario.odometry_params)
            if odometry.active:
                self.odometry = Odometry(odometry, self.world.starts, shape, self.streams.odometry)
        self.sensing = Sensing(
            self.world,
            self.robots,
            self.comms,
            self.stamps,
            arrival_only=scenario.sensing == "arrival",
            sensor=sensor,
            odometry=self.odometry,
            sensor_rngs=self.streams.sensor,
        )
        self.motion = Motion(
            scenario,
            self.robots,
            self.truth,
            self.sensing.truth_state,
            self.world.sensor_range_cells,
            self.stamps,
            odometry=self.odometry,
            sensing=self.sensing,
        )
        self.end = EndCondition(scenario, self.world, self.roster, self.sensing, self.comm)
        self.recorder = Recorder(
            scenario,
            self.world,
            roster=self.roster,
            comms=self.comms,
            deciding=self.deciding,
            sensing=self.sensing,
            stamps=self.stamps,
            end=self.end,
            comm_range_cells=comm_range,
            odometry=self.odometry,
        )
        self.n_explorable = self.world.n_explorable
        self.max_ticks = self.end.max_ticks
        self.first_known = self.sensing.first_known
        """The first tick at which any robot knew each cell (-1: not yet)."""
        self.robot_first_known = self.stamps.robot_first_known
        # Stepping state (see start/step/finish).
        self.tick = -1
        self.status: str | None = None
        self._started = 0.0

    @property
    def known_explorable(self) -> int:
        """Explorable cells the team knows now."""
        return self.sensing.known_explorable

    @property
    def decisions(self) -> int:
        """Decide calls so far."""
        return self.deciding.decisions

    @property
    def decide_seconds(self) -> float:
        """Seconds spent in decide calls so far."""
        return self.deciding.decide_seconds

    def view_of(self, robot_id: int, all_links: Links | None = None) -> RobotView:
        """What robot ``robot_id`` knows at the current tick: the view its strategy gets."""
        return self.deciding.view_of(robot_id, self.tick, all_links)

    # ------------------------------------------------------------------ loop
    def start(self) -> None:
        """Tick 0: links, first sensing, first flush, first record. Called by
        :meth:`run`; callers that drive the run tick by tick (the RL environment)
        call it once, then :meth:`step` until :attr:`status` is set."""
        if self.tick >= 0:
            raise RuntimeError("Simulation.start() called twice")
        self._started = time.perf_counter()
        self.tick = 0
        self.comms.update_links(0, self.roster.alive())
        self.sensing.sense(0)
        self.comms.flush(0)
        self.recorder.record(0)
        self.status = self.end.start()

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
        self.roster.wake(tick)
        self.roster.fail(tick, self.known_explorable / self.n_explorable)
        self.comms.update_links(tick, self.roster.alive())
        self.comms.deliver(tick)
        self.deciding.decide(tick, decide)
        self.motion.move(tick)
        self.sensing.sense(tick)
        self.comms.flush(tick)
        self.recorder.record(tick)
        self.status = self.end.check(tick)
        return self.status

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
        wall_time = time.perf_counter() - self._started
        return self.recorder.run_record(self.status or "max_ticks", self.tick, wall_time)


def simulate(scenario: Scenario) -> RunRecord:
    """Run one scenario and return its record."""
    return Simulation(scenario).run()
