"""Map-sharing mechanisms: how robots keep their belief maps in sync.

A mechanism turns a robot's new observations into messages and merges received
messages into a belief. It never sees ground truth.

* ``full``: every new observation is broadcast to the sub-network as one
  ``map_update`` message per robot per tick (5 bytes a cell plus the header);
  a receiver writes the received cells it does not know yet.
* ``none``: nothing is shared (for ablations).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, cell_updates_size
from mrexplore.comm.messages import MAP_UPDATE, Message
from mrexplore.errors import ScenarioError, UnknownIdError
from mrexplore.grid.occupancy import UNKNOWN, BeliefGrid


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

    def bind(self, n_robots: int, shape: tuple[int, int]) -> None:
        """Called once before the run with the team size and the grid shape."""
        self.n_robots = n_robots
        self.shape = shape

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

    @abstractmethod
    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        """Merge ``message`` into ``belief``; return how many cells became known."""

    def on_receive_all(self, robot: int, belief: BeliefGrid, messages: list[Message]) -> int:
        """Merge every message ``robot`` got this tick, in order; return the new cells."""
        return sum(self.on_receive(robot, belief, message) for message in messages)

    def metrics(self) -> dict[str, Any]:
        """Mechanism-specific metrics for ``result.json`` (default: none)."""
        return {}


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


class FullSharing(MapSharing):
    """Broadcast every new observation to the sub-network."""

    id = "full"
    message_types = frozenset({MAP_UPDATE})

    def on_observe(
        self, robot: int, tick: int, observation: Observation, belief: BeliefGrid
    ) -> list[Message]:
        new = observation.was_unknown
        if not new.any():
            return []
        payload = CellUpdates(observation.rows[new], observation.cols[new], observation.values[new])
        size = cell_updates_size(int(payload.rows.size))
        return [Message(MAP_UPDATE, robot, BROADCAST, size, payload, tick)]

    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        payload = message.payload
        assert isinstance(payload, CellUpdates)
        return merge_unknown(belief, payload)

    def on_receive_all(self, robot: int, belief: BeliefGrid, messages: list[Message]) -> int:
        # One merge for the whole tick: observations never disagree (cells only go
        # from unknown to their true state), so the order does not matter.
        payloads = [m.payload for m in messages]
        if len(payloads) == 1:
            return merge_unknown(belief, payloads[0])
        merged = CellUpdates(
            np.concatenate([p.rows for p in payloads]),
            np.concatenate([p.cols for p in payloads]),
            np.concatenate([p.values for p in payloads]),
        )
        current = belief[merged.rows, merged.cols]
        unknown = current == UNKNOWN
        rows, cols = merged.rows[unknown], merged.cols[unknown]
        belief[rows, cols] = merged.values[unknown]
        # A cell may arrive from several robots at once: count it once.
        return int(np.unique(rows * belief.shape[1] + cols).size)


class NoSharing(MapSharing):
    """Robots keep what they sense to themselves."""

    id = "none"

    def on_observe(
        self, robot: int, tick: int, observation: Observation, belief: BeliefGrid
    ) -> list[Message]:
        return []

    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        return 0


SHARING: dict[str, Callable[..., MapSharing]] = {"full": FullSharing, "none": NoSharing}


def make_sharing(name: str, **params: Any) -> MapSharing:
    """Build a map-sharing mechanism by registry id."""
    try:
        factory = SHARING[name]
    except KeyError:
        raise UnknownIdError("sharing mechanism", name, list(SHARING)) from None
    converted = {key: _number_or_text(value) for key, value in params.items()}
    try:
        return factory(**converted)
    except (TypeError, ValueError) as error:
        given = ", ".join(f"{k}={v}" for k, v in params.items())
        raise ScenarioError(f"--share {given}: not valid for {name!r} ({error})") from None


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
