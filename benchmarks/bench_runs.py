"""Whole-run benchmark: wall time per run, ticks, and time per decision.

Runs 1, 8 and 32 robots on 200 x 200 and 500 x 500 generated offices and on the
Intel lab map (the catalogue map ``intel``, native 0.05 m cells), with the
baseline strategies by default. Prints one row per run. Not a test: numbers
depend on the machine.

    python benchmarks/bench_runs.py [--strategies burgard ...] [--robots 1 8 32]
"""

from __future__ import annotations

import argparse
import time

from mrexplore.sim.engine import Simulation
from mrexplore.sim.scenario import Scenario


def scenarios(
    strategies: list[str], robots: list[int], max_ticks: int | None
) -> list[tuple[str, Scenario]]:
    maps: list[tuple[str, dict[str, object]]] = [
        ("office 200x200", {"map": "office", "size": (200, 200), "sensor_range": 10}),
        ("office 500x500", {"map": "office", "size": (500, 500), "sensor_range": 10}),
        ("intel 0.05m", {"map": "intel", "sensor_range": "1.5m"}),
    ]
    out = []
    for label, settings in maps:
        for strategy in strategies:
            for n in robots:
                out.append(
                    (
                        label,
                        Scenario(
                            **settings, robots=n, strategy=strategy, seed=1, max_ticks=max_ticks
                        ),
                    )  # type: ignore[arg-type]
                )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strategies", nargs="+", default=["nearest-frontier", "burgard"])
    parser.add_argument("--robots", nargs="+", type=int, default=[1, 8, 32])
    parser.add_argument("--max-ticks", type=int, default=None, help="default: automatic")
    args = parser.parse_args()
    Simulation(Scenario(map="sheng40", robots=2, strategy="burgard")).run()  # compile kernels
    header = (
        f"{'map':<16}{'strategy':<18}{'robots':>6}{'status':>10}{'ticks':>8}"
        f"{'wall s':>9}{'ms/tick':>9}{'plans':>8}{'ms/plan':>9}"
    )
    print(header)
    print("-" * len(header))
    for label, scenario in scenarios(args.strategies, args.robots, args.max_ticks):
        started = time.perf_counter()
        record = Simulation(scenario).run()
        wall = time.perf_counter() - started
        result = record.result()
        print(
            f"{label:<16}{scenario.strategy:<18}{scenario.robots:>6}{record.status:>10}"
            f"{record.ticks:>8}{wall:>9.2f}{1000 * wall / max(record.ticks, 1):>9.2f}"
            f"{record.plans:>8}{result['decide_ms_per_plan']:>9.3f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
