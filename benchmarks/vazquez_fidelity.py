"""vazquez-network against nearest-frontier in the setting of the fidelity review.

    python benchmarks/vazquez_fidelity.py [--workers 2] [--set key=value ...]

Office 72 x 72 (``map_seed`` 1, the reproduction's small environment at 5 cm a cell),
sensor radius 4.5 cells, start together, coverage 1.0, seeds 1-3, 2 / 4 / 8 robots;
communication range 20 and 40 cells (1 m and 2 m) with ``broadcast`` (the paper's
sharing: sensed cells relayed hop by hop) and ``full`` (whole maps on reconnection)
sharing, and unlimited range with ``full``. Both methods re-plan on arrival only (the
paper's rule: ``replan_on_target_explored=false``). ``--set`` passes parameters to
vazquez-network (e.g. ``broken_bridge_frontier=both-leave``).

Prints, per setting, method and team size, the mean over the seeds of ``T100`` (the
team's union of beliefs holds every explorable cell), ``first`` (``T100_first_robot``:
one robot's own map does; ``broadcast`` runs end when it does, ``complete_when=robot``)
and ``conn`` (share of ticks the team is one sub-network), and how many runs did not
complete. The table is in docs/strategies/vazquez-network.md ("Results").
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
from multiprocessing import Pool
from typing import Any

import numpy as np

from mrexplore.sim import Scenario, simulate

SETTINGS = [(20.0, "broadcast"), (20.0, "full"), (40.0, "broadcast"), (40.0, "full"),
            (math.inf, "full")]  # fmt: skip
METHODS = ("vazquez-network", "nearest-frontier")
ROBOTS, SEEDS = (2, 4, 8), (1, 2, 3)


def one(job: tuple[float, str, str, int, int, dict[str, Any]]) -> dict[str, Any]:
    comm_range, sharing, method, robots, seed, extra = job
    params = {"replan_on_target_explored": False}
    if method == "vazquez-network":
        params.update(extra)
    record = simulate(
        Scenario(
            map="office",
            size=(72, 72),
            map_seed=1,
            robots=robots,
            seed=seed,
            sensor_range=4.5,
            start="together",
            coverage_threshold=1.0,
            comm_range=comm_range,
            sharing=sharing,
            strategy=method,
            params=params,
            complete_when="robot" if sharing == "broadcast" else "team",
        )
    )
    metrics = record.result()
    return {
        "job": job[:5],
        "status": record.status,
        "T100": metrics["T100"] if metrics["T100"] is not None else record.ticks,
        "first": metrics.get("T100_first_robot"),
        "conn": float((np.asarray(record.subnetworks) <= 1).mean()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--set", nargs="+", default=[], help="KEY=VALUE for vazquez-network")
    args = parser.parse_args()
    extra = dict(item.split("=", 1) for item in args.set)  # text, as --set gives it
    jobs = [
        (r, s, m, n, seed, extra)
        for (r, s), m, n, seed in itertools.product(SETTINGS, METHODS, ROBOTS, SEEDS)
    ]
    with Pool(args.workers) as pool:
        results = pool.map(one, jobs)
    print("| setting | method | " + " | ".join(f"{n} robots: T100 / first / conn" for n in ROBOTS))
    print("|---" * (2 + len(ROBOTS)) + "|")
    for (r, s), m in itertools.product(SETTINGS, METHODS):
        cells = []
        for n in ROBOTS:
            runs = [x for x in results if x["job"][:4] == (r, s, m, n)]
            t100 = statistics.mean(x["T100"] for x in runs)
            firsts = [x["first"] for x in runs if x["first"] is not None]
            first = f"{statistics.mean(firsts):.0f}" if len(firsts) == len(runs) else "-"
            conn = statistics.mean(x["conn"] for x in runs)
            failed = sum(x["status"] != "complete" for x in runs)
            cells.append(
                f"{t100:.0f} / {first} / {conn:.2f}" + (f" ({failed} not)" if failed else "")
            )
        print(f"| range {r:g}, `{s}` | `{m}` | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
