"""Communication layer: range, walls, multi-hop, bandwidth, latency, loss, failures."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.checks import check_trace
from mrexplore.comm import BROADCAST, Message, make_network
from mrexplore.comm.links import AllLinks, RangeLinks, components
from mrexplore.sensing import is_visible
from mrexplore.sim import Scenario, simulate

positions_strategy = st.lists(
    st.tuples(st.integers(1, 28), st.integers(1, 28)), min_size=2, max_size=8, unique=True
)


def run_network(
    network_args: dict[str, object],
    positions: list[tuple[int, int]],
    messages: list[Message],
    *,
    ticks: int = 40,
) -> tuple[object, dict[int, list[tuple[int, Message]]]]:
    """Send every message at tick 0 from static robots; collect (tick, message) per robot."""
    n = len(positions)
    network = make_network(n, **network_args)  # type: ignore[arg-type]
    network.keep_hop_log = True
    where = dict(enumerate(positions))
    alive = frozenset(range(n))
    received: dict[int, list[tuple[int, Message]]] = {i: [] for i in range(n)}
    for tick in range(ticks):
        network.update(tick, where, alive)
        for robot, inbox in network.deliver(tick).items():
            received[robot].extend((tick, m) for m in inbox)
        if tick == 0:
            for message in messages:
                network.send(message, tick)
        network.flush(tick)
    return network, received


def some_messages(n: int, size: int = 40) -> list[Message]:
    out = [Message("map_update", s, BROADCAST, size, tick_sent=0) for s in range(n)]
    out += [Message("status", s, (s + 1) % n, 15, tick_sent=0) for s in range(n)]
    return out


@settings(max_examples=60, deadline=None)
@given(positions=positions_strategy, comm_range=st.floats(2.0, 20.0))
def test_no_hop_is_longer_than_the_range(
    positions: list[tuple[int, int]], comm_range: float
) -> None:
    network, _ = run_network({"comm_range": comm_range}, positions, some_messages(len(positions)))
    for _tick, tx, rx, _arrival, _kind in network.hop_log:  # type: ignore[attr-defined]
        assert math.dist(positions[tx], positions[rx]) <= comm_range + 1e-9


@settings(max_examples=40, deadline=None)
@given(positions=positions_strategy, seed=st.integers(0, 1000))
def test_walls_block_links_when_asked(positions: list[tuple[int, int]], seed: int) -> None:
    rng = np.random.default_rng(seed)
    occupied = rng.random((30, 30)) < 0.2
    for r, c in positions:
        occupied[r, c] = False
    network, _ = run_network(
        {"comm_range": 25.0, "comm_los": True, "occupied": occupied},
        positions,
        some_messages(len(positions)),
    )
    for _tick, tx, rx, _arrival, _kind in network.hop_log:  # type: ignore[attr-defined]
        assert is_visible(occupied, positions[tx], positions[rx])


@settings(max_examples=40, deadline=None)
@given(
    positions=positions_strategy,
    bandwidth=st.integers(5, 60),
    size=st.integers(10, 200),
)
def test_nobody_sends_more_than_the_bandwidth(
    positions: list[tuple[int, int]], bandwidth: int, size: int
) -> None:
    network, _ = run_network(
        {"comm_range": 12.0, "bandwidth": float(bandwidth)},
        positions,
        some_messages(len(positions), size),
        ticks=400,
    )
    per_tick = network.ledger.bytes_by_robot_tick  # type: ignore[attr-defined]
    assert max(per_tick.values(), default=0) <= bandwidth
    # Nothing is silently dropped: with no loss, everything queued is eventually delivered.
    assert network.in_flight() == 0  # type: ignore[attr-defined]


@settings(max_examples=40, deadline=None)
@given(positions=positions_strategy, latency=st.integers(1, 6))
def test_every_hop_takes_exactly_the_latency(
    positions: list[tuple[int, int]], latency: int
) -> None:
    network, _ = run_network(
        {"comm_range": 10.0, "latency": latency}, positions, some_messages(len(positions))
    )
    for tick, _tx, _rx, arrival, _kind in network.hop_log:  # type: ignore[attr-defined]
        assert arrival == tick + latency


@settings(max_examples=60, deadline=None)
@given(positions=positions_strategy, comm_range=st.floats(2.0, 20.0))
def test_without_loss_every_message_reaches_its_subnetwork(
    positions: list[tuple[int, int]], comm_range: float
) -> None:
    n = len(positions)
    messages = some_messages(n)
    network, received = run_network({"comm_range": comm_range}, positions, messages)
    groups = components(
        frozenset(range(n)), RangeLinks(comm_range).links(dict(enumerate(positions)))
    )
    group_of = {r: g for g in groups for r in g}
    for message in messages:
        expected = (
            group_of[message.sender] - {message.sender}
            if message.dest == BROADCAST
            else ({message.dest} & group_of[message.sender])
        )
        got = {r for r, inbox in received.items() if any(m is message for _, m in inbox)}
        assert got == expected
    assert network.ledger.lost == sum(  # type: ignore[attr-defined]
        1 for m in messages if m.dest != BROADCAST and m.dest not in group_of[m.sender]
    )


@settings(max_examples=60, deadline=None)
@given(positions=positions_strategy, comm_range=st.floats(2.0, 30.0), loss=st.floats(0.0, 0.9))
def test_byte_totals_are_the_sum_of_the_hops(
    positions: list[tuple[int, int]], comm_range: float, loss: float
) -> None:
    rng = np.random.default_rng(0)
    network, _ = run_network(
        {"comm_range": comm_range, "loss": loss, "rng": rng},
        positions,
        some_messages(len(positions)),
    )
    ledger = network.ledger  # type: ignore[attr-defined]
    sizes = {"map_update": 40, "status": 15}
    expected = sum(sizes[kind] * hops for kind, hops in ledger.hops_by_type.items())
    assert ledger.total == expected == int(ledger.bytes_by_robot.sum())
    assert ledger.total == int(ledger.bytes_per_tick(100).sum())


def test_relays_carry_a_broadcast_along_a_chain() -> None:
    chain = [(5, 5 + 4 * i) for i in range(5)]  # neighbours 4 cells apart, range 5
    message = Message("map_update", 0, BROADCAST, 20, tick_sent=0)
    network, received = run_network({"comm_range": 5.0, "latency": 2}, chain, [message])
    arrivals = {r: [t for t, m in inbox if m is message] for r, inbox in received.items()}
    assert arrivals == {0: [], 1: [2], 2: [4], 3: [6], 4: [8]}
    assert network.ledger.total == 20 * 4  # the sender and three relays; the last one is a leaf


def test_signal_strength_falls_with_the_square_of_distance() -> None:
    links = AllLinks()
    assert links.signal_strength((0, 0), (0, 2)) == 0.25
    assert links.signal_strength((0, 0), (3, 4)) == 1 / 25


def test_failures_and_loss_still_end_with_a_valid_trace() -> None:
    failing = simulate(
        Scenario(
            map="office",
            size=(80, 60),
            robots=8,
            strategy="burgard",
            seed=3,
            comm_range=20,
            fail=[(0, 30), (3, 60), (5, 90)],
        )
    )
    result = failing.result()
    assert result["status"] in {"complete", "max_ticks", "stalled"}
    assert result["robots_failed"] == 3
    assert check_trace(failing.trace_arrays(), result) == []
    assert (failing.positions[30:, 0] == failing.positions[30, 0]).all()  # a dead robot stays

    lossy = simulate(
        Scenario(map="office", size=(80, 60), robots=4, strategy="burgard", seed=3, loss=0.3)
    )
    result = lossy.result()
    assert result["status"] == "complete"
    assert result["messages_lost"] > 0
    assert check_trace(lossy.trace_arrays(), result) == []


def test_limited_range_splits_the_team_into_subnetworks() -> None:
    record = simulate(
        Scenario(map="office", size=(100, 60), robots=4, seed=1, comm_range=6, start="separate")
    )
    result = record.result()
    assert result["subnetworks_max"] > 1
    assert record.trace_arrays()["subnetworks"].shape == (record.ticks + 1,)
