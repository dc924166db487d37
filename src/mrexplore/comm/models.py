"""Communication models: each tick, who can talk and what gets delivered.

The built-in model is a store-and-forward :class:`Network` composed of

* a :class:`~mrexplore.comm.links.LinkModel` (unlimited range, or a range in cells,
  optionally blocked by walls): who hears whom directly; the connected components
  of its links are the sub-networks, and every robot knows the topology of its
  own sub-network;
* a per-robot bandwidth (bytes per tick; excess waits in a FIFO queue per sender,
  lower ``priority`` first, nothing is silently dropped);
* a :class:`~mrexplore.comm.channels.Channel` per hop: latency in ticks and
  independent loss, composed by wrapping.

Broadcasts reach every robot of the sender's sub-network (as it was when the
message was sent) by relaying: a robot that receives a broadcast re-transmits it
once if one of its current neighbours still lacks it. A unicast follows a
shortest path (in hops) over the current links, re-routed at every relay. Each
transmission over one hop costs the message's size once (radio). A message that
cannot be delivered (receiver dead, unreachable, or the reception lost) is
counted as lost, never as delivered.

Timing: messages emitted during tick ``t`` are transmitted in the network's
:meth:`Network.flush` at the end of tick ``t`` (as far as the bandwidth allows)
and arrive at tick ``t + latency`` (``latency >= 1``, default 1); each relay adds
its own hop.

Communication models are looked up by id in :data:`COMM_MODELS` (``--comm-model
ID``; the default ``network`` is :class:`Network`); third-party models register
through the entry-point group ``mrexplore.comm`` and can be checked with
:func:`mrexplore.checks.check_comm_model`. ``docs/comm-models.md`` explains the
protocol.
"""

from __future__ import annotations

import heapq
import itertools
import math
from abc import ABC, abstractmethod
from collections import defaultdict, deque
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from mrexplore.comm.channels import Channel, Delayed, Lossy, Perfect
from mrexplore.comm.ledger import ByteLedger
from mrexplore.comm.links import AllLinks, Link, LinkModel, RangeLinks, components
from mrexplore.comm.messages import Message
from mrexplore.errors import ScenarioError
from mrexplore.params import Param
from mrexplore.registry import Registry

Position = tuple[int, int]

COMM_ENTRY_POINT_GROUP = "mrexplore.comm"
DEFAULT_COMM_MODEL = "network"


@dataclass(frozen=True)
class CommSetup:
    """What the simulator hands a communication model to build it from.

    Attributes:
        n_robots: the team size (robot ids ``0 .. n_robots - 1``).
        occupied: ground-truth walls (``True`` = occupied), for models in which walls
            block or weaken radio. Strategies never see it; neither may a model pass
            it on to them.
        rng: the seed's own ``comm`` stream; every random choice of the model comes
            from it (same seed, same deliveries).
        comm_range: ``--comm-range`` in cells (``inf`` = unlimited).
        comm_los: ``--comm-los``.
        bandwidth: ``--bandwidth``, bytes per tick per robot (``inf`` = unlimited).
        latency: ``--latency``, ticks per hop (>= 1).
        loss: ``--loss``, probability that one reception is lost.
        metres_per_cell: the map's resolution, ``None`` if it has none.
    """

    n_robots: int
    occupied: npt.NDArray[np.bool_]
    rng: np.random.Generator
    comm_range: float = math.inf
    comm_los: bool = False
    bandwidth: float = math.inf
    latency: int = 1
    loss: float = 0.0
    metres_per_cell: float | None = None


@dataclass(frozen=True)
class CommStats:
    """What a communication model reports for the run's metrics (besides its
    :class:`~mrexplore.comm.ledger.ByteLedger`).

    Attributes:
        subnetwork_counts: number of sub-networks after each :meth:`CommModel.update`
            (one per tick, tick 0 first).
        partition_events: times an old sub-network split.
        merge_events: times old sub-networks joined.
        queue_delay_mean: mean ticks a transmission waited in a queue (0 if none).
    """

    subnetwork_counts: tuple[int, ...] = ()
    partition_events: int = 0
    merge_events: int = 0
    queue_delay_mean: float = 0.0


class CommModel(ABC):
    """Base class of communication models: each tick, who can talk and what gets through.

    The simulator calls, each tick: :meth:`update` with the robots' positions,
    :meth:`deliver` to get every robot's inbox, :meth:`send` for every message a
    robot emits during the tick, and :meth:`flush` at the end of the tick; at the
    end of the run it reads :attr:`ledger` (every byte put on the air, counted
    with :class:`~mrexplore.comm.ledger.ByteLedger`) and :meth:`stats`.

    A registered model sets ``id``, ``summary`` and ``params`` (its own settings,
    ``--comm key=value``) and builds itself in :meth:`from_setup`. The contract,
    checked by :func:`mrexplore.checks.check_comm_model`:

    * a message reaches only live robots of its sender's sub-network as it was
      when it was sent, never its sender, each receiver at most once, and never at
      the tick it was sent;
    * :meth:`subnetworks` are the connected components of :meth:`links` over the
      live robots (a robot alone is its own sub-network);
    * what is not delivered is counted as lost (``ledger.record_lost``);
    * every random choice comes from ``setup.rng``.

    :meth:`record_topology` keeps the sub-network statistics that :meth:`stats`
    reports; a model calls it from :meth:`update`.
    """

    id: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    params: ClassVar[Mapping[str, Param]] = {}

    def __init__(self, n_robots: int) -> None:
        self.n_robots = n_robots
        self.ledger = ByteLedger(n_robots)
        self.subnetwork_counts: list[int] = []
        self.partition_events = 0
        self.merge_events = 0
        self.queue_delays: list[int] = []

    @classmethod
    @abstractmethod
    def from_setup(cls, setup: CommSetup, **params: Any) -> CommModel:
        """Build the model for one run; ``params`` are :attr:`params`' values,
        already converted and range-checked (defaults filled in)."""

    @abstractmethod
    def update(self, tick: int, positions: Mapping[int, Position], alive: frozenset[int]) -> None:
        """Recompute the links for ``tick`` from positions of the live robots."""

    @abstractmethod
    def links(self) -> frozenset[Link]:
        """The direct links after the last :meth:`update`."""

    @abstractmethod
    def subnetworks(self) -> list[frozenset[int]]:
        """The connected groups of live robots after the last :meth:`update`."""

    @abstractmethod
    def send(self, message: Message, tick: int) -> None:
        """Accept ``message`` emitted at ``tick``."""

    def flush(self, tick: int) -> None:  # noqa: B027  # optional hook, empty by default
        """End of ``tick``: transmit what the bandwidth allows."""

    @abstractmethod
    def deliver(self, tick: int) -> dict[int, list[Message]]:
        """Messages arriving at ``tick``, keyed by receiving robot id."""

    @abstractmethod
    def in_flight(self) -> int:
        """How many messages are queued or travelling."""

    @abstractmethod
    def describe(self) -> str:
        """A short description for reports."""

    def stats(self) -> CommStats:
        """The model's network statistics for the run's metrics."""
        return CommStats(
            subnetwork_counts=tuple(self.subnetwork_counts),
            partition_events=self.partition_events,
            merge_events=self.merge_events,
            queue_delay_mean=float(np.mean(self.queue_delays or [0])),
        )

    def record_topology(
        self,
        tick: int,
        previous: list[frozenset[int]],
        groups: list[frozenset[int]],
        alive: frozenset[int],
    ) -> None:
        """Count the sub-networks after an update, and (after tick 0) the partitions and
        merges between the ``previous`` groups and the new ``groups`` of live robots."""
        if tick > 0:
            live_previous = [g & alive for g in previous]
            for group in groups:
                if sum(1 for old in live_previous if old & group) > 1:
                    self.merge_events += 1
            for old in live_previous:
                if sum(1 for group in groups if group & old) > 1:
                    self.partition_events += 1
        self.subnetwork_counts.append(len(groups))

    def subnetwork_of(self, robot: int) -> frozenset[int]:
        """The sub-network holding ``robot`` (just itself if it is isolated)."""
        for group in self.subnetworks():
            if robot in group:
                return group
        return frozenset({robot})


COMM_MODELS: Registry[type[CommModel]] = Registry("communication model", COMM_ENTRY_POINT_GROUP)
"""Communication models by id (``--comm-model``); plugins: entry-point group
``mrexplore.comm``, each entry point naming a :class:`CommModel` subclass."""


def make_comm_model(
    name: str, setup: CommSetup, params: Mapping[str, Any] | None = None
) -> CommModel:
    """Build communication model ``name`` for one run; ``params`` (``--comm key=value``
    for the model's own settings) are converted and checked against its declaration.

    Raises:
        UnknownIdError: no model has this id.
        ScenarioError: an unknown parameter or a value out of range.
    """
    cls = COMM_MODELS.get(name)
    resolved = COMM_MODELS.resolve_params(name, params or {}, option="--comm")
    return cls.from_setup(setup, **resolved)


@dataclass(eq=False)
class _Packet:
    """A message on its way: who it is for, who has it, who will have it.

    ``uncovered`` is kept equal to ``destinations - reached - pending`` (the
    destinations no transmission has reached or is bringing yet), so that the
    relay tests of a broadcast intersect it instead of re-deriving it from the
    three sets at every reception.
    """

    message: Message
    destinations: frozenset[int]
    reached: set[int] = field(default_factory=set)
    pending: set[int] = field(default_factory=set)
    uncovered: set[int] = field(init=False)

    def __post_init__(self) -> None:
        self.uncovered = set(self.destinations).difference(self.reached, self.pending)


@dataclass(eq=False)
class _Transmission:
    packet: _Packet
    transmitter: int
    remaining: int
    queued_tick: int


@COMM_MODELS.register
class Network(CommModel):
    """Store-and-forward network over a link model, with bandwidth and a channel.

    If the link model declares per-link delivery probabilities
    (:attr:`LinkModel.lossy`), each reception over a link is also lost with one minus
    its :meth:`~mrexplore.comm.links.LinkModel.delivery_probability`, drawn from ``rng``.
    """

    id = DEFAULT_COMM_MODEL
    summary = (
        "store-and-forward multi-hop network: --comm-range (walls block with --comm-los), "
        "--bandwidth, --latency, --loss"
    )

    def __init__(
        self,
        n_robots: int,
        links: LinkModel,
        *,
        channel: Channel | None = None,
        bandwidth: float = math.inf,
        rng: np.random.Generator | None = None,
    ) -> None:
        super().__init__(n_robots)
        if not bandwidth > 0:
            raise ScenarioError(f"--bandwidth {bandwidth}: must be positive (bytes per tick)")
        if links.lossy and rng is None:
            raise ScenarioError(f"{links.describe()}: lossy links need a random generator")
        self.link_model = links
        self.channel = channel if channel is not None else Perfect()
        self.bandwidth = bandwidth
        self.rng = rng
        self._alive: frozenset[int] = frozenset(range(n_robots))
        self._links: frozenset[Link] = frozenset()
        self._topology_set = False
        self._neighbours: dict[int, set[int]] = {}
        self._groups: list[frozenset[int]] = []
        self._group_of: dict[int, frozenset[int]] = {}
        self._queues: dict[int, list[tuple[int, int, _Transmission]]] = defaultdict(list)
        self._order = itertools.count()
        self._arrivals: dict[int, list[tuple[_Packet, int, int]]] = defaultdict(list)
        self.hop_log: list[tuple[int, int, int, int | None, str]] = []
        """(tick sent, transmitter, receiver, arrival tick or None if lost, type)"""
        self.keep_hop_log = False

    @classmethod
    def from_setup(cls, setup: CommSetup, **params: Any) -> Network:
        return make_network(
            setup.n_robots,
            comm_range=setup.comm_range,
            comm_los=setup.comm_los,
            bandwidth=setup.bandwidth,
            latency=setup.latency,
            loss=setup.loss,
            occupied=setup.occupied,
            rng=setup.rng,
        )

    # ----------------------------------------------------------------- topology
    def update(self, tick: int, positions: Mapping[int, Position], alive: frozenset[int]) -> None:
        live_positions = {r: positions[r] for r in alive}
        links = self.link_model.links(live_positions)
        previous = self._groups
        if not self._topology_set or alive != self._alive or links != self._links:
            self._topology_set = True
            self._alive = alive
            self._links = links
            self._neighbours = {r: set() for r in alive}
            for a, b in links:
                self._neighbours[a].add(b)
                self._neighbours[b].add(a)
            self._groups = components(alive, links)
            self._group_of = {r: g for g in self._groups for r in g}
        # else: the same robots and links as at the previous tick, so the same
        # neighbours and sub-networks (a team in range of each other most ticks)
        self.record_topology(tick, previous, self._groups, alive)
        for robot in list(self._queues):
            if robot not in alive:  # a dead robot's queue dies with it
                for _, _, transmission in self._queues.pop(robot):
                    self.ledger.record_lost(transmission.packet.message)

    def links(self) -> frozenset[Link]:
        return self._links

    def subnetworks(self) -> list[frozenset[int]]:
        return list(self._groups)

    # ----------------------------------------------------------------- sending
    def send(self, message: Message, tick: int) -> None:
        sender = message.sender
        if sender not in self._alive:
            return
        self.ledger.count_message(message)
        group = self._group_of.get(sender, frozenset({sender}))
        if message.is_broadcast:
            destinations = group - {sender}
            if message.recipients is not None:
                destinations &= message.recipients
        elif message.dest in group and message.dest != sender:
            destinations = frozenset({message.dest})
        else:
            self.ledger.record_lost(message)  # receiver dead or out of reach
            return
        if not destinations:
            return
        packet = _Packet(message, destinations, reached={sender})
        self._enqueue(_Transmission(packet, sender, message.size_bytes, tick))

    def _enqueue(self, transmission: _Transmission) -> None:
        priority = transmission.packet.message.priority
        heapq.heappush(
            self._queues[transmission.transmitter],
            (priority, next(self._order), transmission),
        )

    def flush(self, tick: int) -> None:
        for robot in sorted(self._queues):
            queue = self._queues[robot]
            budget = self.bandwidth
            while queue and budget > 0:
                transmission = queue[0][2]
                n_bytes = int(min(transmission.remaining, budget))
                self.ledger.record_bytes(transmission.packet.message, robot, tick, n_bytes)
                transmission.remaining -= n_bytes
                budget -= n_bytes
                if transmission.remaining > 0:
                    break
                heapq.heappop(queue)
                self._complete(transmission, tick)

    def _complete(self, transmission: _Transmission, tick: int) -> None:
        """A hop finished transmitting at ``tick``: schedule its receptions."""
        packet = transmission.packet
        message = packet.message
        transmitter = transmission.transmitter
        self.ledger.count_hop(message)
        self.queue_delays.append(tick - transmission.queued_tick)
        neighbours = self._neighbours.get(transmitter, set())
        if message.is_broadcast:
            receivers = sorted(neighbours.intersection(packet.uncovered))
        else:
            hop = self._next_hop(transmitter, message.dest)
            if hop is None:
                self.ledger.record_lost(message)
                return
            receivers = [hop]
        arrivals = self.channel.arrivals(receivers, tick)
        if self.link_model.lossy and receivers:
            arrivals = self._link_losses(transmitter, receivers, arrivals, message.size_bytes)
        for receiver, arrival in zip(receivers, arrivals, strict=True):
            if self.keep_hop_log:
                self.hop_log.append((tick, transmitter, receiver, arrival, message.type))
            if arrival is None:
                if receiver in packet.destinations:
                    self.ledger.record_lost(message)
                continue
            packet.pending.add(receiver)
            packet.uncovered.discard(receiver)
            self._arrivals[arrival].append((packet, receiver, transmitter))

    def _link_losses(
        self, transmitter: int, receivers: list[int], arrivals: list[int | None], n_bytes: int
    ) -> list[int | None]:
        """Lose each reception with one minus its link's delivery probability."""
        assert self.rng is not None  # checked in __init__
        draws = self.rng.random(len(receivers))
        chance = self.link_model.delivery_probability
        return [
            None if arrival is None or draw >= chance(transmitter, receiver, n_bytes) else arrival
            for receiver, arrival, draw in zip(receivers, arrivals, draws, strict=True)
        ]

    def _next_hop(self, source: int, dest: int) -> int | None:
        """First robot on a shortest path (in hops) from ``source`` to ``dest``."""
        if dest in self._neighbours.get(source, set()):
            return dest
        previous: dict[int, int] = {source: source}
        frontier = deque([source])
        while frontier:
            node = frontier.popleft()
            for nxt in sorted(self._neighbours.get(node, set())):
                if nxt not in previous:
                    previous[nxt] = node
                    if nxt == dest:
                        while previous[nxt] != source:
                            nxt = previous[nxt]
                        return nxt
                    frontier.append(nxt)
        return None

    def deliver(self, tick: int) -> dict[int, list[Message]]:
        inbox: dict[int, list[Message]] = defaultdict(list)
        for packet, receiver, _transmitter in self._arrivals.pop(tick, []):
            message = packet.message
            packet.pending.discard(receiver)
            if receiver not in self._alive:
                if receiver in packet.destinations:
                    self.ledger.record_lost(message)
                    if receiver not in packet.reached and receiver not in packet.pending:
                        packet.uncovered.add(receiver)
                continue
            if receiver in packet.reached:
                continue
            packet.reached.add(receiver)
            if message.is_broadcast:
                inbox[receiver].append(message)
                neighbours = self._neighbours.get(receiver)
                # neighbours still to reach (set operations run in C)
                if neighbours and not neighbours.isdisjoint(packet.uncovered):
                    self._enqueue(_Transmission(packet, receiver, message.size_bytes, tick))
            elif receiver == message.dest:
                inbox[receiver].append(message)
            else:  # relay a unicast
                self._enqueue(_Transmission(packet, receiver, message.size_bytes, tick))
        return inbox

    def in_flight(self) -> int:
        queued = sum(len(q) for q in self._queues.values())
        return queued + sum(len(a) for a in self._arrivals.values())

    def describe(self) -> str:
        bandwidth = "" if math.isinf(self.bandwidth) else f", {self.bandwidth:g} B/tick"
        return f"{self.link_model.describe()}{bandwidth}, {self.channel.describe()}"


def make_network(
    n_robots: int,
    *,
    comm_range: float = math.inf,
    comm_los: bool = False,
    bandwidth: float = math.inf,
    latency: int = 1,
    loss: float = 0.0,
    occupied: npt.NDArray[np.bool_] | None = None,
    rng: np.random.Generator | None = None,
) -> Network:
    """Compose the built-in network from the scenario's communication settings."""
    if math.isinf(comm_range) and not comm_los:
        links: LinkModel = AllLinks()
    else:
        links = RangeLinks(comm_range, line_of_sight=comm_los, occupied=occupied)
    channel: Channel = Perfect()
    if latency != 1:
        channel = Delayed(channel, latency)
    if loss > 0:
        if rng is None:
            raise ScenarioError(f"--loss {loss}: a lossy channel needs a random generator")
        channel = Lossy(channel, loss, rng)
    return Network(n_robots, links, channel=channel, bandwidth=bandwidth)
