"""Zlot et al. (2002): tour and market formulas on hand-checked cases, one auction
played message by message, the contract checker, and runs that complete."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import robot_view
from mrexplore.checks import check_strategy
from mrexplore.comm.bytes import BID_BYTES, TARGET_BYTES, fixed_size
from mrexplore.comm.messages import BID, Message
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import distance_field
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies.base import RobotView
from mrexplore.strategies.registry import register
from mrexplore.strategies.zlot_market import (
    AUCTION,
    AWARD,
    AuctionPayload,
    AwardPayload,
    BidPayload,
    TickDistances,
    ZlotMarket,
    hops_to_farthest,
    insertion_cost,
    octile_distances,
    removal_savings,
    revenue,
    spread_goals,
    winning_bid,
)

register(ZlotMarket)


# ---------------------------------------------------------------------- formulas
def test_revenue_is_weighted_information_gain() -> None:
    # r = w_r * I: 2 * 25 = 50, 2 * 0 = 0.
    assert revenue(np.array([25, 0]), 2.0).tolist() == [50.0, 0.0]


def test_cheapest_insertion_on_a_line() -> None:
    # Robot p0 at column 0, goals p1 at 4 and p2 at 10 on a straight corridor.
    # legs: d(p0, p1) = 4, d(p1, p2) = 6.
    legs = np.array([4.0, 6.0])
    # x at column 2 lies between p0 and p1: 2 + 2 - 4 = 0, before p1 (index 0).
    assert insertion_cost(np.array([2.0, 2.0, 8.0]), legs) == (0.0, 0)
    # x at column 7: between p0, p1: 7 + 3 - 4 = 6; between p1, p2: 3 + 3 - 6 = 0 (index 1);
    # after p2: 3.
    assert insertion_cost(np.array([7.0, 3.0, 3.0]), legs) == (0.0, 1)
    # x at column 13: 13 + 9 - 4 = 18; 9 + 3 - 6 = 6; after p2: 3 -> end (index 2).
    assert insertion_cost(np.array([13.0, 9.0, 3.0]), legs) == (3.0, 2)
    # Empty tour: the cost is the distance from the robot.
    assert insertion_cost(np.array([5.0]), np.zeros(0)) == (5.0, 0)
    # Unreachable: infinite.
    assert insertion_cost(np.array([np.inf]), np.zeros(0))[0] == np.inf


def test_removal_savings_on_a_detour() -> None:
    # p0 = (0, 0), p1 = (3, 0) off the way, p2 = (0, 4); d(p0, p1) = 3, d(p1, p2) = 5,
    # d(p0, p2) = 4. s_1 = 3 + 5 - 4 = 4 (the detour); s_2 = the last leg = 5.
    assert removal_savings(np.array([3.0, 5.0]), np.array([4.0])).tolist() == [4.0, 5.0]
    # One goal: removing it saves its leg.
    assert removal_savings(np.array([7.0]), np.zeros(0)).tolist() == [7.0]


def test_winning_bid_must_beat_the_reserve() -> None:
    assert winning_bid({1: 5.0, 2: 8.0, 3: 8.0}, 6.0) == (2, 8.0)  # tie -> lowest id
    assert winning_bid({1: 6.0}, 6.0) is None  # equal to the reserve: the auctioneer keeps it
    assert winning_bid({}, -1.0) is None


def test_spread_goals_keeps_the_spacing_and_uses_only_the_given_stream() -> None:
    rows, cols = np.nonzero(np.ones((20, 20), dtype=bool))
    picks = spread_goals(rows, cols, 6, 5.0, np.random.default_rng(3))
    assert len(picks) == 6
    cells = np.column_stack((rows[picks], cols[picks])).astype(float)
    gaps = np.hypot(*(cells[:, None, :] - cells[None, :, :]).transpose(2, 0, 1))
    assert gaps[~np.eye(6, dtype=bool)].min() > 5.0
    again = spread_goals(rows, cols, 6, 5.0, np.random.default_rng(3))
    assert again.tolist() == picks.tolist()


def test_hops_to_farthest_robot() -> None:
    # Chain 0 - 1 - 2 - 3: from 1 the farthest (3) is 2 hops away; alone: 0.
    links = [(0, 1), (1, 2), (2, 3)]
    assert hops_to_farthest(1, links) == 2
    assert hops_to_farthest(0, links) == 3
    assert hops_to_farthest(5, []) == 0


def test_octile_distance_is_a_lower_bound_of_path_length() -> None:
    # (0, 0) -> (3, 1): one diagonal + two straight steps = 2 + sqrt 2.
    assert octile_distances((0, 0), [(3, 1)]).tolist() == pytest.approx([2 + 2**0.5])
    free = np.ones((12, 12), dtype=bool)
    free[1:11, 5] = False  # a wall to walk around
    field = distance_field(free, (5, 2))
    others = [(5, 9), (0, 0), (11, 11)]
    paths = field[tuple(np.array(others).T)]
    assert (octile_distances((5, 2), others) <= paths + 1e-12).all()


def test_tick_distances_match_distance_fields() -> None:
    free = np.ones((12, 12), dtype=bool)
    free[1:11, 5] = False
    distances = TickDistances()
    distances.reset(0, free)
    targets = [(5, 9), (0, 0), (11, 11), (5, 2)]
    field = distance_field(free, (5, 2))
    expected = field[tuple(np.array(targets).T)]
    assert distances.between((5, 2), targets).tolist() == pytest.approx(expected.tolist())
    # Symmetric, memoised, and a bounded query leaves far targets at inf.
    assert distances.between((5, 9), [(5, 2)])[0] == pytest.approx(expected[0])
    fresh = TickDistances()
    fresh.reset(1, free)
    bounded = fresh.between((5, 2), targets, max_distance=3.0)
    assert bounded.tolist()[:3] == [np.inf, np.inf, np.inf]
    assert bounded[3] == 0.0


def test_parameters_are_checked() -> None:
    with pytest.raises(ScenarioError, match="goals_per_round"):
        ZlotMarket(0, 2, goals_per_round=0)


# ---------------------------------------------------------------------- one auction
def _corridor() -> np.ndarray:
    """Rows 1..3, columns 0..20 known free, walls above and below, unknown beyond column 20.

    The frontier cells are column 20 (rows 1..3).
    """
    belief = np.full((5, 30), UNKNOWN, dtype=np.int8)
    belief[0, :22] = belief[4, :22] = OCCUPIED
    belief[1:4, 0:21] = FREE
    belief.flags.writeable = False
    return belief


def _view(
    robot: int, tick: int, position: tuple[int, int], inbox: tuple[Message, ...] = ()
) -> RobotView:
    return RobotView(
        robot_id=robot,
        n_robots=2,
        tick=tick,
        position=position,
        belief=_corridor(),
        goal=None,
        path_remaining=0,
        arrived=False,
        blocked=False,
        inbox=inbox,
        subnetwork=frozenset({0, 1}),
        links=frozenset({(0, 1)}),
        sensor_range=2.0,
        speed=1.0,
        rng=np.random.default_rng(robot),
        new_cells=0,
    )


def test_the_closer_robot_buys_the_goal() -> None:
    """Robot 0 at column 0 holds goal g = (2, 20); robot 1 stands at column 18.

    Revenue: r(g) = unknown cells within 2 of g = (2, 21), (2, 22), (1, 21), (3, 21) -> 4
    (with w_r = 1). Robot 0's value = 4 - d = 4 - 20 = -16 (the reserve); robot 1's bid
    = 4 - 2 = 2 > -16. Announced at tick 10 (the first re-auction), bid at 11, awarded
    at 12 (auction_ticks = 2 = 2 x latency x 1 hop), adopted at 13.
    """
    goal = (2, 20)
    seller, buyer = ZlotMarket(0, 2), ZlotMarket(1, 2)
    seller.tour = [goal]
    seller.next_generation = buyer.next_generation = 10**9  # only the auction under test

    announce = seller.decide(_view(0, 10, (2, 0)))
    assert [m.type for m in announce.messages] == [AUCTION]
    auction = announce.messages[0]
    assert auction.payload == AuctionPayload(0, goal, -16.0)
    assert auction.size_bytes == fixed_size(BID_BYTES)  # header + robot, row, col, float32

    answer = buyer.decide(_view(1, 11, (2, 18), (auction,)))
    assert [m.type for m in answer.messages] == [BID]
    bid = answer.messages[0]
    assert (bid.dest, bid.payload, bid.size_bytes) == (
        0,
        BidPayload(1, goal, 2.0),
        fixed_size(BID_BYTES),
    )

    close = seller.decide(_view(0, 12, (2, 0), (bid,)))
    awards = [m for m in close.messages if m.type == AWARD]
    assert [m.payload for m in awards] == [AwardPayload(1, goal)]
    assert awards[0].size_bytes == fixed_size(TARGET_BYTES)
    assert seller.tour == []

    adopt = buyer.decide(_view(1, 13, (2, 18), (awards[0],)))
    assert buyer.tour == [goal]
    assert adopt.goal == goal


def test_an_auction_without_bids_closes_on_time_and_the_seller_keeps_the_goal() -> None:
    goal = (2, 20)
    seller = ZlotMarket(0, 2)
    seller.tour = [goal]
    seller.next_generation = 10**9
    seller.decide(_view(0, 10, (2, 0)))
    assert goal in seller.auctions
    seller.decide(_view(0, 11, (2, 0)))  # bids lost
    assert goal in seller.auctions
    close = seller.decide(_view(0, 12, (2, 0)))
    assert not seller.auctions
    assert not [m for m in close.messages if m.type == AWARD]
    assert seller.tour == [goal]


def test_a_bid_below_the_reserve_is_not_sent() -> None:
    # Robot 1 at column 0 values g at 4 - 20 = -16; the reserve is 0: no bid.
    buyer = ZlotMarket(1, 2)
    buyer.next_generation = 10**9
    auction = Message(AUCTION, 0, 0xFFFF, 17, AuctionPayload(0, (2, 20), 0.0))
    answer = buyer.decide(_view(1, 11, (2, 0), (auction,)))
    assert not [m for m in answer.messages if m.type == BID]


def test_generated_goals_are_reachable_frontier_cells_in_the_tour() -> None:
    robot = ZlotMarket(0, 2, goals_per_round=2, goal_spacing=1.0)
    decision = robot.decide(_view(0, 1, (2, 10)))
    assert 1 <= len(robot.tour) <= 2
    assert all(cell[1] == 20 for cell in robot.tour)  # column 20 is the frontier
    assert [m.type for m in decision.messages] == [AUCTION] * len(robot.tour)
    assert decision.goal == robot.tour[0]


# ---------------------------------------------------------------------- runs
def test_passes_the_strategy_checker() -> None:
    check_strategy("zlot-market")


@pytest.mark.parametrize(
    ("map_name", "size"), [("sheng40", None), ("office", (60, 60))], ids=["sheng40", "office60"]
)
def test_three_robots_complete_and_bytes_follow_the_byte_model(
    map_name: str, size: tuple[int, int] | None
) -> None:
    record = simulate(Scenario(map=map_name, size=size, robots=3, strategy="zlot-market", seed=1))
    assert record.status == "complete"
    hops = record.result()["hops_by_type"]
    offer, award = fixed_size(BID_BYTES), fixed_size(TARGET_BYTES)
    assert record.bytes_by_type["auction"] == offer * hops["auction"]
    assert record.bytes_by_type.get("bid", 0) == offer * hops.get("bid", 0)
    assert record.bytes_by_type.get("award", 0) == award * hops.get("award", 0)


def test_completes_with_a_quarter_map_comm_range() -> None:
    record = simulate(
        Scenario(
            map="office", size=(60, 60), robots=3, strategy="zlot-market", seed=1, comm_range=15
        )
    )
    assert record.status == "complete"


def test_a_lone_robot_holds_no_auctions() -> None:
    record = simulate(Scenario(map="sheng40", robots=1, strategy="zlot-market", seed=1))
    assert record.status == "complete"
    assert record.result()["bytes_total"] == 0


# ---------------------------------------------------------------------- compiled paths
def _plain_generate_goals(
    market: ZlotMarket, view: RobotView
) -> tuple[list[tuple[int, int]], dict[tuple[int, int], int]]:
    """Step 1 as first written: one field to every frontier cell, then the numpy
    selection (the formulation the bounded searches must reproduce)."""
    from mrexplore.planning import frontier_mask
    from mrexplore.strategies.base import passable, reachable_frontier_cells
    from mrexplore.strategies.zlot_market import spread_goals as spread

    frontier = frontier_mask(view.belief)
    foreign = dict(market.foreign_goals)
    if not frontier.any():
        return [], foreign
    dist = distance_field(passable(view.belief), view.position, targets=frontier)
    rows, cols = reachable_frontier_cells(frontier, dist)
    if rows.size == 0:
        return [], foreign
    foreign = {g: r for g, r in foreign.items() if frontier[g]}
    spacing = market.goal_spacing or view.sensor_range
    held = market.tour + [g for g, r in foreign.items() if r in view.subnetwork]
    unclaimed = np.ones(rows.size, dtype=bool)
    for row, col in held:
        unclaimed &= np.hypot(rows - row, cols - col) > spacing
    if unclaimed.any():
        rows, cols = rows[unclaimed], cols[unclaimed]
    cost = dist[rows, cols]
    near = cost <= cost.min() + market.generation_radius
    rows, cols = rows[near], cols[near]
    chosen = spread(rows, cols, market.goals_per_round, spacing, view.rng)
    return [(int(rows[i]), int(cols[i])) for i in chosen], foreign


@pytest.mark.parametrize("seed", range(12))
def test_generate_goals_matches_the_full_field_formulation(seed: int) -> None:
    """Random beliefs, positions, held goals, spacings and radii: the two bounded
    searches pick the goals one full field picks, and draw the same random numbers."""
    rng = np.random.default_rng(seed)
    height, width = int(rng.integers(8, 40)), int(rng.integers(8, 40))
    belief = np.full((height, width), UNKNOWN, dtype=np.int8)
    known = rng.random((height, width)) < rng.uniform(0.3, 0.9)
    belief[known] = np.where(rng.random(int(known.sum())) < 0.8, FREE, OCCUPIED)
    free_cells = np.argwhere(belief == FREE)
    if free_cells.size == 0:
        return
    position = tuple(int(v) for v in free_cells[rng.integers(len(free_cells))])
    params = {
        "goal_spacing": float(rng.choice([0.0, 2.0, 5.5])),
        "generation_radius": float(rng.choice([0.0, 1.0, 3.7])),
    }
    plain, fast = ZlotMarket(0, 3, **params), ZlotMarket(0, 3, **params)
    held = [tuple(int(v) for v in free_cells[i]) for i in rng.integers(len(free_cells), size=3)]
    for market in (plain, fast):
        market.tour = [held[0]]
        market.foreign_goals = {held[1]: 1, held[2]: 2}
    views = [
        robot_view(
            belief,
            position,
            n_robots=3,
            tick=0,
            subnetwork=frozenset({0, 1}),
            sensor_range=3.0,
            rng=np.random.default_rng(seed),
        )
        for _ in range(2)
    ]
    expected, foreign = _plain_generate_goals(plain, views[0])
    assert fast.generate_goals(views[1]) == expected
    assert fast.foreign_goals == foreign
    assert views[0].rng.random() == views[1].rng.random()  # same draws


def test_clear_disk_and_cells_within_match_numpy() -> None:
    from mrexplore.strategies.zlot_market import cells_within, clear_disk

    rng = np.random.default_rng(3)
    for _ in range(50):
        shape = (int(rng.integers(1, 30)), int(rng.integers(1, 30)))
        mask = rng.random(shape) < 0.5
        row, col = int(rng.integers(-5, shape[0] + 5)), int(rng.integers(-5, shape[1] + 5))
        radius = float(rng.uniform(0, 12))
        rows, cols = np.indices(shape)
        expected = mask & (np.hypot(rows - row, cols - col) > radius)
        clear_disk(mask, row, col, radius)
        np.testing.assert_array_equal(mask, expected)

        field = np.where(rng.random(shape) < 0.3, np.inf, rng.uniform(0, 20, shape))
        source = (int(rng.integers(shape[0])), int(rng.integers(shape[1])))
        chebyshev = np.maximum(abs(rows - source[0]), abs(cols - source[1]))
        field = np.maximum(field, chebyshev)  # a path is never shorter
        bound = float(rng.uniform(0, 25))
        got = cells_within(field, mask, source, bound)
        want = np.nonzero(mask & (field <= bound))
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])
