"""Imperfect robots (issue 19): the sensor's error rates, the log-odds fusion, the
odometry's drift and its reset, measured against the configured values; runs with
both noises on; and noise-free runs left as they were."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import stats

from mrexplore.cli import main
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.seeding import make_streams
from mrexplore.sim.engine import Simulation
from mrexplore.sim.noise import Odometry, OdometryModel, odometry_model, sensor_model
from mrexplore.sim.scenario import Scenario
from mrexplore.strategies.base import Decision
from mrexplore.strategies.registry import available_strategies

IDLE = Decision(idle=True)


def _first_readings(scenario: Scenario, seeds: range) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For robot 0's tick-0 sensing over ``seeds``: each visible cell's truth, belief
    (one reading: the belief is the reading) and distance to the robot."""
    truths, beliefs, ranges = [], [], []
    for seed in seeds:
        sim = Simulation(dataclasses.replace(scenario, seed=seed))
        sim.start()
        robot = sim.robots[0]
        visible = sim.sensing._visible(robot)
        rows, cols = np.divmod(visible, sim.truth.shape[1])
        keep = (rows != robot.position[0]) | (cols != robot.position[1])
        rows, cols = rows[keep], cols[keep]
        truths.append(sim.truth[rows, cols])
        beliefs.append(robot.belief[rows, cols])
        ranges.append(np.hypot(rows - robot.position[0], cols - robot.position[1]))
    return np.concatenate(truths), np.concatenate(beliefs), np.concatenate(ranges)


def _within(count: int, n: int, p: float, sigmas: float = 4.5) -> bool:
    """``count`` successes of ``n`` are within ``sigmas`` binomial deviations of ``n p``."""
    return abs(count - n * p) <= sigmas * math.sqrt(n * p * (1 - p)) + 1


def test_the_error_rates_of_single_readings_match_the_configured_ones() -> None:
    scenario = Scenario(
        map="office",
        size=(40, 40),
        robots=1,
        sensor_range=6,
        sensor_noise=0.1,
        sensor_params={"false_free": 0.2},
    )
    truth, belief, _ = _first_readings(scenario, range(60))
    free, occupied = ~truth, truth
    assert free.sum() > 2500 and occupied.sum() > 500
    assert not (belief == UNKNOWN).any()  # one reading decides a cell
    read_occupied = int((belief[free] == OCCUPIED).sum())
    read_free = int((belief[occupied] == FREE).sum())
    assert _within(read_occupied, int(free.sum()), 0.1), read_occupied / free.sum()
    assert _within(read_free, int(occupied.sum()), 0.2), read_free / occupied.sum()


def test_the_error_rate_grows_with_range_as_configured() -> None:
    scenario = Scenario(
        map="office",
        size=(40, 40),
        robots=1,
        sensor_range=6,
        sensor_noise=0.1,
        sensor_params={"range_growth": 2.0},
    )
    truth, belief, ranges = _first_readings(scenario, range(60))
    wrong = (belief == OCCUPIED) != truth
    for low, high in ((0.5, 2.5), (2.5, 4.5), (4.5, 6.01)):
        in_bin = (ranges >= low) & (ranges < high)
        expected = float(np.mean(0.1 * (1 + 2.0 * ranges[in_bin] / 6)))
        assert _within(int(wrong[in_bin].sum()), int(in_bin.sum()), expected), (low, expected)


def test_repeated_readings_fuse_as_clamped_log_odds() -> None:
    """A robot standing still reads its disk every tick; its log-odds equal a
    reference binary Bayes filter run on the same draws of its sensor stream."""
    scenario = Scenario(
        map="office",
        size=(30, 30),
        robots=1,
        sensor_range=5,
        sensor_noise=0.3,
        seed=4,
        idle_ticks=50,
    )
    sim = Simulation(scenario)
    model = sensor_model(0.3, {})
    sim.start()
    for _ in range(12):
        sim.step(lambda i, view: IDLE)
    robot = sim.robots[0]
    visible = sim.sensing._visible(robot)
    rng = make_streams(4, 1).sensor[0]
    truth = sim.truth.reshape(-1)
    level = np.zeros(truth.size)
    up = math.log(0.7 / 0.3)  # log((1 - false_free) / false_occupied)
    for _ in range(13):  # ticks 0..12
        draws = rng.random(visible.size)
        for k, i in enumerate(visible):
            if i == robot.position[0] * sim.truth.shape[1] + robot.position[1]:
                level[i] = model.clamp_low
                continue
            read_occupied = truth[i] != (draws[k] < 0.3)
            level[i] = min(
                max(level[i] + (up if read_occupied else -up), model.clamp_low), model.clamp_high
            )
    log_odds = sim.sensing.log_odds[0]
    np.testing.assert_allclose(log_odds[visible], level[visible], atol=1e-5)
    expected = np.where(level > 0, OCCUPIED, np.where(level < 0, FREE, UNKNOWN))
    assert (robot.belief.reshape(-1)[visible] == expected[visible]).all()
    # the clamp keeps a cell read wrongly from being held for long: most are right
    assert ((robot.belief.reshape(-1)[visible] == OCCUPIED) == truth[visible]).mean() > 0.75


def test_position_drift_grows_with_the_square_root_of_distance() -> None:
    n_robots, steps, k = 4000, 100, 0.05
    rngs = [np.random.default_rng(s) for s in np.random.SeedSequence(1).spawn(n_robots)]
    odometry = Odometry(OdometryModel(k, 0.0, "never"), [(500, 500)] * n_robots, (1000, 1000), rngs)
    for robot in range(n_robots):
        for _ in range(steps):
            odometry.moved(robot, 0, 1)  # east, one cell
    error = odometry.estimate - np.array([500.0, 500.0 + steps])
    expected = k * math.sqrt(steps)  # 0.5 cells per axis
    for axis in range(2):
        sample = error[:, axis]
        assert abs(sample.mean()) < 5 * expected / math.sqrt(n_robots)
        # the sample variance against the chi-square interval (two-sided, 1e-4)
        low, high = stats.chi2.ppf([5e-5, 1 - 5e-5], n_robots - 1) / (n_robots - 1)
        assert low * expected**2 < sample.var(ddof=1) < high * expected**2
    assert np.allclose(odometry.variance, steps * k * k)


def test_diagonal_steps_drift_in_proportion_to_their_length() -> None:
    n_robots, steps, k = 4000, 50, 0.1
    rngs = [np.random.default_rng(s) for s in np.random.SeedSequence(2).spawn(n_robots)]
    odometry = Odometry(OdometryModel(k, 0.0, "never"), [(0, 0)] * n_robots, (500, 500), rngs)
    for robot in range(n_robots):
        for _ in range(steps):
            odometry.moved(robot, 1, 1)
    error = odometry.estimate[:, 0] - steps
    expected_var = steps * (k * math.sqrt(2)) ** 2
    low, high = stats.chi2.ppf([5e-5, 1 - 5e-5], n_robots - 1) / (n_robots - 1)
    assert low * expected_var < error.var(ddof=1) < high * expected_var


def test_heading_drift_matches_its_per_cell_deviation() -> None:
    n_robots, steps = 4000, 64
    model = odometry_model(0.0, {"heading_deg": 0.5})
    rngs = [np.random.default_rng(s) for s in np.random.SeedSequence(3).spawn(n_robots)]
    odometry = Odometry(model, [(100, 100)] * n_robots, (400, 400), rngs)
    for robot in range(n_robots):
        for _ in range(steps):
            odometry.moved(robot, 0, 1)
    expected_var = steps * math.radians(0.5) ** 2
    low, high = stats.chi2.ppf([5e-5, 1 - 5e-5], n_robots - 1) / (n_robots - 1)
    assert low * expected_var < odometry.heading.var(ddof=1) < high * expected_var
    # a turned heading bends the path: the estimate ends off the true row
    assert np.abs(odometry.estimate[:, 0] - 100).mean() > 0.1


def test_meeting_gives_the_robot_with_the_larger_variance_the_others_error() -> None:
    rngs = [np.random.default_rng(s) for s in range(3)]
    odometry = Odometry(
        OdometryModel(0.1, 0.0, "meeting"), [(5, 5), (5, 7), (9, 9)], (20, 20), rngs
    )
    odometry.estimate[:] = [[5.5, 4.0], [8.0, 7.5], [9.0, 9.0]]
    odometry.variance[:] = [0.2, 0.9, 0.0]
    odometry.heading[:] = [0.1, -0.3, 0.0]
    odometry.meet([(0, 1)], [(5, 5), (5, 7), (9, 9)])
    assert odometry.estimate[1].tolist() == [5.5, 6.0]  # robot 0's error (0.5, -1)
    assert odometry.heading[1] == 0.1 and odometry.variance[1] == 0.2
    assert odometry.estimate[0].tolist() == [5.5, 4.0]
    assert odometry.resets == 1


def test_a_robot_writes_what_it_senses_at_its_believed_pose() -> None:
    scenario = Scenario(map="office", size=(40, 40), robots=1, sensor_range=5, odometry_noise=0.01)
    sim = Simulation(scenario)
    sim.start()
    robot = sim.robots[0]
    assert sim.odometry is not None
    # the robot believes it is 3 rows south of where it is
    sim.odometry.estimate[0] += (3.0, 0.0)
    robot.believed = sim.odometry.believed_cell(0)
    robot.belief[:] = UNKNOWN
    robot.sensed[:] = False
    sim.sensing.log_odds[0][:] = 0
    sim.step(lambda i, view: IDLE)
    visible = sim.sensing._visible(robot)
    rows, cols = np.divmod(visible, 40)
    inside = rows + 3 < 40
    rows, cols = rows[inside], cols[inside]
    shifted = robot.belief[rows + 3, cols]
    own = (rows + 3 == robot.believed[0]) & (cols == robot.believed[1])
    expected = np.where(sim.truth[rows, cols], OCCUPIED, FREE)
    assert (shifted[~own] == expected[~own]).all()


def test_a_robot_that_believes_a_wall_elsewhere_bumps_into_it_and_learns() -> None:
    scenario = Scenario(
        map="office", size=(30, 30), robots=1, sensor_range=4, odometry_noise=0.01, start=[(1, 5)]
    )
    sim = Simulation(scenario)
    sim.start()
    robot = sim.robots[0]
    assert sim.truth[0, 5]  # the outer wall is north of the robot
    sim.odometry.estimate[0] = (3.0, 5.0)  # it believes it is two rows further south
    robot.believed = (3, 5)
    robot.belief[1:4, 4:7] = FREE
    path = np.array([(3, 5), (2, 5)], dtype=np.int32)
    sim.step(lambda i, view: Decision(goal=(2, 5), path=path))
    assert robot.position == (1, 5) and robot.blocked
    assert robot.belief[2, 5] == OCCUPIED  # the wall, where it believes it is
    assert sim.sensing.log_odds[0][2 * 30 + 5] == pytest.approx(sensor_model(0, {}).clamp_high)


def test_without_noise_the_noise_settings_change_nothing() -> None:
    base = Scenario(map="office", size=(40, 40), robots=3, strategy="burgard", seed=5)
    quiet = dataclasses.replace(
        base,
        sensor_params={"range_growth": 1.0, "clamp_occupied": 0.9},
        odometry_params={"reset": "meeting"},
    )
    assert not quiet.noisy
    a, b = Simulation(base).run(), Simulation(quiet).run()
    for name, array in a.trace_arrays().items():
        np.testing.assert_array_equal(array, b.trace_arrays()[name], err_msg=name)


@pytest.mark.parametrize("strategy", sorted(available_strategies()))
@pytest.mark.parametrize(
    "where", [{"map": "office", "size": (40, 40)}, {"map": "intel", "cell_size": 0.4}]
)
def test_every_strategy_completes_or_stalls_with_both_noises(strategy: str, where: dict) -> None:
    scenario = Scenario(
        **where,
        robots=3,
        strategy=strategy,
        seed=2,
        max_ticks=300,
        sensor_noise=0.1,
        sensor_params={"range_growth": 1.0},
        odometry_noise=0.05,
        odometry_params={"heading_deg": 0.5},
    )
    record = Simulation(scenario).run()
    assert record.status in {"complete", "stalled", "max_ticks"}
    assert record.known_explorable[-1] > 0
    positions = record.positions
    assert not record.world.grid.occupied[positions[..., 0], positions[..., 1]].any()


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--sensor-noise", "0.5"], "--sensor-noise 0.5: must be a probability in [0, 0.5)"),
        (["--odometry", "reset=later"], "--odometry reset=later: must be one of never, meeting"),
        (["--sensor", "gain=2"], "--sensor gain: the sensor model has no such parameter"),
        (["--odometry-noise", "nan"], "--odometry-noise nan: must be a finite number >= 0"),
        (
            ["--sensor-noise", "0.3", "--sensor", "range_growth=1"],
            "--sensor range_growth=1: false_occupied would reach 0.6",
        ),
    ],
)
def test_bad_noise_options_are_one_line_errors(
    argv: list[str], message: str, tmp_path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    assert main(["run", "--map", "office", "--size", "30x30", *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"mrexplore: error: {message}") and "\n" not in err
    assert not out.exists()


def test_noise_options_reach_result_json(tmp_path) -> None:
    import json

    out = tmp_path / "run"
    argv = ["run", "--map", "office", "--size", "30x30", "--robots", "2", "--max-ticks", "60"]
    extra = ["--sensor-noise", "0.05", "--odometry-noise", "0.02", "--odometry", "reset=meeting"]
    assert main([*argv, *extra, "--out", str(out)]) == 0
    result = json.loads((out / "result.json").read_text())
    assert result["sensor_noise"] == 0.05 and result["odometry_noise"] == 0.02
    assert result["odometry_params"] == {"reset": "meeting"}


def test_the_trace_checker_accepts_noisy_runs_and_still_catches_far_cells() -> None:
    from mrexplore.checks import check_trace
    from mrexplore.metrics import json_safe

    scenario = Scenario(
        map="office",
        size=(40, 40),
        robots=3,
        seed=3,
        sensor_noise=0.1,
        odometry_noise=0.05,
        odometry_params={"heading_deg": 1.0, "reset": "meeting"},
    )
    record = Simulation(scenario).run()
    trace, result = record.trace_arrays(), json_safe(record.result())
    assert (trace["localisation_error"] > 0).any()
    assert check_trace(trace, result) == []
    # a cell stamped at tick 1 far from every robot is still a violation
    far = dict(trace)
    far["first_known"] = trace["first_known"].copy()
    rows, cols = np.nonzero(trace["first_known"] < 0)
    start = trace["positions"][1]
    distance = np.hypot(rows[:, None] - start[:, 0], cols[:, None] - start[:, 1]).min(axis=1)
    k = int(np.argmax(distance))
    far["first_known"][rows[k], cols[k]] = 1
    assert any("out of every robot's sight" in p for p in check_trace(far))
