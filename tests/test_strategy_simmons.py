"""Simmons et al. (2000): the bid and overlap formulas on hand-checked cases, the
coordinator's greedy loop, the contract checker, and runs that complete."""

from __future__ import annotations

import numpy as np
import pytest

from mrexplore.checks import check_strategy
from mrexplore.comm.bytes import BID_BYTES, HEADER_BYTES, TARGET_BYTES
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import disk_mask
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies.registry import register
from mrexplore.strategies.simmons import (
    Bid,
    Simmons,
    assign_bids,
    bid_value,
    bids_size,
    overlap,
    select_bids,
)

register(Simmons)


# ---------------------------------------------------------------------- formulas
def test_bid_is_gain_minus_weighted_cost() -> None:
    # B = I - w C: 60 - 4 * 10 = 20; 30 - 4 * 2.5 = 20; 12 - 4 * 0 = 12.
    values = bid_value(np.array([60, 30, 12]), np.array([10.0, 2.5, 0.0]), 4.0)
    assert values.tolist() == [20.0, 20.0, 12.0]


def test_bid_message_size_follows_the_byte_model() -> None:
    # header + one bid item per bid (robot u16, row u16, col u16, value f32).
    assert bids_size(0) == HEADER_BYTES
    assert bids_size(5) == HEADER_BYTES + 5 * BID_BYTES


def test_disk_mask_marks_cells_within_the_radius_clipped_at_the_border() -> None:
    # Radius 1 around (0, 0): (0, 0), (0, 1), (1, 0); (-1, 0) and (0, -1) fall off the grid.
    mask = disk_mask((3, 3), [(0, 0)], 1.0)
    assert mask.astype(int).tolist() == [[1, 1, 0], [1, 0, 0], [0, 0, 0]]


def test_overlap_counts_unknown_cells_in_both_disks() -> None:
    # All unknown; radius 1. Disk of f = (3, 3): (2,3) (3,2) (3,3) (3,4) (4,3).
    # Assigned target (3, 4): (2,4) (3,3) (3,4) (3,5) (4,4). Shared: (3,3) and (3,4) -> 2.
    belief = np.full((7, 7), UNKNOWN, dtype=np.int8)
    assigned = disk_mask((7, 7), [(3, 4)], 1.0)
    assert overlap(belief, np.array([[3, 3]]), 1.0, assigned).tolist() == [2]
    # A known cell is no information: make (3, 4) free and the overlap drops to 1.
    belief[3, 4] = FREE
    assert overlap(belief, np.array([[3, 3]]), 1.0, assigned).tolist() == [1]
    # Nothing assigned: no overlap.
    nothing = np.zeros((7, 7), dtype=bool)
    assert overlap(belief, np.array([[3, 3]]), 1.0, nothing).tolist() == [0]


def test_select_bids_spreads_the_best_candidates() -> None:
    # Values 9, 8, 7, 1 at columns 0, 1, 10, 20; separation 3: column 1 is within 3 of
    # column 0, so the three bids are columns 0, 10 and 20.
    rows = np.zeros(4, dtype=np.int64)
    cols = np.array([0, 1, 10, 20])
    chosen = select_bids(rows, cols, np.array([9.0, 8.0, 7.0, 1.0]), 3, 3.0)
    assert chosen.tolist() == [0, 2, 3]
    assert select_bids(rows, cols, np.array([9.0, 8.0, 7.0, 1.0]), 2, 0.0).tolist() == [0, 1]


def _strip() -> np.ndarray:
    """One row of 20 unknown cells: the disk of radius 2 around (0, c) is columns c-2..c+2."""
    return np.full((1, 20), UNKNOWN, dtype=np.int8)


def test_assignment_takes_the_best_bid_then_reduces_the_others_by_overlap() -> None:
    # Robot 0 bids 10 on A = (0, 5); robot 1 bids 9 on A, 8 on B = (0, 7), 6 on C = (0, 15).
    # Round 1: the best bid is robot 0 on A (10). A's disk covers columns 3..7.
    # Round 2: A is taken; B's disk (columns 5..9) shares columns 5, 6, 7 with A's:
    # 8 - 3 = 5; C shares nothing: 6 - 0 = 6. Robot 1 gets C, not B.
    bids = {
        0: [Bid(0, (0, 5), 10.0)],
        1: [Bid(1, (0, 5), 9.0), Bid(1, (0, 7), 8.0), Bid(1, (0, 15), 6.0)],
    }
    assert assign_bids(bids, _strip(), 2.0) == {0: (0, 5), 1: (0, 15)}


def test_goals_held_by_other_robots_count_as_assigned() -> None:
    # Robot 1 alone re-bids while another robot holds (0, 5): same reduction as above.
    bids = {1: [Bid(1, (0, 7), 8.0), Bid(1, (0, 15), 6.0)]}
    assert assign_bids(bids, _strip(), 2.0, [(0, 5)]) == {1: (0, 15)}
    assert assign_bids(bids, _strip(), 2.0) == {1: (0, 7)}


def test_ties_go_to_the_lowest_robot_id_and_one_cell_serves_one_robot() -> None:
    # Both bid 5 on the only cell: robot 0 gets it, robot 1 is left without a goal.
    bids = {1: [Bid(1, (0, 5), 5.0)], 0: [Bid(0, (0, 5), 5.0)]}
    assert assign_bids(bids, _strip(), 2.0) == {0: (0, 5)}


def test_make_bids_uses_gain_and_path_cost_of_the_robot() -> None:
    from mrexplore.strategies.base import RobotView

    # A known corridor, columns 1..8 of row 2, walls above and below; unknown beyond
    # both ends (column 0 and column 9). Robot at (2, 2), sensor range 1.
    # Frontier cells: (2, 1) (unknown (2, 0)) and (2, 8) (unknown (2, 9)).
    # I((2, 1)) = unknown cells within 1 of it: only (2, 0) -> 1; cost 1.
    # I((2, 8)) = (2, 9) -> 1; cost 6. With w = 0.1: bids 0.9 and 0.4.
    belief = np.full((5, 10), UNKNOWN, dtype=np.int8)
    belief[1, :] = belief[3, :] = OCCUPIED
    belief[2, 1:9] = FREE
    belief.flags.writeable = False
    view = RobotView(
        robot_id=0,
        n_robots=1,
        tick=1,
        position=(2, 2),
        belief=belief,
        goal=None,
        path_remaining=0,
        arrived=False,
        blocked=False,
        inbox=(),
        subnetwork=frozenset({0}),
        sensor_range=1.0,
        speed=1.0,
        rng=np.random.default_rng(0),
        new_cells=0,
    )
    robot = Simmons(0, 1, cost_weight=0.1, bid_separation=1.0)
    bids = robot.make_bids(view)
    assert [(b.cell, round(b.value, 5)) for b in bids] == [((2, 1), 0.9), ((2, 8), 0.4)]


def test_bids_per_robot_must_be_positive() -> None:
    with pytest.raises(ScenarioError, match="bids_per_robot"):
        Simmons(0, 1, bids_per_robot=0)


# ---------------------------------------------------------------------- runs
def test_passes_the_strategy_checker() -> None:
    check_strategy("simmons")


@pytest.mark.parametrize(
    ("map_name", "size"), [("sheng40", None), ("office", (60, 60))], ids=["sheng40", "office60"]
)
def test_three_robots_complete_and_bytes_follow_the_byte_model(
    map_name: str, size: tuple[int, int] | None
) -> None:
    record = simulate(Scenario(map=map_name, size=size, robots=3, strategy="simmons", seed=1))
    assert record.status == "complete"
    hops = record.result()["hops_by_type"]
    # assign: header + target per hop; bid: header + k bid items per hop.
    assert record.bytes_by_type["assign"] == (HEADER_BYTES + TARGET_BYTES) * hops["assign"]
    assert (record.bytes_by_type["bid"] - HEADER_BYTES * hops["bid"]) % BID_BYTES == 0


def test_completes_with_a_quarter_map_comm_range() -> None:
    record = simulate(
        Scenario(map="office", size=(60, 60), robots=3, strategy="simmons", seed=1, comm_range=15)
    )
    assert record.status == "complete"


def test_a_lone_robot_sends_no_messages() -> None:
    record = simulate(Scenario(map="sheng40", robots=1, strategy="simmons", seed=1))
    assert record.status == "complete"
    assert record.bytes_by_type.get("bid", 0) == 0
