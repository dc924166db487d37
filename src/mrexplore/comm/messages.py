"""Messages: what robots send each other, with a type and an exact size."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from mrexplore.comm.bytes import BROADCAST

# Message types. Strategies may define their own; these are the built-in ones.
MAP_UPDATE = "map_update"
MAP_FULL = "map_full"
MAP_MULTICAST = "map_multicast"
MAP_DELTA = "map_delta"
SEQ_TABLE = "seq_table"
MAP_SYNC = "map_sync"
STATUS = "status"
ASSIGN = "assign"
TARGET = "target"
BID = "bid"


@dataclass(frozen=True, slots=True)
class Message:
    """One message on the network.

    Attributes:
        type: message type (``"map_update"``, ``"assign"``, ...).
        sender: robot id of the sender.
        dest: robot id of the receiver, or :data:`BROADCAST` for every robot the
            communication model lets it reach.
        size_bytes: size on the wire from :mod:`mrexplore.comm.bytes`.
        payload: the content; treat it as read-only.
        tick_sent: the tick at which it was sent (set by the simulator).
        priority: queue priority at the sender under a bandwidth limit (lower first;
            equal priorities keep their order).
        recipients: for a broadcast, restrict it to these robots (a multicast);
            ``None`` = the whole sub-network.
    """

    type: str
    sender: int
    dest: int
    size_bytes: int
    payload: Any = field(default=None, compare=False)
    tick_sent: int = -1
    priority: int = 0
    recipients: frozenset[int] | None = field(default=None, compare=False)

    @property
    def is_broadcast(self) -> bool:
        return self.dest == BROADCAST
