"""The public strategy checker, run over every registered strategy."""

from __future__ import annotations

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


def test_burgard_spreads_robots_more_than_nearest_frontier() -> None:
    """Discounting keeps robots from chasing the same frontier: fewer cells sensed twice."""

    def overlap(strategy: str) -> float:
        values = [
            simulate(
                Scenario(map="office", size=(80, 60), robots=4, strategy=strategy, seed=s)
            ).result()["overlap"]
            for s in range(3)
        ]
        return sum(values) / len(values)

    assert overlap("burgard") < overlap("nearest-frontier")


def test_replan_every_parameter_changes_behaviour() -> None:
    base = simulate(Scenario(map="office", size=(60, 40), robots=2, seed=1))
    every = simulate(
        Scenario(map="office", size=(60, 40), robots=2, seed=1, params={"replan_every": 1})
    )
    assert every.plans > base.plans
