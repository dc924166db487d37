"""``sheng-bidding``: Sheng et al. (2006) eqs. (1)-(2), the bid, the session protocol, runs."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from mrexplore.checks import check_strategy
from mrexplore.comm.bytes import BID_BYTES, HEADER_BYTES, POSITION_BYTES, TARGET_BYTES
from mrexplore.comm.messages import BID, BidItem, CellItem, Message
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import disk_mask
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies.base import RobotView
from mrexplore.strategies.network import hop_diameter
from mrexplore.strategies.registry import register
from mrexplore.strategies.sheng_bidding import (
    BIDDING,
    POSITION,
    TRAVELLING,
    WAITING,
    WINNER,
    ShengBidding,
    compute_bid,
    information_gains,
    nearness,
    net_gain,
    session_timing,
)

register(ShengBidding)


# ----------------------------------------------------------------------------- eq. (1)
def test_nearness_is_eq_1_over_sorted_distances() -> None:
    # d = (8, 4, inf) sorted -> (4, 8, inf); r_c = 16, alpha = 0.5:
    # e^(-4/16) + 0.5 e^(-8/16) + 0.25 e^(-inf) = 0.7788008 + 0.3032653 + 0 = 1.0820661
    assert nearness([8.0, 4.0, math.inf], 16.0, 0.5) == pytest.approx(1.0820661, abs=1e-7)


def test_nearness_terms_fade_by_alpha_and_vanish_without_neighbours() -> None:
    # One neighbour on the same cell: e^0 = 1. No neighbour (a lone robot): 0.
    assert nearness([0.0], 16.0, 0.5) == pytest.approx(1.0)
    assert nearness([], 16.0, 0.5) == 0.0
    # alpha = 0 keeps only the nearest robot: e^(-16/16) = 0.3678794.
    assert nearness([32.0, 16.0], 16.0, 0.0) == pytest.approx(0.3678794, abs=1e-7)
    # Three robots at r_c: (1 + 0.5 + 0.25) e^-1 = 1.75 * 0.3678794 = 0.6437890.
    assert nearness([16.0, 16.0, 16.0], 16.0, 0.5) == pytest.approx(0.6437890, abs=1e-7)


def test_nearness_of_many_cells_at_once() -> None:
    # Rows are frontier cells, columns other robots: row 0 as above, row 1 = e^-1 + 0.5 e^-2
    # = 0.3678794 + 0.0676676 = 0.4355470.
    rows = np.array([[8.0, 4.0], [32.0, 16.0]])
    assert nearness(rows, 16.0, 0.5) == pytest.approx([1.0820661, 0.4355470], abs=1e-7)


def test_nearness_is_largest_for_the_robot_closest_to_the_others() -> None:
    # Sheng Fig. 2: the robot far (beyond r_c) from every other has the least nearness.
    close = nearness([3.0, 5.0, 6.0], 16.0, 0.5)
    far = nearness([20.0, 22.0, 25.0], 16.0, 0.5)
    assert far < close


# ----------------------------------------------------------------------------- eq. (2)
def test_net_gain_is_eq_2() -> None:
    # g = w1 I - w2 D + w3 lambda: 1*20 - 1*7.5 + 1.5*1.0 = 14.0; 10 - 2 + 0 = 8.0.
    g = net_gain([20, 10], [7.5, 2.0], [1.0, 0.0], 1.0, 1.0, 1.5)
    assert g.tolist() == [14.0, 8.0]
    # w3 = 0 (the paper's "without nearness"): 20 - 7.5 = 12.5.
    assert float(net_gain(20, 7.5, 1.0, 1.0, 1.0, 0.0)) == 12.5
    # Other weights: 2*20 - 0.5*7.5 + 3*1.0 = 40 - 3.75 + 3 = 39.25.
    assert float(net_gain(20, 7.5, 1.0, 2.0, 0.5, 3.0)) == 39.25


# ----------------------------------------------------------------------------- I_i
def test_information_gain_excludes_other_robots_sensor_disks() -> None:
    belief = np.full((7, 7), UNKNOWN, dtype=np.int8)
    candidate = np.array([[3, 3]])
    # The radius-1 disk of (3, 3) is (2,3), (3,2), (3,3), (3,4), (4,3): 5 unknown cells.
    assert information_gains(belief, candidate, 1.0, []).tolist() == [5]
    # Another robot at (3, 4) senses (2,4), (3,3), (3,4), (3,5), (4,4): two of them
    # are in the candidate's disk, so I = 5 - 2 = 3.
    assert information_gains(belief, candidate, 1.0, [(3, 4)]).tolist() == [3]
    # A robot far away removes nothing.
    assert information_gains(belief, candidate, 1.0, [(0, 0)]).tolist() == [5]


def test_exclusion_mask_clips_at_the_border() -> None:
    mask = disk_mask((3, 3), [(0, 0)], 1.0)
    assert mask.astype(int).tolist() == [[1, 1, 0], [1, 0, 0], [0, 0, 0]]


# ----------------------------------------------------------------------------- the bid
def _corridor() -> np.ndarray:
    """A 1-cell corridor: unknown at both ends (cols 0-2, 10-12), free cols 3-9.

    Frontier cells: (1, 3) and (1, 9). Walls above and below.
    """
    belief = np.full((3, 13), OCCUPIED, dtype=np.int8)
    belief[1, :] = UNKNOWN
    belief[1, 3:10] = FREE
    return belief


def _bid(belief: np.ndarray, position: tuple[int, int], sensing: list[Any], **kw: Any) -> Any:
    weights: dict[str, Any] = {"w1": 1.0, "w2": 1.0, "w3": 1.5, "alpha": 0.5}
    weights.update(kw)
    result = compute_bid(
        belief, position, sensing, [], sensor_range=2.0, comm_range=16.0, **weights
    )
    assert result is not None
    return result[0]


def test_bid_without_others_is_gain_minus_distance() -> None:
    # From (1, 6) both frontier cells are D = 3 away; each sees 2 unknown cells within
    # r_s = 2 ((1,1),(1,2) and (1,10),(1,11)): g = 2 - 3 = -1 for both; raster order wins.
    bid = _bid(_corridor(), (1, 6), [])
    assert (bid.target, bid.value, bid.information, bid.distance) == ((1, 3), -1.0, 2.0, 3.0)
    assert bid.nearness == 0.0


def test_nearness_pulls_the_bid_towards_the_other_robot() -> None:
    # Another robot senses at (1, 7) (its disk, cols 5-9, holds no unknown cell).
    # lambda(1,3) = e^(-4/16) = 0.7788008; lambda(1,9) = e^(-2/16) = 0.8824969.
    # Raw: g(1,3) = 2 - 3 + 1.5 * 0.7788008 = 0.1682012; g(1,9) = -1 + 1.3237454.
    raw = _bid(_corridor(), (1, 6), [(1, 7)], units="raw")
    assert raw.target == (1, 9)
    assert raw.value == pytest.approx(0.3237454, abs=1e-6)
    assert raw.value == float(np.float32(raw.value))  # float32 on the wire
    # Cells (default): lambda in units of r_c = 16 cells: g(1,9) = -1 + 1.5 * 16 * 0.8824969.
    cells = _bid(_corridor(), (1, 6), [(1, 7)])
    assert cells.target == (1, 9) and cells.value == pytest.approx(20.179926, abs=1e-5)
    # Unit-free: I over the 13 cells of the r_s = 2 disk, D over r_c.
    free = _bid(_corridor(), (1, 6), [(1, 7)], units="unit-free")
    expected = 2 / 13 - 3 / 16 + 1.5 * 0.8824969
    assert free.target == (1, 9) and free.value == pytest.approx(expected, abs=1e-6)
    assert (free.information, free.distance, free.nearness) == (2.0, 3.0, cells.nearness)
    # Without nearness (w3 = 0) the two cells tie again at -1.
    assert _bid(_corridor(), (1, 6), [(1, 7)], w3=0.0).target == (1, 3)


def test_other_robots_sensor_disk_lowers_the_gain() -> None:
    # Another robot senses at (1, 4): its disk (cols 2-6) covers the unknown (1, 2), so
    # I(1,3) = 1 and I(1,9) = 2. With w3 = 0: g(1,3) = 1 - 3 = -2, g(1,9) = 2 - 3 = -1.
    bid = _bid(_corridor(), (1, 6), [(1, 4)], w3=0.0)
    assert (bid.target, bid.value, bid.information) == ((1, 9), -1.0, 2.0)


def test_no_reachable_frontier_gives_no_bid() -> None:
    belief = np.full((3, 5), OCCUPIED, dtype=np.int8)
    belief[1, 1:4] = FREE
    assert (
        compute_bid(
            belief,
            (1, 2),
            [],
            [],
            sensor_range=2.0,
            comm_range=16.0,
            alpha=0.5,
            w1=1.0,
            w2=1.0,
            w3=1.5,
        )
        is None
    )


# ----------------------------------------------------------------------------- timing
def test_session_timing_follows_the_latency() -> None:
    # Unlimited range, latency 1: every robot one hop away, t_d = 1, T_grace = 2,
    # t_bid = max(1, T_grace) = 2, T_win = 2 - 2 = 0, timeout = 2 + 2 * 1 = 4.
    timing = session_timing(1, 1)
    assert (timing.max_delay, timing.grace, timing.bid, timing.send_map_window) == (1, 2, 2, 0)
    assert timing.declare_timeout == 4
    # The earlier reading, t_bid = max(bid_time, t_d) = 1: T_win = -1, timeout 3.
    earlier = session_timing(1, 1, floor="delay")
    assert (earlier.bid, earlier.send_map_window, earlier.declare_timeout) == (1, -1, 3)
    # A chain of four robots, latency 2: diameter 3 hops, t_d = 6, T_grace = 7,
    # t_bid = max(10, 6) = 10, T_win = 3, timeout = 10 + 12 = 22.
    diameter = hop_diameter([0, 1, 2, 3], [(0, 1), (1, 2), (2, 3)])
    timing = session_timing(2 * diameter, 10)
    assert (timing.max_delay, timing.grace, timing.bid, timing.send_map_window) == (6, 7, 10, 3)
    assert timing.declare_timeout == 22
    assert session_timing(1, 1, declare_timeout=7).declare_timeout == 7


# ----------------------------------------------------------------------------- protocol
def _open_belief() -> np.ndarray:
    """A 9 x 9 room, walls around, known free in rows 1-4, unknown below."""
    belief = np.full((9, 9), UNKNOWN, dtype=np.int8)
    belief[0, :] = belief[:, 0] = belief[:, 8] = belief[8, :] = OCCUPIED
    belief[1:5, 1:8] = FREE
    return belief


def _view(
    robot: int,
    tick: int,
    *,
    inbox: tuple[Message, ...] = (),
    team: frozenset[int] = frozenset({0, 1}),
    position: tuple[int, int] = (2, 4),
    goal: tuple[int, int] | None = None,
    new_cells: int = 0,
) -> RobotView:
    members = sorted(team)
    belief = _open_belief()
    belief.flags.writeable = False
    return RobotView(
        robot_id=robot,
        n_robots=2,
        tick=tick,
        position=position,
        belief=belief,
        goal=goal,
        path_remaining=0,
        arrived=False,
        blocked=False,
        inbox=inbox,
        subnetwork=team,
        sensor_range=2.0,
        speed=1.0,
        rng=np.random.default_rng(0),
        new_cells=new_cells,
        links=frozenset((a, b) for i, a in enumerate(members) for b in members[i + 1 :]),
        comm_latency=1,
    )


def _bid_from(robot: int, value: float, target: tuple[int, int] = (4, 7)) -> Message:
    return Message(BID, robot, 0xFFFF, HEADER_BYTES + BID_BYTES, BidItem(robot, target, value))


def _types(decision: Any) -> list[str]:
    return [m.type for m in decision.messages]


def test_messages_have_the_byte_model_sizes() -> None:
    robot = ShengBidding(0, 2)
    decision = robot.decide(_view(0, 1))
    assert _types(decision) == [POSITION, BID]
    sizes = {m.type: m.size_bytes for m in decision.messages}
    assert sizes == {POSITION: HEADER_BYTES + POSITION_BYTES, BID: HEADER_BYTES + BID_BYTES}
    assert all(m.dest == 0xFFFF and m.sender == 0 for m in decision.messages)
    assert robot.decide(_view(0, 2)).messages == []  # t_bid = T_grace = 2 ticks
    win = robot.decide(_view(0, 3))
    assert _types(win) == [WINNER]
    assert win.messages[0].size_bytes == HEADER_BYTES + TARGET_BYTES


def test_a_lone_robot_wins_its_own_session_after_t_bid() -> None:
    robot = ShengBidding(0, 1)
    first = robot.decide(_view(0, 1, team=frozenset({0})))
    assert first.goal is None and robot.state == BIDDING
    # t_d = 0 for a lone robot, t_bid = max(1, 0) = 1: it wins at the next tick.
    second = robot.decide(_view(0, 2, team=frozenset({0})))
    assert second.goal is not None and robot.state == TRAVELLING
    assert second.path is not None and tuple(second.path[-1]) == second.goal
    payload = second.messages[0].payload
    assert isinstance(payload, CellItem) and payload.cell == second.goal


def test_a_better_bid_makes_the_robot_wait_and_a_silent_winner_times_out() -> None:
    robot = ShengBidding(0, 2)
    robot.decide(_view(0, 1))
    # Tick 2: robot 1's bid (1000) beats any bid robot 0 can make in this room.
    waiting = robot.decide(_view(0, 2, inbox=(_bid_from(1, 1000.0),)))
    assert waiting.goal is None and robot.state == BIDDING
    # Robot 1 never declares. Expiry is tick 1 + t_bid = 3; the timeout is t_bid + 2 t_d
    # = 4 ticks: robot 0 waits through ticks 3-6 and bids again at tick 7 ...
    for tick in (3, 4, 5, 6):
        assert robot.decide(_view(0, tick)).messages == []
    rebid = robot.decide(_view(0, 7))
    assert _types(rebid) == [BID]
    # ... and, with nobody better left, wins when its session ends at tick 9.
    assert robot.decide(_view(0, 8)).goal is None
    assert robot.decide(_view(0, 9)).goal is not None


def test_a_declaration_ends_the_session_and_the_loser_bids_again() -> None:
    robot = ShengBidding(0, 2)
    first = robot.decide(_view(0, 1))
    first_target = first.messages[1].payload.cell
    robot.decide(_view(0, 2, inbox=(_bid_from(1, 1000.0),)))
    # Robot 1 declares itself the winner, with robot 0's former target as its own.
    declaration = Message(WINNER, 1, 0xFFFF, HEADER_BYTES + TARGET_BYTES, CellItem(1, first_target))
    again = robot.decide(_view(0, 3, inbox=(declaration,)))
    assert _types(again) == [BID]
    assert robot.targets == {1: first_target}
    assert again.messages[0].payload.cell != first_target


def test_ties_go_to_the_lower_id() -> None:
    low, high = ShengBidding(0, 2), ShengBidding(1, 2)
    bid_low = low.decide(_view(0, 1)).messages[1]
    bid_high = high.decide(_view(1, 1)).messages[1]
    assert bid_low.payload.value == bid_high.payload.value  # same map, same cell
    low.decide(_view(0, 2, inbox=(bid_high,)))
    high.decide(_view(1, 2, inbox=(bid_low,)))
    assert low.decide(_view(0, 3)).goal is not None  # t_bid = 2 ticks
    assert high.decide(_view(1, 3)).goal is None


def test_a_robot_finishing_sensing_in_a_closing_session_waits_for_the_next() -> None:
    robot = ShengBidding(0, 2)
    # Robot 1's bid arrives at tick 4 (sent at tick 3 over one hop). Robot 0 finishes
    # sensing at tick 4: 4 - 3 = 1 > T_win = 0, so it stays out and waits.
    position = Message(POSITION, 1, 0xFFFF, 13, CellItem(1, (3, 3)))
    waiting = robot.decide(_view(0, 4, inbox=(position, _bid_from(1, 5.0))))
    assert robot.state == WAITING
    assert _types(waiting) == [POSITION]
    assert robot.positions == {1: (3, 3)}
    declaration = Message(WINNER, 1, 0xFFFF, 13, CellItem(1, (4, 7)))
    joined = robot.decide(_view(0, 6, inbox=(declaration,)))
    assert robot.state == BIDDING and _types(joined) == [BID]


def test_a_waiting_robot_never_waits_forever() -> None:
    robot = ShengBidding(0, 2)
    robot.decide(_view(0, 4, inbox=(_bid_from(1, 5.0),)))
    assert robot.state == WAITING
    for tick in range(5, 12):
        if robot.decide(_view(0, tick)).messages:
            break
    assert robot.state == BIDDING  # deadline: 4 + t_bid + timeout = 4 + 2 + 4 = 10


def test_a_bidder_that_left_the_sub_network_is_forgotten() -> None:
    robot = ShengBidding(0, 2)
    robot.decide(_view(0, 1))
    robot.decide(_view(0, 2, inbox=(_bid_from(1, 1000.0),)))
    # Robot 1 drives out of range: robot 0 is alone and wins at once.
    assert robot.decide(_view(0, 3, team=frozenset({0}))).goal is not None


def test_a_robot_joining_the_sub_network_hears_the_travelling_robots_target() -> None:
    robot = ShengBidding(0, 2)
    robot.decide(_view(0, 1, team=frozenset({0})))
    win = robot.decide(_view(0, 2, team=frozenset({0})))
    assert win.goal is not None
    moving = robot.decide(_view(0, 3, team=frozenset({0, 1}), goal=win.goal))
    assert _types(moving) == ["target"]
    assert moving.messages[0].payload == CellItem(0, win.goal)


def test_bad_parameters_are_input_errors() -> None:
    with pytest.raises(ScenarioError, match="alpha"):
        ShengBidding(0, 1, alpha=1.5)
    with pytest.raises(ScenarioError, match="bid_time"):
        ShengBidding(0, 1, bid_time=0)
    with pytest.raises(ScenarioError, match="comm_range"):
        ShengBidding(0, 1, comm_range=-1.0)


# ----------------------------------------------------------------------------- runs
def test_r_c_is_the_runs_range_or_the_papers_16_when_unlimited() -> None:
    import dataclasses

    view = _view(0, 0)
    assert math.isinf(view.comm_range)
    assert ShengBidding(0, 2)._r_c(view) == 16.0
    assert ShengBidding(0, 2)._r_c(dataclasses.replace(view, comm_range=25.0)) == 25.0
    assert ShengBidding(0, 2, comm_range=9)._r_c(dataclasses.replace(view, comm_range=25.0)) == 9.0


def test_passes_the_strategy_checker() -> None:
    check_strategy("sheng-bidding")


@pytest.mark.parametrize(
    "scenario",
    [
        {"map": "sheng40", "robots": 3},
        {"map": "office", "size": (60, 60), "robots": 3},
        # The paper's setting: r_s = 4, r_c = 16, sensing on arrival.
        {
            "map": "sheng40",
            "robots": 4,
            "sensor_range": 4,
            "comm_range": 16,
            "sensing": "arrival",
        },
        # Limited range: a quarter of the map's width.
        {
            "map": "office",
            "size": (60, 60),
            "robots": 3,
            "comm_range": 15,
        },
        # Lost and late messages: timeouts keep every robot going.
        {
            "map": "sheng40",
            "robots": 5,
            "comm_range": 10,
            "latency": 2,
            "loss": 0.3,
        },
    ],
    ids=["sheng40-3", "office60-3", "paper-setting", "office60-3-range15", "lossy-slow"],
)
def test_quick_runs_complete(scenario: dict[str, Any]) -> None:
    record = simulate(Scenario(strategy="sheng-bidding", seed=1, **scenario))
    assert record.status == "complete"
    result = record.result()
    # Every broadcast costs its size once per hop (byte model).
    sizes = {
        BID: HEADER_BYTES + BID_BYTES,
        WINNER: HEADER_BYTES + TARGET_BYTES,
        POSITION: HEADER_BYTES + POSITION_BYTES,
    }
    for kind, size in sizes.items():
        assert result["bytes_by_type"][kind] == size * result["hops_by_type"][kind]


def test_w3_zero_and_random_frontier_are_the_papers_other_cases() -> None:
    base: dict[str, Any] = {
        "map": "sheng40",
        "robots": 3,
        "seed": 2,
        "sensor_range": 4,
        "comm_range": 16,
        "sensing": "arrival",
    }
    without = simulate(Scenario(strategy="sheng-bidding", params={"w3": 0.0}, **base))
    random = simulate(Scenario(strategy="random-frontier", **base))
    assert without.status == random.status == "complete"
    assert without.result()["params"]["w3"] == 0.0


def test_a_bidder_announcing_itself_to_new_members_keeps_its_bid() -> None:
    """§3.3: a robot that heard a better bid "will wait for the winner to declare its
    ID". When the better bidder's sub-network grows mid-session and it announces its
    position to the newcomers, its bid stays live: the worse bidder must not win too."""
    params = {"bid_time": 4}
    low, high = ShengBidding(0, 3, **params), ShengBidding(1, 3, **params)
    pair, trio = frozenset({0, 1}), frozenset({0, 1, 2})
    sent_low = low.decide(_view(0, 1, position=(1, 4), team=pair)).messages
    sent_high = high.decide(_view(1, 1, position=(4, 4), team=pair)).messages
    assert sent_high[1].payload.value > sent_low[1].payload.value
    # Tick 2: each hears the other; robot 1 re-bids for the new bidder, robot 0 waits.
    rebid = low.decide(_view(0, 2, position=(1, 4), inbox=tuple(sent_high), team=pair))
    assert rebid.goal is None
    second = high.decide(_view(1, 2, position=(4, 4), inbox=tuple(sent_low), team=pair))
    # Tick 3: robot 2 joins robot 1's sub-network; robot 1 announces itself to it.
    announced = high.decide(_view(1, 3, position=(4, 4), inbox=tuple(rebid.messages), team=trio))
    assert POSITION in _types(announced) and high.state == BIDDING
    # From tick 3 robot 0 hears it; the session is still robot 1's until it declares.
    inboxes = {3: second.messages, 4: announced.messages, 5: [], 6: []}
    decisions = [
        low.decide(_view(0, t, position=(1, 4), inbox=tuple(m), team=trio))
        for t, m in inboxes.items()
    ]
    assert all(d.goal is None for d in decisions)
    assert WINNER not in [t for d in decisions for t in _types(d)]


def test_new_map_cells_inside_the_send_map_window_make_the_robot_bid_again() -> None:
    """§3.3: "If during that bidding time, one or several other robots finish sensing and
    mapping and send in the new map updates, this bidding robot recalculates its bid ...
    and broadcasts the bid again" (inside T_win; the paper's t_bid is long against t_d)."""
    robot = ShengBidding(0, 2, bid_time=3)  # t_d = 1: t_bid 3, T_grace 2, T_win 1
    robot.decide(_view(0, 1))
    assert robot.timing.send_map_window == 1
    assert _types(robot.decide(_view(0, 2, new_cells=5))) == [BID]  # 2 - 1 <= T_win
    assert robot.decide(_view(0, 3, new_cells=9)).messages == []  # 3 - 1 > T_win: too late


def test_a_robot_finishing_sensing_early_in_a_session_joins_it() -> None:
    """§3.4: a robot that finishes sensing no later than T_win after the best session
    began takes part in it (it sends its updates and bids) instead of waiting."""
    robot = ShengBidding(0, 2, bid_time=3)
    position = Message(POSITION, 1, 0xFFFF, 13, CellItem(1, (3, 3)))
    # Robot 1's bid, sent at tick 1, arrives at tick 2: the session began at tick 1.
    joined = robot.decide(_view(0, 2, inbox=(position, _bid_from(1, 1000.0))))
    assert robot.state == BIDDING and _types(joined) == [POSITION, BID]
    # Robot 1's bid is better: robot 0 waits for it to declare.
    assert all(robot.decide(_view(0, t)).goal is None for t in (3, 4, 5))


def test_eq_1_can_measure_to_robots_outside_the_sub_network() -> None:
    """``nearness_over=known``: eq. (1) measures to every robot last heard of (Fig. 2's
    robot 6, far from the others), while I_i still excludes only the sub-network's."""
    apart = _bid(_corridor(), (1, 6), [], nearness_cells=[(1, 7)])
    assert apart.target == (1, 9) and apart.nearness == pytest.approx(math.exp(-2 / 16))
    assert _bid(_corridor(), (1, 6), []).target == (1, 3)  # nobody known: the tie again
    bids = {}
    for over in ("subnetwork", "known"):
        robot = ShengBidding(0, 3, nearness_over=over)
        robot.positions = {1: (1, 7), 2: (3, 3)}  # robot 2 was heard of; it is not in range
        result = robot._evaluate(_view(0, 1, team=frozenset({0, 1})))
        assert result is not None
        bids[over] = result[0]
    assert bids["known"].nearness > bids["subnetwork"].nearness > 0
