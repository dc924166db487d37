"""``sheng-sync``: Sheng et al. (2006) §4, map synchronisation "with tracking".

W. Sheng, Q. Yang, J. Tan, N. Xi, "Distributed multi-robot coordination in area
exploration", Robotics and Autonomous Systems 54 (2006) 945-955, §4.

Each robot R_i keeps

* a **raw map table** (Table 1) indexed by discoverer p and sequence number q:
  ``table[p][q] = ΔM_pq``, the cells robot p discovered at its q-th sensing;
* a **last-sequence-number table** (Table 2): ``last[p]``, the largest q such that
  R_i holds ΔM_p1 .. ΔM_pq.

While connected, every robot broadcasts each new ΔM_pq to its sub-network
(``map_delta``). When a new link joins R_i's and R_j's sub-networks, the two run
the 10-step algorithm of §4.2:

(1-3) if R_j was not already in R_i's sub-network (we detect this from the
      previous tick's sub-networks: one link per pair of joined sub-networks);
(4-5) R_i and R_j send each other their last-sequence-number tables (``seq_table``);
(6-7) each computes eq. (3) ``ΔM_{i→j} = ∪_p ΔM_p(j_p, i_p]`` (eq. (4) on R_j's side)
      and sends it (``map_sync``);
(8-9) on receipt, each stores the deltas and updates its table to Table 3
      (``max(i_p, j_p)``);
(10)  each multicasts the deltas it received to the rest of its old sub-network
      (``map_multicast``).

Byte layout (header 7 bytes, see :mod:`mrexplore.comm.bytes`): a delta is
``discoverer uint16, seq uint32`` (6 bytes) plus 5 bytes a cell; ``map_delta``,
``map_sync`` and ``map_multicast`` carry one or more deltas; ``seq_table`` carries
one 6-byte entry (robot uint16, seq uint32) per robot of the team.

Interpretations: a ΔM_pq holds only the cells that were new to R_p when it
sensed them (cells it already knew from others are not re-announced); a robot
that receives a delta out of order stores it but advances ``last[p]`` only over a
contiguous run; if the link breaks during steps 4-10 the missing messages are
counted as lost and the next merge repairs the tables.

Table 4's two volumes, from the same run (:meth:`ShengSync.metrics`): Sheng et al.
"record the volumes of map data exchanged and compare with the volumes of map data
that are supposed to be exchanged if the map update tracking scheme is not used".
At every merge we count the bytes of the messages of steps 4-10 as they are sent
(``sync_bytes_with_tracking``) and, beside them, what §4's brute force would have
sent at the same moment (``sync_bytes_without_tracking``): each of the two robots
its whole known map (5 bytes a cell, as ``full`` sharing), and each the map it
received to the rest of its old sub-network. Both count a message once, whatever
its number of hops (the network's ledger counts every hop); ``sync_merges`` and
``sync_cells_per_merge`` say how many merges and how many cells each synchronised,
``sync_cells_with_tracking`` / ``_without_tracking`` how many cell entries the two
volumes hold (for another byte model: 5 bytes a cell here).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import (
    BROADCAST,
    CELL_UPDATE_BYTES,
    HEADER_BYTES,
    SEQUENCE_ENTRY_BYTES,
    cell_updates_size,
)
from mrexplore.comm.messages import MAP_DELTA, MAP_MULTICAST, MAP_SYNC, SEQ_TABLE, Message
from mrexplore.comm.sharing import (
    CellUpdates,
    Join,
    MapSharing,
    Observation,
    merge_many,
    new_cells,
)
from mrexplore.grid.occupancy import UNKNOWN, BeliefGrid

DELTA_HEADER_BYTES = SEQUENCE_ENTRY_BYTES  # discoverer uint16 + seq uint32


@dataclass(frozen=True, slots=True)
class Delta:
    """ΔM_pq: the cells robot ``p`` discovered at its ``q``-th sensing."""

    discoverer: int
    seq: int
    cells: CellUpdates

    @property
    def size_bytes(self) -> int:
        return DELTA_HEADER_BYTES + CELL_UPDATE_BYTES * int(self.cells.rows.size)


def deltas_size(deltas: Sequence[Delta]) -> int:
    """Bytes of a message carrying ``deltas``."""
    return HEADER_BYTES + sum(d.size_bytes for d in deltas)


class ShengSync(MapSharing):
    """Sequence-numbered raw map tables and the §4.2 synchronisation on merges."""

    id = "sheng-sync"
    message_types = frozenset({MAP_DELTA, SEQ_TABLE, MAP_SYNC, MAP_MULTICAST})
    acts_on_joins = True

    def bind(self, n_robots: int, shape: tuple[int, int]) -> None:
        super().bind(n_robots, shape)
        # Robot i's raw map table holds ΔM_pq for q <= last[i][p] (Table 2) and for
        # the q in ahead[(i, p)] (received out of order, beyond a gap). Every ΔM_pq
        # is one object, made by its discoverer p, so the table's entries are kept
        # once, in deltas[p][q - 1], not once per robot that holds them.
        self.deltas: list[list[Delta]] = [[] for _ in range(n_robots)]
        self.ahead: dict[tuple[int, int], set[int]] = {}
        self.last: npt.NDArray[np.int64] = np.zeros((n_robots, n_robots), dtype=np.int64)
        self.merges = self.with_tracking = self.without_tracking = self.synced_cells = 0
        self.cells_with = self.cells_without = 0  # cell entries in those bytes

    # ------------------------------------------------------------ tables
    def holds(self, robot: int, discoverer: int, seq: int) -> bool:
        """Whether ``robot``'s raw map table holds ΔM_{discoverer, seq}."""
        if seq <= self.last[robot, discoverer]:
            return True
        ahead = self.ahead.get((robot, discoverer))
        return ahead is not None and seq in ahead

    def _store(self, robot: int, delta: Delta) -> bool:
        """Put ``delta`` into ``robot``'s raw map table; False if it was there already."""
        p, q = delta.discoverer, delta.seq
        if self.holds(robot, p, q):
            return False
        last = self.last[robot]
        if q != last[p] + 1:
            self.ahead.setdefault((robot, p), set()).add(q)
            return True
        last[p] = q
        ahead = self.ahead.get((robot, p))
        while ahead and q + 1 in ahead:
            q += 1
            ahead.discard(q)
            last[p] = q
        return True

    def missing_for(self, robot: int, their_last: npt.NDArray[np.int64]) -> list[Delta]:
        """Eq. (3): ΔM_{i→j} = ∪_p ΔM_p(j_p, i_p] from robot i's table."""
        out: list[Delta] = []
        mine = self.last[robot]
        for p in range(self.n_robots):
            out.extend(self.deltas[p][int(their_last[p]) : int(mine[p])])
        return out

    # ------------------------------------------------------------ events
    def on_observe(
        self, robot: int, tick: int, observation: Observation, belief: BeliefGrid
    ) -> list[Message]:
        cells = new_cells(observation)
        if cells is None:
            return []
        seq = int(self.last[robot, robot]) + 1
        delta = Delta(robot, seq, cells)
        self.deltas[robot].append(delta)  # deltas[p][q - 1] = ΔM_pq
        self._store(robot, delta)
        return [Message(MAP_DELTA, robot, BROADCAST, deltas_size([delta]), (delta,), tick)]

    def on_join(self, tick: int, join: Join, beliefs: Sequence[BeliefGrid]) -> list[Message]:
        # The base class noted each end's old sub-network: step 10's recipients.
        self.merges += 1
        messages = []
        sides = ((join.a, join.b, join.group_b), (join.b, join.a, join.group_a))
        for me, peer, peer_group in sides:
            size = HEADER_BYTES + SEQUENCE_ENTRY_BYTES * self.n_robots
            table = self.last[me].copy()
            messages.append(Message(SEQ_TABLE, me, peer, size, table, tick))  # step 4
            self.with_tracking += size
            # Without tracking: my whole map to the peer, which multicasts it on.
            known = int(np.count_nonzero(beliefs[me] != UNKNOWN))
            copies = 1 + (len(peer_group) > 1)
            self.without_tracking += cell_updates_size(known) * copies
            self.cells_without += known * copies
        return messages

    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        return self.on_receive_all(robot, belief, [message])

    def on_receive_all(self, robot: int, belief: BeliefGrid, messages: list[Message]) -> int:
        fresh: list[CellUpdates] = []
        for message in messages:
            if message.type == SEQ_TABLE:  # steps 5-7
                missing = self.missing_for(robot, message.payload)
                size = deltas_size(missing)
                self.outbox.append(Message(MAP_SYNC, robot, message.sender, size, tuple(missing)))
                cells = sum(int(d.cells.rows.size) for d in missing)
                self.with_tracking += size
                self.synced_cells += cells
                self.cells_with += cells
                continue
            stored = [d for d in message.payload if self._store(robot, d)]  # steps 8-9
            fresh.extend(d.cells for d in stored)
            if message.type == MAP_SYNC:  # step 10
                others = self.rest_of_old_group(robot, message.sender)
                if others and message.payload:
                    self.with_tracking += message.size_bytes
                    self.cells_with += sum(int(d.cells.rows.size) for d in message.payload)
                    self.outbox.append(
                        Message(
                            MAP_MULTICAST,
                            robot,
                            BROADCAST,
                            message.size_bytes,
                            message.payload,
                            recipients=others,
                        )
                    )
        return merge_many(belief, fresh) if fresh else 0

    def metrics(self) -> dict[str, Any]:
        """Table 4's volumes of this run (see the module's docstring)."""
        per_merge = self.synced_cells / self.merges if self.merges else 0.0
        return {
            "sync_merges": self.merges,
            "sync_bytes_with_tracking": self.with_tracking,
            "sync_bytes_without_tracking": self.without_tracking,
            "sync_cells_per_merge": per_merge,
            "sync_cells_with_tracking": self.cells_with,
            "sync_cells_without_tracking": self.cells_without,
        }
