"""The public strategy checker, run over every registered strategy."""

from __future__ import annotations

import numpy as np
import pytest

from mrexplore.checks import check_strategy
from mrexplore.errors import ScenarioError, UnknownIdError
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies import available_strategies, get_strategy
from mrexplore.strategies.burgard import coverage_probability


@pytest.mark.parametrize("name", sorted(available_strategies()))
def test_registered_strategy_passes_the_checker(name: str) -> None:
    check_strategy(name)


def test_unknown_strategy_is_an_input_error() -> None:
    with pytest.raises(UnknownIdError, match="unknown strategy 'nope'"):
        get_strategy("nope")


def test_bad_parameter_value_is_an_input_error() -> None:
    with pytest.raises(ScenarioError, match="beta"):
        simulate(Scenario(map="sheng40", robots=2, strategy="burgard", params={"beta": "abc"}))


def test_coverage_probability_is_meier_eq_1() -> None:
    import numpy as np

    d = np.array([0.0, 2.0, 4.0, 6.0])
    assert coverage_probability(d, 4.0).tolist() == [1.0, 0.5, 0.0, 0.0]


def test_burgard_discounting_sends_two_robots_to_opposite_frontiers() -> None:
    """Two robots side by side in a known corridor with unknown space at both ends:
    nearest-frontier sends both left; Burgard's discounting sends the second right."""
    from mrexplore.grid.occupancy import FREE, UNKNOWN
    from mrexplore.planning import frontier_mask
    from mrexplore.strategies.burgard import assign_greedy

    belief = np.full((5, 40), UNKNOWN, dtype=np.int8)
    belief[1:4, 3:37] = FREE
    belief[0, :] = belief[4, :] = 100
    positions = {0: (2, 12), 1: (2, 13)}
    frontier = frontier_mask(belief)
    goals = assign_greedy(
        [0, 1],
        positions,
        {},
        belief == FREE,
        frontier,
        beta=1.0,
        max_range=8.0,
        normalize_cost=True,
    )
    columns = sorted(goal[1] for goal in goals.values())
    assert columns == [3, 36]


def test_replan_every_parameter_changes_behaviour() -> None:
    base = simulate(Scenario(map="office", size=(60, 40), robots=2, seed=1))
    every = simulate(
        Scenario(map="office", size=(60, 40), robots=2, seed=1, params={"replan_every": 1})
    )
    assert every.plans > base.plans


def test_entry_point_plugins_are_loaded_and_checked(monkeypatch: pytest.MonkeyPatch) -> None:
    """A third-party strategy named in the entry-point group is found and passes the checker."""
    from importlib.metadata import EntryPoint

    from mrexplore.strategies import registry
    from mrexplore.strategies.frontier_baselines import NearestFrontier

    class FarthestFrontier(NearestFrontier):
        id = "test-farthest-frontier"
        summary = "test plugin: the farthest reachable frontier cell"

        def choose_goal(self, view, frontier, dist):  # type: ignore[no-untyped-def]
            from mrexplore.strategies.base import reachable_frontier_cells

            rows, cols = reachable_frontier_cells(frontier, dist)
            if rows.size == 0:
                return None
            best = int(np.argmax(dist[rows, cols]))
            return int(rows[best]), int(cols[best])

    import sys
    import types

    module = types.ModuleType("fake_plugin")
    module.FarthestFrontier = FarthestFrontier  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "fake_plugin", module)
    entry = EntryPoint(
        name="test-farthest-frontier",
        value="fake_plugin:FarthestFrontier",
        group=registry.ENTRY_POINT_GROUP,
    )
    import mrexplore.registry

    monkeypatch.setattr(
        mrexplore.registry,
        "entry_points",
        lambda group: [entry] if group == registry.ENTRY_POINT_GROUP else [],
    )
    registry.STRATEGIES.forget_plugins()
    try:
        assert get_strategy("test-farthest-frontier") is FarthestFrontier
        check_strategy("test-farthest-frontier")
    finally:
        registry.STRATEGIES.forget_plugins()
