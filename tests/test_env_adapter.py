"""Registered strategies run through the env give exactly the run of ``mrexplore run``."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from mrexplore.cli import main  # imported after importorskip (E402 allows it)
from mrexplore.env import StrategyPolicy, parallel_env
from mrexplore.errors import MrexploreInputError, ScenarioError
from mrexplore.sim import RunRecord, Scenario, simulate
from mrexplore.strategies.base import Decision

LIMITED: dict[str, Any] = {
    "map": "office",
    "size": (32, 32),
    "robots": 3,
    "sensor_range": 4,
    "comm_range": 8,
    "latency": 2,
    "loss": 0.1,
    "fail": [(1, 20)],
}
# Wall-clock timings are the only fields allowed to differ.
TIMING_KEYS = {"wall_time_s", "decide_ms_per_plan"}


def _through_env(settings: dict[str, Any], seed: int, episodes: int = 1) -> RunRecord:
    env = parallel_env(**settings, action_mode="decision")
    policy = StrategyPolicy(env)
    for _ in range(episodes):  # later episodes must not inherit strategy state
        observations, _ = env.reset(seed=seed)
        while env.agents:
            observations, *_ = env.step(policy(observations))
    return env.record()


def _assert_same_run(ours: RunRecord, theirs: RunRecord) -> None:
    ours_arrays, their_arrays = ours.trace_arrays(), theirs.trace_arrays()
    assert ours_arrays.keys() == their_arrays.keys()
    for name, array in their_arrays.items():
        assert np.array_equal(ours_arrays[name], array), name
    ours_result, their_result = ours.result(), theirs.result()
    for key in their_result.keys() - TIMING_KEYS:
        assert ours_result[key] == their_result[key], key


@pytest.mark.parametrize("strategy", ["nearest-frontier", "random-frontier", "burgard"])
def test_strategy_through_the_env_gives_the_same_trace_as_run(strategy: str) -> None:
    settings = {**LIMITED, "strategy": strategy}
    ours = _through_env(settings, seed=7, episodes=2)
    theirs = simulate(Scenario(**settings, seed=7))
    assert theirs.alive[-1].tolist() == [True, False, True]
    if strategy == "burgard":
        assert {"status", "assign"} <= set(theirs.bytes_by_type)  # it coordinates by messages
    _assert_same_run(ours, theirs)


def test_saved_env_episode_equals_the_files_of_mrexplore_run(tmp_path: Path) -> None:
    argv = ["run", "--map", "office", "--size", "32x32", "--robots", "3", "--strategy"]
    argv += ["burgard", "--sensor-range", "4", "--comm-range", "8", "--fail", "1@20"]
    assert main([*argv, "--seed", "5", "--out", str(tmp_path / "cli")]) == 0
    env = parallel_env(
        map="office",
        size="32x32",
        robots=3,
        strategy="burgard",
        sensor_range="4",
        comm_range="8",
        fail=["1@20"],
        action_mode="decision",
    )
    policy = StrategyPolicy(env)
    observations, _ = env.reset(seed=5)
    while env.agents:
        observations, *_ = env.step(policy(observations))
    env.save(tmp_path / "env", png=False)
    with (
        np.load(tmp_path / "cli" / "trace.npz") as cli,
        np.load(tmp_path / "env" / "trace.npz") as ours,
    ):
        assert cli.files == ours.files
        for name in cli.files:
            assert np.array_equal(cli[name], ours[name]), name
    cli_result = json.loads((tmp_path / "cli" / "result.json").read_text())
    env_result = json.loads((tmp_path / "env" / "result.json").read_text())
    for key in cli_result.keys() - TIMING_KEYS:
        assert env_result[key] == cli_result[key], key


def test_decision_mode_takes_decisions_and_callables() -> None:
    env = parallel_env(**LIMITED, action_mode="decision", max_ticks=5)
    env.reset(seed=1)
    # Decision() keeps going (here: nobody has a goal, so everyone stays).
    env.step(dict.fromkeys(env.agents, Decision()))
    simulation = env.simulation
    assert simulation is not None
    assert [r.distance for r in simulation.robots] == [0.0, 0.0, 0.0]
    seen: list[int] = []

    def idle(view: Any) -> Decision:
        seen.append(view.tick)
        return Decision(idle=True)

    env.step({"robot_0": idle})
    assert seen == [2]
    with pytest.raises(MrexploreInputError, match="not int"):
        env.step({"robot_0": 3})
    with pytest.raises(ScenarioError, match="decision"):
        StrategyPolicy(parallel_env(**LIMITED, action_mode="move"))
    with pytest.raises(ScenarioError, match="status_messages"):
        parallel_env(**LIMITED, action_mode="decision", status_messages=True)


def test_the_comparison_example_runs_both_policies_on_the_same_world() -> None:
    path = Path(__file__).resolve().parents[1] / "examples" / "compare_policies.py"
    spec = importlib.util.spec_from_file_location("compare_policies", path)
    assert spec is not None and spec.loader is not None
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    scenario = {"map": "office", "size": "32x32", "robots": 2, "max_ticks": 60}
    random_result = example.run_episode("random", scenario, 2, None)
    burgard_result = example.run_episode("burgard", scenario, 2, None)
    assert random_result["strategy"] == "random" and burgard_result["strategy"] == "burgard"
    assert random_result["starts"] == burgard_result["starts"]
    assert random_result["map_shape"] == burgard_result["map_shape"] == [32, 32]
