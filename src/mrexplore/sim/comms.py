"""Links and delivery: the run's communication model and map-sharing mechanism.

Each tick the network first sees where the robots are (links, sub-networks), the
sharing mechanism reacts to the new topology, then the messages due are delivered:
map messages are merged into beliefs, the rest go to the strategies' inboxes. What
robots send during the tick is handed to the network, which transmits it at the
end of the tick (:meth:`Comms.flush`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import numpy as np

from mrexplore.comm import CommModel, MapSharing, Message
from mrexplore.sim.roster import Robot
from mrexplore.sim.stamps import BeliefStamps

Links = frozenset[tuple[int, int]]


class Comms:
    """The network and the sharing mechanism of a run, driven by the tick loop."""

    def __init__(
        self,
        network: CommModel,
        sharing: MapSharing,
        sharing_id: str,
        robots: Sequence[Robot],
        stamps: BeliefStamps,
    ) -> None:
        self.network = network
        self.sharing = sharing
        self.sharing_id = sharing_id
        self.robots = robots
        self.stamps = stamps
        # The links of each sub-network at one tick, shared by its members' views.
        self._group_links: tuple[object, dict[frozenset[int], Links]] = (None, {})

    def send(self, message: Message, tick: int) -> None:
        """Hand a message to the communication model.

        A robot knows its sub-network, so it does not transmit a broadcast when it
        has nobody to reach (a lone robot sends nothing).
        """
        if message.is_broadcast and len(self.network.subnetwork_of(message.sender)) < 2:
            return
        self.network.send(message, tick)

    def update_links(self, tick: int, alive: frozenset[int]) -> None:
        """Let the communication model see where the robots are; let sharing react."""
        self.network.update(tick, {r.id: r.position for r in self.robots}, alive)
        beliefs = [r.belief for r in self.robots]
        subnetworks = self.network.subnetworks()
        for message in self.sharing.on_topology(tick, subnetworks, self.network.links(), beliefs):
            self.send(message, tick)

    def deliver(self, tick: int) -> None:
        """Hand over the messages due at ``tick``: map messages are merged into the
        live robots' beliefs, the others go to their inboxes; then send what the
        sharing mechanism queued in reply."""
        map_types = self.sharing.message_types
        for robot_id, messages in self.network.deliver(tick).items():
            robot = self.robots[robot_id]
            if not robot.alive:
                continue
            map_messages = [m for m in messages if m.type in map_types]
            if map_messages:
                robot.new_cells += self.sharing.on_receive_all(robot_id, robot.belief, map_messages)
                self.stamps.received(robot, map_messages, tick)
            robot.inbox.extend(m for m in messages if m.type not in map_types)
        for message in self.sharing.drain():
            self.send(dataclasses.replace(message, tick_sent=tick), tick)

    def flush(self, tick: int) -> None:
        """Transmit what was sent during ``tick``."""
        self.network.flush(tick)

    def subnetwork_links(self, tick: int, subnetwork: frozenset[int], all_links: Links) -> Links:
        """The links between members of ``subnetwork`` (computed once per tick)."""
        key = (tick, all_links)
        if self._group_links[0] != key:
            self._group_links = (key, {})
        links = self._group_links[1].get(subnetwork)
        if links is None:
            links = frozenset(link for link in all_links if link[0] in subnetwork)
            self._group_links[1][subnetwork] = links
        return links

    def network_stats(self) -> dict[str, Any]:
        """The comm model's own counts (:meth:`CommModel.stats
        <mrexplore.comm.CommModel.stats>`), as :class:`~mrexplore.sim.record.RunRecord`
        fields."""
        stats = self.network.stats()
        return {
            "subnetworks": np.asarray(stats.subnetwork_counts, dtype=np.int64),
            "partition_events": int(stats.partition_events),
            "merge_events": int(stats.merge_events),
            "queue_delay_mean": float(stats.queue_delay_mean),
        }
