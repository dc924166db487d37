"""market-occupancy (decentralised market, §III) and the RRT frontier detector."""

from __future__ import annotations

import math
from collections.abc import Callable
from itertools import pairwise

import numpy as np
import pytest

from conftest import robot_view
from mrexplore.checks import check_strategy
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import distance_field, frontier_mask
from mrexplore.planning.rrt_frontiers import (
    EDGE_FREE,
    EDGE_FRONTIER,
    EDGE_OBSTACLE,
    RrtFrontierDetector,
    nearest_vertex,
    steer,
    thin_points,
    walk_edges,
)
from mrexplore.sim import Scenario, simulate
from mrexplore.sim.engine import Simulation
from mrexplore.strategies.base import Decision, RobotView
from mrexplore.strategies.market_occupancy import (
    INFEASIBLE,
    WEIGHT_REQUEST,
    WEIGHTS,
    MarketOccupancy,
    assign,
    cost,
    occupancy,
    request_size,
    utility,
    weight,
    weights_size,
)
from mrexplore.strategies.registry import register

register(MarketOccupancy)

U, F, X = UNKNOWN, FREE, OCCUPIED


# ---------------------------------------------------------------- eqs. (3)-(6)
def test_eq3_cost_is_the_euclidean_distance() -> None:
    # (0, 0) -> (3, 4): sqrt(9 + 16) = 5; -> (0, 2): 2; -> (1, 1): sqrt 2.
    assert cost((0, 0), np.array([[3, 4], [0, 2], [1, 1]])).tolist() == pytest.approx(
        [5.0, 2.0, math.sqrt(2)]
    )


def test_eq4_utility_counts_unknown_cells_within_r() -> None:
    """5 x 5 map, left two columns free, the rest unknown; point (2, 1), r = 1.

    The disk of radius 1 around (2, 1) holds (1,1), (3,1), (2,0), (2,2), (2,1):
    only (2, 2) is unknown, so c = 1 and U = lambda_u * 1. With r = 2 the disk
    (13 cells, clipped to the map: columns -1 .. 3) holds the unknown cells
    (2,2), (2,3), (1,2), (3,2): c = 4 (columns 2-3 of rows 1-3 within
    distance 2: (1,2) d=1.41, (3,2) 1.41, (2,2) 1, (2,3) 2; (1,3), (3,3) are at 2.24).
    """
    belief = np.full((5, 5), UNKNOWN, dtype=np.int8)
    belief[:, :2] = FREE
    point = np.array([[2, 1]])
    assert utility(belief, point, 1.0, 0.5).tolist() == [0.5]
    assert utility(belief, point, 2.0, 0.25).tolist() == [1.0]


def test_eq5_occupancy_is_a_gaussian_with_3_sigma_r_f_cut_at_r_f() -> None:
    """r_f = 6: sigma = 2. At distance 3: exp(-9 / 8) = 0.32465; at 6: exp(-36 / 8) = 0.01111;
    beyond 6: zero. Two other robots' points add up."""
    points = np.array([[0, 0], [0, 3], [0, 6], [0, 7]])
    f = occupancy(points, [(0, 0)], 6.0, 1.0)
    assert f.tolist() == pytest.approx([1.0, math.exp(-9 / 8), math.exp(-36 / 8), 0.0])
    both = occupancy(np.array([[0, 3]]), [(0, 0), (0, 6)], 6.0, 2.0)
    assert both.tolist() == pytest.approx([4 * math.exp(-9 / 8)])
    assert occupancy(points, [], 6.0, 1.0).tolist() == [0.0] * 4


def test_eq6_weight_is_cost_minus_utility_plus_occupancy() -> None:
    # W = C - U + F = 5 - 2 + 0.5 = 3.5, and 2 - 0 + 0 = 2.
    assert weight(np.array([5.0, 2.0]), np.array([2.0, 0.0]), np.array([0.5, 0.0])).tolist() == [
        3.5,
        2.0,
    ]


def test_eq8_hungarian_minimises_the_total_weight() -> None:
    """W = [[1, 2], [1.5, 9]]: greedy gives robot 0 point 0 (1) and robot 1 point 1 (9),
    total 10; the optimum is 2 + 1.5 = 3.5: robot 0 -> point 1, robot 1 -> point 0."""
    assert assign(np.array([[1.0, 2.0], [1.5, 9.0]])).tolist() == [1, 0]


def test_robots_left_over_take_their_least_weight() -> None:
    """Three robots, two points. Pairs of rows: {0, 1}: min(1 + 9, 2 + 1.5) = 3.5;
    {0, 2}: min(1 + 5, 2 + 0) = 2; {1, 2}: min(1.5 + 5, 9 + 0) = 6.5. The optimum gives
    robot 0 point 1 and robot 2 point 0; robot 1 is left over and takes its least, point 0."""
    assert assign(np.array([[1.0, 2.0], [1.5, 9.0], [0.0, 5.0]])).tolist() == [1, 0, 0]
    assert assign(np.zeros((2, 0))).tolist() == [-1, -1]


def test_byte_model_of_the_two_messages() -> None:
    # request: header 7 + (requester, round, M) 6 + 8 per point; weights: 7 + 6 + 4 per point.
    assert request_size(0) == 13 and request_size(10) == 93
    assert weights_size(0) == 13 and weights_size(10) == 53


# ---------------------------------------------------------------- the RRT detector
def test_walk_edges_free_obstacle_frontier() -> None:
    belief = np.array(
        [
            [F, F, F, F, F, U],
            [F, F, X, F, F, U],
            [F, F, F, F, F, U],
        ],
        dtype=np.int8,
    )
    starts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 0.0]])
    ends = np.array([[0.0, 3.0], [1.0, 4.0], [2.0, 5.0], [1.0, 1.0]])
    outcome, cells = walk_edges(belief, starts, ends)
    assert outcome.tolist() == [EDGE_FREE, EDGE_OBSTACLE, EDGE_FRONTIER, EDGE_FREE]
    assert cells.tolist() == [[-1, -1], [-1, -1], [2, 4], [-1, -1]]
    # Off the map counts as an obstacle.
    outcome, _ = walk_edges(belief, np.array([[0.0, 0.0]]), np.array([[-3.0, 0.0]]))
    assert outcome.tolist() == [EDGE_OBSTACLE]


def test_walk_edges_never_cuts_a_corner() -> None:
    """A diagonal step between two occupied cells (or beside one) meets an obstacle;
    a diagonal step beside an unknown cell is a frontier at the cell before it."""
    squeeze = np.array([[F, X], [X, U]], dtype=np.int8)
    outcome, _ = walk_edges(squeeze, np.array([[0.0, 0.0]]), np.array([[1.0, 1.0]]))
    assert outcome.tolist() == [EDGE_OBSTACLE]
    beside = np.array([[F, U], [F, F]], dtype=np.int8)
    outcome, cells = walk_edges(beside, np.array([[0.0, 0.0]]), np.array([[1.0, 1.0]]))
    assert outcome.tolist() == [EDGE_FRONTIER]
    assert cells.tolist() == [[0, 0]]
    between = np.array([[F, F], [F, U]], dtype=np.int8)
    outcome, cells = walk_edges(between, np.array([[0.0, 0.0]]), np.array([[1.0, 1.0]]))
    assert outcome.tolist() == [EDGE_FRONTIER]
    assert cells.tolist() == [[1, 0]]  # a free cell 4-adjacent to the unknown one


def test_steer_nearest_and_thinning() -> None:
    # From (0, 0) towards (0, 10) by eta = 4: (0, 4); a sample within eta is reached.
    assert steer(
        np.array([[0.0, 0.0], [1.0, 1.0]]), np.array([[0.0, 10.0], [2.0, 2.0]]), 4.0
    ).tolist() == [
        [0.0, 4.0],
        [2.0, 2.0],
    ]
    vertices = np.array([[0.0, 0.0], [5.0, 5.0], [0.0, 9.0]])
    assert nearest_vertex(vertices, np.array([[1.0, 7.0], [4.0, 4.0]])).tolist() == [2, 1]
    # Greedy, oldest first: (0, 1) is within 2 of (0, 0); (0, 5) is kept.
    assert thin_points(np.array([[0, 0], [0, 1], [0, 5], [1, 5]]), 2.0).tolist() == [0, 2]


def test_detector_finds_only_frontier_cells_and_is_deterministic() -> None:
    belief = np.full((40, 40), UNKNOWN, dtype=np.int8)
    belief[10:30, 10:30] = FREE
    belief[10:30, 20] = OCCUPIED
    belief[19:21, 20] = FREE  # a door in the wall
    results = []
    for _ in range(2):
        detector = RrtFrontierDetector(eta=6.0, samples=20, clustering="greedy", cluster_radius=3.0)
        rng = np.random.default_rng(5)
        for _ in range(30):
            detector.step(belief, (15, 15), rng)
        results.append(detector.points(belief))
    points = results[0]
    assert np.array_equal(points, results[1])
    assert points.shape[0] > 4
    assert frontier_mask(belief)[points[:, 0], points[:, 1]].all()
    # Both sides of the wall: the global tree went through the door.
    assert (points[:, 1] < 20).any() and (points[:, 1] > 20).any()
    gaps = np.hypot(*(points[:, None, :] - points[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    assert gaps.min() >= 3.0


# ---------------------------------------------------------------- protocol and runs
def test_market_occupancy_passes_the_strategy_checker() -> None:
    check_strategy("market-occupancy")


def test_unknown_detector_is_bad_input() -> None:
    with pytest.raises(ScenarioError, match="frontier_detector"):
        MarketOccupancy(0, 1, frontier_detector="sonar")


def test_every_robot_solves_the_same_matrix_under_unlimited_comm() -> None:
    """Algorithm 1 runs on every robot: with every row delivered, all robots hold the
    same assigned points q_a at the end of every tick."""
    simulation = Simulation(
        Scenario(map="office", size=(60, 60), robots=4, strategy="market-occupancy", seed=2)
    )
    strategies = [s for s in simulation.strategies if isinstance(s, MarketOccupancy)]
    last = strategies[-1]
    last_decide = last.decide
    disagreements: list[int] = []

    def decide_and_compare(view: RobotView) -> Decision:
        decision = last_decide(view)
        if any(s.assigned != last.assigned for s in strategies):
            disagreements.append(view.tick)
        return decision

    last.decide = decide_and_compare  # type: ignore[method-assign]  # observe every tick
    record = simulation.run()
    assert record.status == "complete"
    assert min(s.rounds_decided for s in strategies) > 5
    assert disagreements == []


def test_messages_follow_the_byte_model() -> None:
    record = simulate(Scenario(map="sheng40", robots=3, strategy="market-occupancy", seed=2))
    assert record.status == "complete"
    n_requests = record.messages_by_type[WEIGHT_REQUEST]
    n_rows = record.messages_by_type[WEIGHTS]
    assert n_rows >= 3 * n_requests > 0  # the requester's row and one per other robot
    # Bytes = headers + round fields + 8 per point (requests) or 4 per weight (rows); a
    # round's rows carry as many weights as its request carries points.
    request_bytes = record.bytes_by_type[WEIGHT_REQUEST] - 13 * n_requests
    row_bytes = record.bytes_by_type[WEIGHTS] - 13 * n_rows
    assert request_bytes % 8 == 0 and row_bytes % 4 == 0
    assert row_bytes // 4 == 3 * (request_bytes // 8)


def test_infeasible_points_are_never_goals() -> None:
    """A robot alone in a walled room: points outside it get the infeasible weight."""
    strategy = MarketOccupancy(0, 1)
    belief = np.full((10, 20), UNKNOWN, dtype=np.int8)
    belief[2:8, 2:8] = FREE
    belief[2:8, 8] = OCCUPIED
    belief[2:8, 12:16] = FREE
    view = robot_view(belief, (4, 4))
    row = strategy.row(view, np.array([[2, 5], [4, 12], [4, 4]]))
    assert row[0] < INFEASIBLE
    assert row[1] == INFEASIBLE  # behind the wall: unreachable
    assert row[2] == INFEASIBLE  # its own cell
    decision = strategy.decide(view)
    assert decision.goal is not None and decision.goal[1] < 8


@pytest.mark.parametrize(
    ("map_name", "size"), [("sheng40", None), ("office", (60, 60))], ids=["sheng40", "office60"]
)
def test_three_robots_complete(map_name: str, size: tuple[int, int] | None) -> None:
    record = simulate(
        Scenario(map=map_name, size=size, robots=3, strategy="market-occupancy", seed=1)
    )
    assert record.status == "complete"


def test_rrt_detector_option_completes() -> None:
    record = simulate(
        Scenario(
            map="sheng40",
            robots=3,
            strategy="market-occupancy",
            seed=1,
            params={"frontier_detector": "rrt"},
        )
    )
    assert record.status == "complete"


def test_limited_comm_a_quarter_of_the_map_completes() -> None:
    record = simulate(
        Scenario(
            map="office",
            size=(60, 60),
            robots=3,
            strategy="market-occupancy",
            seed=1,
            comm_range=15,
        )
    )
    assert record.status == "complete"
    assert record.result()["subnetworks_max"] > 1


# ------------------------------------------------- event-based vs time-triggered
def test_time_triggered_rounds_need_a_period() -> None:
    with pytest.raises(ScenarioError, match="replan_every"):
        MarketOccupancy(0, 2, event_based=False)
    MarketOccupancy(0, 2, event_based="false", replan_every=5)  # the --set text form


def _request_ticks(params: dict[str, object]) -> dict[int, list[int]]:
    """Ticks at which each robot opened a round (sent a ``weight_request``)."""
    simulation = Simulation(
        Scenario(
            map="office",
            size=(60, 60),
            robots=2,
            strategy="market-occupancy",
            seed=1,
            max_ticks=120,
            idle_ticks=50,
            params=params,
        )
    )
    opened: dict[int, list[int]] = {0: [], 1: []}

    def observed(original: Callable[[RobotView], Decision]) -> Callable[[RobotView], Decision]:
        def decide(view: RobotView) -> Decision:
            decision = original(view)
            if any(m.type == WEIGHT_REQUEST for m in decision.messages):
                opened[view.robot_id].append(view.tick)
            return decision

        return decide

    for strategy in simulation.strategies:
        assert isinstance(strategy, MarketOccupancy)
        strategy.decide = observed(strategy.decide)  # type: ignore[method-assign]  # observe
    simulation.run()
    return opened


def test_time_triggered_rounds_open_on_the_clock_only() -> None:
    """``event_based=false``: each robot opens a round at once and then every
    ``replan_every`` ticks, whether or not it reached its goal."""
    opened = _request_ticks({"event_based": False, "replan_every": 7})
    for ticks in opened.values():
        assert len(ticks) >= 10
        assert all(b - a == 7 for a, b in pairwise(ticks))
    events = _request_ticks({})
    gaps = [b - a for ticks in events.values() for a, b in pairwise(ticks)]
    assert len(set(gaps)) > 1  # event-based rounds follow the arrivals, not a clock


def test_a_timer_that_does_not_idle_also_opens_rounds_on_events() -> None:
    """``idle_until_clock=false``: the clock's rounds, plus a round whenever a robot
    needs a goal, so rounds come at most ``replan_every`` ticks apart and some sooner."""
    opened = _request_ticks({"event_based": False, "replan_every": 7, "idle_until_clock": False})
    gaps = [b - a for ticks in opened.values() for a, b in pairwise(ticks)]
    assert gaps and max(gaps) <= 7
    assert min(gaps) < 7


def _corridor_view(belief: np.ndarray) -> RobotView:
    return robot_view(belief, (5, 10))


def test_the_frontier_filter_drops_points_that_would_reveal_little() -> None:
    """Umari & Mukhopadhyay's filter: a frontier point with fewer than ``filter_min_gain``
    unknown cells within ``filter_radius`` is no task; a wide opening is kept."""
    belief = np.full((11, 30), OCCUPIED, dtype=np.int8)
    belief[1:10, 1:29] = FREE
    belief[1:10, 29] = UNKNOWN  # the east wall missing: a wide opening to the unknown
    belief[1:10, 0] = OCCUPIED
    belief[0, 5] = UNKNOWN  # one unknown cell in the north wall: a pocket
    view = _corridor_view(belief)
    unfiltered = MarketOccupancy(0, 1).frontier_points(view)
    assert {int(c) for _, c in unfiltered} >= {5, 28}  # the pocket is a cluster of its own
    filtered = MarketOccupancy(0, 1, filter_radius=2.5, filter_min_gain=5).frontier_points(view)
    assert filtered.shape[0] == 1 and filtered[0, 1] == 28
    # Every point under the threshold: all kept (the run must still reach its coverage).
    strict = MarketOccupancy(0, 1, filter_radius=2.5, filter_min_gain=100).frontier_points(view)
    assert strict.shape == unfiltered.shape


def test_path_cost_reading_weighs_the_way_round_a_wall() -> None:
    """``cost=path``: C_ij is the shortest-path length on the robot's map, not eq. (3)'s
    straight line; the weights differ by exactly the detour."""
    belief = np.full((11, 30), OCCUPIED, dtype=np.int8)
    belief[1:10, 1:29] = FREE
    belief[1:8, 12] = OCCUPIED  # a wall with a gap at rows 8-9
    view = _corridor_view(belief)
    points = np.array([[5, 16], [5, 6]])
    straight = MarketOccupancy(0, 1).row(view, points).astype(np.float64)
    around = MarketOccupancy(0, 1, cost="path").row(view, points).astype(np.float64)
    dist = distance_field(belief == FREE, (5, 10))
    detour = np.array([dist[5, 16] - 6.0, dist[5, 6] - 4.0])
    assert detour[0] > 1 and detour[1] == 0
    assert np.allclose(around - straight, detour, atol=1e-4)
