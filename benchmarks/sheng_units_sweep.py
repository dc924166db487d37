"""The w3 x eq2_units sweep of sheng-bidding on the paper's Table 4 scenario.

    python benchmarks/sheng_units_sweep.py [SPEED] [--table4]   # SPEED 1 (default) or 0.25

``sheng40``, r_s 4, r_c 16, 5 robots starting together, sensing on arrival,
``sheng-sync``, seeds 1-6; with ``--table4`` as the reproduction's Table 4 runs (the
same cells in every run, start ticks drawn from 0..16). For each reading of eq. (2)'s
units and each w3: mean T100 (ticks; the run's length if unfinished), total distance
(cells), mean group diameter (cells), the share of ticks with more than one
sub-network, and the map data of the merges (bytes per run, ``sheng-sync``'s steps
4-10 as sent, and what the brute force would have sent in the same run). The table is
in ``docs/reproductions/sheng2006.md`` ("What does not").
"""

from __future__ import annotations

import statistics
import sys
from multiprocessing import Pool
from typing import Any

import numpy as np

from mrexplore.sim import Scenario, simulate

UNITS = ("raw", "cells", "unit-free")
W3 = (0.0, 0.5, 1.0, 1.5, 2.0)
SEEDS = range(1, 7)


def one(job: tuple[str, float, int, float, bool]) -> tuple[tuple[str, float], dict[str, Any]]:
    units, w3, seed, speed, table4 = job
    start: Any = "together"
    if table4:
        from mrexplore.experiments.reproduce.sheng2006 import START_DELAY, table4_starts

        start, delay = [tuple(c) for c in table4_starts()], START_DELAY
    else:
        delay = 0
    scenario = Scenario(
        map="sheng40",
        robots=5,
        seed=seed,
        sensor_range=4,
        comm_range=16,
        sensing="arrival",
        start=start,
        start_delay=delay,
        coverage_threshold=1.0,
        sharing="sheng-sync",
        strategy="sheng-bidding",
        speed=speed,
        params={"w3": w3, "eq2_units": units},
    )
    record = simulate(scenario)
    result = record.result()
    return (units, w3), {
        "time": result["T100"] or result["ticks"],
        "distance": result["total_distance"],
        "diameter": result["group_diameter_mean"],
        "partitioned": float((np.asarray(record.subnetworks) > 1).mean()),
        "with": float(result.get("sync_bytes_with_tracking") or 0),
        "without": float(result.get("sync_bytes_without_tracking") or 0),
        "complete": result["status"] == "complete",
    }


def main() -> None:
    args = [a for a in sys.argv[1:] if a != "--table4"]
    speed, table4 = float(args[0]) if args else 1.0, "--table4" in sys.argv
    jobs = [(u, w, s, speed, table4) for u in UNITS for w in W3 for s in SEEDS]
    found: dict[tuple[str, float], list[dict[str, Any]]] = {}
    with Pool(2) as pool:
        for key, values in pool.imap(one, jobs):
            found.setdefault(key, []).append(values)
    head = "eq2_units | w3 | time | distance | diameter | partitioned | bytes with | without"
    print(f"speed {speed:g}{', Table 4 starts' if table4 else ''}: {head} | complete")
    for (units, w3), runs in found.items():
        mean = {k: statistics.mean(r[k] for r in runs) for k in runs[0] if k != "complete"}
        done = sum(r["complete"] for r in runs)
        print(
            f"{units} | {w3:g} | {mean['time']:.0f} | {mean['distance']:.0f} | "
            f"{mean['diameter']:.1f} | {mean['partitioned']:.2f} | {mean['with']:.0f} | "
            f"{mean['without']:.0f} | {done}/{len(runs)}"
        )


if __name__ == "__main__":
    main()
