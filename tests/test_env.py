"""The PettingZoo environment: API conformance, seeding, spaces, knowledge, rewards, records.

PettingZoo's own checkers (``parallel_api_test``, ``parallel_seed_test``, the
state test) run on a generated map and on a real MovingAI map, with limited
communication and a robot failing at tick 20. They report problems with
``warnings.warn``; under this suite's ``filterwarnings = error`` any such warning
fails the test, which is what we want, so none is filtered.
"""

from __future__ import annotations

import importlib
import json
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("pettingzoo")
pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import data_equivalence  # imported after importorskip
from pettingzoo.test import parallel_api_test, parallel_seed_test

from mrexplore.checks import check_trace
from mrexplore.env import (
    MOVES,
    ExplorationEnv,
    RandomPolicy,
    frontier_candidates,
    parallel_env,
)
from mrexplore.errors import MrexploreInputError, ScenarioError
from mrexplore.grid.occupancy import FREE
from mrexplore.strategies.base import frontier_at

# pettingzoo.test re-exports a function under the submodule's name: import the module.
state_test = importlib.import_module("pettingzoo.test.state_test")

GENERATED: dict[str, Any] = {
    "map": "office",
    "size": (32, 32),
    "robots": 3,
    "sensor_range": 4,
    "comm_range": 8,
    "fail": [(1, 20)],
    "max_ticks": 40,
}


def _real() -> dict[str, Any]:
    """The MovingAI map room-64-64-8 of the package's catalogue."""
    return {**GENERATED, "map": "room-64-64-8", "size": None, "sensor_range": 6}


MAPS = {"generated": lambda: dict(GENERATED), "room-64-64-8": _real}


@pytest.mark.parametrize("mode", ["frontier", "move"])
@pytest.mark.parametrize("map_kind", sorted(MAPS))
def test_pettingzoo_api_seed_and_state(mode: str, map_kind: str) -> None:
    settings = {**MAPS[map_kind](), "action_mode": mode}
    parallel_api_test(parallel_env(**settings), num_cycles=100)
    parallel_seed_test(partial(parallel_env, **settings), num_cycles=100)
    state_test.test_parallel_env(parallel_env(**settings))


@pytest.mark.parametrize("mode", ["frontier", "move"])
def test_pettingzoo_api_with_status_messages_and_individual_rewards(mode: str) -> None:
    settings = {
        **GENERATED,
        "action_mode": mode,
        "status_messages": True,
        "reward": "individual",
        "global_map_size": 0,
        "n_candidates": 3,
    }
    parallel_api_test(parallel_env(**settings), num_cycles=100)
    parallel_seed_test(partial(parallel_env, **settings), num_cycles=100)


def _episode(env: ExplorationEnv, seed: int, policy_seed: int) -> list[Any]:
    """Every return value of one full episode under a random masked policy."""
    observations, infos = env.reset(seed=seed)
    policy = RandomPolicy(env, seed=policy_seed, stay=True)
    returned: list[Any] = [observations, infos]
    while env.agents:
        returned.append(env.step(policy(observations)))
        observations = returned[-1][0]
    return returned


@pytest.mark.parametrize("mode", ["frontier", "move"])
def test_whole_episodes_are_deterministic(mode: str) -> None:
    settings = {**GENERATED, "action_mode": mode}
    first = _episode(parallel_env(**settings), seed=3, policy_seed=1)
    second = _episode(parallel_env(**settings), seed=3, policy_seed=1)
    assert len(first) == len(second)
    for a, b in zip(first, second, strict=True):
        assert data_equivalence(a, b)
    other = _episode(parallel_env(**settings), seed=4, policy_seed=1)
    assert not data_equivalence(first[0], other[0])


def test_reset_seeds_and_the_env_generator() -> None:
    env = parallel_env(**GENERATED, action_mode="move")
    first, _ = env.reset(seed=5)
    seed_after_5 = (env.reset()[0], env.episode_seed)
    again, _ = env.reset(seed=5)
    assert data_equivalence(first, again)
    assert data_equivalence(seed_after_5, (env.reset()[0], env.episode_seed))
    assert env.episode_seed != 5
    # The env's `seed` setting seeds its generator of episode seeds.
    seeded = [parallel_env(**GENERATED, seed=9) for _ in range(2)]
    for other in seeded:
        other.reset()
    assert seeded[0].episode_seed == seeded[1].episode_seed is not None


@pytest.mark.parametrize("mode", ["frontier", "move"])
def test_observations_stay_in_their_space_and_a_failed_robot_leaves(mode: str) -> None:
    env = parallel_env(**{**GENERATED, "max_ticks": 30}, action_mode=mode)
    observations, infos = env.reset(seed=2)
    policy = RandomPolicy(env, seed=0)
    assert env.agents == env.possible_agents == ["robot_0", "robot_1", "robot_2"]
    while env.agents:
        live = list(env.agents)
        observations, rewards, terminated, truncated, infos = env.step(policy(observations))
        assert set(observations) == set(rewards) == set(terminated) == set(live)
        for agent, obs in observations.items():
            assert env.observation_space(agent).contains(obs), agent
            assert obs["action_mask"][env.stay_action] == 1
            assert np.array_equal(infos[agent]["action_mask"], obs["action_mask"])
        if env.tick == 20:
            assert terminated["robot_1"] and not infos["robot_1"]["alive"]
            assert rewards["robot_1"] == 0.0
            assert "robot_1" not in env.agents and "robot_0" in env.agents
        elif env.tick < 20:
            assert "robot_1" in env.agents
    assert env.tick == 30 and env.simulation is not None
    assert env.simulation.status == "max_ticks"
    assert all(truncated.values()) and not any(terminated.values())
    with pytest.raises(RuntimeError, match="episode is over"):
        env.step({})


def test_state_is_the_global_view() -> None:
    env = parallel_env(**GENERATED)
    env.reset(seed=1)
    state = env.state()
    assert env.state_space.contains(state)
    simulation = env.simulation
    assert simulation is not None
    assert np.array_equal(state[0], simulation.truth)
    assert np.array_equal(state[1], simulation.first_known >= 0)
    assert state[2].sum() == 3 and state[3].sum() == 0


def test_teammates_are_known_only_through_contact() -> None:
    """A teammate's position is heard only while in the same sub-network, then ages."""
    settings = {**GENERATED, "comm_range": 4, "start": "separate", "max_ticks": 80}
    env = parallel_env(**settings, action_mode="frontier")
    observations, _ = env.reset(seed=11)
    policy = RandomPolicy(env, seed=3)
    simulation = env.simulation
    assert simulation is not None
    positions = [np.array([r.position for r in simulation.robots])]
    saw_out_of_contact = saw_in_contact = False
    while env.agents:
        observations, *_ = env.step(policy(observations))
        positions.append(np.array([r.position for r in simulation.robots]))
        groups = simulation.comm.subnetworks()
        for agent, obs in observations.items():
            me = int(agent.split("_")[1])
            others = [j for j in range(env.n_robots) if j != me]
            for row, other in zip(obs["teammates"], others, strict=True):
                heard, in_contact, r, c, _, _, age = (int(v) for v in row)
                contact = any(me in g and other in g for g in groups)
                assert in_contact == contact
                if not heard:
                    assert (r, c, age) == (-1, -1, -1)
                    continue
                # The value is the teammate's true position at the tick it was heard.
                assert (r, c) == tuple(positions[env.tick - age][other])
                saw_in_contact |= contact
                saw_out_of_contact |= not contact and age > 0
    assert saw_in_contact and saw_out_of_contact


def test_status_messages_carry_teammate_knowledge_and_cost_bytes() -> None:
    settings = {**GENERATED, "fail": [], "latency": 2, "max_ticks": 25}
    env = parallel_env(**settings, action_mode="move", status_messages=True)
    observations, _ = env.reset(seed=1)
    assert observations["robot_0"]["teammates"][:, 0].tolist() == [0, 0]  # nothing heard yet
    policy = RandomPolicy(env, seed=2)
    while env.agents:
        observations, *_ = env.step(policy(observations))
        for obs in observations.values():
            mates = obs["teammates"]
            heard = mates[:, 0] == 1
            assert (mates[heard, 6] >= 2).all()  # a message takes `latency` ticks per hop
    assert (observations["robot_0"]["teammates"][:, 0] == 1).any()
    result = env.record().result()
    assert result["bytes_by_type"]["env_status"] > 0
    assert result["messages_by_type"]["env_status"] > 0


def test_move_mode_moves_masks_and_penalises() -> None:
    settings = {**GENERATED, "robots": 1, "fail": []}
    env = parallel_env(**settings, action_mode="move", invalid_action_penalty=0.5, step_cost=0.0)
    for seed in range(50):  # a start cell with a free straight move and a blocked one
        observations, _ = env.reset(seed=seed)
        mask = observations["robot_0"]["action_mask"]
        straight = [a for a in (1, 3, 5, 7) if mask[a]]
        if straight and not mask[1:].all():
            break
    simulation = env.simulation
    assert simulation is not None
    robot = simulation.robots[0]
    belief = robot.belief
    for action, (d_row, d_col) in enumerate(MOVES[1:], start=1):
        cell = (robot.position[0] + d_row, robot.position[1] + d_col)
        inside = 0 <= cell[0] < belief.shape[0] and 0 <= cell[1] < belief.shape[1]
        if not inside or belief[cell] != FREE:
            assert mask[action] == 0
    start = robot.position
    observations, _, _, _, infos = env.step({"robot_0": straight[0]})
    assert robot.position == (start[0] + MOVES[straight[0]][0], start[1] + MOVES[straight[0]][1])
    assert not infos["robot_0"]["invalid_action"]
    observations, _, _, _, infos = env.step({"robot_0": 0})  # sense all there is from here
    here = robot.position
    mask = observations["robot_0"]["action_mask"]
    invalid = [a for a in range(1, 9) if not mask[a]]
    assert invalid
    _, rewards, _, _, infos = env.step({"robot_0": invalid[0]})
    assert robot.position == here
    assert infos["robot_0"]["invalid_action"]
    assert rewards["robot_0"] == -0.5  # no new cell, no step cost, the penalty
    with pytest.raises(MrexploreInputError, match="Discrete"):
        env.step({"robot_0": 9})


def test_frontier_mode_goes_to_the_chosen_candidate_and_ignores_actions_en_route() -> None:
    env = parallel_env(**{**GENERATED, "fail": []}, action_mode="frontier", n_candidates=4)
    _, infos = env.reset(seed=8)
    simulation = env.simulation
    assert simulation is not None
    for agent in env.agents:
        assert infos[agent]["needs_decision"]
        robot = simulation.robots[int(agent.split("_")[1])]
        expected = frontier_candidates(robot.belief, robot.position, 4)
        assert infos[agent]["candidate_targets"] == [c.target for c in expected]
        distances = [c.distance for c in expected]
        assert distances == sorted(distances)
    targets = {a: infos[a]["candidate_targets"][0] for a in env.agents}
    _, _, _, _, infos = env.step(dict.fromkeys(env.agents, 0))
    for agent in env.agents:
        robot = simulation.robots[int(agent.split("_")[1])]
        assert robot.goal == targets[agent] or robot.goal is None  # None: reached in 1 tick
    travelling = [a for a in env.agents if not infos[a]["needs_decision"]]
    assert travelling
    goals = {a: simulation.robots[int(a.split("_")[1])].goal for a in travelling}
    _, _, _, _, infos = env.step(dict.fromkeys(env.agents, 1))
    for agent in travelling:
        assert infos[agent]["action_ignored"]
        goal = simulation.robots[int(agent.split("_")[1])].goal
        assert goal in (goals[agent], None)
    # needs_decision is exactly: no goal, or the goal is no longer a frontier cell.
    for agent in env.agents:
        robot = simulation.robots[int(agent.split("_")[1])]
        expected_flag = robot.goal is None or not frontier_at(robot.belief, *robot.goal)
        assert infos[agent]["needs_decision"] == expected_flag


@pytest.mark.parametrize("reward", ["team", "individual"])
def test_rewards_add_up_to_the_team_coverage_gain(reward: str) -> None:
    cost = 0.01
    settings = {**GENERATED, "fail": [], "max_ticks": 50}
    env = parallel_env(**settings, action_mode="frontier", reward=reward, step_cost=cost)
    observations, _ = env.reset(seed=4)
    simulation = env.simulation
    assert simulation is not None
    policy = RandomPolicy(env, seed=4)
    known = simulation.known_explorable
    total = 0.0
    while env.agents:
        observations, rewards, *_ = env.step(policy(observations))
        gain = (simulation.known_explorable - known) / simulation.n_explorable
        known = simulation.known_explorable
        shaped = [r + cost for r in rewards.values()]
        if reward == "team":
            assert shaped == pytest.approx([gain] * len(shaped))
        else:
            assert sum(shaped) == pytest.approx(gain)
        total += gain
    assert total > 0


def test_coverage_threshold_terminates_every_agent() -> None:
    settings = {**GENERATED, "fail": [], "max_ticks": None, "coverage_threshold": 0.3}
    env = parallel_env(**settings, action_mode="frontier")
    observations, _ = env.reset(seed=1)
    policy = RandomPolicy(env, seed=1)
    while env.agents:
        observations, _, terminated, truncated, _ = env.step(policy(observations))
    assert env.simulation is not None and env.simulation.status == "complete"
    assert all(terminated.values()) and not any(truncated.values())


@pytest.mark.parametrize("mode", ["frontier", "move"])
def test_an_episode_writes_a_valid_run_record(mode: str, tmp_path: Path) -> None:
    env = parallel_env(**GENERATED, action_mode=mode)
    observations, _ = env.reset(seed=3)
    policy = RandomPolicy(env, seed=3)
    while env.agents:
        observations, *_ = env.step(policy(observations))
    written = env.save(tmp_path / "run", policy="random", png=False)
    result = json.loads(written["result"].read_text())
    assert result["strategy"] == "random"
    assert result["params"]["action_mode"] == mode
    assert result["status"] == "max_ticks" and result["ticks"] == 40
    assert result["robots_failed"] == 1
    with np.load(written["trace"]) as trace:
        arrays = {name: trace[name] for name in trace.files}
    assert arrays["positions"].shape == (41, 3, 2)
    assert check_trace(arrays, result) == []


def test_bad_settings_and_actions_are_refused() -> None:
    with pytest.raises(ScenarioError, match="unknown setting 'colour'"):
        parallel_env(**GENERATED, colour="red")
    with pytest.raises(ScenarioError, match="action_mode"):
        parallel_env(**GENERATED, action_mode="teleport")
    with pytest.raises(ScenarioError, match="robots"):
        parallel_env(**{**GENERATED, "robots": 0})
    with pytest.raises(ScenarioError, match="start_delay 5: not in the env"):
        parallel_env(**GENERATED, start_delay=5)
    env = parallel_env(**GENERATED)
    with pytest.raises(RuntimeError, match="reset"):
        env.step({})
    env.reset(seed=0)
    with pytest.raises(MrexploreInputError, match="no agent"):
        env.step({"robot_9": 0})
    with pytest.raises(MrexploreInputError, match="Discrete"):
        env.step({"robot_0": "left"})


def test_cli_style_values_and_render() -> None:
    env = parallel_env(
        map="office", size="32x32", robots=2, fail=["1@5"], render_mode="rgb_array", max_ticks=8
    )
    env.reset(seed=1)
    image = env.render()
    assert image is not None and image.shape == (32, 32, 3) and image.dtype == np.uint8
    assert env.scenario_kwargs["fail"] == [(1, 5)]
