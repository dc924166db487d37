"""How many of the grid detector's frontiers the RRT detector finds, and T99 with each.

    PYTHONPATH=src python benchmarks/rrt_coverage.py [--maps intel office] [--every 25]
        [--configs grid rrt rrt-old] [--seeds 1] [--workers 2]

Runs ``market-occupancy`` with 2 robots, seed 1, in the settings of ``mrexplore
reproduce market2018`` (start together, unlimited communication, latency 1, 99%
coverage, no frontier filter): the Intel lab at 0.2 m cells with a 3 m sensor (15
cells), and the generated office 120 x 80 (``map_seed = 1``, sensor 15 cells).

Every ``--every`` ticks, for each robot: the 8-connected clusters of frontier cells of
its map with at least 5 cells, and the points its RRT detector holds (the clustered
store, :meth:`RrtFrontierDetector.points`, computed on a copy so that measuring does not
change the run). A cluster is *covered* when a point lies within 2 cells (Euclidean)
of one of its cells. Printed: the share of covered clusters over all snapshots and
robots, the mean number of points a robot holds, and T99 (ticks to 99% of the
explorable cells) of each configuration.

Configurations: ``grid`` (grid detector), ``rrt`` (RRT detector with the defaults of
the code on the path), ``rrt-old`` (the RRT detector with the parameter values that
were the defaults before issue 17: 20 samples per tree per tick, ``eta`` = sensor
range, greedy merging within half the sensor range, no RRT gain filter; on code after
issue 17 the iterations of a tick are sequential, so this is not the earlier code: run
the script with an older ``src`` on the path for that, configurations ``grid rrt``); on request,
the new defaults with one value back at its old one (``rrt-20``, ``rrt-eta-r``,
``rrt-greedy``, ``rrt-nofilter``).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from mrexplore.planning import frontier_clusters, frontier_mask
from mrexplore.sim.engine import Simulation
from mrexplore.sim.scenario import Scenario

MAPS: dict[str, dict[str, Any]] = {
    "intel": {"map": "intel", "cell_size": 0.2, "sensor_range": "3m", "max_ticks": 10000},
    "office": {
        "map": "office",
        "size": (120, 80),
        "map_seed": 1,
        "sensor_range": 15,
        "max_ticks": 10000,
    },
}
FIXED: dict[str, Any] = {
    "robots": 2,
    "seed": 1,
    "strategy": "market-occupancy",
    "start": "together",
    "comm_range": math.inf,
    "latency": 1,
    "coverage_threshold": 0.99,
    "idle_ticks": 70,
}
CONFIGS: dict[str, dict[str, Any]] = {
    "grid": {"frontier_detector": "grid"},
    "rrt": {"frontier_detector": "rrt"},
    "rrt-old": {
        "frontier_detector": "rrt",
        "rrt_samples": 20,
        "rrt_eta": 0.0,
        "rrt_clustering": "greedy",
        "rrt_cluster_radius": 0.0,
        "rrt_filter_min_gain": 0.0,
    },
    # The new defaults with one of them back at its old value (not run unless asked).
    "rrt-20": {"frontier_detector": "rrt", "rrt_samples": 20},
    "rrt-eta-r": {"frontier_detector": "rrt", "rrt_eta": 0.0},
    "rrt-greedy": {"frontier_detector": "rrt", "rrt_clustering": "greedy"},
    "rrt-nofilter": {"frontier_detector": "rrt", "rrt_filter_min_gain": 0.0},
}
DEFAULT_CONFIGS = ("grid", "rrt", "rrt-old")
MIN_CLUSTER = 5
NEAR = 2.0


def coverage(simulation: Simulation) -> tuple[int, int, int]:
    """``(covered, total)`` clusters of >= 5 cells over the robots, and the points held, now."""
    covered = total = held = 0
    for robot, strategy in zip(simulation.robots, simulation.strategies, strict=True):
        detector = getattr(strategy, "detector", None)
        if detector is None:
            continue
        belief = robot.belief
        points = dataclasses.replace(detector, store=detector.store.copy()).points(belief)
        held += points.shape[0]
        for cluster in frontier_clusters(frontier_mask(belief), min_size=MIN_CLUSTER):
            total += 1
            if points.shape[0] == 0:
                continue
            cells = cluster.cells.astype(np.float64)
            d2 = (cells[:, None, 0] - points[None, :, 0]) ** 2
            d2 += (cells[:, None, 1] - points[None, :, 1]) ** 2
            covered += bool((d2 <= NEAR * NEAR).any())
    return covered, total, held


Row = tuple[str, str, int, str, int | None, int, int, int, int, float]


def one(job: tuple[str, str, int, int]) -> Row:
    map_key, config, seed, every = job
    scenario = Scenario(**MAPS[map_key], **{**FIXED, "seed": seed}, params=CONFIGS[config])
    simulation = Simulation(scenario)
    simulation.start()
    covered = total = held = snapshots = 0
    while simulation.step() is None:
        if simulation.tick % every == 0:
            c, t, h = coverage(simulation)
            covered, total, held, snapshots = covered + c, total + t, held + h, snapshots + 1
    result = simulation.finish().result()
    per_decide_ms = 1000 * simulation.decide_seconds / max(1, simulation.decisions)
    status, t99 = result["status"], result["T99"]
    return map_key, config, seed, status, t99, covered, total, held, snapshots, per_decide_ms


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", nargs="+", default=list(MAPS), choices=list(MAPS))
    parser.add_argument(
        "--configs", nargs="+", default=list(DEFAULT_CONFIGS), choices=list(CONFIGS)
    )
    parser.add_argument("--seeds", nargs="+", type=int, default=[1])
    parser.add_argument("--every", type=int, default=25, help="ticks between snapshots")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    jobs = [(m, c, s, args.every) for m in args.maps for c in args.configs for s in args.seeds]
    print(
        f"{'map':<8}{'config':<14}{'seed':>5}  {'status':<10}{'T99':>6}"
        f"{'covered':>15}{'points':>8}{'ms/decide':>11}"
    )
    with ProcessPoolExecutor(args.workers) as pool:
        for row in pool.map(one, jobs):
            map_key, config, seed, status, t99, covered, total, held, snapshots, ms = row
            share = f"{100 * covered / total:.0f}% of {total}" if total else "-"
            points = f"{held / snapshots / FIXED['robots']:.0f}" if held else "-"
            print(
                f"{map_key:<8}{config:<14}{seed:>5}  {status:<10}{t99 or '-':>6}"
                f"{share:>15}{points:>8}{ms:>11.2f}"
            )


if __name__ == "__main__":
    main()
