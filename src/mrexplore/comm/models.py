"""Communication models: each tick, who can talk and what gets delivered.

A model has one job: given the robots' positions and who is alive, decide which
robots are linked (and so which sub-networks exist) and deliver the messages
sent to it. Every message handed to :meth:`CommModel.send` is counted in the
model's :class:`~mrexplore.comm.ledger.ByteLedger` when it is transmitted.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections import defaultdict
from collections.abc import Callable, Mapping
from typing import Any

from mrexplore.comm.ledger import ByteLedger
from mrexplore.comm.messages import Message
from mrexplore.errors import UnknownIdError

Position = tuple[int, int]


class CommModel(ABC):
    """Base class of communication models.

    The simulator calls, each tick: :meth:`update` with the robots' positions,
    then :meth:`deliver` to get every robot's inbox, and :meth:`send` for every
    message a robot emits during the tick.
    """

    id: str = ""

    def __init__(self, n_robots: int) -> None:
        self.n_robots = n_robots
        self.ledger = ByteLedger(n_robots)

    @abstractmethod
    def update(self, tick: int, positions: Mapping[int, Position], alive: frozenset[int]) -> None:
        """Recompute the links for ``tick`` from positions of the live robots."""

    @abstractmethod
    def subnetworks(self) -> list[frozenset[int]]:
        """The connected groups of live robots after the last :meth:`update`."""

    @abstractmethod
    def send(self, message: Message, tick: int) -> None:
        """Accept ``message`` emitted at ``tick``."""

    @abstractmethod
    def deliver(self, tick: int) -> dict[int, list[Message]]:
        """Messages arriving at ``tick``, keyed by receiving robot id."""

    @abstractmethod
    def in_flight(self) -> int:
        """How many messages are sent but not yet delivered or lost."""

    def subnetwork_of(self, robot: int) -> frozenset[int]:
        """The sub-network holding ``robot`` (just itself if it is isolated)."""
        for group in self.subnetworks():
            if robot in group:
                return group
        return frozenset({robot})


class Unlimited(CommModel):
    """Unlimited range and bandwidth, no loss: every message arrives at the next tick.

    A broadcast reaches every other live robot; a unicast reaches its live
    receiver. All live robots form one sub-network.
    """

    id = "unlimited"

    def __init__(self, n_robots: int) -> None:
        super().__init__(n_robots)
        self._alive: frozenset[int] = frozenset(range(n_robots))
        self._queue: dict[int, list[Message]] = defaultdict(list)

    def update(self, tick: int, positions: Mapping[int, Position], alive: frozenset[int]) -> None:
        self._alive = alive

    def subnetworks(self) -> list[frozenset[int]]:
        return [self._alive] if self._alive else []

    def send(self, message: Message, tick: int) -> None:
        self.ledger.record(message, tick)
        self._queue[tick + 1].append(message)

    def deliver(self, tick: int) -> dict[int, list[Message]]:
        inbox: dict[int, list[Message]] = defaultdict(list)
        for message in self._queue.pop(tick, []):
            if message.is_broadcast:
                for robot in sorted(self._alive):
                    if robot != message.sender:
                        inbox[robot].append(message)
            elif message.dest in self._alive:
                inbox[message.dest].append(message)
        return inbox

    def in_flight(self) -> int:
        return sum(len(messages) for messages in self._queue.values())


COMM_MODELS: dict[str, Callable[..., CommModel]] = {"unlimited": Unlimited}


def make_comm_model(name: str, n_robots: int, **params: Any) -> CommModel:
    """Build a communication model by registry id."""
    try:
        factory = COMM_MODELS[name]
    except KeyError:
        raise UnknownIdError("communication model", name, list(COMM_MODELS)) from None
    return factory(n_robots, **params)
