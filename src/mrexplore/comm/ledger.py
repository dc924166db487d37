"""Exact byte accounting: totals per message type, per robot and per tick."""

from __future__ import annotations

from collections import defaultdict

import numpy as np
import numpy.typing as npt

from mrexplore.comm.messages import Message


class ByteLedger:
    """Counts every transmission (bytes and messages) as it is sent.

    Counts are kept per type, per sending robot and per tick; the three views
    always sum to the same total.
    """

    def __init__(self, n_robots: int) -> None:
        self.n_robots = n_robots
        self.bytes_by_type: dict[str, int] = defaultdict(int)
        self.messages_by_type: dict[str, int] = defaultdict(int)
        self.bytes_by_robot = np.zeros(n_robots, dtype=np.int64)
        self._bytes_by_tick: dict[int, int] = defaultdict(int)
        self.lost_by_type: dict[str, int] = defaultdict(int)

    def record(self, message: Message, tick: int) -> None:
        """Count one transmission of ``message`` at ``tick``."""
        self.bytes_by_type[message.type] += message.size_bytes
        self.messages_by_type[message.type] += 1
        self.bytes_by_robot[message.sender] += message.size_bytes
        self._bytes_by_tick[tick] += message.size_bytes

    def record_lost(self, message: Message) -> None:
        """Count a transmission that never arrived (it was already recorded as sent)."""
        self.lost_by_type[message.type] += 1

    @property
    def total(self) -> int:
        return int(sum(self.bytes_by_type.values()))

    def bytes_per_tick(self, n_ticks: int) -> npt.NDArray[np.int64]:
        """Bytes sent at each tick ``0 .. n_ticks - 1``."""
        out = np.zeros(n_ticks, dtype=np.int64)
        for tick, n_bytes in self._bytes_by_tick.items():
            if 0 <= tick < n_ticks:
                out[tick] = n_bytes
        return out
