"""The record phase: what the run leaves behind, logged at the end of every tick and
assembled into a :class:`~mrexplore.sim.record.RunRecord` when the run ends."""

from __future__ import annotations

from collections.abc import Callable
from typing import Generic, TypeVar

import numpy as np
import numpy.typing as npt

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


class Recorder:
    """Per-tick logs of positions, knowledge and links, and the run record."""

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

    def record(self, tick: int) -> None:
        """Log the end of ``tick``: sub-networks, links, the robots' own knowledge,
        positions, liveness, distances, goals and the team's knowledge."""
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

    def run_record(self, status: str, ticks: int, wall_time_s: float) -> RunRecord:
        """The run record of ticks ``0..ticks``."""
        ledger = self.comms.network.ledger
        deciding = self.deciding
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
        )
