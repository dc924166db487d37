"""The ``polygon`` map-sharing mechanism (Meier, Stachniss & Burgard 2005, §3).

The mechanism is driven directly: robot 0 walks through a generated office and
senses with :func:`mrexplore.sensing.visible_cells`; every package it sends is
handed to robot 1 (unless a test drops it).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cache

import numpy as np
import numpy.typing as npt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from mrexplore.comm.bytes import BROADCAST, HEADER_BYTES
from mrexplore.comm.messages import Message
from mrexplore.comm.polygon import PolygonSharing
from mrexplore.comm.polygon_packages import (
    PAPER_PACKAGE_TYPES,
    TPT,
    BrokenBoundary,
    EdgeSplits,
    EmergedPoints,
    PolygonRecord,
    Resync,
    VanishedPoints,
)
from mrexplore.comm.sharing import Observation
from mrexplore.errors import MrexploreInputError
from mrexplore.grid import generate_map
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, new_belief
from mrexplore.planning import distance_field, extract_path
from mrexplore.sensing import visible_cells

Cell = tuple[int, int]
SENSOR_RANGE = 8.0
TEAM = [frozenset({0, 1})]


@cache
def office() -> npt.NDArray[np.bool_]:
    return generate_map("office", 60, 40, seed=1).occupied


@cache
def walk() -> tuple[Cell, ...]:
    """A path through the office's free cells via a few random waypoints."""
    truth = office()
    free = np.argwhere(~truth)
    rng = np.random.default_rng(0)
    position: Cell = (int(free[0][0]), int(free[0][1]))
    path = [position]
    while len(path) < 160:
        target = tuple(int(v) for v in free[rng.integers(len(free))])
        dist = distance_field(~truth, position)
        if not np.isfinite(dist[target]) or target == position:
            continue
        path.extend((int(r), int(c)) for r, c in extract_path(dist, target)[1:])
        position = target  # type: ignore[assignment]  # a 2-tuple of ints
    return tuple(path[:160])


def sense(
    truth: npt.NDArray[np.bool_], belief: npt.NDArray[np.int8], position: Cell
) -> Observation:
    """What a robot at ``position`` sees; writes it into ``belief`` like the simulator."""
    rows, cols = visible_cells(truth, position, SENSOR_RANGE)
    values = np.where(truth[rows, cols], OCCUPIED, FREE).astype(np.int8)
    was_unknown = belief[rows, cols] == UNKNOWN
    belief[rows, cols] = values
    return Observation(rows, cols, values, was_unknown)


@cache
def observations() -> tuple[Observation, ...]:
    truth = office()
    belief = new_belief(truth.shape)
    return tuple(sense(truth, belief, position) for position in walk())


Deliver = Callable[[int, list[Message]], list[Message]]


def run(
    sharing: PolygonSharing,
    n_ticks: int | None = None,
    deliver: Deliver = lambda tick, messages: messages,
    with_ticks: bool = False,
) -> tuple[list[Message], npt.NDArray[np.int8]]:
    """Robot 0 senses along the walk; robot 1 gets what ``deliver`` lets through.

    Returns every message robot 0 sent and robot 1's belief.
    """
    truth = office()
    sharing.bind(2, truth.shape)
    sender_belief = new_belief(truth.shape)
    receiver_belief = new_belief(truth.shape)
    sent: list[Message] = []
    for tick, observation in enumerate(observations()[:n_ticks]):
        messages = []
        if with_ticks:
            messages += sharing.on_tick(tick, TEAM, [sender_belief, receiver_belief])
            messages = [m for m in messages if m.sender == 0]
        sender_belief[observation.rows, observation.cols] = observation.values
        messages += sharing.on_observe(0, tick, observation, sender_belief)
        sent += messages
        sharing.on_receive_all(1, receiver_belief, deliver(tick, messages))
    return sent, receiver_belief


def canonical(records: list[PolygonRecord]) -> dict[int, tuple[int, list[list[int]]]]:
    """Polygons keyed by id, each rotated to start at its smallest vertex id."""
    out = {}
    for record in records:
        points = record.points
        if points.shape[0]:
            points = np.roll(points, -int(np.argmin(points[:, 2])), axis=0)
        out[record.polygon_id] = (record.layer, points.tolist())
    return out


def agreement(sharing: PolygonSharing, belief: npt.NDArray[np.int8]) -> float:
    """Share of robot 0's observed cells on which ``belief`` holds robot 0's observation."""
    own = sharing.own_map(0)
    observed = own != UNKNOWN
    return float(np.mean(belief[observed] == own[observed]))


def expected_size(message: Message) -> int:
    """Size by the documented byte layout, recomputed from the payload."""
    payload = message.payload
    point, polygon_header = 12, 4 + 1 + 2
    if isinstance(payload, VanishedPoints):
        body = 4 + 2 + 4 * payload.point_ids.size
    elif isinstance(payload, EdgeSplits):
        body = 4 + 2 + (4 + point) * payload.after_ids.size
    elif isinstance(payload, BrokenBoundary):
        runs = sum(polygon_header + 8 * p.runs.shape[0] for p in payload.polygons)
        body = 4 + 1 + 2 + point * payload.new_points.shape[0] + 2 + runs
    elif isinstance(payload, Resync):
        body = 4 + 1 + 2 + sum(polygon_header + point * p.points.shape[0] for p in payload.polygons)
    else:
        assert isinstance(payload, EmergedPoints)
        body = 4 + 2 + sum(polygon_header + point * p.points.shape[0] for p in payload.polygons)
    return HEADER_BYTES + body


def test_message_types_and_sizes() -> None:
    sharing = PolygonSharing(split_rate=5.0, resync_every=50)
    sent, _ = run(sharing, 80, with_ticks=True)
    assert sent
    kinds = {m.type for m in sent}
    assert kinds <= PAPER_PACKAGE_TYPES
    assert kinds == {"ES", "B", "VP", "EP"}
    assert sharing.message_types == frozenset({"ES", "B", "VP", "EP", "RQ"})
    # TPT is the coordination strategy's: the simulator must route it to the inbox.
    assert TPT not in sharing.message_types
    for message in sent:
        assert message.size_bytes == expected_size(message)
        assert message.dest == BROADCAST and message.sender == 0
    # Sequence numbers count robot 0's packages without gaps, in sending order.
    assert [m.payload.seq for m in sent] == list(range(1, len(sent) + 1))
    assert any(isinstance(m.payload, Resync) for m in sent)  # tick 50


def test_receiver_rebuilds_the_senders_polygons() -> None:
    sharing = PolygonSharing(split_rate=2.0, resync_every=0)
    truth = office()
    sharing.bind(2, truth.shape)
    belief = new_belief(truth.shape)
    receiver = new_belief(truth.shape)
    for tick, observation in enumerate(observations()):
        messages = sharing.on_observe(0, tick, observation, belief)
        sharing.on_receive_all(1, receiver, messages)
        assert canonical(sharing.received(1, 0)) == canonical(sharing.polygons(0))
    # Robot 1's belief is robot 0's polygon map (robot 1 observed nothing itself).
    np.testing.assert_array_equal(receiver, sharing.polygon_map(0))


def test_receiver_never_overwrites_its_own_cells() -> None:
    truth = office()
    sharing = PolygonSharing(split_rate=1.0)
    sharing.bind(2, truth.shape)
    beliefs = [new_belief(truth.shape), new_belief(truth.shape)]
    own_1 = new_belief(truth.shape)
    path_1 = walk()[::-1]
    for tick, observation in enumerate(observations()[:100]):
        messages = sharing.on_observe(0, tick, observation, beliefs[0])
        if tick % 5 == 0:  # robot 1 senses too, now and then
            seen = sense(truth, beliefs[1], path_1[tick])
            own_1[seen.rows, seen.cols] = seen.values
            sharing.on_observe(1, tick, seen, beliefs[1])
        sharing.on_receive_all(1, beliefs[1], messages)
        mine = own_1 != UNKNOWN
        np.testing.assert_array_equal(beliefs[1][mine], own_1[mine])
    assert (own_1 != UNKNOWN).any()
    assert (beliefs[1][own_1 == UNKNOWN] != UNKNOWN).any()  # it did receive something


def test_exact_when_refined_to_zero_tolerance() -> None:
    sharing = PolygonSharing(split_rate=math.inf, epsilon=0.0)
    _, receiver = run(sharing, 60)
    own = sharing.own_map(0)
    assert sharing.approximation_error(0) == 0.0
    np.testing.assert_array_equal(sharing.polygon_map(0), own)
    np.testing.assert_array_equal(receiver, own)


def test_high_split_rate_gives_a_small_error() -> None:
    sharing = PolygonSharing(split_rate=1000.0, epsilon=0.5)
    _, receiver = run(sharing)
    assert sharing.approximation_error(0) < 0.02
    assert sharing.approximation_errors()[0] == sharing.approximation_error(0)
    assert agreement(sharing, receiver) > 0.98


def test_error_does_not_increase_with_the_split_rate() -> None:
    errors = []
    for split_rate in (0.1, 1.0, 10.0):
        sharing = PolygonSharing(split_rate=split_rate, epsilon=0.5)
        truth = office()
        sharing.bind(1, truth.shape)
        belief = new_belief(truth.shape)
        per_tick = []
        for tick, observation in enumerate(observations()):
            sharing.on_observe(0, tick, observation, belief)
            per_tick.append(sharing.approximation_error(0))
        errors.append((float(np.mean(per_tick)), per_tick[-1]))
    means, finals = zip(*errors, strict=True)
    assert means[0] >= means[1] >= means[2]
    assert finals[0] >= finals[1] >= finals[2]


def test_split_budget_follows_the_split_rate() -> None:
    """0.1 splits/s at one tick per second: one split every ten ticks."""
    sharing = PolygonSharing(split_rate=0.1, epsilon=0.0, resync_every=0)
    truth = office()
    sharing.bind(1, truth.shape)
    belief = new_belief(truth.shape)
    splits = []
    for tick in range(40):
        messages = sharing.on_observe(0, tick, observations()[0], belief)
        messages += sharing.on_tick(tick, [frozenset({0})], [belief])
        splits += [tick] * sum(m.payload.after_ids.size for m in messages if m.type == "ES")
    assert splits == [9, 19, 29, 39]
    # Twice the ticks per second halves the splits per tick.
    slow = PolygonSharing(split_rate=0.1, ticks_per_second=2.0, epsilon=0.0)
    slow.bind(1, truth.shape)
    count = 0
    for tick in range(40):
        messages = slow.on_observe(0, tick, observations()[0], belief)
        count += sum(m.payload.after_ids.size for m in messages if m.type == "ES")
    assert count == 2  # ticks 19 and 39


def test_resync_restores_agreement_after_losses() -> None:
    truth = office()
    sharing = PolygonSharing(split_rate=2.0, resync_every=30)

    def lossy(tick: int, messages: list[Message]) -> list[Message]:
        return [] if 10 <= tick < 14 else messages

    sharing.bind(2, truth.shape)
    sender = new_belief(truth.shape)
    receiver = new_belief(truth.shape)
    for tick, observation in enumerate(observations()[:45]):
        messages = sharing.on_tick(tick, TEAM, [sender, receiver])
        messages = [m for m in messages if m.sender == 0]
        messages += sharing.on_observe(0, tick, observation, sender)
        sharing.on_receive_all(1, receiver, lossy(tick, messages))
        if 14 <= tick < 30:  # a gap was seen: increments are ignored until the resync
            assert not sharing.in_sync(1, 0)
            assert canonical(sharing.received(1, 0)) != canonical(sharing.polygons(0))
        if tick >= 30:
            assert sharing.in_sync(1, 0)
            assert canonical(sharing.received(1, 0)) == canonical(sharing.polygons(0))
    np.testing.assert_array_equal(receiver, sharing.polygon_map(0))


def test_a_gap_triggers_a_resync_request_and_the_resync_restores_agreement() -> None:
    """With no periodic resync (the default), the receiver asks for one after a loss."""
    truth = office()
    sharing = PolygonSharing(split_rate=2.0)
    assert sharing.resync_every == 0
    sharing.bind(2, truth.shape)
    sender = new_belief(truth.shape)
    receiver = new_belief(truth.shape)
    requests: list[Message] = []
    pending: list[Message] = []
    for tick, observation in enumerate(observations()[:45]):
        sharing.on_receive_all(0, sender, pending)  # the request reaches the sender
        messages = sharing.on_tick(tick, TEAM, [sender, receiver])
        messages = [m for m in messages if m.sender == 0]
        messages += sharing.on_observe(0, tick, observation, sender)
        sharing.on_receive_all(1, receiver, [] if 10 <= tick < 12 else messages)
        pending = [m for m in sharing.drain() if m.type == "RQ"]
        assert all(m.sender == 1 and m.dest == 0 and m.size_bytes == 11 for m in pending)
        requests += pending
    assert requests, "the receiver never asked for a resync"
    assert sharing.in_sync(1, 0)
    assert canonical(sharing.received(1, 0)) == canonical(sharing.polygons(0))
    np.testing.assert_array_equal(receiver, sharing.polygon_map(0))


def test_late_and_reordered_packages() -> None:
    sharing = PolygonSharing(split_rate=2.0, resync_every=0)
    held: list[Message] = []

    def shuffle(tick: int, messages: list[Message]) -> list[Message]:
        # Tick 5's packages arrive with tick 6's, in reverse order: no gap.
        if tick == 5:
            held.extend(messages)
            return []
        if tick == 6:
            return messages + held[::-1]
        return messages

    run(sharing, 20, deliver=shuffle)
    assert len(held) > 1
    assert sharing.in_sync(1, 0)
    assert canonical(sharing.received(1, 0)) == canonical(sharing.polygons(0))
    # A package that arrives after later ones were applied is dropped, and the
    # gap it left makes the receiver wait for a resync.
    sharing = PolygonSharing(split_rate=2.0, resync_every=0)
    late: list[Message] = []

    def delay(tick: int, messages: list[Message]) -> list[Message]:
        if tick == 5:
            late.extend(messages)
            return []
        return messages + late if tick == 8 else messages

    run(sharing, 20, deliver=delay)
    assert late
    assert not sharing.in_sync(1, 0)


def test_resync_when_the_subnetwork_gains_robots() -> None:
    truth = office()
    sharing = PolygonSharing(split_rate=0.0, resync_every=0)
    sharing.bind(3, truth.shape)
    beliefs = [new_belief(truth.shape) for _ in range(3)]
    sharing.on_observe(0, 0, observations()[0], beliefs[0])
    apart = [frozenset({0}), frozenset({1}), frozenset({2})]
    assert sharing.on_tick(1, apart, beliefs) == []
    assert sharing.on_tick(2, apart, beliefs) == []
    joined = [frozenset({0, 1}), frozenset({2})]
    resyncs = [m for m in sharing.on_tick(3, joined, beliefs) if isinstance(m.payload, Resync)]
    assert sorted(m.sender for m in resyncs) == [0, 1]
    sync_0 = next(m for m in resyncs if m.sender == 0)
    assert canonical(list(sync_0.payload.polygons)) == canonical(sharing.polygons(0))
    assert sharing.on_tick(4, joined, beliefs) == []
    # A receiver that missed everything is repaired by the resync alone.
    receiver = beliefs[2]
    sharing.on_receive_all(2, receiver, [sync_0])
    assert canonical(sharing.received(2, 0)) == canonical(sharing.polygons(0))
    np.testing.assert_array_equal(receiver, sharing.polygon_map(0))


def square_room_observations() -> tuple[Observation, Observation]:
    """A 20 x 20 observed square with a 10 x 10 unobserved hole, then a band across it."""
    shape = (30, 30)
    seen = np.zeros(shape, dtype=bool)
    seen[5:25, 5:25] = True
    seen[10:20, 10:20] = False
    band = np.zeros(shape, dtype=bool)
    band[14:16, 10:20] = True

    def observe(mask: npt.NDArray[np.bool_]) -> Observation:
        rows, cols = np.nonzero(mask)
        values = np.full(rows.size, FREE, dtype=np.int8)
        values[(rows == 5) | (rows == 24)] = OCCUPIED  # two walls
        return Observation(rows, cols, values, np.ones(rows.size, dtype=bool))

    return observe(seen), observe(band)


def test_a_hole_that_splits_in_two() -> None:
    """Paper Figure 4 (d)-(f): the boundary of an unobserved hole breaks in two."""
    first, band = square_room_observations()
    sharing = PolygonSharing(split_rate=math.inf, epsilon=0.0, resync_every=0)
    sharing.bind(2, (30, 30))
    receiver = new_belief((30, 30))
    messages = sharing.on_observe(0, 0, first, new_belief((30, 30)))
    sharing.on_receive_all(1, receiver, messages)
    observed = [r for r in sharing.polygons(0) if r.layer == 0]
    assert len(observed) == 2  # the outer border and the hole
    hole = next(r for r in observed if r.points[:, :2].min() >= 9)
    hole_ids = set(hole.points[:, 2].tolist())
    messages = sharing.on_observe(0, 1, band, new_belief((30, 30)))
    sharing.on_receive_all(1, receiver, messages)
    assert "B" in {m.type for m in messages}
    after = [r for r in sharing.polygons(0) if r.layer == 0]
    assert len(after) == 3
    # Both halves keep vertices of the old hole polygon (no re-sending as new).
    halves = [r for r in after if set(r.points[:, 2].tolist()) & hole_ids]
    assert len(halves) == 2
    assert canonical(sharing.received(1, 0)) == canonical(sharing.polygons(0))
    assert sharing.approximation_error(0) == 0.0
    np.testing.assert_array_equal(receiver, sharing.own_map(0))


def test_obstacles_that_merge() -> None:
    shape = (12, 20)
    sharing = PolygonSharing(split_rate=math.inf, epsilon=0.0, resync_every=0)
    sharing.bind(2, shape)
    receiver = new_belief(shape)
    wall = np.zeros(shape, dtype=bool)
    wall[6, 2:18] = True

    def observe(cols: slice) -> Observation:
        mask = np.zeros(shape, dtype=bool)
        mask[2:10, cols] = True
        rows, cc = np.nonzero(mask)
        values = np.where(wall[rows, cc], OCCUPIED, FREE).astype(np.int8)
        return Observation(rows, cc, values, np.ones(rows.size, dtype=bool))

    for tick, cols in enumerate([slice(0, 8), slice(12, 20), slice(8, 12)]):
        messages = sharing.on_observe(0, tick, observe(cols), new_belief(shape))
        sharing.on_receive_all(1, receiver, messages)
        assert canonical(sharing.received(1, 0)) == canonical(sharing.polygons(0))
    obstacles = [r for r in sharing.polygons(0) if r.layer == 1]
    assert len(obstacles) == 1  # the two wall pieces became one
    np.testing.assert_array_equal(receiver, sharing.own_map(0))


def test_bad_parameters() -> None:
    for kwargs in (
        {"split_rate": -1.0},
        {"ticks_per_second": 0.0},
        {"epsilon": -0.5},
        {"resync_every": -1},
        {"resync_every": 2.5},
    ):
        with pytest.raises(MrexploreInputError):
            PolygonSharing(**kwargs)  # type: ignore[arg-type]
    with pytest.raises(MrexploreInputError, match="bind"):
        PolygonSharing().approximation_error(0)


@st.composite
def small_worlds(draw: st.DrawFn) -> tuple[npt.NDArray[np.bool_], list[Cell], float]:
    height = draw(st.integers(4, 16))
    width = draw(st.integers(4, 16))
    density = draw(st.sampled_from([0.05, 0.15, 0.3, 0.5]))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    truth = rng.random((height, width)) < density
    free = np.argwhere(~truth)
    if free.size == 0:
        truth[0, 0] = False
        free = np.argwhere(~truth)
    n_views = draw(st.integers(1, 4))
    views = [tuple(int(v) for v in free[rng.integers(len(free))]) for _ in range(n_views)]
    epsilon = draw(st.sampled_from([0.0, 0.5, 1.0, 2.0]))
    return truth, views, epsilon  # type: ignore[return-value]  # 2-tuples of ints


@settings(max_examples=60, deadline=None)
@given(small_worlds(), st.sampled_from([3.0, 6.0, 30.0]))
def test_refined_polygons_stay_near_what_was_observed(
    world: tuple[npt.NDArray[np.bool_], list[Cell], float], radius: float
) -> None:
    """Invariant of a fully refined approximation (every edge within ``epsilon``).

    A cell the polygons mark occupied lies within ``epsilon + 1/2 + sqrt(1/2)``
    cells (centre to centre) of an observed obstacle, and a cell they mark known
    within that distance of an observed cell. Why: every point of an edge is
    within ``epsilon`` of the polyline through the contour's cell centres, which
    is within ``sqrt(1/2)`` of a contour cell; an edge's Bresenham cells are
    within 1/2 of the edge; and a cell farther than ``epsilon`` from that
    polyline is inside the approximation exactly when it is inside the contours
    (the edge can be slid onto its contour piece without crossing the cell), and
    the contours filled by the even-odd rule are exactly the observed cells.
    With ``epsilon = 0`` the approximation is exact.
    """
    truth, views, epsilon = world
    sharing = PolygonSharing(split_rate=math.inf, epsilon=epsilon)
    sharing.bind(1, truth.shape)
    belief = new_belief(truth.shape)
    for tick, view in enumerate(views):
        rows, cols = visible_cells(truth, view, radius)
        values = np.where(truth[rows, cols], OCCUPIED, FREE).astype(np.int8)
        observation = Observation(rows, cols, values, belief[rows, cols] == UNKNOWN)
        belief[rows, cols] = values
        sharing.on_observe(0, tick, observation, belief)
    own = sharing.own_map(0)
    approximation = sharing.polygon_map(0)
    bound = epsilon + 0.5 + math.sqrt(0.5) + 1e-9
    for marked, reference in (
        (approximation == OCCUPIED, own == OCCUPIED),
        (approximation != UNKNOWN, own != UNKNOWN),
    ):
        if not reference.any():
            assert not marked.any()
            continue
        distance = ndimage.distance_transform_edt(~reference)
        assert (distance[marked] <= bound).all()
    if epsilon == 0.0:
        np.testing.assert_array_equal(approximation, own)
