"""The tick loop: completion, invariants, determinism, beliefs and bytes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mrexplore.checks import check_trace
from mrexplore.comm.bytes import STATUS_BYTES, TARGET_BYTES, fixed_size
from mrexplore.errors import ScenarioError
from mrexplore.grid.occupancy import UNKNOWN
from mrexplore.metrics import coverage_curve
from mrexplore.sim import RunRecord, Scenario, Simulation, simulate
from mrexplore.strategies.base import Decision

STRATEGIES = ["random-frontier", "nearest-frontier", "burgard"]


@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize("robots", [1, 4])
def test_sheng40_completes_with_a_valid_trace(strategy: str, robots: int) -> None:
    record = simulate(Scenario(map="sheng40", robots=robots, strategy=strategy, seed=2))
    assert record.status == "complete"
    result = record.result()
    assert result["explored_fraction"] >= 0.99
    assert check_trace(record.trace_arrays(), result) == []


@pytest.mark.parametrize(
    "generator", ["blank", "unstructured", "cityblock", "office", "corridor", "maze"]
)
def test_every_generator_completes(generator: str) -> None:
    record = simulate(
        Scenario(map=generator, size=(60, 50), robots=4, strategy="burgard", seed=1, sensor_range=6)
    )
    assert record.status == "complete", generator
    assert check_trace(record.trace_arrays(), record.result()) == []


def test_same_seed_same_trace_and_different_seed_differs() -> None:
    def trace(seed: int) -> dict[str, np.ndarray]:
        scenario = Scenario(
            map="office", size=(60, 40), robots=3, strategy="random-frontier", seed=seed
        )
        return simulate(scenario).trace_arrays()

    first, second, other = trace(5), trace(5), trace(6)
    for name in first:
        assert np.array_equal(first[name], second[name]), name
    # A different seed gives a different map, different starts and different choices.
    assert not np.array_equal(first["truth"], other["truth"])
    assert not np.array_equal(first["positions"][0], other["positions"][0])


def test_beliefs_are_private_without_sharing() -> None:
    simulation = Simulation(
        Scenario(map="office", size=(60, 40), robots=3, sharing="none", seed=4, max_ticks=60)
    )
    simulation.run()
    for robot in simulation.robots:
        known = robot.belief != UNKNOWN
        assert np.array_equal(known, robot.sensed), "a robot knows a cell it never sensed"
    assert simulation.comm.ledger.total == 0


def test_full_sharing_keeps_beliefs_equal_to_the_team_knowledge() -> None:
    simulation = Simulation(Scenario(map="office", size=(60, 40), robots=3, seed=4, max_ticks=40))
    simulation.run()
    team_known = simulation.first_known >= 0
    for robot in simulation.robots:
        # Everything sensed up to the tick before last has been delivered.
        delivered = (simulation.first_known >= 0) & (simulation.first_known < 40)
        known = robot.belief != UNKNOWN
        assert (known <= team_known).all()
        assert known[delivered].all()


def test_byte_totals_agree_across_views() -> None:
    record = simulate(Scenario(map="sheng40", robots=4, strategy="burgard", seed=1))
    total = sum(record.bytes_by_type.values())
    assert total > 0
    assert total == int(record.bytes_per_tick.sum()) == int(record.bytes_by_robot.sum())
    assert set(record.bytes_by_type) == {"map_update", "status", "assign"}
    # Status and assign messages have fixed sizes: the header + a status / a target.
    status, assign = fixed_size(STATUS_BYTES), fixed_size(TARGET_BYTES)
    assert record.bytes_by_type["status"] == status * record.messages_by_type["status"]
    assert record.bytes_by_type["assign"] == assign * record.messages_by_type["assign"]


def test_a_lone_robot_sends_nothing() -> None:
    record = simulate(Scenario(map="sheng40", robots=1, seed=1))
    assert sum(record.bytes_by_type.values()) == 0


def test_coverage_never_decreases_and_matches_known_count() -> None:
    record = simulate(Scenario(map="maze", size=(41, 41), robots=2, seed=3))
    trace = record.trace_arrays()
    curve = coverage_curve(trace["first_known"], trace["explorable"], len(trace["positions"]))
    assert (np.diff(curve) >= 0).all()
    assert np.array_equal(
        np.round(curve * trace["explorable"].sum()).astype(np.int64), trace["known_explorable"]
    )


def test_sensing_on_arrival_only_senses_when_not_travelling() -> None:
    moving = simulate(Scenario(map="sheng40", robots=2, seed=1, sensing="moving"))
    arrival = simulate(Scenario(map="sheng40", robots=2, seed=1, sensing="arrival"))
    assert arrival.status == moving.status == "complete"
    assert int(arrival.sense_count.sum()) < int(moving.sense_count.sum())


def _run_idle(scenario: Scenario) -> RunRecord:
    """Run ``scenario`` with every robot told to stay where it is, every tick."""
    simulation = Simulation(scenario)
    simulation.start()
    while simulation.status is None:
        simulation.step(lambda robot_id, view: Decision(idle=True))
    return simulation.finish()


def test_max_ticks_and_stall_end_a_run() -> None:
    short = simulate(Scenario(map="office", size=(80, 60), robots=1, max_ticks=5))
    assert short.status == "max_ticks" and short.ticks == 5
    base = Scenario(map="office", size=(40, 40), robots=2, seed=1, max_ticks=500)
    # Every robot idle and nothing in flight for idle_ticks ticks: stalled, then.
    idle = _run_idle(dataclasses.replace(base, idle_ticks=10))
    assert (idle.status, idle.ticks) == ("stalled", 10)
    # No new team knowledge for stall_ticks ticks: stalled, then (idling never ends it).
    still = _run_idle(dataclasses.replace(base, idle_ticks=10**6, stall_ticks=7))
    assert (still.status, still.ticks) == ("stalled", 7)
    # Nobody left to explore: stalled at the tick the last robot fails.
    failed = simulate(dataclasses.replace(base, robots=1, fail=[(0, 3)]))
    assert (failed.status, failed.ticks) == ("stalled", 3)
    for record in (idle, still, failed):
        assert record.known_explorable[-1] < 0.99 * record.world.n_explorable


def test_a_robot_that_learns_every_tick_is_not_idle() -> None:
    # Its goal is always the next cell (sensor_range 1), so it has no path after each
    # move; the idle rule once stopped it at tick 10 although it moved and learned.
    record = simulate(Scenario(map="sheng40", robots=1, max_ticks=60, sensor_range=1))
    assert (np.diff(record.known_explorable[:11]) > 0).all()  # new cells at every tick
    assert record.status == "max_ticks"


def test_given_start_cells_are_used_and_checked() -> None:
    record = simulate(Scenario(map="sheng40", robots=2, start=[(5, 5), (5, 8)], seed=1))
    assert record.positions[0].tolist() == [[5, 5], [5, 8]]
    with pytest.raises(ScenarioError, match="inside a wall"):
        simulate(Scenario(map="sheng40", robots=1, start=[(0, 0)]))
    with pytest.raises(ScenarioError, match="more robots than free start cells"):
        simulate(Scenario(map="sheng40", robots=5_000))  # <= MAX_ROBOTS, > its 1600 cells


def test_no_two_robots_ever_share_a_cell_in_a_crowd() -> None:
    record = simulate(
        Scenario(map="corridor", size=(60, 40), robots=8, seed=7, strategy="nearest-frontier")
    )
    assert check_trace(record.trace_arrays()) == []
    assert record.status == "complete"


@pytest.mark.parametrize(
    ("name", "options"),
    [
        ("lse-arena", {"sensor_range": "1m"}),
        ("room-32-32-4", {}),
        ("den312d", {}),
        ("intel", {"cell_size": 0.2, "sensor_range": "3m"}),
    ],
)
def test_real_maps_complete_with_a_valid_trace(name: str, options: dict[str, object]) -> None:
    scenario = Scenario(
        map=name,
        robots=4,
        strategy="burgard",
        seed=1,
        **options,  # type: ignore[arg-type]
    )
    record = simulate(scenario)
    assert record.status == "complete"
    assert check_trace(record.trace_arrays(), record.result()) == []


@pytest.mark.parametrize("sharing", ["broadcast", "full", "none"])
def test_robot_completion_matches_each_robots_own_knowledge(sharing: str) -> None:
    """robot_complete[i] is the last tick at which robot i's own first_known stamps an
    explorable cell, or -1 if it never held them all; T100_first_robot is the first."""
    for complete_when in ("team", "robot"):
        scenario = Scenario(
            map="office",
            size=(40, 40),
            robots=3,
            seed=2,
            sensor_range=4,
            comm_range=12,
            coverage_threshold=1.0,
            sharing=sharing,
            complete_when=complete_when,
            max_ticks=3000,
        )
        record = simulate(scenario)
        trace, result = record.trace_arrays(), record.result()
        assert check_trace(trace, result) == []
        explorable = trace["explorable"]
        for robot in range(3):
            own = trace["robot_first_known"][robot][explorable]
            expected = int(own.max()) if (own >= 0).all() else -1
            assert trace["robot_complete"][robot] == expected
        done = [t for t in result["T100_by_robot"] if t is not None]
        assert result["T100_first_robot"] == (min(done) if done else None)
        if complete_when == "robot" and record.status == "complete":
            assert result["T100_first_robot"] == record.ticks
            assert result["T100"] is not None and result["T100"] <= record.ticks
        if complete_when == "team":
            assert record.status == "complete" and result["T100"] == record.ticks


def test_robot_completion_waits_for_one_robot_to_hold_the_map() -> None:
    """With broadcast sharing and a short range, the team's union completes well before
    any one robot holds the whole map; complete_when=robot runs on until one does."""
    base = dict(map="office", size=(60, 60), robots=4, seed=1, sensor_range=4.5,
                comm_range=20, coverage_threshold=1.0, sharing="broadcast")  # fmt: skip
    team = simulate(Scenario(**base)).result()
    robot = simulate(Scenario(**base, complete_when="robot")).result()
    assert team["status"] == robot["status"] == "complete"
    assert team["T100"] == robot["T100"] < robot["T100_first_robot"] == robot["ticks"]
    with pytest.raises(ScenarioError, match="--complete-when all: choose team"):
        Scenario(complete_when="all").validate()


def test_the_run_id_of_a_default_scenario_leaves_later_fields_out() -> None:
    """Runs stored before complete_when existed keep their ids (and resume)."""
    from mrexplore.experiments.sweep import scenario_id

    scenario = Scenario(map="office", size=(30, 30), robots=2, seed=3)
    assert scenario_id(scenario) != scenario_id(
        dataclasses.replace(scenario, complete_when="robot")
    )
    assert scenario_id(scenario) == "f1f0292222cded5e"  # its id before complete_when existed
