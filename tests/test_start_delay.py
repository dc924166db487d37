"""Robots that start at different ticks (``Scenario.start_delay``; Sheng et al. §5
"by varying the starting time of each robot")."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from mrexplore.experiments.sweep import scenario_id
from mrexplore.sim import Scenario, simulate


def _run(**settings: object) -> object:
    base = {"map": "office", "size": (30, 30), "robots": 4, "seed": 3, "sensor_range": 4}
    return simulate(Scenario(**{**base, **settings}))  # type: ignore[arg-type]


def test_dormant_robots_stand_still_sense_nothing_and_wake_at_their_tick() -> None:
    record = _run(start_delay=30)
    starts = record.result()["start_ticks"]
    assert min(starts) == 0 and max(starts) <= 30 and len(set(starts)) > 1
    alive = np.asarray(record.alive)
    positions = np.asarray(record.positions)
    for robot, start in enumerate(starts):
        assert not alive[:start, robot].any() and alive[start:, robot].all()
        assert (positions[: start + 1, robot] == positions[0, robot]).all()
        assert (np.asarray(record.distance)[:start, robot] == 0).all()
    assert record.status == "complete"
    assert record.result()["robots_failed"] == 0


def test_start_ticks_follow_the_seed_and_nothing_else() -> None:
    a = _run(start_delay=20).result()["start_ticks"]
    assert a == _run(start_delay=20, strategy="burgard").result()["start_ticks"]
    assert a != _run(start_delay=20, seed=4).result()["start_ticks"]
    # The start cells are drawn from their own stream: the delays do not move them.
    assert _run(start_delay=20).world.starts == _run().world.starts


def test_no_delay_changes_nothing_and_keeps_the_run_ids() -> None:
    plain, zero = _run(), _run(start_delay=0)
    assert np.array_equal(plain.positions, zero.positions)
    assert "start_ticks" not in zero.result()
    assert scenario_id(Scenario(map="office", seed=1)) == scenario_id(
        Scenario(map="office", seed=1, start_delay=0)
    )
    assert scenario_id(Scenario(map="office", seed=1, start_delay=5)) != scenario_id(
        Scenario(map="office", seed=1)
    )


def test_a_dormant_robot_that_fails_never_wakes() -> None:
    delayed = _run(start_delay=40).result()["start_ticks"]
    late = int(np.argmax(delayed))
    record = _run(start_delay=40, fail=[(late, 1)])
    assert not np.asarray(record.alive)[:, late].any()
    assert record.result()["start_ticks"][late] is None


def test_a_negative_delay_is_a_one_line_error() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "mrexplore", "run", "--map", "office", "--start-delay", "-2"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "mrexplore: error: --start-delay -2: must be a whole number of ticks >= 0"
    ]
