"""Map sharing: full and sheng-sync agree after a merge; sheng-sync sends less."""

from __future__ import annotations

import numpy as np
import pytest

from mrexplore.comm import make_network, make_sharing
from mrexplore.comm.sharing import Observation
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, new_belief
from mrexplore.sim import Scenario, simulate


def exchange(name: str, seed: int = 0) -> tuple[list[np.ndarray], int]:
    """Two pairs of robots explore apart for 10 ticks, then meet; return beliefs and bytes."""
    shape = (24, 24)
    rng = np.random.default_rng(seed)
    truth = np.where(rng.random(shape) < 0.3, OCCUPIED, FREE).astype(np.int8)
    sharing = make_sharing(name)
    sharing.bind(4, shape)
    network = make_network(4, comm_range=5.0)
    beliefs = [new_belief(shape) for _ in range(4)]
    positions = {0: (1, 1), 1: (1, 4), 2: (20, 20), 3: (20, 17)}
    alive = frozenset(range(4))
    for tick in range(40):
        if tick == 12:
            positions = {0: (1, 1), 1: (1, 4), 2: (1, 8), 3: (1, 11)}
        network.update(tick, positions, alive)
        for message in sharing.on_topology(tick, network.subnetworks(), network.links(), beliefs):
            network.send(message, tick)
        for robot, inbox in network.deliver(tick).items():
            sharing.on_receive_all(robot, beliefs[robot], inbox)
        for message in sharing.drain():
            network.send(message, tick)
        if tick < 10:
            for robot in range(4):
                flat = rng.choice(shape[0] * shape[1], size=12, replace=False)
                rows, cols = np.divmod(flat, shape[1])
                own_new = beliefs[robot][rows, cols] == UNKNOWN
                values = truth[rows, cols]
                beliefs[robot][rows, cols] = values
                observation = Observation(rows, cols, values, own_new)
                for message in sharing.on_observe(robot, tick, observation, beliefs[robot]):
                    network.send(message, tick)
        network.flush(tick)
    assert network.in_flight() == 0
    return beliefs, network.ledger.total


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_full_and_sheng_sync_give_identical_beliefs_after_a_merge(seed: int) -> None:
    full, _ = exchange("full", seed)
    sheng, _ = exchange("sheng-sync", seed)
    for belief in full[1:] + sheng:
        assert np.array_equal(belief, full[0])
    assert (full[0] != UNKNOWN).sum() > 100


def test_sheng_sync_sends_fewer_map_bytes_with_table_4_radios() -> None:
    """Table 4's map and radios (5 robots, 40 x 40, r_s = 4, r_c = 16, sense on arrival),
    with nearest-frontier and the robots starting apart: not Table 4's experiment."""

    def map_bytes(sharing: str, seed: int) -> int:
        record = simulate(
            Scenario(
                map="sheng40",
                robots=5,
                seed=seed,
                sensor_range=4,
                comm_range=16,
                sensing="arrival",
                start="separate",
                sharing=sharing,
            )
        )
        assert record.status == "complete"
        return sum(record.bytes_by_type.values())

    for seed in range(3):
        assert map_bytes("sheng-sync", seed) < 0.7 * map_bytes("full", seed)


@pytest.mark.parametrize("seed", [0, 1])
def test_broadcast_relays_what_is_sensed_and_nothing_on_reconnection(seed: int) -> None:
    """The two pairs were apart while sensing: within a pair they agree, across the
    pairs nothing arrives when they meet (full sharing would exchange whole maps)."""
    beliefs, sent = exchange("broadcast", seed)
    _, full_sent = exchange("full", seed)
    assert np.array_equal(beliefs[0], beliefs[1]) and np.array_equal(beliefs[2], beliefs[3])
    only_second_pair = (beliefs[2] != UNKNOWN) & (beliefs[0] == UNKNOWN)
    assert only_second_pair.sum() > 20
    assert 0 < sent < full_sent


def test_broadcast_sharing_runs_through_the_simulator_multi_hop() -> None:
    """Through the simulator: map traffic is ``map_update`` only, and the run ends."""
    record = simulate(
        Scenario(
            map="sheng40",
            robots=3,
            seed=1,
            sensor_range=4,
            comm_range=16,
            start="together",
            sharing="broadcast",
            max_ticks=400,
        )
    )
    assert set(record.bytes_by_type) == {"map_update"}
    assert record.status == "complete"


def test_sheng_sync_counts_table_4_volumes_with_and_without_tracking() -> None:
    """Sheng Table 4 from one run: at a merge, the bytes of steps 4-10 as sent, and what
    the brute force would have sent then: each end's whole known map, plus its multicast
    to the rest of the receiver's old sub-network."""
    from mrexplore.comm.bytes import HEADER_BYTES, SEQUENCE_ENTRY_BYTES, cell_updates_size

    sharing = make_sharing("sheng-sync")
    sharing.bind(3, (6, 6))
    beliefs = [new_belief((6, 6)) for _ in range(3)]
    beliefs[0][0, :] = FREE  # robots 0 and 1 (one sub-network) know row 0
    beliefs[1][0, :] = FREE
    beliefs[2][5, :3] = OCCUPIED  # robot 2 (alone) knows three cells
    apart = [frozenset({0, 1}), frozenset({2})]
    sharing.on_topology(0, apart, frozenset({(0, 1)}), beliefs)
    sent = sharing.on_topology(1, [frozenset({0, 1, 2})], frozenset({(0, 1), (1, 2)}), beliefs)
    assert [(m.type, m.sender, m.dest) for m in sent] == [("seq_table", 1, 2), ("seq_table", 2, 1)]
    for message in sent:  # nothing was observed: both answer with empty syncs
        sharing.on_receive_all(message.dest, beliefs[message.dest], [message])
    metrics = sharing.metrics()
    tables = 2 * (HEADER_BYTES + 3 * SEQUENCE_ENTRY_BYTES)
    assert metrics["sync_bytes_with_tracking"] == tables + 2 * HEADER_BYTES
    # Robot 1's 6 cells to robot 2 (alone: no multicast); robot 2's 3 cells to robot 1,
    # which would multicast them on to robot 0.
    without = cell_updates_size(6) + 2 * cell_updates_size(3)
    assert metrics["sync_bytes_without_tracking"] == without
    assert (metrics["sync_merges"], metrics["sync_cells_per_merge"]) == (1, 0.0)
    assert (metrics["sync_cells_with_tracking"], metrics["sync_cells_without_tracking"]) == (0, 12)


def test_sheng_sync_tables_out_of_order_and_eq_3() -> None:
    """Table 2 advances only over a contiguous run; a delta received beyond a gap is
    held (not stored twice) and counted once the gap closes; eq. (3) sends exactly the
    deltas the peer's table lacks, in sequence order."""
    from mrexplore.comm.sharing import CellUpdates
    from mrexplore.comm.sheng_sync import Delta

    sharing = make_sharing("sheng-sync")
    sharing.bind(3, (4, 4))
    cells = CellUpdates(np.array([0]), np.array([0]), np.array([FREE], dtype=np.int8))
    mine = [Delta(0, q, cells) for q in (1, 2, 3, 4)]
    sharing.deltas[0].extend(mine)
    for delta in mine:
        assert sharing._store(0, delta)
    assert sharing.last[0].tolist() == [4, 0, 0]
    # robot 1 receives q = 3 and 4 first, then 1, then 2
    assert sharing._store(1, mine[2]) and sharing._store(1, mine[3])
    assert not sharing._store(1, mine[3])  # already held, beyond the gap
    assert sharing.last[1, 0] == 0 and sharing.holds(1, 0, 3) and not sharing.holds(1, 0, 1)
    assert sharing._store(1, mine[0])
    assert sharing.last[1, 0] == 1
    assert sharing._store(1, mine[1])
    assert sharing.last[1, 0] == 4 and not sharing._store(1, mine[1])
    # eq. (3): robot 0 owes robot 2 (which holds up to q = 1) the deltas 2..4
    their = np.array([1, 0, 0], dtype=np.int64)
    assert sharing.missing_for(0, their) == mine[1:]
    assert sharing.missing_for(2, sharing.last[0]) == []
