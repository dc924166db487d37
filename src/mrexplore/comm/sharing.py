"""Map-sharing mechanisms: how robots keep their belief maps in sync.

A mechanism turns a robot's new observations into messages and merges received
messages into a belief. It never sees ground truth.

* ``broadcast``: every new observation is broadcast to the sub-network as one
  ``map_update`` message per robot per tick (5 bytes a cell plus the header),
  relayed hop by hop; a receiver writes the received cells it does not know yet.
  Nothing else: robots that were apart when a cell was sensed never learn it from
  each other (Vazquez & Malcolm §4: "each broadcasts its sensorial information every
  half second. The information arrives by multi hops to all the members of the team").
* ``full``: ``broadcast``, and when sub-networks join, the two robots of the new
  link exchange their whole maps (Sheng's "without tracking").
* ``none``: nothing is shared (for ablations).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, cell_updates_size
from mrexplore.comm.messages import MAP_FULL, MAP_MULTICAST, MAP_UPDATE, Message
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import UNKNOWN, BeliefGrid
from mrexplore.registry import Registry


@dataclass(frozen=True, slots=True)
class CellUpdates:
    """Payload of a ``map_update``: parallel arrays of rows, cols and states."""

    rows: npt.NDArray[np.int64]
    cols: npt.NDArray[np.int64]
    values: npt.NDArray[np.int8]


@dataclass(frozen=True, slots=True)
class Observation:
    """Cells one robot sensed itself for the first time at one tick.

    ``values`` are the cells' true states (FREE / OCCUPIED); ``was_unknown`` says
    which of them the robot's belief did not hold yet (not even from messages).
    """

    rows: npt.NDArray[np.int64]
    cols: npt.NDArray[np.int64]
    values: npt.NDArray[np.int8]
    was_unknown: npt.NDArray[np.bool_]


class MapSharing(ABC):
    """Base class of map-sharing mechanisms.

    One object serves the whole team, but it keeps each robot's protocol state
    apart and builds robot ``i``'s messages only from what robot ``i`` knows.
    The simulator calls, each tick: :meth:`on_tick` after the links are updated
    (to react to sub-networks merging or splitting), :meth:`on_receive_all` with
    each robot's map messages, and :meth:`on_observe` after each robot senses.
    """

    id: str = ""
    message_types: frozenset[str] = frozenset()

    acts_on_joins: bool = False
    """Whether :meth:`on_topology` looks for links joining sub-networks and calls
    :meth:`on_join` for each (off by default: it costs a pass over the links)."""

    def bind(self, n_robots: int, shape: tuple[int, int]) -> None:
        """Called once before the run with the team size and the grid shape."""
        self.n_robots = n_robots
        self.shape = shape
        self.outbox: list[Message] = []
        self.previous: list[frozenset[int]] = []
        self.old_group: dict[tuple[int, int], frozenset[int]] = {}

    def drain(self) -> list[Message]:
        """Messages the mechanism decided to send while receiving (e.g. a multicast)."""
        out, self.outbox = self.outbox, []
        return out

    @abstractmethod
    def on_observe(
        self, robot: int, tick: int, observation: Observation, belief: BeliefGrid
    ) -> list[Message]:
        """Messages to send after ``robot`` sensed new cells at ``tick``.

        ``belief`` already holds the observation.
        """

    def on_tick(
        self, tick: int, subnetworks: list[frozenset[int]], beliefs: Sequence[BeliefGrid]
    ) -> list[Message]:
        """Messages to send when the links are known for ``tick`` (default: none)."""
        return []

    def on_topology(
        self,
        tick: int,
        subnetworks: list[frozenset[int]],
        links: frozenset[tuple[int, int]],
        beliefs: Sequence[BeliefGrid],
    ) -> list[Message]:
        """Like :meth:`on_tick`, with the direct links too; the simulator calls this one.

        With :attr:`acts_on_joins`, also :meth:`on_join` for every link that joins
        sub-networks which were apart at the previous tick, after noting each end's
        old sub-network for :meth:`rest_of_old_group`.
        """
        messages = self.on_tick(tick, subnetworks, beliefs)
        if self.acts_on_joins:
            if self.previous:
                for join in joining_links(self.previous, links):
                    self.old_group[(join.a, join.b)] = join.group_a
                    self.old_group[(join.b, join.a)] = join.group_b
                    messages.extend(self.on_join(tick, join, beliefs))
            self.previous = subnetworks
        return messages

    def on_join(self, tick: int, join: Join, beliefs: Sequence[BeliefGrid]) -> list[Message]:
        """Messages to send when the new link ``(join.a, join.b)`` joins ``a``'s old
        sub-network ``join.group_a`` to ``b``'s ``join.group_b`` (with
        :attr:`acts_on_joins`; default: none)."""
        return []

    def rest_of_old_group(self, robot: int, peer: int) -> frozenset[int]:
        """The rest of ``robot``'s sub-network before it joined ``peer``'s: who it
        passes on what ``peer`` sent over their new link (once; empty afterwards)."""
        return self.old_group.pop((robot, peer), frozenset()) - {robot}

    @abstractmethod
    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        """Merge ``message`` into ``belief``; return how many cells became known."""

    def on_receive_all(self, robot: int, belief: BeliefGrid, messages: list[Message]) -> int:
        """Merge every message ``robot`` got this tick, in order; return the new cells."""
        return sum(self.on_receive(robot, belief, message) for message in messages)

    def metrics(self) -> dict[str, Any]:
        """Mechanism-specific metrics for ``result.json`` (default: none)."""
        return {}


def new_cells(observation: Observation) -> CellUpdates | None:
    """The cells of ``observation`` the robot did not know yet (``None`` if there are none):
    what a mechanism announces of its own sensing."""
    new = observation.was_unknown
    if not new.any():
        return None
    return CellUpdates(observation.rows[new], observation.cols[new], observation.values[new])


def known_cells(belief: BeliefGrid) -> CellUpdates:
    """Every cell ``belief`` knows, as cell updates (raster order)."""
    rows, cols = np.nonzero(belief != UNKNOWN)
    return CellUpdates(rows.astype(np.int64), cols.astype(np.int64), belief[rows, cols].copy())


@numba.njit(cache=True, nogil=True)
def _merge_kernel(
    rows: npt.NDArray[np.int64],
    cols: npt.NDArray[np.int64],
    values: npt.NDArray[np.int8],
    belief: npt.NDArray[np.int8],
    was_unknown: npt.NDArray[np.bool_],
) -> int:  # pragma: no cover - compiled
    """The numpy merge of :func:`merge_many` in one compiled pass, for values that are
    never ``UNKNOWN`` (the caller checks): which cells were unknown is read before any
    write, writes go in order (the last wins, as numpy's fancy assignment does), and
    the first write to a cell (it still reads ``UNKNOWN``) counts it once."""
    n = rows.shape[0]
    for k in range(n):
        was_unknown[k] = belief[rows[k], cols[k]] == -1
    new = 0
    for k in range(n):
        if was_unknown[k]:
            r, c = rows[k], cols[k]
            if belief[r, c] == -1:
                new += 1
            belief[r, c] = values[k]
    return new


def merge_many(belief: BeliefGrid, payloads: Sequence[CellUpdates]) -> int:
    """Merge several updates at once into the unknown cells; count each new cell once."""
    if len(payloads) == 1:
        return merge_unknown(belief, payloads[0])
    rows = np.concatenate([p.rows for p in payloads])
    cols = np.concatenate([p.cols for p in payloads])
    values = np.concatenate([p.values for p in payloads])
    if (
        belief.flags.c_contiguous
        and rows.dtype == np.int64
        and cols.dtype == np.int64
        and values.dtype == np.int8
        and not (values == UNKNOWN).any()
    ):
        return int(_merge_kernel(rows, cols, values, belief, np.empty(rows.size, dtype=np.bool_)))
    unknown = belief[rows, cols] == UNKNOWN
    rows, cols = rows[unknown], cols[unknown]
    belief[rows, cols] = values[unknown]
    return int(np.unique(rows * belief.shape[1] + cols).size)


def merge_unknown(belief: BeliefGrid, updates: CellUpdates) -> int:
    """Write ``updates`` into the cells of ``belief`` that are still unknown.

    Returns the number of cells that changed.
    """
    current = belief[updates.rows, updates.cols]
    unknown = current == UNKNOWN
    n_new = int(np.count_nonzero(unknown))
    if n_new:
        belief[updates.rows[unknown], updates.cols[unknown]] = updates.values[unknown]
    return n_new


class Join(NamedTuple):
    """A new link ``(a, b)`` between robots whose old sub-networks were apart."""

    a: int
    b: int
    group_a: frozenset[int]
    """``a``'s sub-network at the previous tick (``{a}`` if it was in none)."""
    group_b: frozenset[int]
    """``b``'s sub-network at the previous tick (``{b}`` if it was in none)."""


def joining_links(previous: list[frozenset[int]], links: frozenset[tuple[int, int]]) -> list[Join]:
    """The new links that join sub-networks which were apart at the previous tick.

    One link per pair of old sub-networks joined (the lowest ``(a, b)``), with the
    old sub-networks of ``a`` and ``b``. Robots that were in no old sub-network
    (tick 0) count as alone.

    >>> joining_links([frozenset({0, 1}), frozenset({2})], frozenset({(0, 1), (1, 2)}))
    [Join(a=1, b=2, group_a=frozenset({0, 1}), group_b=frozenset({2}))]
    """
    old_group = {robot: group for group in previous for robot in group}
    # Most ticks every link lies inside one old sub-network: nothing joins.
    if all((group := old_group.get(a)) is not None and group is old_group.get(b) for a, b in links):
        return []
    parent: dict[frozenset[int], frozenset[int]] = {}

    def root(group: frozenset[int]) -> frozenset[int]:
        while parent.get(group, group) != group:
            group = parent[group]
        return group

    joins = []
    for a, b in sorted(links):
        group_a = old_group.get(a, frozenset({a}))
        group_b = old_group.get(b, frozenset({b}))
        root_a, root_b = root(group_a), root(group_b)
        if root_a != root_b:
            parent[root_b] = root_a
            joins.append(Join(a, b, group_a, group_b))
    return joins


class BroadcastSharing(MapSharing):
    """Broadcast every new observation to the sub-network, nothing more.

    Vazquez & Malcolm §4: "each broadcasts its sensorial information every half second.
    The information arrives by multi hops to all the members of the team". A robot
    that was out of reach when a cell was broadcast never receives it: there is no
    exchange when sub-networks join.
    """

    id = "broadcast"
    message_types = frozenset({MAP_UPDATE})

    def on_observe(
        self, robot: int, tick: int, observation: Observation, belief: BeliefGrid
    ) -> list[Message]:
        payload = new_cells(observation)
        if payload is None:
            return []
        size = cell_updates_size(int(payload.rows.size))
        return [Message(MAP_UPDATE, robot, BROADCAST, size, payload, tick)]

    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        payload = message.payload
        assert isinstance(payload, CellUpdates)
        return merge_unknown(belief, payload)

    def on_receive_all(self, robot: int, belief: BeliefGrid, messages: list[Message]) -> int:
        updates = [m.payload for m in messages]
        return merge_many(belief, updates) if updates else 0


class FullSharing(BroadcastSharing):
    """``broadcast``; on a merge exchange whole explored maps.

    Sheng et al. §4's brute-force solution ("without tracking"): when a new link
    joins two sub-networks, its two robots send each other every cell they know
    (``map_full``, 5 bytes a cell), and each multicasts what it received to the
    rest of its old sub-network (``map_multicast``).
    """

    id = "full"
    message_types = frozenset({MAP_UPDATE, MAP_FULL, MAP_MULTICAST})
    acts_on_joins = True

    def on_join(self, tick: int, join: Join, beliefs: Sequence[BeliefGrid]) -> list[Message]:
        messages = []
        for me, peer in ((join.a, join.b), (join.b, join.a)):
            known = known_cells(beliefs[me])
            size = cell_updates_size(int(known.rows.size))
            messages.append(Message(MAP_FULL, me, peer, size, known, tick))
        return messages

    def on_receive_all(self, robot: int, belief: BeliefGrid, messages: list[Message]) -> int:
        new = super().on_receive_all(robot, belief, [m for m in messages if m.type != MAP_FULL])
        for message in messages:
            if message.type != MAP_FULL:
                continue
            payload = message.payload
            assert isinstance(payload, CellUpdates)
            new += merge_unknown(belief, payload)
            others = self.rest_of_old_group(robot, message.sender)
            if others:
                size = cell_updates_size(int(payload.rows.size))
                self.outbox.append(
                    Message(MAP_MULTICAST, robot, BROADCAST, size, payload, recipients=others)
                )
        return new


class NoSharing(MapSharing):
    """Robots keep what they sense to themselves."""

    id = "none"

    def on_observe(
        self, robot: int, tick: int, observation: Observation, belief: BeliefGrid
    ) -> list[Message]:
        return []

    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        return 0


SHARING: Registry[Callable[..., MapSharing]] = Registry("sharing mechanism", "mrexplore.sharing")
"""Registry of sharing mechanisms (plugins: entry-point group ``mrexplore.sharing``);
``mrexplore.comm`` registers the ones in their own modules."""
for _mechanism in (BroadcastSharing, FullSharing, NoSharing):
    SHARING.register(_mechanism)


def make_sharing(name: str, **params: Any) -> MapSharing:
    """Build a map-sharing mechanism by registry id."""
    factory = SHARING.get(name)  # UnknownIdError names the known ids
    converted = {key: _number_or_text(value) for key, value in params.items()}
    accepted = _parameter_names(factory)
    foreign = [key for key in params if accepted is not None and key not in accepted]
    if foreign:
        key = foreign[0]
        owners = [other for other, made in SHARING.items() if key in (_parameter_names(made) or ())]
        where = (
            f"it is a parameter of --sharing {' / '.join(owners)}"
            if owners
            else "no sharing mechanism has it"
        )
        takes = ", ".join(sorted(accepted or ())) or "no parameters"
        raise ScenarioError(f"--share {key}={params[key]}: sharing {name!r} takes {takes}; {where}")
    try:
        return factory(**converted)
    except (TypeError, ValueError) as error:
        given = ", ".join(f"{k}={v}" for k, v in params.items())
        raise ScenarioError(f"--share {given}: not valid for {name!r} ({error})") from None


def _parameter_names(factory: Callable[..., MapSharing]) -> set[str] | None:
    """The keyword parameters a sharing mechanism's constructor accepts (``None``:
    unknown, it takes ``**kwargs`` or has no signature)."""
    import inspect

    try:
        signature = inspect.signature(factory)
    except (TypeError, ValueError):
        return None
    if any(p.kind is p.VAR_KEYWORD for p in signature.parameters.values()):
        return None
    return {
        name
        for name, parameter in signature.parameters.items()
        if parameter.kind in (parameter.POSITIONAL_OR_KEYWORD, parameter.KEYWORD_ONLY)
    }


def _number_or_text(value: Any) -> Any:
    """``--share`` values arrive as text: turn numbers into int or float."""
    if not isinstance(value, str):
        return value
    for kind in (int, float):
        try:
            return kind(value)
        except ValueError:
            pass
    return value
