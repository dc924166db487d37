"""Run every baseline strategy with 1, 4 and 8 robots on every generator and every
map of the catalogue (:data:`mrexplore.grid.catalogue.CATALOGUE`), check each trace
against the run contract, and print one row per run.

    python benchmarks/check_all_maps.py [--workers 2] [--strategies ...] [--robots ...]

Settings: generators at their default size with an 8-cell sensor; MovingAI maps
at their own cells with an 8-cell sensor; ROS maps resampled to 0.1 m cells (never
finer than the file) with a 3 m sensor.
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

from mrexplore.checks import check_trace
from mrexplore.grid import GENERATORS
from mrexplore.grid.catalogue import CATALOGUE
from mrexplore.sim.engine import simulate
from mrexplore.sim.scenario import Scenario


def settings() -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = [{"map": name, "sensor_range": 8} for name in GENERATORS]
    for entry in CATALOGUE:
        if entry.kind == "movingai":
            out.append({"map": entry.name, "sensor_range": 8})
        else:
            out.append({"map": entry.name, "cell_size": 0.1, "sensor_range": "3m"})
    return out


def one(args: tuple[dict[str, Any], str, int, int | None]) -> str:
    setting, strategy, robots, max_ticks = args
    scenario = Scenario(**setting, robots=robots, strategy=strategy, seed=1, max_ticks=max_ticks)
    started = time.perf_counter()
    record = simulate(scenario)
    wall = time.perf_counter() - started
    problems = check_trace(record.trace_arrays(), record.result())
    name = str(setting["map"])
    shape = "x".join(str(v) for v in record.world.grid.shape[::-1])
    return (
        f"{name:<28}{shape:>10}{strategy:>18}{robots:>4}{record.status:>10}{record.ticks:>7}"
        f"{100 * record.known_explorable[-1] / record.world.n_explorable:>8.1f}%{wall:>8.1f}s"
        f"  {'trace ok' if not problems else 'TRACE: ' + problems[0]}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument(
        "--strategies", nargs="+", default=["random-frontier", "nearest-frontier", "burgard"]
    )
    parser.add_argument("--robots", nargs="+", type=int, default=[1, 4, 8])
    parser.add_argument("--max-ticks", type=int, default=None, help="default: automatic")
    args = parser.parse_args()
    jobs = [
        (setting, strategy, robots, args.max_ticks)
        for setting in settings()
        for strategy in args.strategies
        for robots in args.robots
    ]
    with ProcessPoolExecutor(args.workers) as pool:
        for row in pool.map(one, jobs):
            print(row, flush=True)


if __name__ == "__main__":
    main()
