"""Do vazquez-network's behaviour readings ever livelock? Every combination, many maps.

    python benchmarks/vazquez_combos.py [--quick] [--workers N]

Runs every combination of the strategy's behaviour readings (``constrain_bridges``,
``no_frontier_rule``, ``zone_includes_targets``, ``zone_between_pair``,
``replan_on_behaviour``) on generated offices (40 x 40 map seed 1, 50 x 50 map seed 2),
with 2, 3, 4 and 6 robots, seeds 1-3, at a range of a third of the map's width
(sensor 4.5 cells, multi-hop ``broadcast`` sharing, coverage 1.0), and prints, per
combination, the runs that did not end ``complete`` with their settings. ``--quick``:
one map, 2 and 4 robots, seeds 1-2.
"""

from __future__ import annotations

import argparse
import itertools
from multiprocessing import Pool
from typing import Any

from mrexplore.sim import Scenario, simulate

READINGS: dict[str, tuple[Any, ...]] = {
    "constrain_bridges": ("stretched", "always"),
    "no_frontier_rule": ("approach", "convoy"),
    "zone_includes_targets": (False, True),
    "zone_between_pair": (True, False),
    "replan_on_behaviour": ("any", "connectivity"),
}


def one(job: tuple[dict[str, Any], int, int, int, int]) -> tuple[str, str, str, int]:
    params, side, map_seed, robots, seed = job
    scenario = Scenario(
        map="office",
        size=(side, side),
        map_seed=map_seed,
        robots=robots,
        seed=seed,
        sensor_range=4.5,
        comm_range=side // 3,
        sharing="broadcast",
        strategy="vazquez-network",
        params=params,
        coverage_threshold=1.0,
    )
    record = simulate(scenario)
    combo = " ".join(f"{k}={v}" for k, v in params.items())
    where = f"office {side}x{side} map_seed {map_seed}, {robots} robots, seed {seed}"
    return combo, where, record.status, record.ticks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    maps = [(40, 1)] if args.quick else [(40, 1), (50, 2)]
    teams, seeds = ((2, 4), (1, 2)) if args.quick else ((2, 3, 4, 6), (1, 2, 3))
    combos = [
        dict(zip(READINGS, values, strict=True)) for values in itertools.product(*READINGS.values())
    ]
    jobs = [
        (combo, side, map_seed, robots, seed)
        for combo in combos
        for side, map_seed in maps
        for robots in teams
        for seed in seeds
    ]
    failed: dict[str, list[str]] = {}
    counts: dict[str, int] = {}
    with Pool(args.workers) as pool:
        for combo, where, status, ticks in pool.imap_unordered(one, jobs):
            counts[combo] = counts.get(combo, 0) + 1
            if status != "complete":
                failed.setdefault(combo, []).append(f"{where}: {status} at tick {ticks}")
    for combo in sorted(counts):
        bad = failed.get(combo, [])
        print(f"{len(bad)}/{counts[combo]} not complete: {combo}")
        for line in bad:
            print(f"    {line}")


if __name__ == "__main__":
    main()
