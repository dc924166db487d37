"""The RRT frontier detector's budget, clustering and filter (issue 17), and its invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import robot_view
from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import filter_by_gain, frontier_mask, information_gain
from mrexplore.planning.rrt_frontiers import (
    RrtFrontierDetector,
    mean_shift,
    samples_per_tick,
    thin_points,
)
from mrexplore.strategies.base import RobotView
from mrexplore.strategies.market_occupancy import MarketOccupancy

U, F, X = UNKNOWN, FREE, OCCUPIED


def _view(belief: np.ndarray, position: tuple[int, int], sensor_range: float = 4.0) -> RobotView:
    return robot_view(belief, position, sensor_range=sensor_range)


# ---------------------------------------------------------------- budget
def test_budget_is_a_density_over_the_map() -> None:
    """ceil(density * H * W / (pi r^2)): four times the area, four times the samples."""
    assert samples_per_tick((186, 172), 15.0, 1.0) == math.ceil(186 * 172 / (math.pi * 225))
    small = samples_per_tick((50, 50), 5.0, 1.0)
    assert small == 32  # 2500 / 78.5 = 31.8
    assert samples_per_tick((100, 100), 5.0, 1.0) == 128  # 10000 / 78.5 = 127.3
    assert samples_per_tick((100, 100), 10.0, 1.0) == small  # a four times larger footprint
    assert samples_per_tick((50, 50), 5.0, 2.0) == 64
    assert samples_per_tick((3, 3), 50.0, 1.0) == 1  # at least one
    with pytest.raises(MrexploreInputError, match="density"):
        samples_per_tick((10, 10), 5.0, 0.0)


def test_strategy_budget_default_and_fixed_count() -> None:
    belief = np.full((60, 80), UNKNOWN, dtype=np.int8)
    belief[20:40, 20:40] = FREE
    view = _view(belief, (30, 30), sensor_range=6.0)
    scaled = MarketOccupancy(0, 1, frontier_detector="rrt")
    scaled.decide(view)
    assert scaled.detector is not None
    assert scaled.detector.samples == samples_per_tick((60, 80), 6.0, 1.0) == 43
    assert scaled.detector.eta == 5.0 and scaled.detector.clustering == "mean-shift"
    assert scaled.detector.bandwidth == 1.5
    fixed = MarketOccupancy(0, 1, frontier_detector="rrt", rrt_samples=20, rrt_eta=0)
    fixed.decide(view)
    assert fixed.detector is not None
    assert fixed.detector.samples == 20
    assert fixed.detector.eta == 6.0  # rrt_eta=0: the sensor range, the earlier default


# ---------------------------------------------------------------- mean shift
def test_mean_shift_two_blobs_give_two_centres() -> None:
    blob_a = [[10, 10], [10, 11], [11, 10], [11, 11], [12, 11]]
    blob_b = [[30, 5], [31, 5], [30, 6]]
    centres = mean_shift(np.array(blob_a + blob_b), bandwidth=3.0)
    assert centres.shape == (2, 2)
    # Densest first: the five-point blob's mean, then the three-point blob's.
    assert np.allclose(centres[0], np.mean(blob_a, axis=0))
    assert np.allclose(centres[1], np.mean(blob_b, axis=0))


def test_mean_shift_single_point_and_empty() -> None:
    assert mean_shift(np.array([[4, 7]]), 1.5).tolist() == [[4.0, 7.0]]
    assert mean_shift(np.zeros((0, 2), dtype=np.int64), 1.5).shape == (0, 2)
    with pytest.raises(MrexploreInputError, match="bandwidth"):
        mean_shift(np.array([[0, 0]]), 0.0)


def test_mean_shift_centres_are_more_than_a_bandwidth_apart() -> None:
    rng = np.random.default_rng(3)
    points = rng.integers(0, 40, size=(200, 2))
    centres = mean_shift(points, 2.5)
    gaps = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    assert gaps.min() > 2.5


def test_thin_points_inclusive_drops_points_at_the_radius() -> None:
    points = np.array([[0.0, 0.0], [0.0, 1.5], [0.0, 3.2]])
    assert thin_points(points, 1.5).tolist() == [0, 1, 2]  # 1.5 apart is far enough
    assert thin_points(points, 1.5, inclusive=True).tolist() == [0, 2]  # mean shift's rule


def test_points_are_stored_cells_one_per_cluster_oldest_first() -> None:
    """Mean-shift centres are replaced by the stored cell nearest to them."""
    belief = np.full((20, 20), FREE, dtype=np.int8)
    belief[:, 10:] = UNKNOWN  # column 9 is the frontier
    store = np.array([[15, 9], [2, 9], [3, 9], [16, 9], [2, 9]], dtype=np.int64)
    detector = RrtFrontierDetector(eta=5.0, bandwidth=1.5, store=store.copy())
    points = detector.points(belief)
    assert points.tolist() == [[15, 9], [2, 9]]  # two clusters; in store order
    assert np.array_equal(detector.store, points)
    greedy = RrtFrontierDetector(eta=5.0, clustering="greedy", cluster_radius=5.0, store=store)
    assert greedy.points(belief).tolist() == [[15, 9], [2, 9]]
    with pytest.raises(MrexploreInputError, match="clustering"):
        RrtFrontierDetector(eta=5.0, clustering="k-means")


# ---------------------------------------------------------------- information-gain filter
def test_filter_by_gain_drops_points_with_little_unknown_around() -> None:
    belief = np.full((12, 12), FREE, dtype=np.int8)
    belief[:, 9:] = UNKNOWN  # three unknown columns on the right
    belief[0, 0] = UNKNOWN  # one unknown cell in a corner
    points = np.array([[6, 8], [1, 0], [6, 2]])
    gains = information_gain(belief, points, 2.5)
    assert gains.tolist() == [8, 1, 0]  # columns 9 and 10 within 2.5: 5 + 3
    assert filter_by_gain(belief, points, 2.5, 5).tolist() == [[6, 8]]
    assert filter_by_gain(belief, points, 2.5, 1).tolist() == [[6, 8], [1, 0]]
    assert filter_by_gain(belief, points, 0.0, 5).tolist() == points.tolist()  # no radius


def test_rrt_points_pass_the_gain_filter_in_the_strategy() -> None:
    """Listed RRT points have rrt_filter_min_gain unknown cells within rrt_filter_radius,
    unless none has (then all are listed); rrt_filter_min_gain=0 lists them all."""
    belief = np.full((12, 12), FREE, dtype=np.int8)
    belief[:, 9:] = UNKNOWN
    belief[0, 0] = UNKNOWN
    store = np.array([[6, 8], [1, 0], [0, 1]], dtype=np.int64)  # frontier cells; gains 8, 1, 1
    view = _view(belief, (6, 4))

    def listed(**params: object) -> list[list[int]]:
        strategy = MarketOccupancy(0, 1, frontier_detector="rrt", rrt_burst=0, **params)
        strategy.detector = RrtFrontierDetector(
            eta=5.0, clustering="greedy", cluster_radius=0.5, store=store.copy()
        )
        return sorted(strategy.frontier_points(view).tolist())

    assert listed() == [[6, 8]]
    assert listed(rrt_filter_min_gain=0.0) == [[0, 1], [1, 0], [6, 8]]
    assert listed(rrt_filter_min_gain=50.0) == [[0, 1], [1, 0], [6, 8]]  # none passes: all


# ---------------------------------------------------------------- trees
def test_global_eta_bounds_the_global_trees_reach() -> None:
    belief = np.full((80, 80), FREE, dtype=np.int8)
    detector = RrtFrontierDetector(eta=10.0, global_eta=1.0, samples=30)
    rng = np.random.default_rng(1)
    detector.step(belief, (40, 40), rng)
    assert detector.global_tree is not None and detector.local_tree is not None
    reach_global = np.hypot(*(detector.global_tree.vertices - 40.0).T).max()
    reach_local = np.hypot(*(detector.local_tree.vertices - 40.0).T).max()
    assert reach_global <= 30 * 1.0 + 1e-9  # at most one step of 1 cell per sample
    assert reach_local > 10.0  # samples build on vertices added before them in the tick


def test_local_tree_restarts_at_the_robot_after_a_frontier() -> None:
    """One local iteration per step (the global tree cannot move): a step that detects a
    frontier point leaves the local tree at the robot's cell; the global tree keeps its root."""
    belief = np.full((30, 30), FREE, dtype=np.int8)
    belief[:, 20:] = UNKNOWN
    detector = RrtFrontierDetector(eta=3.0, global_eta=1e-12, samples=1)
    rng = np.random.default_rng(0)
    grew = detected = 0
    for tick in range(200):
        position = (10 + tick % 5, 5 + tick % 7)
        found = detector.step(belief, position, rng)
        assert detector.local_tree is not None
        if found.shape[0]:
            detected += 1
            assert detector.local_tree.vertices.tolist() == [[float(position[0]), position[1]]]
        grew = max(grew, detector.local_tree.size)
    assert detected > 0 and grew > 3
    assert detector.global_tree is not None
    assert detector.global_tree.vertices.tolist() == [[10.0, 5.0]]  # rooted at the start


@st.composite
def _beliefs(draw: st.DrawFn) -> tuple[np.ndarray, list[np.ndarray], tuple[int, int], int]:
    """A map, a sequence of growing beliefs of it, a start cell, a seed."""
    height = draw(st.integers(6, 24))
    width = draw(st.integers(6, 24))
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    truth = np.where(rng.random((height, width)) < draw(st.floats(0.0, 0.35)), X, F)
    start = (int(rng.integers(height)), int(rng.integers(width)))
    truth[start] = F
    order = rng.permutation(height * width)
    beliefs = []
    known = np.zeros(height * width, dtype=bool)
    known[np.ravel_multi_index(start, (height, width))] = True
    for chunk in np.array_split(order, draw(st.integers(1, 5))):
        known[chunk[: len(chunk) // 2]] = True
        belief = np.where(known.reshape(height, width), truth, U).astype(np.int8)
        beliefs.append(belief)
    return truth, beliefs, start, seed


@settings(max_examples=60, deadline=None)
@given(case=_beliefs(), clustering=st.sampled_from(["mean-shift", "greedy"]))
def test_every_stored_point_is_a_frontier_cell_after_each_step(
    case: tuple[np.ndarray, list[np.ndarray], tuple[int, int], int], clustering: str
) -> None:
    _, beliefs, start, seed = case
    detector = RrtFrontierDetector(eta=3.0, samples=15, clustering=clustering, bandwidth=1.5)
    rng = np.random.default_rng(seed)
    for belief in beliefs:
        for _ in range(3):
            found = detector.step(belief, start, rng)
            frontier = frontier_mask(belief)
            assert frontier[found[:, 0], found[:, 1]].all()
            assert frontier[detector.store[:, 0], detector.store[:, 1]].all()
            points = detector.points(belief)
            assert frontier[points[:, 0], points[:, 1]].all()
            for tree in (detector.global_tree, detector.local_tree):
                assert tree is not None
                cells = np.floor(tree.vertices + 0.5).astype(np.int64)
                assert (belief[cells[:, 0], cells[:, 1]] == F).all()
