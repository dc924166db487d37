"""meier-polygon: Algorithm 1 of Meier et al. over polygon maps."""

from __future__ import annotations

import numpy as np
import pytest

from mrexplore.checks import check_trace
from mrexplore.comm.bytes import HEADER_BYTES, POLYGON_POINT_BYTES
from mrexplore.grid.occupancy import FREE, UNKNOWN
from mrexplore.planning import distance_field, frontier_mask
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies.base import RobotView
from mrexplore.strategies.meier_polygon import TPT, MeierPolygon


def corridor_view(robot_id: int, position: tuple[int, int]) -> RobotView:
    belief = np.full((5, 40), UNKNOWN, dtype=np.int8)
    belief[1:4, 3:37] = FREE
    belief[0, :] = belief[4, :] = 100
    return RobotView(
        robot_id=robot_id,
        n_robots=2,
        tick=1,
        position=position,
        belief=belief,
        goal=None,
        path_remaining=0,
        arrived=False,
        blocked=False,
        inbox=(),
        subnetwork=frozenset({0, 1}),
        sensor_range=8.0,
        speed=1.0,
        rng=np.random.default_rng(0),
        new_cells=0,
    )


def test_algorithm_1_discounts_around_a_received_target_of_higher_priority() -> None:
    # Robot 1 stands nearer the left end; robot 0 announced the left end (column 3).
    view = corridor_view(1, (2, 12))
    strategy = MeierPolygon(1, 2)
    frontier = frontier_mask(view.belief)
    dist = distance_field(view.belief == FREE, view.position)
    assert strategy.choose_goal(view, frontier, dist)[1] == 3  # alone: the near end
    strategy.received_targets[0] = (2, 3)
    # U = 1 - P(d) is ~0 near (2, 3); the far end keeps U = 1 and wins: 1 - 1 > 0 - 0.39.
    assert strategy.choose_goal(view, frontier, dist)[1] == 36
    # Robot 0 has the highest priority: a target from robot 1 does not move it.
    zero = MeierPolygon(0, 2)
    zero.received_targets[1] = (2, 3)
    assert zero.choose_goal(corridor_view(0, (2, 12)), frontier, dist)[1] == 3


def test_the_target_is_broadcast_as_a_tpt_package() -> None:
    decision = MeierPolygon(0, 2).decide(corridor_view(0, (2, 12)))
    assert decision.goal is not None
    (message,) = decision.messages
    assert message.type == TPT
    assert message.size_bytes == HEADER_BYTES + POLYGON_POINT_BYTES


@pytest.mark.parametrize("comm_range", [float("inf"), 15.0])
def test_completes_over_polygon_maps(comm_range: float) -> None:
    record = simulate(
        Scenario(
            map="office",
            size=(60, 60),
            robots=3,
            strategy="meier-polygon",
            seed=1,
            comm_range=comm_range,
        )
    )
    result = record.result()
    assert result["sharing"] == "polygon"
    assert record.status == "complete"
    assert result["bytes_by_type"].get(TPT, 0) > 0
    assert "polygon_approximation_error" in result
    assert check_trace(record.trace_arrays(), result) == []
