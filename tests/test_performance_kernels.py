"""The compiled fast paths of issue 7 equal the code they replace, on random inputs."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.comm.links import RangeLinks
from mrexplore.comm.sharing import CellUpdates, merge_many
from mrexplore.errors import StrategyError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import distance_field, extract_path, frontier_mask
from mrexplore.planning.distance import FieldCounter
from mrexplore.planning.frontier_search import nearest_frontier
from mrexplore.planning.visibility import _build_ray_table, ray_table
from mrexplore.sim.engine import check_path
from mrexplore.sim.record import mark_known, mark_known_changed
from mrexplore.strategies.base import reachable_frontier_cells

U, F, W = UNKNOWN, FREE, OCCUPIED


@st.composite
def beliefs(draw: st.DrawFn) -> npt.NDArray[np.int8]:
    height = draw(st.integers(1, 25))
    width = draw(st.integers(1, 25))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    weights = rng.dirichlet(np.ones(3) * 0.7)
    return rng.choice(np.array([U, F, W], dtype=np.int8), size=(height, width), p=weights)


def reference_nearest(
    belief: npt.NDArray[np.int8], source: tuple[int, int]
) -> tuple[tuple[int, int], npt.NDArray[np.int32]] | None:
    """FrontierStrategy.decide + NearestFrontier.choose_goal as they were."""
    frontier = frontier_mask(belief)
    if not frontier.any():
        return None
    targets = frontier.copy()
    targets[source] = False
    dist = distance_field(belief == FREE, source, targets=targets, stop_after=1)
    rows, cols = reachable_frontier_cells(frontier, dist)
    if rows.size == 0:
        return None
    best = int(np.argmin(dist[rows, cols]))
    goal = (int(rows[best]), int(cols[best]))
    return goal, extract_path(dist, goal)


@settings(max_examples=300, deadline=None)
@given(beliefs(), st.integers(0, 10_000))
def test_nearest_frontier_equals_field_then_argmin(belief: npt.NDArray[np.int8], pick: int) -> None:
    source = divmod(pick % belief.size, belief.shape[1])
    want = reference_nearest(belief, source)
    got = nearest_frontier(belief, source)
    if want is None:
        assert got is None
        return
    assert got is not None
    assert got[0] == want[0]
    assert got[1].dtype == want[1].dtype and np.array_equal(got[1], want[1])
    # the buffers are clean again: a second call gives the same answer
    again = nearest_frontier(belief, source)
    assert again is not None and again[0] == got[0] and np.array_equal(again[1], got[1])


def test_nearest_frontier_counts_one_field() -> None:
    belief = np.full((5, 5), FREE, dtype=np.int8)
    belief[:, 4] = UNKNOWN
    counter = FieldCounter()
    nearest_frontier(belief, (2, 0))  # outside the counter: not counted
    with counter:
        nearest_frontier(belief, (2, 0))
    assert counter.count == 1


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 40), st.integers(1, 40), st.integers(0, 2**32 - 1), st.integers(1, 6))
def test_mark_known_changed_equals_full_scan(
    height: int, width: int, seed: int, n_ticks: int
) -> None:
    rng = np.random.default_rng(seed)
    belief = np.full((height, width), UNKNOWN, dtype=np.int8)
    want = np.full((height, width), -1, dtype=np.int32)
    got = np.full(height * width, -1, dtype=np.int32)
    padded = -(-height * width // 8) * 8
    shadow_row = np.full(padded, UNKNOWN, dtype=np.int8)
    shadow = shadow_row[: height * width]
    n_words = height * width // 8
    for tick in range(n_ticks):
        # cells become known, known cells change value, some even become unknown again
        change = rng.random((height, width)) < 0.2
        belief[change] = rng.choice(np.array([U, F, W], dtype=np.int8), size=int(change.sum()))
        mark_known(belief, want, tick, UNKNOWN)
        flat = belief.reshape(-1)
        mark_known_changed(
            flat,
            shadow,
            flat[: 8 * n_words].view(np.uint64),
            shadow[: 8 * n_words].view(np.uint64),
            got,
            tick,
            UNKNOWN,
        )
        assert np.array_equal(got.reshape(height, width), want)


def numpy_merge_many(belief: npt.NDArray[np.int8], payloads: list[CellUpdates]) -> int:
    """merge_many as it was (numpy only)."""
    rows = np.concatenate([p.rows for p in payloads])
    cols = np.concatenate([p.cols for p in payloads])
    values = np.concatenate([p.values for p in payloads])
    unknown = belief[rows, cols] == UNKNOWN
    rows, cols = rows[unknown], cols[unknown]
    belief[rows, cols] = values[unknown]
    return int(np.unique(rows * belief.shape[1] + cols).size)


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 5))
def test_merge_many_kernel_equals_numpy(seed: int, n_payloads: int) -> None:
    rng = np.random.default_rng(seed)
    shape = (int(rng.integers(1, 20)), int(rng.integers(1, 20)))
    start = rng.choice(np.array([U, F, W], dtype=np.int8), size=shape)
    payloads = []
    for _ in range(n_payloads):
        n = int(rng.integers(0, 30))
        payloads.append(
            CellUpdates(
                rng.integers(0, shape[0], n).astype(np.int64),
                rng.integers(0, shape[1], n).astype(np.int64),
                rng.choice(np.array([F, W], dtype=np.int8), size=n),
            )
        )
    want_belief = start.copy()
    got_belief = start.copy()
    want = numpy_merge_many(want_belief, payloads)
    got = merge_many(got_belief, payloads)
    assert got == want
    # duplicate cells with different values: numpy's last write wins, and so does the kernel
    assert np.array_equal(got_belief, want_belief)


def numpy_check_path(path: npt.NDArray[np.int32], belief: npt.NDArray[np.int8]) -> str | None:
    """check_path's numpy checks as they were; returns the message or None."""
    cells = path
    height, width = belief.shape
    if (cells < 0).any() or (cells[:, 0] >= height).any() or (cells[:, 1] >= width).any():
        return "path leaves the map"
    rows, cols = cells[:, 0], cells[:, 1]
    if (belief[rows[1:], cols[1:]] != FREE).any():
        return "path crosses a cell its robot does not know to be free"
    steps = np.diff(cells, axis=0)
    if (np.abs(steps).max(axis=1, initial=0) != 1).any():
        return "path has a step that is not to an 8-neighbour"
    diagonal = (steps[:, 0] != 0) & (steps[:, 1] != 0)
    if diagonal.any():
        r0, c0 = rows[:-1][diagonal], cols[:-1][diagonal]
        dr, dc = steps[diagonal, 0], steps[diagonal, 1]
        if (belief[r0 + dr, c0] != FREE).any() or (belief[r0, c0 + dc] != FREE).any():
            return "path cuts a corner"
    return None


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_check_path_kernel_gives_the_same_verdict(seed: int) -> None:
    rng = np.random.default_rng(seed)
    shape = (int(rng.integers(2, 8)), int(rng.integers(2, 8)))
    belief = rng.choice(np.array([U, F, W], dtype=np.int8), size=shape, p=[0.1, 0.8, 0.1])
    n = int(rng.integers(1, 8))
    steps = rng.integers(-1, 2, size=(n - 1, 2)) * rng.integers(1, 3, size=(n - 1, 1))
    start = np.array([[rng.integers(0, shape[0]), rng.integers(0, shape[1])]])
    path = np.concatenate([start, start + np.cumsum(steps, axis=0)]).astype(np.int32)
    if (path < 0).any() or (path[:, 0] >= shape[0]).any() or (path[:, 1] >= shape[1]).any():
        want = "path leaves the map"
    else:
        want = numpy_check_path(path, belief)
    start_cell = (int(path[0, 0]), int(path[0, 1]))
    goal_cell = (int(path[-1, 0]), int(path[-1, 1]))
    if want is None:
        check_path(path, start_cell, goal_cell, belief)
    else:
        with pytest.raises(StrategyError, match=want):
            check_path(path, start_cell, goal_cell, belief)


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 60))
def test_range_links_small_and_large_teams_agree(seed: int, n_robots: int) -> None:
    rng = np.random.default_rng(seed)
    positions = {i: (int(rng.integers(0, 60)), int(rng.integers(0, 60))) for i in range(n_robots)}
    comm_range = float(rng.uniform(1, 40))
    model = RangeLinks(comm_range)
    got = model.links(positions)
    ids = sorted(positions)
    want = frozenset(
        (a, b)
        for i, a in enumerate(ids)
        for b in ids[i + 1 :]
        if (positions[a][0] - positions[b][0]) ** 2 + (positions[a][1] - positions[b][1]) ** 2
        <= comm_range**2
    )
    assert got == want


@pytest.mark.parametrize("radius", [3.0, 7.5])
def test_ray_table_from_disk_cache_equals_a_fresh_build(radius: float) -> None:
    cached = ray_table(radius)
    fresh = _build_ray_table(radius)
    for name in ("flags", "cell", "parent", "skip"):
        assert np.array_equal(getattr(cached, name), getattr(fresh, name))
        assert getattr(cached, name).dtype == getattr(fresh, name).dtype
    assert (cached.n_cells, cached.reach) == (fresh.n_cells, fresh.reach)
