"""One place defines valid input: :meth:`Scenario.check` (issue 18 step 6).

The Python API (:class:`Simulation`), sweeps and the CLI all refuse a bad scenario
through it, with the same one-line message naming the option, as an error of
:mod:`mrexplore.errors` (the CLI: exit status 2, no traceback).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mrexplore.cli import EXIT_BAD_INPUT, main
from mrexplore.errors import MrexploreInputError, ScenarioError, UnknownIdError
from mrexplore.experiments.sweep import SweepError, sweep_from_dict
from mrexplore.planning import distance_field
from mrexplore.planning.distance import FieldCounter
from mrexplore.sim import Scenario, Simulation, simulate
from mrexplore.sim.stamps import BeliefStamps, DirectStamps, ShadowStamps

# A field of the wrong type or out of range -> the option named in the message.
BAD_FIELDS: list[tuple[dict[str, Any], str]] = [
    ({"robots": 0}, "--robots 0"),
    ({"robots": 2.5}, "--robots 2.5"),
    ({"robots": True}, "--robots True"),
    ({"seed": -1}, "--seed -1"),
    ({"map_seed": "7"}, "--map-seed 7"),
    ({"map": 3}, "--map 3"),
    ({"strategy": None}, "--strategy None"),
    ({"sharing": 1}, "--sharing 1"),
    ({"params": [("w", 1)]}, "--set"),
    ({"sharing_params": "a=1"}, "--share"),
    ({"size": (30,)}, "--size (30,)"),
    ({"size": ("30", "30")}, "--size"),
    ({"size": (0, 30)}, "--size 0x30"),
    ({"speed": "fast"}, "--speed fast"),
    ({"speed": math.nan}, "--speed nan"),
    ({"max_ticks": 0}, "--max-ticks 0"),
    ({"max_ticks": "10"}, "--max-ticks 10"),
    ({"max_ticks": 10.5}, "--max-ticks 10.5"),
    ({"stall_ticks": 0}, "--stall-ticks 0"),
    ({"idle_ticks": -1}, "--idle-ticks -1"),
    ({"patience": "3"}, "--patience 3"),
    ({"coverage_threshold": "0.9"}, "--coverage-threshold 0.9"),
    ({"start_delay": -2}, "--start-delay -2"),
    ({"sensing": "never"}, "--sensing never"),
    ({"start": "apart"}, "--start apart"),
    ({"start": [(1, 2, 3)] * 4}, "--start"),
    ({"sensor_range": [3]}, "--sensor-range [3]"),
    ({"sensor_range": 0}, "--sensor-range 0"),
    ({"comm_range": "far"}, "--comm-range 'far'"),
    ({"comm_range": -math.inf}, "--comm-range -inf"),
    ({"comm_los": "no"}, "--comm-los 'no'"),
    ({"bandwidth": "lots"}, "--bandwidth lots"),
    ({"latency": True}, "--latency True"),
    ({"latency": 0}, "--latency 0"),
    ({"loss": 1.5}, "--loss 1.5"),
    ({"failure_rate": "0.1"}, "--failure-rate 0.1"),
    ({"fail": [(1,)]}, "--fail"),
    ({"fail": [(9, 3)]}, "--fail 9@3: no robot 9"),
    ({"fail": [(1, 3), (1, 5)]}, "--fail 1@5: robot 1 already fails"),
    ({"complete_when": "all"}, "--complete-when all"),
    ({"cell_size": 0.1}, "--cell-size 0.1: applies to map files only"),
]


@pytest.mark.parametrize(("fields", "option"), BAD_FIELDS)
def test_a_bad_field_is_one_line_naming_the_option(fields: dict[str, Any], option: str) -> None:
    with pytest.raises(ScenarioError) as caught:
        Scenario(**{"map": "office", "size": (30, 30), **fields}).check()
    message = str(caught.value)
    assert message.startswith(option), message
    assert "\n" not in message


@pytest.mark.parametrize(
    ("fields", "error", "text"),
    [
        ({"strategy": "greedy"}, UnknownIdError, "unknown strategy 'greedy'"),
        ({"sharing": "gossip"}, UnknownIdError, "unknown sharing mechanism 'gossip'"),
        ({"map": "no-such-map"}, UnknownIdError, "'no-such-map'"),
        ({"map": "missing.pgm"}, MrexploreInputError, "missing.pgm: no such file"),
        ({"params": {"w": 1}}, ScenarioError, "--set w: strategy 'nearest-frontier' has no"),
        ({"sharing_params": {"epsilon": 1}}, ScenarioError, "--share epsilon=1"),
        ({"comm_model": "radio"}, UnknownIdError, "unknown communication model 'radio'"),
        ({"comm_params": {"exponent": 3}}, ScenarioError, "--comm exponent: communication model"),
    ],
)
def test_ids_and_parameters_are_checked_too(
    fields: dict[str, Any], error: type[Exception], text: str
) -> None:
    with pytest.raises(error) as caught:
        Scenario(**fields).check()
    assert text in str(caught.value)


def test_valid_scenarios_pass_with_numpy_numbers() -> None:
    Scenario().check()
    Scenario(
        map="office",
        size=(np.int64(30), np.int64(20)),
        robots=np.int64(3),
        seed=np.uint32(4),
        speed=np.float64(1.5),
        comm_range=np.float64(math.inf),
        comm_los=np.bool_(True),
        start=[(np.int32(5), np.int32(5)), (5, 6), (6, 5)],
        fail=[(np.int64(1), np.int64(4))],
        sharing_params={},
    ).check()


def test_the_api_the_sweep_and_the_cli_refuse_alike(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    settings = {"map": "office", "size": (30, 30), "robots": 2, "fail": [(5, 3)]}
    want = "--fail 5@3: no robot 5 in a team of 2"
    with pytest.raises(ScenarioError, match=want):
        Simulation(Scenario(**settings))
    data = {
        "sweep": {"seeds": [1]},
        "fixed": {"map": "office", "size": "30x30", "robots": 2, "fail": ["5@3"]},
    }
    with pytest.raises(SweepError, match=want):
        sweep_from_dict(data, "s.toml")
    argv = ["run", "--map", "office", "--size", "30x30", "--robots", "2", "--fail", "5@3"]
    assert main(argv) == EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert err.strip() == f"mrexplore: error: {want}"


@pytest.mark.parametrize(
    "line", ['speed = "fast"', 'max_ticks = "10"', "sensor_range = [3]", 'comm_los = "no"']
)
def test_a_sweep_value_of_the_wrong_type_is_bad_input_not_an_internal_error(
    line: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    sweep = tmp_path / "s.toml"
    sweep.write_text(f'[sweep]\nseeds = [1]\n[fixed]\nmap = "sheng40"\n{line}\n')
    assert main(["sweep", str(sweep), "--out", str(tmp_path / "out"), "--dry-run"]) == (
        EXIT_BAD_INPUT
    )
    err = capsys.readouterr().err
    lines = [text for text in err.splitlines() if text.strip()]
    assert len(lines) == 1 and lines[0].startswith("mrexplore: error: "), err
    assert "internal error" not in err and "Traceback" not in err
    assert "--" + line.split(" =")[0].replace("_", "-") in lines[0]


# ------------------------------------------------------------------ the run's own parts


def test_a_field_counter_counts_only_while_active() -> None:
    grid = np.ones((4, 4), dtype=bool)
    outer, inner = FieldCounter(), FieldCounter()
    distance_field(grid, (0, 0))
    with outer:
        distance_field(grid, (0, 0))
        with inner:
            distance_field(grid, (1, 1))
        distance_field(grid, (2, 2))
    assert (outer.count, inner.count) == (2, 1)


def test_fields_of_a_run_are_its_own() -> None:
    """Two runs stepped in turn count their own decisions' fields."""
    scenario = Scenario(map="sheng40", robots=2, strategy="burgard", seed=1)
    alone = simulate(scenario)
    first, second = Simulation(scenario), Simulation(scenario)
    first.start()
    second.start()
    while first.status is None or second.status is None:
        for simulation in (first, second):
            if simulation.status is None:
                simulation.step()
    for record in (first.finish(), second.finish()):
        assert (record.fields, record.field_decisions) == (alone.fields, alone.field_decisions)
    assert alone.fields >= alone.field_decisions > 0


@pytest.mark.parametrize(
    ("sharing", "record_beliefs", "kind"),
    [
        ("full", True, DirectStamps),
        ("none", True, DirectStamps),
        ("broadcast", True, DirectStamps),
        ("sheng-sync", True, ShadowStamps),
        ("polygon", True, ShadowStamps),
        ("full", False, BeliefStamps),
    ],
)
def test_belief_stamps_are_chosen_once_per_run(
    sharing: str, record_beliefs: bool, kind: type[BeliefStamps]
) -> None:
    simulation = Simulation(
        Scenario(map="sheng40", robots=2, sharing=sharing), record_beliefs=record_beliefs
    )
    assert type(simulation.stamps) is kind
    assert (simulation.stamps.robot_first_known is not None) == record_beliefs
