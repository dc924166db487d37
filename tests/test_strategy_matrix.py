"""The strategy matrix: every registered strategy with 1, 3 and 8 robots on six maps.

Each case is one run with seed 1 that must end ``complete`` with a valid trace:
``sheng40``, 100 x 100 ``office``, ``cityblock`` and ``unstructured``, the MovingAI
``room-64-64-8`` and the Intel lab (0.2 m cells, 3 m sensor), under unlimited
communication; the strategies designed for limited communication also with a range
of a quarter of the map's width. The whole matrix takes about an hour on two cores,
so it is marked slow (``make test-slow`` or ``pytest -m slow -k matrix``); the
default run keeps one small case per strategy.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

from mrexplore.checks import check_trace
from mrexplore.sim import Scenario, simulate
from mrexplore.sim.world import load_scenario_map
from mrexplore.strategies.registry import available_strategies

BUILT_IN = sorted(
    name
    for name, cls in available_strategies().items()
    if cls.__module__.startswith("mrexplore.strategies.")
)

MAPS: dict[str, dict[str, Any]] = {
    "sheng40": {"map": "sheng40"},
    "office": {"map": "office", "size": (100, 100)},
    "cityblock": {"map": "cityblock", "size": (100, 100)},
    "unstructured": {"map": "unstructured", "size": (100, 100)},
    "room-64-64-8": {"map": "room-64-64-8"},
    "intel": {
        "map": "intel",
        "cell_size": 0.2,
        "sensor_range": "3m",
    },
}
LIMITED_COMM = {"sheng-bidding", "vazquez-network", "meier-polygon", "market-occupancy", "kme"}
"""Strategies also run at a quarter-width range (kme is not designed for it, but copes)."""
VARIANTS: dict[str, list[dict[str, Any]]] = {
    "market-occupancy": [{}, {"frontier_detector": "rrt"}],
}


def _cases() -> list[Any]:
    cases = []
    for strategy in BUILT_IN:
        for params in VARIANTS.get(strategy, [{}]):
            variant = "".join(f"-{value}" for value in params.values())
            for map_name in MAPS:
                for robots in (1, 3, 8):
                    comms = ["unlimited", "quarter"] if strategy in LIMITED_COMM else ["unlimited"]
                    for comm in comms:
                        cases.append(
                            pytest.param(
                                strategy,
                                params,
                                map_name,
                                robots,
                                comm,
                                id=f"{strategy}{variant}-{map_name}-{robots}-{comm}",
                            )
                        )
    return cases


def _run(strategy: str, params: dict[str, Any], map_name: str, robots: int, comm: str) -> None:
    settings = MAPS[map_name]
    comm_range = math.inf
    if comm == "quarter":
        probe = Scenario(strategy=strategy, **settings)
        comm_range = load_scenario_map(probe).shape[1] / 4
    scenario = Scenario(
        strategy=strategy, robots=robots, seed=1, comm_range=comm_range, params=params, **settings
    )
    record = simulate(scenario)
    assert record.status == "complete", (
        f"{record.status} at tick {record.ticks}: "
        f"{100 * record.known_explorable[-1] / record.world.n_explorable:.1f} % known"
    )
    problems = check_trace(record.trace_arrays(), record.result())
    assert not problems, problems[:3]


@pytest.mark.slow
@pytest.mark.parametrize(("strategy", "params", "map_name", "robots", "comm"), _cases())
def test_matrix_run_completes(
    strategy: str, params: dict[str, Any], map_name: str, robots: int, comm: str
) -> None:
    _run(strategy, params, map_name, robots, comm)


@pytest.mark.parametrize("strategy", BUILT_IN)
def test_small_case_completes(strategy: str) -> None:
    """The default run's share of the matrix: 3 robots on sheng40, limited range where
    the strategy is meant for it."""
    comm = "quarter" if strategy in LIMITED_COMM else "unlimited"
    _run(strategy, {}, "sheng40", 3, comm)
