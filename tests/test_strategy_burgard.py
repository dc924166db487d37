"""burgard: the whole team assigned at once, and discounting over the visibility area."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mrexplore.comm.messages import ASSIGN, BID, STATUS, Message, StatusItem
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies.base import RobotView
from mrexplore.strategies.burgard import BID_CALL, Burgard, bids_size, discount


def _room(robot_id: int, tick: int, inbox: tuple[Message, ...] = (), **view: object) -> RobotView:
    """A 9 x 30 room known free in columns 5-24; frontiers at both ends."""
    belief = np.full((9, 30), UNKNOWN, dtype=np.int8)
    belief[1:8, 5:25] = FREE
    belief[0, :] = belief[8, :] = OCCUPIED
    belief.flags.writeable = False
    fields: dict[str, object] = {
        "position": (4, 14),
        "goal": None,
        "path_remaining": 0,
        "arrived": False,
        "blocked": False,
        "subnetwork": frozenset({0, 1, 2}),
        **view,
    }
    return RobotView(
        robot_id=robot_id,
        n_robots=3,
        tick=tick,
        belief=belief,
        inbox=inbox,
        sensor_range=4.0,
        speed=1.0,
        rng=np.random.default_rng(0),
        new_cells=0,
        **fields,  # type: ignore[arg-type]
    )


def _status(robot: int, position: tuple[int, int], needs_goal: bool) -> Message:
    return Message(STATUS, robot, 0, 15, StatusItem(robot, position, needs_goal))


def test_the_coordinator_assigns_every_waiting_robot_in_one_call() -> None:
    """Meier §5.1: "Only a centralized coordination technique has the ability to choose
    that robot-target tuple that provides the (globally) highest expected utility":
    one call assigns the coordinator and both robots that asked."""
    coordinator = Burgard(0, 3)
    inbox = (_status(1, (2, 6), True), _status(2, (6, 23), True))
    decision = coordinator.decide(_room(0, 5, inbox))
    assigned = {m.payload.robot: m.payload.cell for m in decision.messages if m.type == ASSIGN}
    assert set(assigned) == {1, 2}
    assert decision.goal is not None
    # Each robot goes to the end it is near: 1 to the left, 2 to the right.
    assert assigned[1][1] < 14 < assigned[2][1]


def test_whole_team_assignment_moves_a_robot_on_its_way_and_the_old_rule_does_not() -> None:
    """With ``assign=team`` a robot that holds a goal is assigned again when another robot
    asks; ``requesting`` leaves its goal fixed."""
    for rule, expected in (("team", {1, 2}), ("requesting", {2})):
        coordinator = Burgard(0, 3, assign=rule)
        # Round 1: robot 1 asks from the right end and gets the right frontier.
        first = coordinator.decide(_room(0, 1, (_status(1, (4, 23), True),), goal=(4, 4)))
        goal_1 = next(m.payload.cell for m in first.messages if m.type == ASSIGN)
        assert goal_1[1] > 14
        # Robot 1 has walked to the left end (its report says so); robot 2 asks from the
        # right end: the best tuple now sends robot 2 right and robot 1 left.
        inbox = (_status(1, (4, 6), False), _status(2, (4, 23), True))
        second = coordinator.decide(_room(0, 2, inbox, goal=(4, 4)))
        assigned = {m.payload.robot: m.payload.cell for m in second.messages if m.type == ASSIGN}
        assert set(assigned) == expected, rule


def test_members_report_their_position_every_status_period_with_whole_team_assignment() -> None:
    member = Burgard(1, 3, status_period=3)
    walking = {"goal": (4, 5), "path_remaining": 6}  # a frontier cell
    reports = [
        t
        for t in range(1, 10)
        if any(m.type == STATUS for m in member.decide(_room(1, t, **walking)).messages)
    ]
    assert reports == [1, 4, 7]
    quiet = Burgard(1, 3, assign="requesting")
    assert not any(quiet.decide(_room(1, t, **walking)).messages for t in range(1, 10))


def test_the_discount_stops_at_a_wall_between_the_goal_and_a_target() -> None:
    """Algorithm 1 step 5: "Reduce the utility of each target point t' in the visibility
    area": a target behind a wall keeps its utility; one in view at the same distance
    is reduced by P(d)."""
    occupied = np.zeros((11, 11), dtype=bool)
    occupied[2:9, 7] = True  # a wall east of the goal
    rows, cols = np.array([5, 5]), np.array([2, 8])  # 3 cells west (in view), 3 east (behind)
    plain, visible = np.ones(2), np.ones(2)
    discount(plain, rows, cols, (5, 5), 6.0)
    discount(visible, rows, cols, (5, 5), 6.0, occupied)
    assert np.allclose(plain, [0.5, 0.5])  # P(3) = 1 - 3 / 6
    assert np.allclose(visible, [0.5, 1.0])


def test_unknown_cells_do_not_block_the_visibility_discount() -> None:
    occupied = np.zeros((11, 11), dtype=bool)  # unknown or free: sight passes
    utility = np.ones(1)
    discount(utility, np.array([5]), np.array([8]), (5, 5), 6.0, occupied)
    assert np.allclose(utility, [0.5])


def test_burgard_completes_with_either_assignment_rule() -> None:
    for rule in ("team", "requesting"):
        record = simulate(
            Scenario(
                map="office",
                size=(40, 40),
                map_seed=1,
                robots=3,
                seed=1,
                strategy="burgard",
                params={"assign": rule},
                max_ticks=3000,
            )
        )
        assert record.status == "complete", rule


def test_bids_protocol_calls_the_team_and_assigns_from_the_costs_the_robots_sent() -> None:
    """``protocol=bids`` (the market paper's [3]: "every robot constructs its bids and
    sends them to a central executive"): a request opens a round, the coordinator calls
    for bids, each member answers with its cost to every frontier cell it can reach, and
    the assignment reads those costs, not the coordinator's own map."""
    coordinator = Burgard(0, 3, protocol="bids")
    member_1, member_2 = Burgard(1, 3, protocol="bids"), Burgard(2, 3, protocol="bids")
    # Robot 1 needs a goal: its request is its bids.
    request = member_1.decide(_room(1, 0, position=(2, 6)))
    (bids_1,) = request.messages
    assert bids_1.type == BID and bids_1.payload.needs_goal
    frontier_cells = int(bids_1.payload.rows.size)
    assert frontier_cells > 0 and bids_1.size_bytes == bids_size(frontier_cells)
    # The coordinator opens the round with a call and waits for the team.
    call = coordinator.decide(_room(0, 1, (bids_1,), goal=(4, 4)))
    assert [m.type for m in call.messages] == [BID_CALL] and call.goal is None
    # Robot 2, on its way, answers the call with its bids; nobody is assigned before.
    walking = {"goal": (4, 24), "path_remaining": 1, "position": (6, 23)}
    answer = member_2.decide(_room(2, 2, (call.messages[0],), **walking))
    (bids_2,) = answer.messages
    assert bids_2.type == BID and not bids_2.payload.needs_goal
    # Robot 2 claims the left end is close for it (it is not: the coordinator's map
    # says 17 cells): the coordinator believes its bid and sends robot 2 left.
    lying = bids_2.payload.costs.copy()
    lying[bids_2.payload.cols < 10] = 0.5
    fake = Message(BID, 2, 0, bids_2.size_bytes, replace(bids_2.payload, costs=lying))
    decided = coordinator.decide(_room(0, 3, (fake,), goal=(4, 4)))
    assigned = {m.payload.robot: m.payload.cell for m in decided.messages if m.type == ASSIGN}
    assert assigned[2][1] < 10
    assert 1 in assigned


def test_bids_protocol_with_a_team_in_a_run_sends_bids_and_no_status() -> None:
    settings = dict(map="office", size=(40, 40), robots=3, seed=1, max_ticks=400)
    bids = simulate(Scenario(**settings, strategy="burgard", params={"protocol": "bids"}))
    positions = simulate(Scenario(**settings, strategy="burgard"))
    assert bids.bytes_by_type.get("bid", 0) > 0 and bids.bytes_by_type.get("bid_call", 0) > 0
    assert "status" not in bids.bytes_by_type
    assert positions.bytes_by_type.get("status", 0) > 0 and "bid" not in positions.bytes_by_type
    assert bids.known_explorable[-1] > 0.5 * bids.world.n_explorable
