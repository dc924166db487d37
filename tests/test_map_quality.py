"""Map quality (DESIGN §7): the team map, wrong and correct cells, and their recording.

Hand-made maps whose counts can be checked by eye, the fast team counts against the
merged map on random grids, and what a run leaves: the final map quality in every
``result.json``, the per-tick arrays in the trace of a noisy run only, and the
columns of the results store.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from mrexplore.checks import check_trace
from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.metrics import (
    NOISY_METRICS,
    TeamCounter,
    localisation_metrics,
    map_quality,
    map_quality_metrics,
    team_counts,
    team_map,
)
from mrexplore.sim import Scenario, Simulation, simulate
from mrexplore.sim.noise import Odometry, odometry_model
from mrexplore.sim.recorder import Recorder
from mrexplore.trace import OPTIONAL_TRACE_ARRAYS, load_trace

U, F, W = UNKNOWN, FREE, OCCUPIED  # W: a wall, as the robots believe
NOISY_ARRAYS = (
    "map_known",
    "map_wrong",
    "correct_known",
    "correct_coverage",
    "estimated_positions",
    "localisation_error",
    "robot_belief",
)
SMALL = Scenario(map="sheng40", robots=3, seed=1)

# A 2 x 4 world: a wall at (0, 0) and (1, 3); the other six cells free, five of them
# explorable ((1, 2) is a free cell no robot can reach).
TRUTH = np.array([[True, False, False, False], [False, False, False, True]])
EXPLORABLE = np.array([[False, True, True, True], [True, True, False, False]])


def belief(rows: list[list[int]]) -> np.ndarray:
    return np.array(rows, dtype=np.int8)


# ------------------------------------------------------------------ one map


def test_one_map_counts_known_wrong_and_correct_cells() -> None:
    #      wall ok, free ok, free held occupied (wrong), unknown
    #      free ok, unknown, unexplorable free ok, wall held free (wrong)
    mine = belief([[W, F, W, U], [F, U, F, F]])
    quality = map_quality(mine, TRUTH, EXPLORABLE)
    assert (quality.known, quality.wrong, quality.correct, quality.explorable) == (6, 2, 2, 5)
    assert quality.error_fraction == pytest.approx(2 / 6)
    assert quality.correct_fraction == pytest.approx(2 / 5)


def test_a_map_that_knows_nothing_has_no_error_and_nothing_correct() -> None:
    quality = map_quality(np.full((2, 4), U, dtype=np.int8), TRUTH, EXPLORABLE)
    assert (quality.known, quality.wrong, quality.correct) == (0, 0, 0)
    assert quality.error_fraction == 0.0
    assert quality.correct_fraction == 0.0


def test_the_truth_is_a_perfect_map() -> None:
    perfect = np.where(TRUTH, W, F).astype(np.int8)
    quality = map_quality(perfect, TRUTH.astype(np.uint8), EXPLORABLE)  # the trace's uint8
    assert quality.error_fraction == 0.0
    assert quality.correct_fraction == 1.0


def test_a_known_value_other_than_free_counts_as_occupied() -> None:
    odd = belief([[50, 50, U, U], [U, U, U, U]])  # right on the wall, wrong on the floor
    quality = map_quality(odd, TRUTH, EXPLORABLE)
    assert (quality.known, quality.wrong, quality.correct) == (2, 1, 0)


# ------------------------------------------------------------------ the team map


def test_team_map_takes_the_majority_of_the_robots_that_know_a_cell() -> None:
    a = belief([[F, F, W, U], [F, U, U, U]])
    b = belief([[F, W, W, U], [U, U, U, U]])
    c = belief([[W, W, F, U], [U, U, W, U]])
    merged = team_map([a, b, c])
    # 2 free / 1 occ -> free; 1 / 2 -> occ; 1 / 2 -> occ; nobody; one robot alone each
    assert merged.tolist() == [[F, W, W, U], [F, U, W, U]]
    assert merged.dtype == np.int8


def test_a_tie_is_occupied() -> None:
    a = belief([[F, W, U, U], [U, U, U, U]])
    b = belief([[W, F, U, U], [U, U, U, U]])
    assert team_map([a, b])[0, :2].tolist() == [W, W]
    four = [belief([[v, U, U, U], [U, U, U, U]]) for v in (F, F, W, W)]
    assert team_map(four)[0, 0] == W


def test_team_counts_of_a_hand_made_team() -> None:
    a = belief([[W, F, F, U], [F, F, U, W]])
    b = belief([[F, F, W, U], [U, W, U, W]])
    # team: (0,0) tie -> W right; (0,1) F right, correct; (0,2) tie -> W wrong;
    # (1,0) F right, correct; (1,1) tie -> W wrong; (1,3) W right
    assert team_map([a, b]).tolist() == [[W, F, W, U], [F, W, U, W]]
    assert team_counts([a, b], TRUTH, EXPLORABLE) == (6, 2, 2)
    team = map_quality(team_map([a, b]), TRUTH, EXPLORABLE)
    assert (team.known, team.wrong, team.correct) == (6, 2, 2)


def test_one_robot_is_its_own_team() -> None:
    mine = belief([[W, F, W, U], [F, U, F, F]])
    assert team_map([mine]).tolist() == mine.tolist()
    assert team_counts([mine], TRUTH, EXPLORABLE) == (6, 2, 2)


def test_the_team_counter_reads_the_maps_as_they_are_now() -> None:
    a = np.full((2, 4), U, dtype=np.int8)
    b = np.full((2, 4), U, dtype=np.int8)
    counter = TeamCounter([a, b], TRUTH, EXPLORABLE)
    assert counter.count() == (0, 0, 0)
    a[0, 1] = F
    b[1, 3] = F  # a wall held free
    assert counter.count() == (2, 1, 1)


def test_the_team_counter_reads_a_map_that_is_a_view() -> None:
    wide = np.full((2, 8), U, dtype=np.int8)
    counter = TeamCounter([wide[:, ::2]], TRUTH, EXPLORABLE)
    wide[0, 2] = F  # (0, 1) of the view
    assert counter.count() == (1, 0, 1)


@pytest.mark.parametrize(
    ("beliefs", "truth", "match"),
    [
        ([], TRUTH, "no belief maps"),
        ([np.full((2, 4), U, dtype=np.int16)], TRUTH, "int8"),
        ([np.full((2, 4), U, dtype=np.int8), np.full((2, 3), U, dtype=np.int8)], TRUTH, "shape"),
        ([np.full(8, U, dtype=np.int8)], TRUTH, "2-D"),
        ([np.full((2, 4), U, dtype=np.int8)], TRUTH[:, :3], "truth has shape"),
    ],
)
def test_bad_maps_are_refused_with_a_message(
    beliefs: list[np.ndarray], truth: np.ndarray, match: str
) -> None:
    with pytest.raises(MrexploreInputError, match=match):
        team_counts(beliefs, truth, EXPLORABLE)


def test_result_keys_of_the_final_maps() -> None:
    a = belief([[W, F, W, U], [F, U, F, F]])  # 6 known, 2 wrong, 2 correct
    b = belief([[W, F, F, F], [F, F, U, W]])  # a perfect map of 7 cells, 5 correct
    metrics = map_quality_metrics([a, b], TRUTH, EXPLORABLE)
    # team: (0,2) tie -> W (wrong), (1,3) tie -> W (right); 8 known, 1 wrong, 4 correct
    assert metrics == {
        "map_error_fraction": pytest.approx(1 / 8),
        "map_correct_fraction": pytest.approx(4 / 5),
        "map_error_by_robot": [pytest.approx(2 / 6), 0.0],
        "map_correct_by_robot": [pytest.approx(2 / 5), 1.0],
    }


# ------------------------------------------------------- fast counts = merged map


def _reference_team_map(beliefs: np.ndarray) -> np.ndarray:
    """The team map, written the slow and obvious way."""
    free = (beliefs == F).sum(axis=0)
    occupied = ((beliefs != F) & (beliefs != U)).sum(axis=0)
    merged = np.where(occupied >= free, W, F).astype(np.int8)
    merged[free + occupied == 0] = U
    return merged


@st.composite
def teams(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    height = draw(st.integers(1, 7))
    width = draw(st.integers(1, 7))
    n_robots = draw(st.integers(1, 5))
    values = st.sampled_from([U, F, W])
    beliefs = draw(hnp.arrays(np.int8, (n_robots, height, width), elements=values))
    truth = draw(hnp.arrays(np.bool_, (height, width)))
    reachable = draw(hnp.arrays(np.bool_, (height, width)))
    return beliefs, truth, reachable & ~truth


@settings(max_examples=300, deadline=None)
@given(teams())
def test_team_counts_equal_the_quality_of_the_merged_map(
    team: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> None:
    beliefs, truth, explorable = team
    merged = team_map(list(beliefs))
    assert merged.tolist() == _reference_team_map(beliefs).tolist()
    quality = map_quality(merged, truth, explorable)
    expected = (quality.known, quality.wrong, quality.correct)
    assert team_counts(list(beliefs), truth, explorable) == expected
    assert team_counts(beliefs, truth, explorable) == expected  # an N x H x W array too
    assert TeamCounter(list(beliefs), truth, explorable).count() == expected


# ------------------------------------------------------------- localisation


def test_localisation_metrics_count_live_robots_only() -> None:
    error = np.array([[0.0, 0.0], [1.0, 3.0], [2.0, 9.0]])
    alive = np.array([[True, True], [True, True], [True, False]])
    assert localisation_metrics(error, alive) == {
        "localisation_error_mean": pytest.approx(6 / 5),
        "localisation_error_max": 3.0,
        "localisation_error_final": 2.0,
    }


def test_localisation_at_the_end_of_a_team_that_all_failed_is_over_every_robot() -> None:
    error = np.array([[0.0, 0.0], [1.0, 3.0]])
    alive = np.array([[True, True], [False, False]])
    metrics = localisation_metrics(error, alive)
    assert metrics["localisation_error_final"] == 2.0
    assert metrics["localisation_error_max"] == 0.0


# ------------------------------------------------------------------ runs


def test_a_run_without_noise_has_a_perfect_map_as_large_as_its_coverage(
    tmp_path: Path,
) -> None:
    record = simulate(SMALL)
    assert record.scenario.noisy is False
    record.save(tmp_path)
    result = json.loads((tmp_path / "result.json").read_text())
    assert result["sharing"] == "full"
    assert result["map_error_fraction"] == 0.0
    assert result["map_correct_fraction"] == pytest.approx(result["explored_fraction"])
    assert result["map_error_by_robot"] == [0.0] * SMALL.robots
    correct = result["map_correct_by_robot"]
    assert len(correct) == SMALL.robots
    assert all(0 < c <= result["map_correct_fraction"] for c in correct)
    # what only a noisy run has is absent, in the result and in the trace
    assert not set(NOISY_METRICS) & set(result)
    assert not set(NOISY_ARRAYS) & set(load_trace(tmp_path / "trace.npz"))
    assert record.final_beliefs is not None
    assert record.final_beliefs.shape == (SMALL.robots, *record.world.grid.shape)


def test_polygon_sharing_without_noise_gives_maps_with_errors() -> None:
    result = simulate(Scenario(map="sheng40", robots=3, seed=1, sharing="polygon")).result()
    assert 0 < result["map_error_fraction"] < 0.05
    assert max(result["map_error_by_robot"]) > 0


@pytest.fixture
def noisy(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every scenario counts as noisy (the recording of a noisy run, without noise)."""
    monkeypatch.setattr(Scenario, "noisy", property(lambda self: True))


@pytest.mark.usefixtures("noisy")
def test_a_noisy_run_records_the_team_map_every_tick(tmp_path: Path) -> None:
    record = simulate(SMALL)
    record.save(tmp_path)
    trace = load_trace(tmp_path / "trace.npz")
    result = json.loads((tmp_path / "result.json").read_text())
    n_ticks, n_robots = record.positions.shape[:2]
    shapes = {name: (trace[name].shape, trace[name].dtype.name) for name in NOISY_ARRAYS}
    assert shapes == {
        "map_known": ((n_ticks,), "int64"),
        "map_wrong": ((n_ticks,), "int64"),
        "correct_known": ((n_ticks,), "int64"),
        "correct_coverage": ((n_ticks,), "float64"),
        "estimated_positions": ((n_ticks, n_robots, 2), "int32"),
        "localisation_error": ((n_ticks, n_robots), "float64"),
        "robot_belief": ((n_robots, *record.world.grid.shape), "int8"),
    }
    assert set(NOISY_ARRAYS) <= set(OPTIONAL_TRACE_ARRAYS)
    # perfect sensing and full sharing: the team map is the truth wherever it is known
    assert not trace["map_wrong"].any()
    np.testing.assert_array_equal(trace["correct_known"], trace["known_explorable"])
    np.testing.assert_array_equal(trace["correct_coverage"], trace["coverage"])
    first_known = trace["first_known"]
    known_by = [np.count_nonzero((first_known >= 0) & (first_known <= t)) for t in range(n_ticks)]
    np.testing.assert_array_equal(trace["map_known"], known_by)
    np.testing.assert_array_equal(trace["estimated_positions"][0], trace["positions"][0])
    assert not trace["localisation_error"].any()  # no odometry
    np.testing.assert_array_equal(trace["robot_belief"], record.final_beliefs)
    # the result: correct coverage as coverage, no localisation error, a perfect map
    assert [result[f"T{p}_correct"] for p in (90, 99, 100)] == [
        result[f"T{p}"] for p in (90, 99, 100)
    ]
    assert result["T90_correct"] is not None
    for key in ("localisation_error_mean", "localisation_error_max", "localisation_error_final"):
        assert result[key] == 0.0
    assert result["map_error_fraction"] == 0.0
    assert check_trace(trace, result) == []


@pytest.mark.usefixtures("noisy")
def test_the_localisation_error_is_the_odometry_s() -> None:
    """With an odometry whose estimate stays at the start cells, each robot's error is
    its distance from its start."""
    simulation = Simulation(SMALL)
    world = simulation.world
    odometry = Odometry(
        odometry_model(0.1, {}),
        world.starts,
        world.grid.shape,
        [np.random.default_rng(i) for i in range(SMALL.robots)],
    )
    simulation.recorder = Recorder(
        SMALL,
        world,
        roster=simulation.roster,
        comms=simulation.comms,
        deciding=simulation.deciding,
        sensing=simulation.sensing,
        stamps=simulation.stamps,
        end=simulation.end,
        comm_range_cells=simulation.comm_range_cells,
        odometry=odometry,
    )
    record = simulation.run()
    assert record.localisation_error is not None
    starts = np.array(world.starts, dtype=np.float64)
    expected = np.hypot(*np.moveaxis(record.positions - starts, -1, 0))
    np.testing.assert_allclose(record.localisation_error, expected)
    result = record.result()
    live = record.alive
    assert result["localisation_error_max"] == pytest.approx(expected[live].max())
    assert result["localisation_error_final"] == pytest.approx(expected[-1].mean())
    assert result["localisation_error_max"] > 0


def test_the_store_has_map_quality_columns(tmp_path: Path) -> None:
    from mrexplore.experiments import query, run_sweep, sweep_from_dict

    sweep = sweep_from_dict(
        {"sweep": {"seeds": [1]}, "fixed": {"map": "sheng40", "robots": 2, "max_ticks": 60}}
    )
    run_sweep(sweep, tmp_path, workers=1, progress=False)
    columns = ", ".join(["map_error_fraction", "map_correct_fraction", *NOISY_METRICS])
    row = query(tmp_path, f"SELECT explored_fraction, {columns} FROM runs").to_pylist()[0]
    assert row["map_error_fraction"] == 0.0
    assert math.isclose(row["map_correct_fraction"], row["explored_fraction"])
    assert all(row[name] is None for name in NOISY_METRICS)
    by_robot = query(tmp_path, "SELECT map_error_by_robot FROM runs").to_pylist()[0]
    assert json.loads(by_robot["map_error_by_robot"]) == [0.0, 0.0]
