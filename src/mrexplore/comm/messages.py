"""Messages: what robots send each other, with a type and an exact size.

The coordination strategies exchange small fixed-size items of the byte model
(:mod:`mrexplore.comm.bytes`): a robot and a cell (a position, or a target
announced or assigned), a status (position and whether the robot needs a goal), a
bid (robot, cell, value). :class:`CellItem`, :class:`StatusItem` and
:class:`BidItem` are those items; :func:`item_message` wraps one in a message whose
size follows from the item's type, so no strategy states a size of its own.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from mrexplore.comm.bytes import BID_BYTES, BROADCAST, POSITION_BYTES, STATUS_BYTES, fixed_size

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


@dataclass(frozen=True, slots=True)
class CellItem:
    """A robot and one cell: its position, or a target it announces or is assigned
    (robot uint16, row uint16, col uint16: ``POSITION_BYTES`` = ``TARGET_BYTES``)."""

    robot: int
    cell: tuple[int, int]


@dataclass(frozen=True, slots=True)
class StatusItem:
    """A robot's position and whether it needs a goal (``STATUS_BYTES``)."""

    robot: int
    position: tuple[int, int]
    needs_goal: bool


@dataclass(frozen=True, slots=True)
class BidItem:
    """A robot's value for one cell; ``value`` travels as float32 (``BID_BYTES``)."""

    robot: int
    cell: tuple[int, int]
    value: float


ITEM_BYTES: dict[type, int] = {
    CellItem: POSITION_BYTES,
    StatusItem: STATUS_BYTES,
    BidItem: BID_BYTES,
}
"""Bytes of each item on the wire, from the byte model."""


def item_message(
    kind: str, sender: int, dest: int, item: CellItem | StatusItem | BidItem
) -> Message:
    """A message of type ``kind`` carrying one item, sized by the byte model.

    >>> item_message(ASSIGN, 0, 2, CellItem(2, (5, 7))).size_bytes
    13
    """
    return Message(kind, sender, dest, fixed_size(ITEM_BYTES[type(item)]), item)
