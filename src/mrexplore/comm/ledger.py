"""Exact byte accounting: totals per message type, per robot and per tick."""

from __future__ import annotations

from collections import defaultdict

import numpy as np
import numpy.typing as npt

from mrexplore.comm.messages import Message


class ByteLedger:
    """Counts every byte put on the air, when it is put there.

    A transmission of a message over one hop is counted once (a radio broadcast
    reaches every neighbour at once). With a bandwidth limit a long message is
    sent over several ticks; its bytes are counted in the ticks they were sent.
    Per-type, per-robot and per-tick views always sum to the same total.
    """

    def __init__(self, n_robots: int) -> None:
        self.n_robots = n_robots
        self.bytes_by_type: dict[str, int] = defaultdict(int)
        self.messages_by_type: dict[str, int] = defaultdict(int)
        self.hops_by_type: dict[str, int] = defaultdict(int)
        self.bytes_by_robot = np.zeros(n_robots, dtype=np.int64)
        self.bytes_by_robot_tick: dict[tuple[int, int], int] = defaultdict(int)
        self._bytes_by_tick: dict[int, int] = defaultdict(int)
        self.lost_by_type: dict[str, int] = defaultdict(int)

    def count_message(self, message: Message) -> None:
        """Count one message handed to the network by its sender."""
        self.messages_by_type[message.type] += 1

    def count_hop(self, message: Message) -> None:
        """Count one completed hop (a transmission by the sender or a relay)."""
        self.hops_by_type[message.type] += 1

    def record_bytes(self, message: Message, transmitter: int, tick: int, n_bytes: int) -> None:
        """Count ``n_bytes`` of ``message`` put on the air by ``transmitter`` at ``tick``."""
        self.bytes_by_type[message.type] += n_bytes
        self.bytes_by_robot[transmitter] += n_bytes
        self.bytes_by_robot_tick[(tick, transmitter)] += n_bytes
        self._bytes_by_tick[tick] += n_bytes

    def record(self, message: Message, tick: int) -> None:
        """Count a whole single-hop transmission of ``message`` by its sender."""
        self.count_message(message)
        self.count_hop(message)
        self.record_bytes(message, message.sender, tick, message.size_bytes)

    def record_lost(self, message: Message) -> None:
        """Count a reception that never happened (lost, receiver dead or unreachable)."""
        self.lost_by_type[message.type] += 1

    @property
    def total(self) -> int:
        return int(sum(self.bytes_by_type.values()))

    @property
    def lost(self) -> int:
        return int(sum(self.lost_by_type.values()))

    def bytes_per_tick(self, n_ticks: int) -> npt.NDArray[np.int64]:
        """Bytes sent at each tick ``0 .. n_ticks - 1``."""
        out = np.zeros(n_ticks, dtype=np.int64)
        for tick, n_bytes in self._bytes_by_tick.items():
            if 0 <= tick < n_ticks:
                out[tick] = n_bytes
        return out
