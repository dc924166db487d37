"""The performance suite of `make bench`: scenarios S1-S6 and the scaling table.

    python benchmarks/bench_suite.py [--only S1 S3] [--repeat 3] [--scaling] [--no-scenarios]
                                     [--timeout SECONDS] [--out benchmarks/results] [--record]

Per scenario (median of ``--repeat`` runs, each in a fresh process so that peak
memory is its own): wall time per run, ticks, decisions (decide calls: one per live
robot per tick), plans (decide calls that changed a robot's goal or idled it),
searching robots (decide calls that computed at least one distance field, counted by
:class:`mrexplore.planning.distance.FieldCounter`), time per decision, peak
resident memory, and the floor ratio

    floor ratio = decide seconds / (t_field x searching robots)

where t_field is the median time of one full distance field on that map (every
free cell of the ground truth passable, from the first start cell): the least a
decision costs if every robot that searched computed one full field.

"Robots that decided" are the robots whose decide call searched, not the robots
that changed goal: an auction strategy (sheng-bidding) computes fields to bid in
many calls that end without a new goal (S1, seed 1: 279 decide calls computed 847
fields, and only 88 changed a goal), so dividing by plans charged it for work the
count did not see. Calls that search nothing (a robot travelling on, a bid
waiting) cost Python time only; they are in the numerator, so the ratio still
shows per-call overhead, which dominates on small maps where t_field is tens of
microseconds (see docs/performance.md). Compilation is not timed: every child warms
the numba cache first (it is cached on disk between processes anyway).

Writes ``OUT/latest.json`` and ``OUT/latest.md``; with ``--record`` also appends
the Markdown table, the machine and the commit to ``benchmarks/RESULTS.md``
(previous entries are kept so regressions show).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent

SCENARIOS: dict[str, dict[str, Any]] = {
    "S1": {
        "about": "sheng40, 5 robots, sheng-bidding (r_s 4, r_c 16, sensing on arrival)",
        "scenario": {
            "map": "sheng40",
            "robots": 5,
            "strategy": "sheng-bidding",
            "sensor_range": 4,
            "comm_range": 16,
            "sensing": "arrival",
        },
    },
    "S2": {
        "about": "office 200x200, 8 robots, burgard",
        "scenario": {"map": "office", "size": (200, 200), "robots": 8, "strategy": "burgard"},
    },
    "S3-nearest": {
        "about": "intel.yaml (native 0.05 m cells), 8 robots, nearest-frontier, sensor 40 cells",
        "scenario": {
            "map": "intel",
            "robots": 8,
            "strategy": "nearest-frontier",
            "sensor_range": 40,
        },
    },
    "S3-kme": {
        "about": "intel.yaml (native 0.05 m cells), 8 robots, kme, sensor 40 cells",
        "scenario": {
            "map": "intel",
            "robots": 8,
            "strategy": "kme",
            "sensor_range": 40,
        },
    },
    "S4": {
        "about": "warehouse.yaml (native 0.03 m cells), 32 robots, nearest-frontier",
        "scenario": {
            "map": "warehouse",
            "robots": 32,
            "strategy": "nearest-frontier",
        },
    },
    "S5": {
        "about": "Sheng Fig. 12 as a sweep: 3 strategies x 8 team sizes x 6 seeds = 144 runs, "
        "local engine, 2 workers",
        "sweep": {
            "sweep": {"name": "S5", "seeds": [1, 2, 3, 4, 5, 6]},
            "fixed": {
                "map": "sheng40",
                "sensor_range": 4,
                "comm_range": 16,
                "sensing": "arrival",
            },
            "grid": {
                "strategy": ["random-frontier", "sheng-bidding"],
                "robots": [1, 2, 3, 4, 5, 6, 7, 8],
            },
            "extra": {"strategy": "sheng-bidding", "set": {"w3": 0.0}},
        },
    },
    "S6": {
        "about": "cityblock 1000x1000, 64 robots, nearest-frontier, comm range 50, sheng-sync",
        "scenario": {
            "map": "cityblock",
            "size": (1000, 1000),
            "robots": 64,
            "strategy": "nearest-frontier",
            "comm_range": 50,
            "sharing": "sheng-sync",
        },
    },
}

SCALING_SIDES = (200, 500, 1000, 2000)
SCALING_ROBOTS = (4, 16, 64)
SCALING_TICKS = 60


def _peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _field_time(record: Any) -> float:
    """Median seconds of one full distance field on the run's map."""
    return field_time(record.world.grid.free, record.world.starts[0])


def field_time(free: Any, start: tuple[int, int]) -> float:
    """Median seconds of one full distance field over ``free`` from ``start`` (5 runs)."""
    import numpy as np

    from mrexplore.planning import distance_field

    free = np.ascontiguousarray(free)
    distance_field(free, start)  # compile or load
    times = []
    for _ in range(5):
        started = time.perf_counter()
        distance_field(free, start)
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def child_run(settings: dict[str, Any]) -> dict[str, Any]:
    """One run in this process; numba warmed first on a tiny map."""
    from mrexplore.sim import Scenario, simulate

    warm = Scenario(
        map="sheng40",
        robots=2,
        strategy=settings["strategy"],
        sharing=settings.get("sharing"),
        comm_range=float(settings.get("comm_range", "inf")),
        sensor_range=4,
        max_ticks=30,
    )
    simulate(warm)  # compiles (or loads from the on-disk cache) every kernel the run uses
    if "size" in settings and settings["size"] is not None:
        settings = dict(settings, size=tuple(settings["size"]))
    scenario = Scenario(seed=1, **settings)
    started = time.perf_counter()
    record = simulate(scenario)
    wall = time.perf_counter() - started
    result = record.result()
    t_field = _field_time(record)
    decisions = max(record.decisions, 1)
    searching = max(getattr(record, "field_decisions", record.plans), 1)
    return {
        "status": record.status,
        "ticks": record.ticks,
        "T99": result["T99"],
        "wall_s": wall,
        "decisions": record.decisions,
        "plans": record.plans,
        "searching": searching,
        "fields": getattr(record, "fields", None),
        "decide_s": record.decide_seconds,
        "ms_per_decision": 1000 * record.decide_seconds / decisions,
        "robots_per_decision": searching / decisions,
        "field_ms": 1000 * t_field,
        "floor_ratio": record.decide_seconds / (t_field * searching),
        "floor_ratio_per_plan": record.decide_seconds / (t_field * max(record.plans, 1)),
        "peak_rss_mb": _peak_rss_mb(),
        "map_shape": list(record.world.grid.shape),
    }


def child_sweep(definition: dict[str, Any]) -> dict[str, Any]:
    from mrexplore.experiments import run_sweep, sweep_from_dict
    from mrexplore.sim import Scenario, simulate

    simulate(Scenario(map="sheng40", robots=2, strategy="sheng-bidding", max_ticks=30))
    definition = json.loads(json.dumps(definition))
    extra = definition.pop("extra")
    main = sweep_from_dict(definition, "S5")
    # The third strategy of Fig. 12 (bidding without nearness) as a second sweep into
    # the same folder: the store keys runs by scenario, so the two share it.
    fixed = dict(definition["fixed"], strategy=extra["strategy"], set=extra["set"])
    second = sweep_from_dict(
        {
            "sweep": definition["sweep"],
            "fixed": fixed,
            "grid": {"robots": definition["grid"]["robots"]},
        },
        "S5",
    )
    out = Path(tempfile.mkdtemp(prefix="mrexplore-bench-S5-"))
    started = time.perf_counter()
    first = run_sweep(main, out, workers=2, progress=False)
    other = run_sweep(second, out, workers=2, progress=False, resume=True)
    wall = time.perf_counter() - started
    return {
        "status": f"{first.done + other.done} runs, {first.failed + other.failed} failed",
        "runs": first.done + other.done,
        "wall_s": wall,
        "peak_rss_mb": _peak_rss_mb(),
    }


def run_child(kind: str, payload: dict[str, Any], timeout: float | None = None) -> dict[str, Any]:
    """One run (or sweep) in a fresh process; a run that exceeds ``timeout`` seconds is
    stopped and reported as not finished."""
    command = [sys.executable, __file__, "--child", kind, json.dumps(payload)]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    try:
        done = subprocess.run(
            command, capture_output=True, text=True, check=False, env=env, timeout=timeout
        )
    except subprocess.TimeoutExpired:
        return {
            "status": f"not finished within {timeout:.0f} s",
            "timed_out": True,
            "wall_s": float(timeout or 0.0),
            "peak_rss_mb": float("nan"),
        }
    if done.returncode != 0:
        raise RuntimeError(f"child failed: {done.stderr.strip().splitlines()[-1:]}")
    result: dict[str, Any] = json.loads(done.stdout.strip().splitlines()[-1])
    return result


def median_of(results: list[dict[str, Any]]) -> dict[str, Any]:
    """The run with the median wall time, plus the spread of wall times."""
    if any(r.get("timed_out") for r in results):
        chosen = dict(next(r for r in results if r.get("timed_out")))
        chosen["wall_all_s"] = [round(r["wall_s"], 3) for r in results]
        return chosen
    ordered = sorted(results, key=lambda r: r["wall_s"])
    chosen = dict(ordered[len(ordered) // 2])
    chosen["wall_all_s"] = [round(r["wall_s"], 3) for r in results]
    chosen["peak_rss_mb"] = max(r["peak_rss_mb"] for r in results)
    return chosen


def scenario_table(
    ids: list[str], repeat: int, timeout: float | None = None
) -> dict[str, dict[str, Any]]:
    rows: dict[str, dict[str, Any]] = {}
    for key in ids:
        spec = SCENARIOS[key]
        results = []
        for _ in range(repeat):
            if "sweep" in spec:
                results.append(run_child("sweep", spec["sweep"], timeout))
            else:
                results.append(run_child("run", spec["scenario"], timeout))
            if results[-1].get("timed_out"):
                break  # the other repeats would time out too
        rows[key] = {"about": spec["about"], **median_of(results)}
        print(f"{key}: {json.dumps(rows[key])}", flush=True)
    return rows


def scaling_table(repeat: int, timeout: float | None = None) -> list[dict[str, Any]]:
    """Time per decision over the first SCALING_TICKS ticks of office maps of growing
    size and teams of growing size (nearest-frontier)."""
    out = []
    for side in SCALING_SIDES:
        for robots in SCALING_ROBOTS:
            settings = {
                "map": "office",
                "size": (side, side),
                "robots": robots,
                "strategy": "nearest-frontier",
                "sensor_range": 10,
                "max_ticks": SCALING_TICKS,
            }
            results = [run_child("run", settings, timeout) for _ in range(repeat)]
            if any(r.get("timed_out") for r in results):
                print(f"scaling: {side} x {side}, {robots} robots: not finished", flush=True)
                continue
            chosen = median_of(results)
            row = {
                "side": side,
                "cells": side * side,
                "robots": robots,
                "ms_per_decision": chosen["ms_per_decision"],
                "robots_per_decision": chosen["robots_per_decision"],
                "field_ms": chosen["field_ms"],
                "floor_ratio": chosen["floor_ratio"],
                "wall_s": chosen["wall_s"],
            }
            out.append(row)
            print(f"scaling: {json.dumps(row)}", flush=True)
    return out


def _head_commit() -> str:
    """The checked-out commit, read from ``.git`` (short hash; ``?`` if unknown)."""
    git = HERE.parent / ".git"
    try:
        head = (git / "HEAD").read_text().strip()
        if head.startswith("ref: "):
            ref = head[5:]
            path = git / ref
            if path.exists():
                return path.read_text().strip()[:7]
            for line in (git / "packed-refs").read_text().splitlines():
                if line.endswith(" " + ref):
                    return line.split()[0][:7]
            return "?"
        return head[:7]
    except OSError:
        return "?"


def machine() -> dict[str, str]:
    import numba
    import numpy

    cpu = platform.processor() or ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    commit = _head_commit()
    return {
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "commit": commit or "?",
        "cpu": cpu,
        "cores": str(len(os.sched_getaffinity(0))),
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "numba": numba.__version__,
        "load_average": " ".join(f"{v:.1f}" for v in os.getloadavg()),
    }


def markdown(info: dict[str, str], rows: dict[str, Any], scaling: list[dict[str, Any]]) -> str:
    lines = [
        f"### {info['date']}, commit {info['commit']}",
        "",
        f"Machine: {info['cpu']}, {info['cores']} cores; Python {info['python']}, numpy "
        f"{info['numpy']}, numba {info['numba']}; load average at the end {info['load_average']}.",
        "",
    ]
    if rows:
        lines += [
            "| id | scenario | status | ticks | wall s (median; all) | decisions | ms/decision "
            "| searching robots/decision | field ms | floor ratio (per plan) | peak MB |",
            "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for key, r in rows.items():
            walls = ", ".join(f"{w:.1f}" for w in r["wall_all_s"])
            if "ticks" in r:
                lines.append(
                    f"| {key} | {r['about']} | {r['status']} | {r['ticks']} | {r['wall_s']:.2f} "
                    f"({walls}) | {r['decisions']} | {r['ms_per_decision']:.2f} | "
                    f"{r['robots_per_decision']:.2f} | {r['field_ms']:.2f} | "
                    f"{r['floor_ratio']:.2f} ({r.get('floor_ratio_per_plan', 0.0):.2f}) | "
                    f"{r['peak_rss_mb']:.0f} |"
                )
            else:
                peak = "-" if r["peak_rss_mb"] != r["peak_rss_mb"] else f"{r['peak_rss_mb']:.0f}"
                lines.append(
                    f"| {key} | {r['about']} | {r['status']} | - | {r['wall_s']:.2f} ({walls}) "
                    f"| - | - | - | - | - | {peak} |"
                )
        lines.append("")
    if scaling:
        lines += [
            f"Scaling (office N x N, nearest-frontier, first {SCALING_TICKS} ticks): "
            "ms per decision; in brackets ms per decision / (cells x searching robots per "
            "decision) in ns.",
            "",
            "| side | cells | " + " | ".join(f"{n} robots" for n in SCALING_ROBOTS) + " |",
            "|---:|---:|" + "---:|" * len(SCALING_ROBOTS),
        ]
        for side in SCALING_SIDES:
            cells = [r for r in scaling if r["side"] == side]
            if not cells:
                continue
            parts = []
            for r in cells:
                deciding = max(r["robots_per_decision"], 1e-9)
                per = 1e6 * r["ms_per_decision"] / (r["cells"] * deciding)
                parts.append(f"{r['ms_per_decision']:.2f} ({per:.1f})")
            while len(parts) < len(SCALING_ROBOTS):
                parts.append("not finished")
            lines.append(f"| {side} | {side * side} | " + " | ".join(parts) + " |")
        lines.append("")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--child", nargs=2, metavar=("KIND", "JSON"), help=argparse.SUPPRESS)
    parser.add_argument("--only", nargs="+", default=list(SCENARIOS))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--scaling", action="store_true", help="also the scaling table")
    parser.add_argument("--no-scenarios", action="store_true")
    parser.add_argument(
        "--timeout",
        type=float,
        default=None,
        help="stop a run after this many seconds and record it as not finished",
    )
    parser.add_argument("--out", type=Path, default=HERE / "results")
    parser.add_argument("--record", action="store_true", help="append to benchmarks/RESULTS.md")
    args = parser.parse_args()
    if args.child:
        kind, payload = args.child
        result = (child_run if kind == "run" else child_sweep)(json.loads(payload))
        print(json.dumps(result))
        return
    unknown = sorted(set(args.only) - set(SCENARIOS))
    if unknown:
        parser.error(f"--only {unknown[0]}: choose from {', '.join(SCENARIOS)}")
    rows = {} if args.no_scenarios else scenario_table(args.only, args.repeat, args.timeout)
    scaling = scaling_table(args.repeat, args.timeout) if args.scaling else []
    info = machine()
    args.out.mkdir(parents=True, exist_ok=True)
    text = markdown(info, rows, scaling)
    (args.out / "latest.json").write_text(
        json.dumps({"machine": info, "scenarios": rows, "scaling": scaling}, indent=2) + "\n"
    )
    (args.out / "latest.md").write_text(text + "\n")
    print(text)
    if args.record:
        results = HERE / "RESULTS.md"
        if not results.exists():
            results.write_text(
                "# Benchmark results\n\nAppended by `make bench` (`benchmarks/bench_suite.py "
                "--record`); newest last. Older entries stay so that regressions show.\n\n"
            )
        with results.open("a") as handle:
            handle.write(text + "\n")


if __name__ == "__main__":
    main()
