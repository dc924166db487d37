"""The record phase: what the run leaves behind, logged at the end of every tick and
assembled into a :class:`~mrexplore.sim.record.RunRecord` when the run ends."""

from __future__ import annotations

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
        # Most ticks change no link: an unchanged tick repeats the previous entry
        # (stacked, so copied, at the end).
        self._components: list[npt.NDArray[np.int16]] = []
        self._last_subnetworks: list[frozenset[int]] | None = None
        self._link_bits: list[npt.NDArray[np.uint8]] = []
        self._last_links: Links | None = None

    def record(self, tick: int) -> None:
        """Log the end of ``tick``: sub-networks, links, the robots' own knowledge,
        positions, liveness, distances, goals and the team's knowledge."""
        robots = self.robots
        n_robots = len(robots)
        network = self.comms.network
        subnetworks = network.subnetworks()
        if self._last_subnetworks is not None and subnetworks == self._last_subnetworks:
            self._components.append(self._components[-1])
        else:
            self._components.append(component_labels(subnetworks, n_robots))
            self._last_subnetworks = subnetworks
        links = network.links()
        if self._last_links is not None and links == self._last_links:
            self._link_bits.append(self._link_bits[-1])
        else:
            self._link_bits.append(pack_links(links, n_robots))
            self._last_links = links
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
            component=np.stack(self._components),
            link_bits=np.stack(self._link_bits),
            robot_first_known=self.stamps.robot_first_known,
        )
