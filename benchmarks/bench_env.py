"""Throughput of the PettingZoo environment: agent-steps per second.

Usage::

    .venv/bin/python benchmarks/bench_env.py [--modes move frontier] [--steps 1000 200]
        [--repeats 3]

Two settings: 4 robots on a 64 x 64 ``office`` map and 16 robots on a 256 x 256
``office`` map (sensor range 8, communication range 16, full map sharing). A
random policy picks a valid action for every live agent at every step
(:class:`mrexplore.env.RandomPolicy`, never ``stay`` while it can move). An
agent-step is one agent acting in one ``env.step``; the time counts
``env.step`` only (the simulator's tick plus building every observation, reward
and info), not the policy nor ``reset``. A short warm-up episode compiles the
numba kernels first. The ``sim share`` column is the part of that time spent in
``Simulation.step`` itself. Each setting is measured ``--repeats`` times (fresh
env, same seeds) and the row with the median throughput is shown.

Needs the ``rl`` extra (pettingzoo, gymnasium).
"""

from __future__ import annotations

import argparse
import statistics
import time
from typing import Any

from mrexplore.env import RandomPolicy, parallel_env
from mrexplore.sim.engine import Decider, Simulation

SETTINGS: list[tuple[str, dict[str, Any]]] = [
    ("4 robots, 64 x 64", {"map": "office", "size": (64, 64), "robots": 4}),
    ("16 robots, 256 x 256", {"map": "office", "size": (256, 256), "robots": 16}),
]
COMMON = {"sensor_range": 8, "comm_range": 16}


def _timed(simulation: Simulation | None, spent: list[float]) -> None:
    """Make this simulation's ``step`` add the seconds it takes to ``spent[0]``."""
    assert simulation is not None
    original = simulation.step

    def step(decide: Decider | None = None) -> str | None:
        started = time.perf_counter()
        try:
            return original(decide)
        finally:
            spent[0] += time.perf_counter() - started

    simulation.step = step  # type: ignore[method-assign]  # benchmark only: time the tick


def measure(settings: dict[str, Any], mode: str, steps: int, seed: int) -> dict[str, float]:
    env = parallel_env(**settings, **COMMON, action_mode=mode, max_ticks=steps + 1)
    policy = RandomPolicy(env, seed=seed)
    observations, _ = env.reset(seed=seed + 1000)  # warm-up: compile the kernels
    for _ in range(5):
        observations, *_ = env.step(policy(observations))
    observations, _ = env.reset(seed=seed)
    sim_seconds = [0.0]
    _timed(env.simulation, sim_seconds)
    agent_steps, env_seconds, done = 0, 0.0, 0
    while done < steps:
        if not env.agents:
            observations, _ = env.reset()
            _timed(env.simulation, sim_seconds)
        actions = policy(observations)
        started = time.perf_counter()
        observations, *_ = env.step(actions)
        env_seconds += time.perf_counter() - started
        agent_steps += len(actions)
        done += 1
    return {
        "steps": done,
        "agent_steps": agent_steps,
        "seconds": env_seconds,
        "agent_steps_per_s": agent_steps / env_seconds,
        "ms_per_step": 1000 * env_seconds / done,
        "sim_share": sim_seconds[0] / env_seconds,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", nargs="+", default=["move"], choices=["move", "frontier"])
    parser.add_argument(
        "--steps", nargs=2, type=int, default=[1000, 200], help="env steps per setting"
    )
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print("| mode | setting | env steps | agent-steps/s | ms per env step | sim share |")
    print("|---|---|---:|---:|---:|---:|")
    for mode in args.modes:
        for (name, settings), steps in zip(SETTINGS, args.steps, strict=True):
            rows = [measure(settings, mode, steps, args.seed) for _ in range(args.repeats)]
            median = statistics.median_low(r["agent_steps_per_s"] for r in rows)
            row = next(r for r in rows if r["agent_steps_per_s"] == median)
            print(
                f"| {mode} | {name} | {row['steps']:.0f} | {row['agent_steps_per_s']:,.0f} "
                f"| {row['ms_per_step']:.2f} | {row['sim_share']:.0%} |"
            )


if __name__ == "__main__":
    main()
