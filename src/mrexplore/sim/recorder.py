"""The record phase: what the run leaves behind, logged at the end of every tick and
assembled into a :class:`~mrexplore.sim.record.RunRecord` when the run ends.

A noisy run (:attr:`Scenario.noisy <mrexplore.sim.scenario.Scenario.noisy>`: sensor
noise or odometry drift) also logs, every tick, the team map's known, wrong and
correct cells (:mod:`mrexplore.metrics.map_quality`), where each robot believes it
is, and how far that is from where it is. A run without noise logs none of them, so
its trace is what it was before noise existed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Generic, TypeVar

import numpy as np
import numpy.typing as npt

from mrexplore.metrics.map_quality import TeamCounter
from mrexplore.sim.comms import Comms, Links
from mrexplore.sim.deciding import Deciding
from mrexplore.sim.end import EndCondition
from mrexplore.sim.record import RunRecord
from mrexplore.sim.roster import Roster
from mrexplore.sim.scenario import Scenario
from mrexplore.sim.sensing import Sensing
from mrexplore.sim.stamps import BeliefStamps
from mrexplore.sim.world import World
from mrexplore.trace import component_labels, pack_links

if TYPE_CHECKING:
    from mrexplore.sim.noise import Odometry

Key = TypeVar("Key")


class _ChangeLog(Generic[Key]):
    """A per-tick log of an array computed from a key that seldom changes (the
    sub-networks, the links): an unchanged key repeats the previous entry (copied
    when the log is stacked) instead of computing it again."""

    def __init__(self, compute: Callable[[Key], npt.NDArray[np.generic]]) -> None:
        self._compute = compute
        self._last: tuple[Key] | None = None
        self.entries: list[npt.NDArray[np.generic]] = []

    def append(self, key: Key) -> None:
        if self._last is not None and key == self._last[0]:
            self.entries.append(self.entries[-1])
        else:
            self.entries.append(self._compute(key))
            self._last = (key,)


class _NoisyLog:
    """The per-tick logs of a noisy run: the team map's counts, the believed cells and
    the localisation errors."""

    def __init__(self, recorder: Recorder, odometry: Odometry | None) -> None:
        self.robots = recorder.robots
        self.world = recorder.world
        self.odometry = odometry
        self.counter = self._counter()
        self.map_known: list[int] = []
        self.map_wrong: list[int] = []
        self.correct_known: list[int] = []
        self.estimated_positions: list[npt.NDArray[np.int32]] = []
        self.localisation_error: list[npt.NDArray[np.float64]] = []

    def _counter(self) -> TeamCounter:
        return TeamCounter(
            [r.belief for r in self.robots], self.world.grid.occupied, self.world.explorable
        )

    def record(self) -> None:
        robots = self.robots
        if any(r.belief is not b for r, b in zip(robots, self.counter.beliefs, strict=True)):
            self.counter = self._counter()  # a belief array was replaced: count the new one
        known, wrong, correct = self.counter.count()
        self.map_known.append(known)
        self.map_wrong.append(wrong)
        self.correct_known.append(correct)
        self.estimated_positions.append(np.array([r.believed for r in robots], dtype=np.int32))
        odometry = self.odometry
        self.localisation_error.append(
            np.zeros(len(robots), dtype=np.float64)
            if odometry is None
            else np.array([odometry.error(r.id, r.position) for r in robots], dtype=np.float64)
        )


class Recorder:
    """Per-tick logs of positions, knowledge and links, and the run record.

    ``odometry`` is the run's odometry (``None`` without odometry drift); a noisy
    run's ``localisation_error`` is its :meth:`~mrexplore.sim.noise.Odometry.error`.
    """

    def __init__(
        self,
        scenario: Scenario,
        world: World,
        *,
        roster: Roster,
        comms: Comms,
        deciding: Deciding,
        sensing: Sensing,
        stamps: BeliefStamps,
        end: EndCondition,
        comm_range_cells: float,
        odometry: Odometry | None = None,
    ) -> None:
        self.scenario = scenario
        self.world = world
        self.robots = roster.robots
        self.comms = comms
        self.deciding = deciding
        self.sensing = sensing
        self.stamps = stamps
        self.end = end
        self.comm_range_cells = comm_range_cells
        self._positions: list[npt.NDArray[np.int32]] = []
        self._alive: list[npt.NDArray[np.bool_]] = []
        self._distance: list[npt.NDArray[np.float64]] = []
        self._goals: list[npt.NDArray[np.int32]] = []
        self._known: list[int] = []
        n_robots = len(self.robots)
        self._components: _ChangeLog[list[frozenset[int]]] = _ChangeLog(
            lambda groups: component_labels(groups, n_robots)
        )
        self._link_bits: _ChangeLog[Links] = _ChangeLog(lambda links: pack_links(links, n_robots))
        self._noisy = _NoisyLog(self, odometry) if scenario.noisy else None

    def record(self, tick: int) -> None:
        """Log the end of ``tick``: sub-networks, links, the robots' own knowledge,
        positions, liveness, distances, goals and the team's knowledge; in a noisy
        run also the team map's counts, the believed cells and the localisation
        errors."""
        robots = self.robots
        self._components.append(self.comms.network.subnetworks())
        self._link_bits.append(self.comms.network.links())
        self.stamps.record(robots, tick)
        self._positions.append(np.array([r.position for r in robots], dtype=np.int32))
        self._alive.append(np.array([r.alive for r in robots], dtype=bool))
        self._distance.append(np.array([r.distance for r in robots], dtype=np.float64))
        self._goals.append(
            np.array([r.goal if r.goal else (-1, -1) for r in robots], dtype=np.int32)
        )
        self._known.append(self.sensing.known_explorable)
        if self._noisy is not None:
            self._noisy.record()

    def run_record(self, status: str, ticks: int, wall_time_s: float) -> RunRecord:
        """The run record of ticks ``0..ticks``."""
        ledger = self.comms.network.ledger
        deciding = self.deciding
        noisy = self._noisy
        return RunRecord(
            scenario=self.scenario,
            world=self.world,
            status=status,
            ticks=ticks,
            positions=np.stack(self._positions),
            alive=np.stack(self._alive),
            distance=np.stack(self._distance),
            goals=np.stack(self._goals),
            known_explorable=np.asarray(self._known, dtype=np.int64),
            robot_complete=self.end.robot_complete.copy(),
            first_known=self.sensing.first_known,
            sense_count=self.sensing.sense_count,
            sensed_by_robot=np.array([int(r.sensed.sum()) for r in self.robots], dtype=np.int64),
            bytes_per_tick=ledger.bytes_per_tick(ticks + 1),
            bytes_by_type=dict(sorted(ledger.bytes_by_type.items())),
            messages_by_type=dict(sorted(ledger.messages_by_type.items())),
            bytes_by_robot=ledger.bytes_by_robot.copy(),
            messages_lost=ledger.lost,
            lost_by_type=dict(sorted(ledger.lost_by_type.items())),
            hops_by_type=dict(sorted(ledger.hops_by_type.items())),
            wall_time_s=wall_time_s,
            decide_seconds=deciding.decide_seconds,
            decisions=deciding.decisions,
            plans=deciding.plans,
            field_decisions=deciding.field_decisions,
            fields=deciding.field_counter.count,
            strategy_params=dict(deciding.strategies[0].p),
            comm_range_cells=self.comm_range_cells,
            comm_description=self.comms.network.describe(),
            **self.comms.network_stats(),
            sharing_metrics=self.comms.sharing.metrics(),
            sharing=self.comms.sharing_id,
            max_ticks=self.end.max_ticks,
            component=np.stack(self._components.entries),
            link_bits=np.stack(self._link_bits.entries),
            robot_first_known=self.stamps.robot_first_known,
            final_beliefs=np.stack([r.belief for r in self.robots]),
            map_known=None if noisy is None else np.asarray(noisy.map_known, dtype=np.int64),
            map_wrong=None if noisy is None else np.asarray(noisy.map_wrong, dtype=np.int64),
            correct_known=None
            if noisy is None
            else np.asarray(noisy.correct_known, dtype=np.int64),
            estimated_positions=None if noisy is None else np.stack(noisy.estimated_positions),
            localisation_error=None if noisy is None else np.stack(noisy.localisation_error),
        )
