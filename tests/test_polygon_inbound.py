"""Receivers' shared copies of polygon maps, and the compiled kernels behind them.

The shared copies (:mod:`mrexplore.comm.polygon_inbound`) must leave every
receiver with what it would hold alone; the kernels must give what the plain
numpy formulations give.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.comm.messages import Message
from mrexplore.comm.polygon import PolygonSharing
from mrexplore.comm.polygon_inbound import SharedMaps
from mrexplore.comm.polygon_kernels import paint_box, rasterise, trace_contours
from mrexplore.comm.polygon_packages import OBSERVED_LAYER, OBSTACLE_LAYER, changed_edges_box
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, new_belief
from test_polygon_sharing import observations, office  # the same walk through the office

CELL_VALUES = np.array([UNKNOWN, FREE, OCCUPIED], dtype=np.int8)


@settings(max_examples=60, deadline=None)
@given(
    height=st.integers(1, 12),
    width=st.integers(1, 12),
    n_senders=st.integers(0, 4),
    seed=st.integers(0, 2**32 - 1),
)
def test_paint_box_is_the_numpy_composition(
    height: int, width: int, n_senders: int, seed: int
) -> None:
    rng = np.random.default_rng(seed)
    rasters = rng.random((n_senders + 2, 2, height, width)) < 0.3
    slots = rng.permutation(n_senders + 2)[:n_senders].astype(np.int64)
    own = CELL_VALUES[rng.integers(0, 3, (height, width))]
    belief = CELL_VALUES[rng.integers(0, 3, (height, width))]
    row0, col0 = int(rng.integers(0, height)), int(rng.integers(0, width))
    row1, col1 = int(rng.integers(row0, height)), int(rng.integers(col0, width))
    # Occupied over free over unknown across the senders, written in the box
    # where the robot observed nothing.
    free = rasters[slots, 0].any(axis=0)
    occupied = rasters[slots, 1].any(axis=0)
    composite = np.full((height, width), UNKNOWN, dtype=np.int8)
    composite[free] = FREE
    composite[occupied] = OCCUPIED
    inside = np.zeros((height, width), dtype=bool)
    inside[row0 : row1 + 1, col0 : col1 + 1] = True
    write = inside & (own == UNKNOWN) & (belief != composite)
    expected = belief.copy()
    expected[write] = composite[write]
    got = belief.copy()
    box = (row0, row1, col0, col1)
    n_changed = paint_box(rasters, slots, own, got, box, FREE, OCCUPIED, UNKNOWN)
    assert n_changed == int(np.count_nonzero(write))
    np.testing.assert_array_equal(got, expected)


@settings(max_examples=60, deadline=None)
@given(
    height=st.integers(3, 16),
    width=st.integers(3, 16),
    seed=st.integers(0, 2**32 - 1),
)
def test_tracing_a_window_gives_the_grids_contours(height: int, width: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    grid = np.zeros((height, width), dtype=bool)
    row0, col0 = int(rng.integers(0, height)), int(rng.integers(0, width))
    row1, col1 = int(rng.integers(row0, height)), int(rng.integers(col0, width))
    grid[row0 : row1 + 1, col0 : col1 + 1] = rng.random((row1 - row0 + 1, col1 - col0 + 1)) < 0.6
    whole = trace_contours(grid)
    window = trace_contours(grid[row0 : row1 + 1, col0 : col1 + 1], None, (row0, col0), width)
    for got, want in zip(window, whole, strict=True):
        np.testing.assert_array_equal(got, want)


def _raster(polygons: list[npt.NDArray[np.int32]], shape: tuple[int, int]) -> npt.NDArray[np.bool_]:
    out = np.zeros(shape, dtype=bool)
    if polygons:
        offsets = np.concatenate([[0], np.cumsum([len(p) for p in polygons])]).astype(np.int64)
        rasterise(np.concatenate(polygons), offsets, 0, 0, out)
    return out


def _check_rasters(maps: SharedMaps) -> None:
    """Every version's rasters are its polygons rasterised over the whole grid."""
    for version in list(maps.versions.values()):
        maps.refresh(version)
        for layer in (OBSERVED_LAYER, OBSTACLE_LAYER):
            raster = maps.rasters[version.slot, layer]
            polygons = [p.xy for p in version.map.polygons.values() if p.layer == layer]
            np.testing.assert_array_equal(raster, _raster(polygons, maps.shape))


@settings(max_examples=8, deadline=None)
@given(
    drop=st.lists(st.sampled_from([0.0, 0.0, 0.1, 0.4]), min_size=4, max_size=4),
    hold=st.lists(st.sampled_from([0.0, 0.0, 0.5]), min_size=4, max_size=4),
    seed=st.integers(0, 2**32 - 1),
)
def test_receivers_sharing_copies_end_as_receivers_alone(
    drop: list[float], hold: list[float], seed: int
) -> None:
    """Four receivers of robot 0, each losing packages at its own rate and getting
    them late (several ticks' packages at once) at its own rate, hold and paint
    what each would with nobody to share copies with."""
    truth = office()
    n_receivers = len(drop)
    shared = PolygonSharing(split_rate=3.0, resync_every=15)
    shared.bind(1 + n_receivers, truth.shape)
    alone = [PolygonSharing(split_rate=3.0, resync_every=15) for _ in range(n_receivers)]
    for sharing in alone:
        sharing.bind(2, truth.shape)
    sender_belief = new_belief(truth.shape)
    beliefs = [new_belief(truth.shape) for _ in range(n_receivers)]
    beliefs_alone = [new_belief(truth.shape) for _ in range(n_receivers)]
    rng = np.random.default_rng(seed)
    queued: list[list[Message]] = [[] for _ in range(n_receivers)]
    for tick, observation in enumerate(observations()[:100]):
        sender_belief[observation.rows, observation.cols] = observation.values
        # Only on_observe runs, so requests for resyncs go unanswered and robot 0
        # sends the same packages whoever receives them.
        messages = shared.on_observe(0, tick, observation, sender_belief)
        for sharing in alone:
            assert _same(sharing.on_observe(0, tick, observation, sender_belief), messages)
        for r in range(n_receivers):
            queued[r] += [m for m in messages if rng.random() >= drop[r]]
            if rng.random() < hold[r]:
                continue
            kept, queued[r] = queued[r], []
            n_shared = shared.on_receive_all(1 + r, beliefs[r], kept)
            n_alone = alone[r].on_receive_all(1, beliefs_alone[r], kept)
            assert n_shared == n_alone
            np.testing.assert_array_equal(beliefs[r], beliefs_alone[r])
        if tick % 25 == 24:
            _check_rasters(shared._maps)
    for r in range(n_receivers):
        got = shared.received(1 + r, 0)
        want = alone[r].received(1, 0)
        assert [(p.polygon_id, p.layer, p.points.tolist()) for p in got] == [
            (p.polygon_id, p.layer, p.points.tolist()) for p in want
        ]
    _check_rasters(shared._maps)


def _same(a: list[Message], b: list[Message]) -> bool:
    return [(m.type, m.size_bytes, m.payload.seq) for m in a] == [
        (m.type, m.size_bytes, m.payload.seq) for m in b
    ]


@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_others=st.integers(0, 3))
def test_a_redefined_polygon_changes_the_raster_only_in_the_changed_edges_box(
    seed: int, n_others: int
) -> None:
    """Replacing a polygon by one that keeps some of its vertices (as B packages
    do) changes the layer's raster, other polygons included, only inside
    changed_edges_box."""
    rng = np.random.default_rng(seed)
    shape = (14, 16)

    def polygon(n: int) -> npt.NDArray[np.int32]:
        return np.column_stack([rng.integers(0, shape[1], n), rng.integers(0, shape[0], n)]).astype(
            np.int32
        )

    old = polygon(int(rng.integers(1, 9)))
    # Keep a random subsequence of old's vertices (cyclically), insert new ones.
    kept = old[np.sort(rng.choice(len(old), int(rng.integers(0, len(old) + 1)), replace=False))]
    parts = [kept[i : i + 1] for i in range(len(kept))]
    for _ in range(int(rng.integers(0, 3))):
        parts.insert(int(rng.integers(0, len(parts) + 1)), polygon(1))
    new = np.concatenate(parts) if parts else polygon(1)
    new = np.roll(new, int(rng.integers(0, len(new))), axis=0)
    others = [polygon(int(rng.integers(1, 6))) for _ in range(n_others)]
    before = _raster([old, *others], shape)
    after = _raster([new, *others], shape)
    box = changed_edges_box(old, new)
    rows, cols = np.nonzero(before != after)
    if box is None:
        assert rows.size == 0
    else:
        x0, y0, x1, y1 = box
        assert ((cols >= x0) & (cols <= x1) & (rows >= y0) & (rows <= y1)).all()
