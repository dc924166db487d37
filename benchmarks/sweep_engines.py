"""Run one 200-run sweep on the local, Ray and Dask engines and compare the rows.

    python benchmarks/sweep_engines.py [--out DIR] [--workers 2] [--engines local ray dask]

The sweep: sheng40 with a quarter-width radio (comm range 10), 4 strategies x
5 team sizes (1..5) x 10 seeds. Prints the wall time per engine and whether the
``runs`` and ``curves`` tables are identical row for row, apart from the timing
columns (``wall_time_s``, ``decide_ms_per_plan``).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from typing import Any

from mrexplore.experiments import Store, run_sweep, sweep_from_dict
from mrexplore.experiments.runner import TIMING_COLUMNS

SWEEP: dict[str, Any] = {
    "sweep": {"name": "engines-200", "seeds": list(range(1, 11)), "curves_every": 10},
    "fixed": {"map": "sheng40", "comm_range": 10, "sensor_range": 6},
    "grid": {
        "strategy": ["nearest-frontier", "burgard", "sheng-bidding", "market-occupancy"],
        "robots": [1, 2, 3, 4, 5],
    },
}


def rows(folder: Path) -> list[dict[str, Any]]:
    table = Store(folder).query("SELECT * FROM runs ORDER BY run_id")
    return [{k: v for k, v in r.items() if k not in TIMING_COLUMNS} for r in table.to_pylist()]


def curves(folder: Path) -> list[dict[str, Any]]:
    return Store(folder).query("SELECT * FROM curves ORDER BY run_id, tick").to_pylist()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--engines", nargs="+", default=["local", "ray", "dask"])
    args = parser.parse_args()
    out = args.out or Path(tempfile.mkdtemp(prefix="mrexplore-engines-"))
    sweep = sweep_from_dict(SWEEP, "benchmarks/sweep_engines.py")
    print(f"{len(sweep)} runs per engine, {args.workers} workers, results under {out}")
    results = {}
    for engine in args.engines:
        folder = out / engine
        started = time.perf_counter()
        summary = run_sweep(sweep, folder, engine=engine, workers=args.workers, progress=False)
        wall = time.perf_counter() - started
        statuses = Store(folder).query("SELECT status, count(*) AS n FROM runs GROUP BY 1")
        print(
            f"{engine:<6} {wall:7.1f} s  {summary.done} runs ({summary.failed} failed)  "
            f"{dict(zip(*statuses.to_pydict().values(), strict=True))}"
        )
        results[engine] = (rows(folder), curves(folder))
    first = args.engines[0]
    for engine in args.engines[1:]:
        same_rows = results[engine][0] == results[first][0]
        same_curves = results[engine][1] == results[first][1]
        print(
            f"{engine} vs {first}: runs identical: {same_rows} ({len(results[engine][0])} rows), "
            f"curves identical: {same_curves} ({len(results[engine][1])} rows)"
        )


if __name__ == "__main__":
    main()
