"""vazquez-network: does every combination of the behaviour readings complete?

    python benchmarks/vazquez_combos.py [--quick] [--workers 2] [--out runs.json]
        [--set broken_bridge_frontier=both-leave]

The 24 combinations of ``constrain_bridges`` (stretched | always), ``no_frontier_rule``
(approach | convoy), ``zone_includes_targets`` (False | True) and
``replan_on_behaviour`` (reroute-collision | any | connectivity), each on generated
offices (40 x 40 and 50 x 50, map seeds 1-2) with 2, 3, 4 and 6 robots, seeds 1-4 and
sensor ranges 3 and 4.5 cells, at a communication range of a third of the map width
(13 and 17 cells), ``coverage_threshold`` 1.0, ``max_ticks`` 6000 and ``stall_ticks``
400 (a run with no new cell for 400 ticks ends ``stalled``): 128 runs per combination.
``--set`` fixes further parameters for every run (e.g. ``broken_bridge_frontier=both-leave``).
The project promises that all of them end ``complete`` (docs/strategies/vazquez-network.md).
``--quick``: the 40 x 40 office of map seed 1, 2 and 3 robots, seeds 1-2, sensor 3
(4 runs per combination).

Prints, per combination, the runs not ``complete`` out of the runs made, and the
settings and status of each of them. ``--out`` writes every run (settings, status,
ticks and a digest of the positions and goals) as JSON, so that two versions of the
strategy can be compared run by run (the default combination must not change).
"""

from __future__ import annotations

import argparse
import hashlib
import itertools
import json
import time
from multiprocessing import Pool
from pathlib import Path
from typing import Any

from mrexplore.sim import Scenario, simulate

RULES: dict[str, tuple[Any, ...]] = {
    "constrain_bridges": ("stretched", "always"),
    "no_frontier_rule": ("approach", "convoy"),
    "zone_includes_targets": (False, True),
    "replan_on_behaviour": ("reroute-collision", "any", "connectivity"),
}
DEFAULT = {"constrain_bridges": "stretched", "no_frontier_rule": "approach",
           "zone_includes_targets": False,
           "replan_on_behaviour": "reroute-collision"}  # fmt: skip
MAX_TICKS = 6000


def combinations() -> list[dict[str, Any]]:
    return [dict(zip(RULES, values, strict=True)) for values in itertools.product(*RULES.values())]


def runs(quick: bool) -> list[dict[str, Any]]:
    """The settings of every run besides the combination (map, team, seed, sensor)."""
    if quick:
        maps, robots, seeds, sensors = [(40, 1)], (2, 3), (1, 2), (3.0,)
    else:
        maps = [(40, 1), (40, 2), (50, 1), (50, 2)]
        robots, seeds, sensors = (2, 3, 4, 6), (1, 2, 3, 4), (3.0, 4.5)
    return [
        {"width": w, "map_seed": m, "robots": n, "seed": s, "sensor_range": r}
        for (w, m), n, s, r in itertools.product(maps, robots, seeds, sensors)
    ]


def scenario(params: dict[str, Any], run: dict[str, Any]) -> Scenario:
    width = run["width"]
    return Scenario(
        map="office",
        size=(width, width),
        map_seed=run["map_seed"],
        robots=run["robots"],
        seed=run["seed"],
        sensor_range=run["sensor_range"],
        comm_range=round(width / 3),
        strategy="vazquez-network",
        params=params,
        coverage_threshold=1.0,
        max_ticks=MAX_TICKS,
        stall_ticks=400,
    )


def one(job: tuple[dict[str, Any], dict[str, Any]]) -> dict[str, Any]:
    params, run = job
    record = simulate(scenario(params, run))
    digest = hashlib.sha256(record.positions.tobytes() + record.goals.tobytes()).hexdigest()
    return {
        "params": params,
        "run": run,
        "status": record.status,
        "ticks": int(record.ticks),
        "coverage": float(record.known_explorable[-1]) / max(record.world.n_explorable, 1),
        "digest": digest[:16],
    }


def label(params: dict[str, Any]) -> str:
    return " ".join(f"{k}={v}" for k, v in params.items())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="4 runs per combination")
    parser.add_argument("--workers", type=int, default=2, help="processes (1 = sequential)")
    parser.add_argument("--out", type=Path, help="write every run as JSON")
    parser.add_argument(
        "--only", nargs="+", type=int, help="combination numbers (0-23, as printed)"
    )
    parser.add_argument("--set", nargs="+", default=[], help="KEY=VALUE for every run")
    args = parser.parse_args()
    extra = dict(item.split("=", 1) for item in args.set)  # text, as --set gives it
    combos = [{**params, **extra} for params in combinations()]
    chosen = args.only if args.only is not None else range(len(combos))
    jobs = [(combos[i], run) for i in chosen for run in runs(args.quick)]
    started = time.perf_counter()
    if args.workers > 1:
        with Pool(args.workers) as pool:
            results = list(pool.imap(one, jobs, chunksize=4))
    else:
        results = [one(job) for job in jobs]
    took = time.perf_counter() - started
    print(f"{len(results)} runs in {took:.0f} s; not complete per combination:")
    failed_total = 0
    for i in chosen:
        params = combos[i]
        mine = [r for r in results if r["params"] == params]
        failed = [r for r in mine if r["status"] != "complete"]
        failed_total += len(failed)
        mark = " (default)" if params == {**DEFAULT, **extra} else ""
        print(f"[{i:2d}] {label(params)}{mark}: {len(failed)}/{len(mine)}")
        for r in failed:
            run = r["run"]
            print(
                f"       {run['width']}x{run['width']} map_seed={run['map_seed']} "
                f"robots={run['robots']} seed={run['seed']} sensor={run['sensor_range']:g}: "
                f"{r['status']} at tick {r['ticks']}, coverage {r['coverage']:.4f}"
            )
    print(f"total not complete: {failed_total}/{len(results)}")
    if args.out is not None:
        args.out.write_text(json.dumps(results, indent=0) + "\n")


if __name__ == "__main__":
    main()
