"""Every strategy on one scenario, as ratios to nearest-frontier measured in the same run.

    python benchmarks/bench_strategies.py [--quick] [--limited] [--scaling] [--no-intel]
                                          [--only kme burgard] [--timeout SECONDS]

The scenario of issue 20: the Intel lab at its native 0.05 m cells, 8 robots, sensor
range 40 cells, unlimited communication, seed 1. ``--limited`` adds the variant with
a 10 m communication range (each strategy with its own sharing, ``sheng-sync`` where
that is ``full``). ``--scaling`` adds a table in robots (4, 16, 64 on a 500 x 500
office) and map side (250, 500, 1000, 2000; 8 robots) for every strategy, over the
first 300 ticks of each run: simulation milliseconds per tick and per plan, as ratios
to nearest-frontier's (a whole exploration of the largest maps takes hours). ``--quick``
pools Intel to 0.2 m cells and the scaling maps to a quarter of their side, for a
check that the script works, not for numbers.

Each run is one ``mrexplore run`` in a fresh process (imports and the numba cache
load included: what a user waits for); the table gives the wall time of that
command, the run's ticks, ``decide_ms_per_plan`` from its ``result.json``, and the
ratio of the wall time to nearest-frontier's in the same invocation. A run over
``--timeout`` is stopped and shown as such.

The compiled floor: a method that needs more shortest-path work per decision than
nearest-frontier (costs from every robot to every target, a team assignment) is
judged against that work done by the compiled kernel. ``result.json`` counts the
distance fields the decisions computed (``distance_fields``, bounded searches
included); the table gives them per plan, the time of one full compiled field on the
map measured in this invocation (``distance_field`` over the true free space from a
start cell of the map, median of 5), the floor ``fields x field time`` and the ratio of the
decide time (``decide_ms_per_plan x plans``) to it. Counting a bounded search as a
full field makes the floor an upper bound, so the ratio errs on the kind side; it is
stated as such.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
BASELINE = "nearest-frontier"
SCALING_TICKS = 300
"""Ticks of each run of the scaling tables."""


def strategy_ids() -> list[str]:
    from mrexplore.strategies.registry import available_strategies

    return sorted(available_strategies())


def own_sharing(strategy: str) -> list[str]:
    """``--sharing sheng-sync`` for a strategy whose own sharing is ``full``, else none."""
    from mrexplore.strategies.registry import get_strategy

    return ["--sharing", "sheng-sync"] if get_strategy(strategy).default_sharing == "full" else []


def run_once(args: list[str], timeout: float) -> dict[str, Any]:
    """Wall seconds of ``mrexplore run ARGS`` and its result.json (empty on a timeout)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        command = [sys.executable, "-m", "mrexplore", "run", *args, "--out", str(out)]
        env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
        started = time.perf_counter()
        try:
            subprocess.run(command, check=True, timeout=timeout, capture_output=True, env=env)
        except subprocess.TimeoutExpired:
            return {"wall": None}
        wall = time.perf_counter() - started
        result = json.loads((out / "result.json").read_text())
    return {"wall": wall, **result}


def field_seconds(base: list[str]) -> float:
    """Median seconds of one full compiled distance field on the map of ``base``."""
    import numpy as np
    from bench_suite import field_time

    from mrexplore.sim import Scenario
    from mrexplore.sim.world import build_world

    options = dict(zip(base[::2], base[1::2], strict=True))
    size = options.get("--size")
    scenario = Scenario(
        map=options["--map"],
        size=tuple(int(v) for v in size.split("x")) if size else None,
        cell_size=float(options["--cell-size"]) if "--cell-size" in options else None,
        robots=int(options.get("--robots", "1")),
    )
    world = build_world(scenario, np.random.default_rng(0))
    return field_time(world.grid.free, world.starts[0])


def table(
    title: str,
    base: list[str],
    strategies: list[str],
    timeout: float,
    *,
    limited: bool = False,
    per_tick: bool = False,
) -> list[str]:
    rows = {
        s: run_once([*base, "--strategy", s, *(own_sharing(s) if limited else [])], timeout)
        for s in strategies
    }
    floor = rows.get(BASELINE, {}).get("wall")
    t_field = field_seconds(base)
    if per_tick:
        return tick_table(title, base, rows, timeout, t_field)
    lines = [
        f"### {title}",
        "",
        f"`mrexplore run {' '.join(base)} --strategy ID`; one full compiled field on "
        f"this map: {1000 * t_field:.2f} ms",
        "",
        "| strategy | wall s | ticks | ms per tick | ms per plan | x nearest-frontier "
        "| fields per plan | floor s | decide s | x floor |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for strategy, row in sorted(rows.items(), key=lambda item: item[1].get("wall") or 1e99):
        wall = row.get("wall")
        if wall is None:
            lines.append(f"| {strategy} | > {timeout:g} (stopped) |{' - |' * 8}")
            continue
        ratio = f"{wall / floor:.1f}" if floor else "-"
        per_tick = 1000 * row["wall_time_s"] / max(int(row["ticks"]), 1)
        plans = max(int(row["plans"]), 1)
        fields = int(row.get("distance_fields", 0))
        decide = row["decide_ms_per_plan"] * plans / 1000
        floor_s = fields * t_field
        floor_ratio = f"{decide / floor_s:.2f}" if floor_s > 0 else "-"
        lines.append(
            f"| {strategy} | {wall:.1f} | {row['ticks']} | {per_tick:.2f} "
            f"| {row['decide_ms_per_plan']:.2f} | {ratio} | {fields / plans:.2f} | {floor_s:.1f} "
            f"| {decide:.1f} | {floor_ratio} |"
        )
    return [*lines, ""]


def tick_table(
    title: str, base: list[str], rows: dict[str, dict[str, Any]], timeout: float, t_field: float
) -> list[str]:
    """The scaling tables: simulation milliseconds per tick (``wall_time_s / ticks``)
    and per plan, as ratios to nearest-frontier's, and the floor ratio."""
    per_tick = {
        s: 1000 * row["wall_time_s"] / max(int(row["ticks"]), 1)
        for s, row in rows.items()
        if row.get("wall") is not None
    }
    base_tick = per_tick.get(BASELINE)
    lines = [
        f"### {title}",
        "",
        f"`mrexplore run {' '.join(base)} --strategy ID`; one full compiled field: "
        f"{1000 * t_field:.2f} ms",
        "",
        "| strategy | ms per tick | x nearest-frontier | ms per plan | fields per plan "
        "| x floor | command s |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for strategy, row in sorted(rows.items(), key=lambda item: per_tick.get(item[0], 1e99)):
        if strategy not in per_tick:
            lines.append(f"| {strategy} | > {timeout:g} s (stopped) | - | - | - | - | - |")
            continue
        plans = max(int(row["plans"]), 1)
        fields = int(row.get("distance_fields", 0))
        decide = row["decide_ms_per_plan"] * plans / 1000
        floor_ratio = f"{decide / (fields * t_field):.2f}" if fields else "-"
        ratio = f"{per_tick[strategy] / base_tick:.1f}" if base_tick else "-"
        lines.append(
            f"| {strategy} | {per_tick[strategy]:.1f} | {ratio} | "
            f"{row['decide_ms_per_plan']:.2f} | {fields / plans:.2f} | {floor_ratio} "
            f"| {row['wall']:.1f} |"
        )
    return [*lines, ""]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--limited", action="store_true")
    parser.add_argument("--scaling", action="store_true")
    parser.add_argument("--no-intel", action="store_true", help="skip the unlimited Intel table")
    parser.add_argument("--only", nargs="+", default=None)
    parser.add_argument("--timeout", type=float, default=600.0)
    args = parser.parse_args(argv)
    strategies = args.only or strategy_ids()
    if BASELINE not in strategies:
        strategies = [BASELINE, *strategies]
    intel = ["--map", "intel", "--robots", "8", "--seed", "1"]
    intel += (
        ["--cell-size", "0.2", "--sensor-range", "10"] if args.quick else ["--sensor-range", "40"]
    )

    def emit(lines: list[str]) -> None:  # each table as soon as it is measured
        print("\n".join(lines), flush=True)

    if not args.no_intel:
        emit(table("Intel, 8 robots, unlimited communication", intel, strategies, args.timeout))
    if args.limited:
        limited = [*intel, "--comm-range", "10m"]
        title = "Intel, 8 robots, 10 m range (sheng-sync where the strategy shares in full)"
        emit(table(title, limited, strategies, args.timeout, limited=True))
    if args.scaling:
        # Cost per tick as the team and the map grow: the first SCALING_TICKS ticks of
        # each run (a whole exploration of a 2000 x 2000 office by 8 robots takes hours).
        side = 125 if args.quick else 500
        ticks = ["--max-ticks", str(SCALING_TICKS)]
        for robots in (4, 16, 64):
            base = ["--map", "office", "--size", f"{side}x{side}", "--robots", str(robots)]
            title = f"office {side}, {robots} robots, first {SCALING_TICKS} ticks"
            emit(table(title, [*base, *ticks], strategies, args.timeout, per_tick=True))
        for full_side in (250, 500, 1000, 2000):
            side = full_side // 4 if args.quick else full_side
            base = ["--map", "office", "--size", f"{side}x{side}", "--robots", "8"]
            title = f"office {side}, 8 robots, first {SCALING_TICKS} ticks"
            emit(table(title, [*base, *ticks], strategies, args.timeout, per_tick=True))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
