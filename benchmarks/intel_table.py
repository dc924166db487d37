"""T99 and total distance of every strategy on the Intel map, 4 robots, seeds 1-5.

    python benchmarks/intel_table.py [--workers 2] [--strategies ...]

Settings: Intel lab (the catalogue map ``intel``) at 0.2 m cells, 3 m sensor,
unlimited communication.
"""

from __future__ import annotations

import argparse
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from mrexplore.sim.engine import simulate
from mrexplore.sim.scenario import Scenario
from mrexplore.strategies import available_strategies


def one(job: tuple[str, int]) -> tuple[str, int, str, int | None, float]:
    strategy, seed = job
    scenario = Scenario(
        map="intel",
        cell_size=0.2,
        sensor_range="3m",
        robots=4,
        strategy=strategy,
        seed=seed,
    )
    result = simulate(scenario).result()
    return strategy, seed, result["status"], result["T99"], result["total_distance"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--strategies", nargs="+", default=list(available_strategies()))
    parser.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3, 4, 5])
    args = parser.parse_args()
    jobs = [(s, seed) for s in args.strategies for seed in args.seeds]
    rows: dict[str, list[tuple[str, int | None, float]]] = {}
    with ProcessPoolExecutor(args.workers) as pool:
        for strategy, _seed, status, t99, distance in pool.map(one, jobs):
            rows.setdefault(strategy, []).append((status, t99, distance))
    print(f"{'strategy':<18}{'T99 mean':>10}{'distance mean':>15}  statuses")
    for strategy, runs in rows.items():
        t99 = [r[1] for r in runs if r[1] is not None]
        statuses = ",".join(sorted({r[0] for r in runs}))
        mean_t99 = f"{np.mean(t99):.1f}" if len(t99) == len(runs) else "n/a"
        print(f"{strategy:<18}{mean_t99:>10}{np.mean([r[2] for r in runs]):>15.1f}  {statuses}")


if __name__ == "__main__":
    main()
