"""KME (Wu, Puig & Garcia §IV): the equations on hand-checked cases, the protocol, runs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mrexplore.checks import check_strategy
from mrexplore.comm.bytes import HEADER_BYTES, STATUS_BYTES, TARGET_BYTES
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import distance_field, frontier_mask
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies.kme import (
    Kme,
    assign_regions,
    cells_of,
    choose_target,
    contour_cells,
    frontier_subset,
    inaccessible_contour_distance,
    kme_round,
    kmeans,
    map_diagonal,
    nearest_centroid,
    nearest_inaccessible_contour,
    partition_unknown,
    robot_fields,
    robot_region_distances,
    target_distance,
)
from mrexplore.strategies.network import hops_from
from mrexplore.strategies.registry import register

register(Kme)

U, F, X = UNKNOWN, FREE, OCCUPIED


def _belief(rows: list[list[int]]) -> np.ndarray:
    return np.array(rows, dtype=np.int8)


# ---------------------------------------------------------------- eqs. (1)-(3)
def test_eq1_accessible_region_distance_is_the_real_path_to_its_frontier() -> None:
    """3 x 5 map, robot at (0, 0); region 0 = column 3, region 1 = column 4.

        F F F U U        frontier cells: (0, 2), (1, 2), both beside region 0
        F F F U U
        X X X U U

    delta(r, (0, 2)) = 2 (two straight steps); delta(r, (1, 2)) = 1 + sqrt 2.
    Eq. (1)/(3): d(r, R0) = min(2, 2.414) = 2, reached beside contour cell (0, 3).
    Region 1 touches no frontier: inaccessible. Its contour cells (all of
    column 4, next to region 0) have g = 4, sqrt 17, sqrt 20; the line to
    (0, 4) crosses (0, 1..3), no obstacle, so rho = 0 and eq. (2)/(3) give 4.
    """
    belief = _belief([[F, F, F, U, U], [F, F, F, U, U], [X, X, X, U, U]])
    labels = np.full(belief.shape, -1, dtype=np.int16)
    labels[:, 3] = 0
    labels[:, 4] = 1
    frontier = frontier_mask(belief)
    assert frontier.nonzero()[0].tolist() == [0, 1]
    delta = distance_field(belief == FREE, (0, 0), targets=frontier)
    result = robot_region_distances([(0, 0)], [delta], labels, frontier, belief == OCCUPIED, k=2)
    assert result.d[0, 0] == pytest.approx(2.0)
    assert result.accessible[0].tolist() == [True, False]
    assert result.closest[0, 0].tolist() == [0, 3]
    assert result.d[0, 1] == pytest.approx(4.0)
    assert result.closest[0, 1].tolist() == [0, 4]


def test_eq2_penalises_a_known_obstacle_on_the_line_by_the_map_diagonal() -> None:
    """5 x 5, obstacle at (2, 2), robot at (2, 0), l = hypot(5, 5) = 7.071.

    To (2, 4): g = 4, the line crosses (2, 1), (2, 2): blocked, d = 4 + l = 11.071.
    To (0, 4): g = sqrt 20 = 4.472; the line is (1, 1), (1, 2), (0, 3), (0, 4): clear.
    To (4, 4): symmetric to (0, 4): 4.472.
    """
    occupied = np.zeros((5, 5), dtype=bool)
    occupied[2, 2] = True
    diag = map_diagonal((5, 5))
    assert diag == pytest.approx(7.0710678)
    d = inaccessible_contour_distance(
        (2, 0), np.array([2, 0, 4]), np.array([4, 4, 4]), occupied, diag
    )
    assert d.tolist() == pytest.approx([4 + diag, math.sqrt(20), math.sqrt(20)])
    # Eq. (3) takes the minimum: the fast version must agree (first of the tie in g order).
    value, index = nearest_inaccessible_contour(
        (2, 0), np.array([2, 0, 4]), np.array([4, 4, 4]), occupied, diag
    )
    assert value == pytest.approx(math.sqrt(20))
    assert index == 1


def test_eq2_every_line_blocked_gives_the_nearest_cell_plus_l() -> None:
    occupied = np.zeros((5, 5), dtype=bool)
    occupied[:, 2] = True  # a wall across the map
    diag = map_diagonal((5, 5))
    value, index = nearest_inaccessible_contour(
        (2, 0), np.array([0, 2, 4]), np.array([4, 4, 3]), occupied, diag
    )
    # g: sqrt(20) = 4.47, 4, sqrt(13) = 3.61: the nearest is (4, 3); all blocked.
    assert value == pytest.approx(math.sqrt(13) + diag)
    assert index == 2


def test_fast_eq3_matches_the_minimum_of_eq2_on_random_maps() -> None:
    rng = np.random.default_rng(7)
    for _ in range(30):
        occupied = rng.random((12, 15)) < 0.2
        robot = (int(rng.integers(12)), int(rng.integers(15)))
        rows, cols = rng.integers(0, 12, 20), rng.integers(0, 15, 20)
        diag = map_diagonal(occupied.shape)
        full = inaccessible_contour_distance(robot, rows, cols, occupied, diag)
        value, index = nearest_inaccessible_contour(robot, rows, cols, occupied, diag)
        assert value == pytest.approx(full.min())
        assert full[index] == pytest.approx(full.min())


def test_contour_cells_are_unknown_cells_on_a_region_edge() -> None:
    labels = np.array([[0, 0, 0, 0], [0, 0, 0, 1], [0, 0, 1, 1], [-1, 0, 1, 1]], dtype=np.int16)
    rows, cols, region = contour_cells(labels)
    cells = set(zip(rows.tolist(), cols.tolist(), strict=True))
    # Region 0 cells next to region 1 or to the known cell (3, 0); the map border is no edge.
    assert (0, 0) not in cells and (0, 1) not in cells
    assert {(0, 3), (1, 2), (2, 1), (3, 1), (2, 0)} <= cells
    assert {(1, 3), (2, 2), (3, 2)} <= cells
    assert (3, 3) not in cells and (2, 3) not in cells
    assert all(labels[r, c] == g for r, c, g in zip(rows, cols, region, strict=True))


def test_contour_cells_match_the_whole_map_shift_comparison() -> None:
    """The compiled pass gives what comparing the edge-padded labels with their four
    shifts gives (raster order, same arrays)."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        labels = rng.integers(-1, 3, size=(9, 13)).astype(np.int16)
        padded = np.pad(labels, 1, mode="edge")
        edge = np.zeros(labels.shape, dtype=bool)
        for d_row, d_col in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            edge |= padded[1 + d_row : 10 + d_row, 1 + d_col : 14 + d_col] != labels
        rows, cols = np.nonzero(edge & (labels >= 0))
        expected = [rows.tolist(), cols.tolist(), labels[rows, cols].tolist()]
        assert [a.tolist() for a in contour_cells(labels)] == expected


def test_fast_paths_give_what_the_plain_numpy_gives() -> None:
    """cells_of is np.nonzero; robot_fields is distance_field with frontier targets (a
    source on a wall included); partition_unknown labels by nearest_centroid."""
    rng = np.random.default_rng(5)
    for _ in range(10):
        belief = rng.choice(np.array([U, F, X], dtype=np.int8), size=(17, 23), p=[0.3, 0.6, 0.1])
        frontier = frontier_mask(belief)
        expected = [a.tolist() for a in np.nonzero(frontier)]
        assert [a.tolist() for a in cells_of(frontier)] == expected
        free = belief == F
        sources = [(int(rng.integers(17)), int(rng.integers(23))) for _ in range(3)]
        fields = robot_fields(free, sources, frontier)
        for source, got in zip(sources, fields, strict=True):
            assert np.array_equal(got, distance_field(free, source, targets=frontier))
        labels, centroids = partition_unknown(
            belief, 3, np.random.default_rng(1), None, max_points=50, max_iterations=5
        )
        rows, cols = np.nonzero(belief == U)
        cells = np.stack([rows, cols], axis=1).astype(np.float64)
        assert (labels[belief != U] == -1).all()
        assert np.array_equal(labels[rows, cols], nearest_centroid(cells, centroids))


# ---------------------------------------------------------------- eqs. (4)-(5)
def test_eq4_5_optimal_region_assignment_beats_the_greedy_one() -> None:
    """d = [[1, 2], [1.5, 9]]: greedy gives r0 -> R0 (1) then r1 -> R1 (9), total 10;
    the optimum is r0 -> R1, r1 -> R0, total 2 + 1.5 = 3.5."""
    d = np.array([[1.0, 2.0], [1.5, 9.0]])
    assert assign_regions(d).tolist() == [1, 0]


def test_assignment_is_one_region_per_robot_and_survives_infinite_distances() -> None:
    d = np.array([[np.inf, 3.0, 1.0], [2.0, np.inf, 5.0], [4.0, 4.0, np.inf]])
    # Finite options: r0 -> R1|R2, r1 -> R0|R2, r2 -> R0|R1.
    # r0 -> R2 (1) + r1 -> R0 (2) + r2 -> R1 (4) = 7 is the optimum.
    assert assign_regions(d).tolist() == [2, 0, 1]
    assert sorted(assign_regions(np.random.default_rng(1).random((6, 6))).tolist()) == list(
        range(6)
    )


# ---------------------------------------------------------------- eqs. (6)-(7)
def test_eq6_target_distance_adds_g_rho1_and_rho2() -> None:
    """FM = (0, 0), (0, 5), (3, 5); cc = (3, 0); delta = 2, inf, 5; l = 7.2, v = 100.

    f0: 2 + g((0,0),(3,0)) = 2 + 3 = 5.       f1: unreachable: inf.
    f2: 5 + g((3,5),(3,0)) = 5 + 5 = 10, chosen by another robot: + v = 110.
    With an obstacle at (1, 0), the line f0 -> cc is blocked: f0 = 5 + l = 12.2.
    """
    occupied = np.zeros((4, 6), dtype=bool)
    fm_rows, fm_cols = np.array([0, 0, 3]), np.array([0, 5, 5])
    delta = np.array([2.0, np.inf, 5.0])
    taken = np.array([False, False, True])
    d = target_distance(delta, fm_rows, fm_cols, (3, 0), occupied, 7.2, taken, 100.0)
    assert d.tolist() == pytest.approx([5.0, math.inf, 110.0])
    assert choose_target(d) == 0  # eq. (7)
    occupied[1, 0] = True
    d = target_distance(delta, fm_rows, fm_cols, (3, 0), occupied, 7.2, taken, 100.0)
    assert d.tolist() == pytest.approx([12.2, math.inf, 110.0])
    assert choose_target(np.array([math.inf, math.inf])) == -1
    assert choose_target(np.array([3.0, 1.0, 1.0])) == 1  # first among ties


def test_fm_keeps_frontiers_at_least_the_spacing_apart_and_covers_the_rest() -> None:
    rng = np.random.default_rng(3)
    frontier = rng.random((30, 40)) < 0.1
    nearest = rng.random((30, 40))
    rows, cols = frontier_subset(frontier, 5.0, nearest)
    points = np.stack([rows, cols], axis=1).astype(float)
    gaps = np.hypot(*(points[:, None, :] - points[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    assert gaps.min() >= 5.0
    all_rows, all_cols = np.nonzero(frontier)
    to_fm = np.hypot(all_rows[:, None] - rows[None], all_cols[:, None] - cols[None]).min(axis=1)
    assert (to_fm < 5.0).all()  # greedy: every dropped frontier is near a kept one
    # The first kept cell is the frontier cell nearest to a robot.
    first = np.argmin(np.where(frontier, nearest, np.inf))
    assert (rows[0], cols[0]) == np.unravel_index(first, frontier.shape)
    rows_c, _ = frontier_subset(frontier, 5.0)  # cluster order: same spacing rule
    assert len(rows_c) > 0


# ---------------------------------------------------------------- §IV.A and a round
def test_kmeans_converges_and_warm_start_is_stable() -> None:
    points = np.array([[0.0, 0.0], [0.0, 2.0], [10.0, 10.0], [10.0, 12.0], [0.0, 1.0]])
    centroids, labels = kmeans(points, np.array([[0.0, 0.0], [10.0, 10.0]]), 20)
    assert labels.tolist() == [0, 0, 1, 1, 0]
    assert centroids.tolist() == [[0.0, 1.0], [10.0, 11.0]]
    again, labels_again = kmeans(points, centroids, 20)
    assert np.array_equal(again, centroids) and np.array_equal(labels_again, labels)
    # An empty cluster is re-seeded at the point farthest from its centroid.
    _, seeded_labels = kmeans(points, np.array([[0.0, 1.0], [50.0, 50.0]]), 20)
    assert sorted(set(seeded_labels.tolist())) == [0, 1]


def test_partition_labels_every_unknown_cell_and_subsamples_with_the_rng() -> None:
    belief = np.full((40, 40), UNKNOWN, dtype=np.int8)
    belief[18:22, 18:22] = FREE
    labels, centroids = partition_unknown(
        belief, 3, np.random.default_rng(0), None, max_points=200, max_iterations=20
    )
    assert ((labels >= 0) == (belief == UNKNOWN)).all()
    assert centroids.shape == (3, 2)
    assert set(np.unique(labels[labels >= 0]).tolist()) == {0, 1, 2}
    same, _ = partition_unknown(
        belief, 3, np.random.default_rng(0), None, max_points=200, max_iterations=20
    )
    assert np.array_equal(same, labels)


def test_a_round_sends_two_robots_in_a_corridor_to_opposite_ends() -> None:
    """Two robots side by side in a known corridor, unknown space at both ends: the
    two K-Means regions lie at the two ends and each robot is sent to its own."""
    belief = np.full((5, 60), UNKNOWN, dtype=np.int8)
    belief[1:4, 10:50] = FREE
    belief[0, :] = belief[4, :] = OCCUPIED
    plan = kme_round(
        belief,
        {0: (2, 29), 1: (2, 30)},
        np.random.default_rng(0),
        None,
        fm_spacing=8.0,
        v=0.0,
        max_points=3000,
        max_iterations=20,
    )
    columns = sorted(goal[1] for goal in plan.targets.values())
    assert columns == [10, 49]
    assert plan.regions[0] != plan.regions[1]
    assert all(plan.accessible.values())


def test_hops_in_a_chain() -> None:
    assert hops_from(0, {0, 1, 2}, {(0, 1), (1, 2)}) == 2
    assert hops_from(1, {0, 1, 2}, {(0, 1), (1, 2)}) == 1
    assert hops_from(0, {0}, set()) == 0


# ---------------------------------------------------------------- protocol and runs
def test_kme_passes_the_strategy_checker() -> None:
    check_strategy("kme")


def test_unknown_fm_order_is_bad_input() -> None:
    with pytest.raises(ScenarioError, match="fm_order"):
        Kme(0, 1, fm_order="spiral")


def test_messages_follow_the_byte_model() -> None:
    record = simulate(Scenario(map="sheng40", robots=3, strategy="kme", seed=2))
    assert record.status == "complete"
    assert set(record.bytes_by_type) >= {"status", "assign"}
    # Every status is 7 + 8 bytes, every assign 7 + 6 (broadcasts count once per hop).
    assert record.bytes_by_type["status"] % (HEADER_BYTES + STATUS_BYTES) == 0
    assert record.bytes_by_type["assign"] == record.messages_by_type["assign"] * (
        HEADER_BYTES + TARGET_BYTES
    )


def test_a_lone_robot_sends_nothing() -> None:
    record = simulate(Scenario(map="sheng40", robots=1, strategy="kme", seed=1))
    assert record.status == "complete"
    assert record.bytes_by_type.get("status", 0) == 0


@pytest.mark.parametrize(
    ("map_name", "size"), [("sheng40", None), ("office", (60, 60))], ids=["sheng40", "office60"]
)
def test_three_robots_complete(map_name: str, size: tuple[int, int] | None) -> None:
    record = simulate(Scenario(map=map_name, size=size, robots=3, strategy="kme", seed=1))
    assert record.status == "complete"


def test_limited_comm_a_quarter_of_the_map_completes() -> None:
    record = simulate(
        Scenario(map="office", size=(60, 60), robots=3, strategy="kme", seed=1, comm_range=15)
    )
    assert record.status == "complete"
    assert record.result()["subnetworks_max"] > 1  # the team did split
