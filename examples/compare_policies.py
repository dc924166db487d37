"""A random policy and ``burgard`` through the RL environment, on the same maps and seeds.

Usage::

    .venv/bin/python examples/compare_policies.py [--seeds 1 2 3] [--robots 4]
        [--map office --size 64x64] [--comm-range 16] [--out runs/compare]

Both run through :func:`mrexplore.env.parallel_env` with the same scenario and
the same episode seeds, so they see the same map, start cells and communication
randomness:

* ``random``: ``action_mode="frontier"``, each robot that must choose picks one
  of its (up to 8) nearest frontier clusters uniformly at random
  (:class:`mrexplore.env.RandomPolicy`); swap in a learned policy here.
* ``burgard``: ``action_mode="decision"``, the registered strategy run through
  the env by :class:`mrexplore.env.StrategyPolicy` (its trace is exactly that of
  ``mrexplore run --strategy burgard``).

Each episode's run record gives the same metrics as ``mrexplore run``; with
``--out`` it is written as ``result.json`` + ``trace.npz`` (open one with
``mrexplore replay``). Needs the ``rl`` extra.
"""

from __future__ import annotations

import argparse
import math
import statistics
from typing import Any

from mrexplore.env import RandomPolicy, StrategyPolicy, parallel_env

METRICS = ("status", "ticks", "T90", "explored_fraction", "total_distance", "bytes_total")


def run_episode(policy_name: str, scenario: dict[str, Any], seed: int, out: str | None) -> dict:
    """One episode of ``policy_name`` (``random`` or a strategy id); its ``result.json``."""
    if policy_name == "random":
        env = parallel_env(**scenario, action_mode="frontier")
        policy: Any = RandomPolicy(env, seed=seed)
    else:
        env = parallel_env(**scenario, strategy=policy_name, action_mode="decision")
        policy = StrategyPolicy(env)
    observations, _ = env.reset(seed=seed)
    while env.agents:
        observations, *_ = env.step(policy(observations))
    if out is not None:
        env.save(f"{out}/{policy_name}-seed{seed}", policy=policy_name)
    return env.record(policy_name).result()


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        return "-" if math.isnan(value) else f"{value:.3g}"
    return "-" if value is None else str(value)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default="office")
    parser.add_argument("--size", default="64x64")
    parser.add_argument("--robots", type=int, default=4)
    parser.add_argument("--sensor-range", type=float, default=6.0)
    parser.add_argument("--comm-range", type=float, default=16.0)
    parser.add_argument("--max-ticks", type=int, default=3000)
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--out", help="write each episode's result.json and trace.npz here")
    args = parser.parse_args()
    scenario = {
        "map": args.map,
        "size": args.size,
        "robots": args.robots,
        "sensor_range": args.sensor_range,
        "comm_range": args.comm_range,
        "max_ticks": args.max_ticks,
    }
    policies = ("random", "burgard")
    results = {
        (name, seed): run_episode(name, scenario, seed, args.out)
        for seed in args.seeds
        for name in policies
    }
    header = ["seed", "metric", *policies]
    rows = []
    for seed in args.seeds:
        for metric in METRICS:
            rows.append(
                [str(seed), metric, *(_fmt(results[p, seed].get(metric)) for p in policies)]
            )
    for metric in METRICS[1:]:
        means = []
        for name in policies:
            values = [results[name, seed].get(metric) for seed in args.seeds]
            numbers = [float(v) for v in values if v is not None]
            means.append(_fmt(statistics.fmean(numbers)) if numbers else "-")
        rows.append(["mean", metric, *means])
    widths = [max(len(row[i]) for row in [header, *rows]) for i in range(len(header))]
    for row in [header, ["-" * w for w in widths], *rows]:
        print("  ".join(cell.rjust(width) for cell, width in zip(row, widths, strict=True)))


if __name__ == "__main__":
    main()
