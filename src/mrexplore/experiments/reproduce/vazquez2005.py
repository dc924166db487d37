"""Vazquez & Malcolm: time to map an office with a mobile network vs Yamauchi (§4).

J. Vazquez, C. Malcolm, "Distributed multirobot exploration maintaining a mobile
network", Proc. 2nd IEEE International Conference on Intelligent Systems (IS'04),
Varna, 2004, vol. 3, pp. 113-118 (§4, Figs. 6-12).

The paper runs Khepera robots in Webots (robot 5 cm, sensor range diameter 45 cm)
in a structured office-like environment of 10.2 m^2 and one of 23.5 m^2, with
radio ranges of 1, 1.5 and 2 m and 2 to 10 robots, ten trials each, and plots the
time to a complete map of the network-keeping behaviours (``vazquez-network``)
against Yamauchi's frontier method (``nearest-frontier``). The figures are plots
only; the text gives the settings and the qualitative results, which are typed in
below (``PAPER_*``) and checked as verdicts.

Our equivalent, at one cell = 5 cm (one robot per cell):

==========================  =======================  ===============================
setting                     paper (§4)               ours
==========================  =======================  ===============================
robot diameter              5 cm                     1 cell
sensor                      range diameter 45 cm     disk of radius 4.5 cells
communication range (d3)    1, 1.5, 2 m              20, 30, 40 cells
environments                10.2 m^2, 23.5 m^2       ``office`` 72 x 72 and 105 x 105
                                                     cells, ``map_seed`` 1
team sizes                  2..10                    2, 4, 6, 8, 10 (Yamauchi in the
                                                     small map: 2..10)
trials                      10                       5 (Yamauchi in the small map: 10)
time                        seconds (Webots)         ticks (1 tick = 1 cell of travel)
complete map                complete map             ``coverage_threshold = 1``, T100
==========================  =======================  ===============================

Everything else (starts, localisation, sharing, limits) is in
:data:`SETTINGS_ROWS` and in ``docs/reproductions/vazquez2005.md``.

Reading the results: :func:`run_records` turns the ``runs`` and ``curves`` tables
into one :class:`RunRecord` per run (completion time, status, share of the time
the team was one sub-network); the ``verdict_*`` functions apply the rules stated
in the report to those records.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from mrexplore.experiments.reproduce.base import Outcome, Reproduction, Verdict, verdict_section
from mrexplore.experiments.stats import Summary, summarize_metric
from mrexplore.experiments.store import Store, StoreError
from mrexplore.experiments.sweep import Sweep, sweep_from_dict

# ------------------------------------------------------------------ the paper (§4)

#: §4: "The robots have a diameter of 5 cm".
PAPER_ROBOT_DIAMETER_M = 0.05
#: §4: "their sensor range diameter is 45cm".
PAPER_SENSOR_DIAMETER_M = 0.45
#: §4: "The communication ranges compared were 1m, 1.5 m and 2m" (Figs. 6-11).
PAPER_COMM_RANGES_M: tuple[float, ...] = (1.0, 1.5, 2.0)
#: §4: "The team sizes range from 2 to 10 robots" (x axis of Figs. 6-12).
PAPER_TEAM_SIZES: tuple[int, ...] = tuple(range(2, 11))
#: §4: "The total space to explore in the environments were 10.2m2 and 23.5m2"
#: (small: Figs. 6-8, large: Figs. 9-11).
PAPER_AREAS_M2: dict[str, float] = {"small": 10.2, "large": 23.5}
#: §4: "For each team of robots ten trials were run and averaged".
PAPER_TRIALS = 10
#: §1 and §4: position known "with an error margin of +-5%".
PAPER_POSITION_ERROR = 0.05
#: §4: "each broadcasts its sensorial information every half second".
PAPER_BROADCAST_PERIOD_S = 0.5
#: §3.1.2: d1 = 3/2 of the sensor diameter, d2 = 0.9 d3.
PAPER_D1_SENSOR_DIAMETERS = 1.5
PAPER_D2_FRACTION = 0.9
#: §4 (text on Figs. 6-8): "in the case of the small environment when the number
#: of robots is above seven robots in Yamauchis approach the robots perform worse".
PAPER_YAMAUCHI_WORSE_ABOVE = 7
#: Figs. 6-12 give no numbers in the text (plots only); these are the results the
#: text states about them, quoted.
PAPER_STATEMENTS: dict[str, str] = {
    "trend": "the time of completition drops in a linear fashion with respect to the "
    "number of robots up to some maximum number of robots ... After the threshold there "
    "are diminishing returns for more robots (§4, Figs. 6-11)",
    "faster": "The robots maintaining the network perform better than the robots in "
    "Yamauchi's approach (§4, Figs. 6-11)",
    "worse_above_seven": "in the case of the small environment when the number of robots "
    "is above seven robots in Yamauchis approach the robots perform worse (§4, Figs. 6-8)",
    "variance": "the varianze of the results [of Yamauchi's approach] is significantly "
    "higher than the varianze in the proposed approach, this is more notorious on "
    "Figure 7 when there are larger number of robots (§4)",
    "range_tradeoff": "the effect of the communication range presents an acceptable "
    "trade-off with respect to the time of completion ... robots are able to maintain a "
    "similar performance (§4, Fig. 12)",
    "range_gap": "as the number of robots increases the difference is diminished (§4, Fig. 12)",
    "incremental": "the approach performs incrementally better with larger teams of robots (§1)",
    "network": "the robots are encouraged to move together forming a mobile network "
    "(abstract, §3): the team keeps its communication network",
}

# ------------------------------------------------------------------ our settings

#: Metres per cell: one Khepera (5 cm) per cell.
CELL_SIZE_M = 0.05
SENSOR_RANGE_CELLS = PAPER_SENSOR_DIAMETER_M / 2 / CELL_SIZE_M  # 4.5
COMM_RANGES_CELLS: tuple[int, ...] = tuple(round(r / CELL_SIZE_M) for r in PAPER_COMM_RANGES_M)
MAP_SEED = 1
YAMAUCHI = "nearest-frontier"
VAZQUEZ = "vazquez-network"
STRATEGY_NAMES = {YAMAUCHI: "Yamauchi (nearest-frontier)", VAZQUEZ: "vazquez-network"}


@dataclass(frozen=True)
class OfficeMap:
    """One of the paper's two environments as a generated office."""

    label: str
    size: str
    paper_area_m2: float
    max_ticks: int
    figures: str


#: ``office`` sizes whose explorable cells at 5 cm give the paper's areas (measured:
#: 4087 cells = 10.22 m^2 and 9340 cells = 23.35 m^2 with ``map_seed`` 1).
MAPS: dict[str, OfficeMap] = {
    "small": OfficeMap("small", "72x72", PAPER_AREAS_M2["small"], 12_000, "Figs. 6-8"),
    "large": OfficeMap("large", "105x105", PAPER_AREAS_M2["large"], 20_000, "Figs. 9-11"),
}
#: The quick run's reduced stand-in for the small environment (1958 explorable
#: cells = 4.9 m^2, about half of it), so that ``--quick`` fits in 40 s.
QUICK_MAP = OfficeMap("small", "50x50", PAPER_AREAS_M2["small"], 6_000, "Figs. 6-8, reduced")
SPEC_OF_SIZE = {spec.size: spec for spec in (*MAPS.values(), QUICK_MAP)}
MAP_OF_SIZE = {size: spec.label for size, spec in SPEC_OF_SIZE.items()}

FULL_TEAM_SIZES = [2, 4, 6, 8, 10]
FULL_SEEDS = [1, 2, 3, 4, 5]
YAMAUCHI_SMALL_SEEDS = list(range(1, PAPER_TRIALS + 1))
QUICK_TEAM_SIZES = [4, 8]
QUICK_SEEDS = [1, 2]
QUICK_RANGES = [COMM_RANGES_CELLS[0], COMM_RANGES_CELLS[-1]]
CURVES_EVERY = 10

#: Rule thresholds (ours, stated in the report).
FASTER_REPRODUCED = 0.9
FASTER_PARTLY = 1 / 3
VARIANCE_REPRODUCED = 0.75
VARIANCE_PARTLY = 0.5
RANGE_SIMILAR_RATIO = 1.25
CONNECTED_REPRODUCED = 0.95
CONNECTED_PARTLY = 0.8

SETTINGS_ROWS: list[tuple[str, str, str]] = [
    ("simulator", "Webots, Khepera robots", "mrexplore occupancy grid, one robot per cell"),
    ("cell size", "-", f"{CELL_SIZE_M * 100:g} cm (one robot diameter)"),
    ("robot diameter", f"{PAPER_ROBOT_DIAMETER_M * 100:g} cm", "1 cell"),
    (
        "sensor",
        f"range diameter {PAPER_SENSOR_DIAMETER_M * 100:g} cm (infrared/sonar)",
        f"disk of radius {SENSOR_RANGE_CELLS:g} cells with line of sight, sensing while moving",
    ),
    (
        "communication range d3",
        ", ".join(f"{r:g} m" for r in PAPER_COMM_RANGES_M),
        ", ".join(f"{r} cells" for r in COMM_RANGES_CELLS)
        + " (the strategy takes d3 from the run's range)",
    ),
    (
        "comfort zone",
        "d1 = 3/2 sensor diameter, d2 = 0.9 d3",
        f"d1 = {PAPER_D1_SENSOR_DIAMETERS * 2 * SENSOR_RANGE_CELLS:g} cells, d2 = "
        + ", ".join(f"{PAPER_D2_FRACTION * r:g}" for r in COMM_RANGES_CELLS)
        + " cells (strategy defaults; the d1 cap 0.75 d2 never binds here)",
    ),
    (
        "radio model",
        "signal decays with the square of distance, walls do not block",
        "disk of radius d3, walls do not block (comm_los off), multi-hop, 1 tick per hop",
    ),
    (
        "environments",
        f"structured office-like, {PAPER_AREAS_M2['small']} m^2 and "
        f"{PAPER_AREAS_M2['large']} m^2 (Fig. 5, not in the text copy)",
        "generator office, 72 x 72 and 105 x 105 cells, map_seed 1 for every run "
        "(explorable cells measured in the report); quick: one reduced office, 50 x 50",
    ),
    ("team sizes", "2-10", "full: 2, 4, 6, 8, 10 (Yamauchi in the small map: 2-10); quick: 4, 8"),
    (
        "trials",
        f"{PAPER_TRIALS} per team size",
        f"full: seeds 1-{len(FULL_SEEDS)} (Yamauchi in the small map: 1-{PAPER_TRIALS}); "
        f"quick: {len(QUICK_SEEDS)}",
    ),
    (
        "start",
        "relative positions to a known location",
        "together: adjacent cells around a free cell drawn from the seed "
        "(the same for both methods at a seed)",
    ),
    (
        "localisation",
        f"known within +-{PAPER_POSITION_ERROR:.0%}",
        "perfect (the simulator has no position noise)",
    ),
    (
        "information sharing",
        f"sensor data broadcast every {PAPER_BROADCAST_PERIOD_S} s, multi-hop to the team",
        "sharing `full`: every new cell is sent to the sub-network each tick; positions "
        "every 2 ticks (strategy default)",
    ),
    (
        "Yamauchi's method",
        "frontier-based, closest frontier, no coordination, common map",
        "nearest-frontier, maps shared only inside a sub-network (same range and sharing)",
    ),
    ("time", "seconds (Webots)", "ticks; a robot moves 1 cell (5 cm) per tick"),
    (
        "time to complete",
        "time to a complete map",
        "T100: first tick at which the team knows every explorable cell (coverage_threshold = 1)",
    ),
    (
        "run limit",
        "-",
        f"max_ticks {MAPS['small'].max_ticks} (small), {MAPS['large'].max_ticks} (large), "
        f"{QUICK_MAP.max_ticks} (quick); "
        "a run that stops early counts with its last tick as a lower bound",
    ),
]


# ------------------------------------------------------------------ the sweeps


def _sweep(
    name: str,
    size: str,
    strategies: list[str],
    robots: list[int],
    ranges: list[int],
    seeds: list[int],
) -> Sweep:
    office = SPEC_OF_SIZE[size]
    return sweep_from_dict(
        {
            "sweep": {"name": name, "seeds": seeds, "curves_every": CURVES_EVERY},
            "fixed": {
                "map": "office",
                "size": size,
                "map_seed": MAP_SEED,
                "sensor_range": SENSOR_RANGE_CELLS,
                "start": "together",
                "coverage_threshold": 1.0,
                "max_ticks": office.max_ticks,
            },
            "grid": {"strategy": strategies, "robots": robots, "comm_range": ranges},
        },
        source=f"vazquez2005:{name}",
    )


def sweeps(quick: bool) -> dict[str, Sweep]:
    """The experiments: Figs. 6-11 (and 12, from the same runs)."""
    small, large = MAPS["small"].size, MAPS["large"].size
    if quick:
        return {
            "small": _sweep(
                "small",
                QUICK_MAP.size,
                [VAZQUEZ, YAMAUCHI],
                QUICK_TEAM_SIZES,
                QUICK_RANGES,
                QUICK_SEEDS,
            )
        }
    ranges = list(COMM_RANGES_CELLS)
    return {
        "small-vazquez": _sweep(
            "small-vazquez", small, [VAZQUEZ], FULL_TEAM_SIZES, ranges, FULL_SEEDS
        ),
        "small-yamauchi": _sweep(
            "small-yamauchi",
            small,
            [YAMAUCHI],
            list(PAPER_TEAM_SIZES),
            ranges,
            YAMAUCHI_SMALL_SEEDS,
        ),
        "large": _sweep("large", large, [VAZQUEZ, YAMAUCHI], FULL_TEAM_SIZES, ranges, FULL_SEEDS),
    }


# ------------------------------------------------------------------ reading the runs


@dataclass(frozen=True)
class RunRecord:
    """One run, reduced to what the figures and verdicts need.

    Attributes:
        map: ``"small"`` or ``"large"`` (the ``size`` column otherwise).
        comm_range: cells.
        time: T100 when the run completed; otherwise its last tick (a lower bound).
        complete: the run reached full coverage (``status == "complete"``).
        connected_share: share of the curve samples with one sub-network (nan
            without curves).
    """

    run_id: str
    map: str
    size: str
    comm_range: float
    strategy: str
    robots: int
    seed: int
    status: str
    time: float
    t99: float
    complete: bool
    connected_share: float
    explorable_cells: int


def connected_shares(curves: pa.Table | None) -> dict[str, float]:
    """Per run id: share of the curve samples at which the team was one sub-network."""
    if curves is None or curves.num_rows == 0:
        return {}
    ids = curves.column("run_id").to_pylist()
    subnetworks = curves.column("subnetworks").to_pylist()
    counts: dict[str, list[int]] = {}
    for run_id, value in zip(ids, subnetworks, strict=True):
        tally = counts.setdefault(run_id, [0, 0])
        tally[0] += int(value is not None and value <= 1)
        tally[1] += 1
    return {run_id: one / total for run_id, (one, total) in counts.items()}


def _number(value: Any) -> float:
    return math.nan if value is None else float(value)


def run_records(runs: pa.Table, curves: pa.Table | None = None) -> list[RunRecord]:
    """The runs as :class:`RunRecord`; failed runs (no metrics) are left out.

    A run that hit ``max_ticks`` or stalled keeps its last tick as its time (a lower
    bound of the time to complete) and ``complete = False``.
    """
    shares = connected_shares(curves)
    out: list[RunRecord] = []
    for row in runs.to_pylist():
        if row.get("status") == "failed":
            continue
        complete = row["status"] == "complete" and row.get("T100") is not None
        time = float(row["T100"]) if complete else float(row["ticks"])
        out.append(
            RunRecord(
                run_id=str(row["run_id"]),
                map=MAP_OF_SIZE.get(str(row["size"]), str(row["size"])),
                size=str(row["size"]),
                comm_range=float(row["comm_range"]),
                strategy=str(row["strategy"]),
                robots=int(row["robots"]),
                seed=int(row["seed"]),
                status=str(row["status"]),
                time=time,
                t99=_number(row.get("T99")),
                complete=complete,
                connected_share=shares.get(str(row["run_id"]), math.nan),
                explorable_cells=int(row.get("explorable_cells") or 0),
            )
        )
    return out


def _records_of_store(store: Store) -> list[RunRecord]:
    runs = store.query(
        "SELECT run_id, size, comm_range, strategy, robots, seed, status, ticks, T99, T100, "
        "explorable_cells FROM runs"
    )
    try:
        curves: pa.Table | None = store.query("SELECT run_id, subnetworks FROM curves")
    except StoreError:  # no run finished, so there are no curves
        curves = None
    return run_records(runs, curves)


# ------------------------------------------------------------------ statistics


Key = tuple[str, float, str, int]
"""``(map, comm_range, strategy, robots)``."""


def group(records: Iterable[RunRecord]) -> dict[Key, list[RunRecord]]:
    """Records by ``(map, comm_range, strategy, robots)``, each list sorted by seed."""
    out: dict[Key, list[RunRecord]] = {}
    for record in records:
        out.setdefault((record.map, record.comm_range, record.strategy, record.robots), []).append(
            record
        )
    for runs in out.values():
        runs.sort(key=lambda r: r.seed)
    return out


def time_summary(runs: Sequence[RunRecord], seeds: Iterable[int] | None = None) -> Summary:
    """Mean, sd, 95% CI of the time to complete, on ``seeds`` only if given."""
    keep = None if seeds is None else set(seeds)
    return summarize_metric([r.time for r in runs if keep is None or r.seed in keep])


def _mean_time(runs: Sequence[RunRecord], seeds: Iterable[int] | None = None) -> float:
    return time_summary(runs, seeds).mean


@dataclass(frozen=True)
class Comparison:
    """``vazquez-network`` against Yamauchi in one setting, on their common seeds."""

    map: str
    comm_range: float
    robots: int
    seeds: tuple[int, ...]
    yamauchi: Summary
    vazquez: Summary
    difference: Summary
    """``vazquez - yamauchi`` per seed (paired)."""

    @property
    def ratio(self) -> float:
        return self.vazquez.mean / self.yamauchi.mean if self.yamauchi.mean else math.nan


def comparisons(records: Iterable[RunRecord]) -> list[Comparison]:
    """Every setting run by both methods, compared on the seeds both ran."""
    groups = group(records)
    out: list[Comparison] = []
    settings = sorted({(m, c, n) for (m, c, s, n) in groups if s == VAZQUEZ}, key=_setting_order)
    for map_label, comm_range, robots in settings:
        vazquez = {r.seed: r for r in groups[(map_label, comm_range, VAZQUEZ, robots)]}
        yamauchi_runs = groups.get((map_label, comm_range, YAMAUCHI, robots), [])
        yamauchi = {r.seed: r for r in yamauchi_runs}
        seeds = tuple(sorted(set(vazquez) & set(yamauchi)))
        if not seeds:
            continue
        out.append(
            Comparison(
                map_label,
                comm_range,
                robots,
                seeds,
                summarize_metric([yamauchi[s].time for s in seeds]),
                summarize_metric([vazquez[s].time for s in seeds]),
                summarize_metric([vazquez[s].time - yamauchi[s].time for s in seeds]),
            )
        )
    return out


def _map_order(label: str) -> tuple[int, str]:
    order = list(MAPS)
    return (order.index(label) if label in order else len(order), label)


def _setting_order(setting: tuple[str, float, int]) -> tuple[tuple[int, str], float, int]:
    return (_map_order(setting[0]), setting[1], setting[2])


def _curves(
    records: Iterable[RunRecord],
) -> dict[tuple[str, float, str], dict[int, list[RunRecord]]]:
    """``(map, comm_range, strategy) -> {robots: runs}``."""
    out: dict[tuple[str, float, str], dict[int, list[RunRecord]]] = {}
    for (map_label, comm_range, strategy, robots), runs in group(records).items():
        out.setdefault((map_label, comm_range, strategy), {})[robots] = runs
    return out


def metres(cells: float) -> str:
    return f"{cells * CELL_SIZE_M:g} m"


def _nanmean(values: Iterable[float]) -> float:
    """Mean of the finite values; nan when there is none (no warning)."""
    finite = [v for v in values if math.isfinite(v)]
    return float(np.mean(finite)) if finite else math.nan


def _fmt(value: float, digits: int = 0) -> str:
    if not math.isfinite(value):
        return "-"
    return f"{value:.{digits}f}"


def _share(hits: int, total: int) -> str:
    return f"{hits}/{total}"


def _outcome(share: float, reproduced: float, partly: float) -> Outcome:
    if share >= reproduced:
        return "reproduced"
    if share >= partly:
        return "partly"
    return "not reproduced"


# ------------------------------------------------------------------ the verdicts


def verdict_team_size_trend(records: Sequence[RunRecord]) -> Verdict:
    """Time falls with team size, with diminishing returns.

    Rule: for every curve (map x range x method) the mean time at the largest team
    is below that at the smallest, and (with 3+ team sizes) the drop from the
    smallest to the middle team size is at least the drop from the middle to the
    largest. Reproduced if every curve passes, partly if at least half do.
    """
    passed = total = falling = 0
    examples: list[str] = []
    for (map_label, comm_range, strategy), by_size in sorted(_curves(records).items()):
        sizes = sorted(by_size)
        if len(sizes) < 2:
            continue
        total += 1
        first, last = sizes[0], sizes[-1]
        t_first, t_last = _mean_time(by_size[first]), _mean_time(by_size[last])
        falls = t_last < t_first
        falling += falls
        diminishing = True
        if len(sizes) >= 3:
            middle = sizes[len(sizes) // 2]
            t_middle = _mean_time(by_size[middle])
            diminishing = (t_first - t_middle) >= (t_middle - t_last)
        passed += falls and diminishing
        if len(examples) < 2 and strategy == VAZQUEZ:
            examples.append(
                f"{map_label}, {metres(comm_range)}, {strategy}: {first} robots "
                f"{_fmt(t_first)} -> {last} robots {_fmt(t_last)} ticks"
            )
    if total == 0:
        return Verdict(PAPER_STATEMENTS["trend"], "not reproduced", "fewer than 2 team sizes run")
    outcome: Outcome = (
        "reproduced" if passed == total else "partly" if 2 * passed >= total else "not reproduced"
    )
    evidence = (
        f"time falls from the smallest to the largest team in {_share(falling, total)} curves "
        f"(map x range x method) and falls with diminishing returns in {_share(passed, total)}; "
        + "; ".join(examples)
    )
    return Verdict(
        "completion time drops with team size, with diminishing returns (Figs. 6-11)",
        outcome,
        evidence,
    )


def verdict_faster(records: Sequence[RunRecord]) -> Verdict:
    """vazquez-network needs less time than Yamauchi.

    Rule: share of the settings (map x range x team size) where the mean time of
    ``vazquez-network`` is lower, on the seeds both ran: reproduced if at least
    90%, partly if at least a third, not reproduced below.
    """
    found = comparisons(records)
    if not found:
        return Verdict(
            "vazquez-network is faster than Yamauchi (Figs. 6-11)",
            "not reproduced",
            "no setting run by both",
        )
    faster = [c for c in found if c.vazquez.mean < c.yamauchi.mean]
    significant = [c for c in faster if c.difference.ci_high < 0]
    slower_significant = [c for c in found if c.difference.ci_low > 0]
    ratios = [c.ratio for c in found if math.isfinite(c.ratio)]
    t99_faster = 0
    groups = group(records)
    for c in found:
        v = [r.t99 for r in groups[(c.map, c.comm_range, VAZQUEZ, c.robots)] if r.seed in c.seeds]
        y = [r.t99 for r in groups[(c.map, c.comm_range, YAMAUCHI, c.robots)] if r.seed in c.seeds]
        t99_faster += _nanmean(v) < _nanmean(y)
    share = len(faster) / len(found)
    best = min(found, key=lambda c: c.ratio)
    evidence = (
        f"vazquez-network's mean time is lower in {_share(len(faster), len(found))} settings "
        f"({len(significant)} with the paired 95% CI of the difference below 0; "
        f"{len(slower_significant)} significantly slower); ratio vazquez/Yamauchi median "
        f"{statistics.median(ratios):.2f}, range {min(ratios):.2f}-{max(ratios):.2f}, best at "
        f"{best.map}, {metres(best.comm_range)}, {best.robots} robots; with T99 instead of "
        f"T100 lower in {_share(t99_faster, len(found))}"
    )
    return Verdict(
        "vazquez-network is faster than Yamauchi (Figs. 6-11)",
        _outcome(share, FASTER_REPRODUCED, FASTER_PARTLY),
        evidence,
    )


def verdict_yamauchi_worse_above_seven(records: Sequence[RunRecord]) -> Verdict:
    """In the small map Yamauchi's time rises above seven robots.

    Rule: per range, every team size above 7 has a higher mean time than the
    largest team size of at most 7. Reproduced if so at every range, partly if at
    some, not reproduced at none.
    """
    claim = "in the small environment Yamauchi's robots do worse above seven robots (Figs. 6-8)"
    held: list[str] = []
    checked: list[str] = []
    for (map_label, comm_range, strategy), by_size in sorted(_curves(records).items()):
        if map_label != "small" or strategy != YAMAUCHI:
            continue
        below = [n for n in by_size if n <= PAPER_YAMAUCHI_WORSE_ABOVE]
        above = sorted(n for n in by_size if n > PAPER_YAMAUCHI_WORSE_ABOVE)
        if not below or not above:
            continue
        reference = max(below)
        t_ref = _mean_time(by_size[reference])
        t_above = {n: _mean_time(by_size[n]) for n in above}
        worse = all(t > t_ref for t in t_above.values())
        text = f"{metres(comm_range)}: {reference} robots {_fmt(t_ref)}, " + ", ".join(
            f"{n}: {_fmt(t)}" for n, t in t_above.items()
        )
        checked.append(text)
        if worse:
            held.append(metres(comm_range))
    if not checked:
        return Verdict(claim, "not reproduced", "no team sizes on both sides of 7 in the small map")
    outcome: Outcome = (
        "reproduced" if len(held) == len(checked) else "partly" if held else "not reproduced"
    )
    evidence = (
        f"Yamauchi's mean time at every team size above {PAPER_YAMAUCHI_WORSE_ABOVE} exceeds "
        f"that at the largest team of at most {PAPER_YAMAUCHI_WORSE_ABOVE} at "
        f"{_share(len(held), len(checked))} ranges; mean ticks: " + "; ".join(checked)
    )
    return Verdict(claim, outcome, evidence)


def verdict_variance(records: Sequence[RunRecord]) -> Verdict:
    """Yamauchi's results vary more than vazquez-network's.

    Rule: share of the settings where Yamauchi's standard deviation (common
    seeds) exceeds vazquez-network's: reproduced if at least 75%, partly if at
    least 50%.
    """
    claim = "Yamauchi's times vary much more than vazquez-network's (Figs. 6-11, esp. Fig. 7)"
    found = [c for c in comparisons(records) if len(c.seeds) >= 2]
    if not found:
        return Verdict(claim, "not reproduced", "fewer than 2 common seeds in every setting")
    higher = [c for c in found if c.yamauchi.sd > c.vazquez.sd]
    ratio = (
        statistics.median(c.yamauchi.sd / c.vazquez.sd for c in found if c.vazquez.sd > 0)
        if any(c.vazquez.sd > 0 for c in found)
        else math.nan
    )
    fig7 = [c for c in found if c.map == "small" and math.isclose(c.comm_range * CELL_SIZE_M, 1.5)]
    fig7_text = ""
    if fig7:
        c = max(fig7, key=lambda c: c.robots)
        fig7_text = (
            f"; Fig. 7 setting (small, 1.5 m, {c.robots} robots, common seeds): sd "
            f"Yamauchi {_fmt(c.yamauchi.sd)}, vazquez {_fmt(c.vazquez.sd)}"
        )
    evidence = (
        f"Yamauchi's sd (seeds both ran) is the higher in {_share(len(higher), len(found))} "
        "settings; median "
        f"sd ratio Yamauchi/vazquez {ratio:.2f}" + fig7_text
    )
    return Verdict(
        claim, _outcome(len(higher) / len(found), VARIANCE_REPRODUCED, VARIANCE_PARTLY), evidence
    )


def _range_table(records: Sequence[RunRecord]) -> dict[str, dict[int, dict[float, float]]]:
    """vazquez-network's mean time: ``map -> robots -> comm_range -> ticks``."""
    out: dict[str, dict[int, dict[float, float]]] = {}
    for (map_label, comm_range, strategy, robots), runs in group(records).items():
        if strategy == VAZQUEZ:
            out.setdefault(map_label, {}).setdefault(robots, {})[comm_range] = _mean_time(runs)
    return out


def verdict_range_tradeoff(records: Sequence[RunRecord]) -> Verdict:
    """A shorter range costs vazquez-network little time (Fig. 12).

    Rule: ratio of the mean time at the shortest range to that at the longest, per
    map and team size: reproduced if at most 1.25 everywhere, partly if at most
    1.25 in at least half of them.
    """
    claim = "a shorter range costs vazquez-network little time: similar performance (Fig. 12)"
    ratios: list[tuple[str, int, float]] = []
    for map_label, by_size in _range_table(records).items():
        for robots, by_range in by_size.items():
            if len(by_range) >= 2:
                shortest, longest = min(by_range), max(by_range)
                ratios.append((map_label, robots, by_range[shortest] / by_range[longest]))
    if not ratios:
        return Verdict(claim, "not reproduced", "fewer than two ranges run")
    similar = [r for r in ratios if r[2] <= RANGE_SIMILAR_RATIO]
    share = len(similar) / len(ratios)
    outcome: Outcome = (
        "reproduced" if share == 1 else "partly" if share >= 0.5 else "not reproduced"
    )
    values = [r[2] for r in ratios]
    worst = max(ratios, key=lambda r: r[2])
    evidence = (
        f"time at the shortest / longest range <= {RANGE_SIMILAR_RATIO} in "
        f"{_share(len(similar), len(ratios))} (map x team size); ratios {min(values):.2f}-"
        f"{max(values):.2f}, worst {worst[2]:.2f} ({worst[0]}, {worst[1]} robots)"
    )
    return Verdict(claim, outcome, evidence)


def verdict_range_gap(records: Sequence[RunRecord]) -> Verdict:
    """The difference between ranges shrinks with more robots (Fig. 12).

    Rule: per map, compare the smallest and the largest team: the gap in mean time
    between the shortest and the longest range, in ticks and as a ratio. Times fall
    with team size, so a shrinking gap in ticks alone says little; reproduced if
    both shrink on every map, partly if the gap in ticks shrinks on some map, not
    reproduced otherwise.
    """
    claim = "the difference between ranges diminishes as robots are added (Fig. 12)"
    both: list[str] = []
    absolute: list[str] = []
    texts: list[str] = []
    for map_label, by_size in sorted(_range_table(records).items(), key=lambda i: _map_order(i[0])):
        sizes = sorted(n for n, by_range in by_size.items() if len(by_range) >= 2)
        if len(sizes) < 2:
            continue

        def gap(
            robots: int, table: Mapping[int, Mapping[float, float]] = by_size
        ) -> tuple[float, float]:
            by_range = table[robots]
            short, long_ = by_range[min(by_range)], by_range[max(by_range)]
            return short - long_, short / long_

        (gap_first, ratio_first), (gap_last, ratio_last) = gap(sizes[0]), gap(sizes[-1])
        texts.append(
            f"{map_label}: {sizes[0]} robots {_fmt(gap_first)} ticks (x{ratio_first:.2f}), "
            f"{sizes[-1]} robots {_fmt(gap_last)} ticks (x{ratio_last:.2f})"
        )
        if gap_last < gap_first:
            absolute.append(map_label)
            if ratio_last < ratio_first:
                both.append(map_label)
    if not texts:
        return Verdict(claim, "not reproduced", "fewer than two ranges or team sizes run")
    outcome: Outcome = (
        "reproduced" if len(both) == len(texts) else "partly" if absolute else "not reproduced"
    )
    return Verdict(
        claim,
        outcome,
        f"gap shortest - longest range in ticks (and as a ratio), smallest vs largest team; "
        f"the gap in ticks shrinks on {_share(len(absolute), len(texts))} maps, the ratio too "
        f"on {_share(len(both), len(texts))}: " + "; ".join(texts),
    )


def verdict_incremental(records: Sequence[RunRecord]) -> Verdict:
    """vazquez-network gains on Yamauchi as the team grows.

    Rule: per map and range, the ratio of mean times vazquez/Yamauchi at the
    largest team is below that at the smallest: reproduced if in every (map,
    range), partly if in at least half.
    """
    claim = "the approach does incrementally better (relative to Yamauchi) with larger teams (§1)"
    by_curve: dict[tuple[str, float], list[Comparison]] = {}
    for c in comparisons(records):
        by_curve.setdefault((c.map, c.comm_range), []).append(c)
    held = total = 0
    texts: list[str] = []
    for (map_label, comm_range), found in by_curve.items():
        if len(found) < 2:
            continue
        found.sort(key=lambda c: c.robots)
        total += 1
        held += found[-1].ratio < found[0].ratio
        texts.append(
            f"{map_label} {metres(comm_range)}: {found[0].ratio:.2f} -> {found[-1].ratio:.2f}"
        )
    if total == 0:
        return Verdict(claim, "not reproduced", "fewer than 2 team sizes run by both methods")
    outcome: Outcome = (
        "reproduced" if held == total else "partly" if 2 * held >= total else "not reproduced"
    )
    return Verdict(
        claim,
        outcome,
        f"ratio vazquez/Yamauchi falls from the smallest to the largest team in "
        f"{_share(held, total)} (map x range): " + "; ".join(texts),
    )


def verdict_network(records: Sequence[RunRecord]) -> Verdict:
    """vazquez-network keeps the team one network.

    Rule: the mean share of the time the team is one sub-network, per setting:
    reproduced if at least 0.95 in every setting, partly if at least 0.8 in every
    setting, not reproduced otherwise.
    """
    claim = "the robots keep one mobile network while exploring (abstract, §3)"
    shares: dict[str, list[float]] = {VAZQUEZ: [], YAMAUCHI: []}
    for (_, _, strategy, _), runs in group(records).items():
        values = [r.connected_share for r in runs if math.isfinite(r.connected_share)]
        if strategy in shares and values:
            shares[strategy].append(float(np.mean(values)))
    if not shares[VAZQUEZ]:
        return Verdict(claim, "not reproduced", "no sub-network curves for vazquez-network")
    low = min(shares[VAZQUEZ])
    outcome: Outcome = (
        "reproduced"
        if low >= CONNECTED_REPRODUCED
        else "partly"
        if low >= CONNECTED_PARTLY
        else "not reproduced"
    )
    contrast = (
        f"; Yamauchi {min(shares[YAMAUCHI]):.2f}-{max(shares[YAMAUCHI]):.2f}"
        if shares[YAMAUCHI]
        else ""
    )
    return Verdict(
        claim,
        outcome,
        f"share of the time in one sub-network, mean per setting: vazquez-network "
        f"{low:.2f}-{max(shares[VAZQUEZ]):.2f}{contrast}",
    )


def verdicts(records: Sequence[RunRecord]) -> list[Verdict]:
    """One verdict per claim of the paper, in the order of the report."""
    return [
        verdict_team_size_trend(records),
        verdict_faster(records),
        verdict_yamauchi_worse_above_seven(records),
        verdict_variance(records),
        verdict_range_tradeoff(records),
        verdict_range_gap(records),
        verdict_incremental(records),
        verdict_network(records),
    ]


# ------------------------------------------------------------------ the report


def _cell(summary: Summary, incomplete: int = 0) -> str:
    if summary.n == 0:
        return "-"
    prefix = ">= " if incomplete else ""
    text = f"{prefix}{_fmt(summary.mean)} +- {_fmt(summary.sd)}"
    if math.isfinite(summary.ci_low):
        text += f" [{_fmt(summary.ci_low)}, {_fmt(summary.ci_high)}]"
    text += f" (n={summary.n}"
    if incomplete:
        text += f", {incomplete} incomplete"
    return text + ")"


def _settings_section() -> list[str]:
    lines = ["| setting | paper (§4) | ours |", "|---|---|---|"]
    lines += [f"| {name} | {paper} | {ours} |" for name, paper, ours in SETTINGS_ROWS]
    return lines


def _map_section(records: Sequence[RunRecord], out: Path) -> list[str]:
    lines = [
        "| map | paper area | ours: size, explorable cells | ours: area | figure |",
        "|---|---|---|---|---|",
    ]
    present = {r.size: r.explorable_cells for r in records}
    for size, spec in SPEC_OF_SIZE.items():
        if size not in present:
            continue
        cells, label = present[size], spec.label
        image = _save_map_png(spec, out / f"map_{label}_{size}.png")
        lines.append(
            f"| {label} ({spec.figures}) | {spec.paper_area_m2} m^2 | office {spec.size}, "
            f"map_seed {MAP_SEED}: {cells} cells | {cells * CELL_SIZE_M**2:.2f} m^2 "
            f"({cells * CELL_SIZE_M**2 / spec.paper_area_m2 - 1:+.1%}) | ![{label}]({image.name}) |"
        )
    return lines


def _save_map_png(spec: OfficeMap, path: Path) -> Path:
    from PIL import Image

    from mrexplore.grid import generate_map
    from mrexplore.viz.render import render_frame

    width, height = (int(v) for v in spec.size.split("x"))
    grid = generate_map("office", width, height, seed=MAP_SEED)
    frame = render_frame(
        grid.occupied.astype(np.uint8),
        np.zeros(grid.occupied.shape, dtype=np.int32),
        np.zeros((1, 0, 2), dtype=np.int64),
        0,
        scale=3,
    )
    Image.fromarray(frame).save(path)
    return path


def _comparison_table(records: Sequence[RunRecord], map_label: str) -> list[str]:
    groups = group(records)
    lines = [
        "| range | robots | paper | Yamauchi: mean +- sd [95% CI] (n) | vazquez-network: "
        "mean +- sd [95% CI] (n) | vazquez / Yamauchi | vazquez - Yamauchi, paired [95% CI] "
        "| one sub-network: Yamauchi / vazquez |",
        "|---|---|---|---|---|---|---|---|",
    ]
    found = [c for c in comparisons(records) if c.map == map_label]
    for c in found:
        y_runs = groups[(c.map, c.comm_range, YAMAUCHI, c.robots)]
        v_runs = groups[(c.map, c.comm_range, VAZQUEZ, c.robots)]
        y_all = time_summary(y_runs)
        v_all = time_summary(v_runs)
        shares = [_nanmean(r.connected_share for r in runs) for runs in (y_runs, v_runs)]
        paper = "vazquez faster"
        if map_label == "small" and c.robots > PAPER_YAMAUCHI_WORSE_ABOVE:
            paper += "; Yamauchi worse than at 7"
        d = c.difference
        lines.append(
            f"| {metres(c.comm_range)} ({_fmt(c.comm_range)} cells) | {c.robots} | {paper} | "
            f"{_cell(y_all, sum(not r.complete for r in y_runs))} | "
            f"{_cell(v_all, sum(not r.complete for r in v_runs))} | {c.ratio:.2f} | "
            f"{_fmt(d.mean)} [{_fmt(d.ci_low)}, {_fmt(d.ci_high)}] (n={d.n}) | "
            f"{_fmt(shares[0], 2)} / {_fmt(shares[1], 2)} |"
        )
    return lines


def _yamauchi_table(records: Sequence[RunRecord]) -> list[str]:
    curves = {
        comm_range: by_size
        for (map_label, comm_range, strategy), by_size in _curves(records).items()
        if map_label == "small" and strategy == YAMAUCHI
    }
    if not curves:
        return []
    sizes = sorted({n for by_size in curves.values() for n in by_size})
    lines = [
        "| range | " + " | ".join(f"{n} robots" for n in sizes) + " |",
        "|---|" + "---|" * len(sizes),
    ]
    for comm_range, by_size in sorted(curves.items()):
        cells = []
        for n in sizes:
            s = time_summary(by_size[n]) if n in by_size else summarize_metric([])
            cells.append(f"{_fmt(s.mean)} +- {_fmt(s.sd)} (n={s.n})" if s.n else "-")
        lines.append(f"| {metres(comm_range)} | " + " | ".join(cells) + " |")
    return lines


def _range_section(records: Sequence[RunRecord]) -> list[str]:
    table = _range_table(records)
    ranges = sorted(
        {c for by_size in table.values() for by_range in by_size.values() for c in by_range}
    )
    if not ranges:
        return []
    lines = [
        "| map | robots | " + " | ".join(metres(c) for c in ranges) + " | shortest / longest |",
        "|---|---|" + "---|" * (len(ranges) + 1),
    ]
    for map_label in sorted(table, key=_map_order):
        for robots in sorted(table[map_label]):
            by_range = table[map_label][robots]
            cells = [_fmt(by_range.get(c, math.nan)) for c in ranges]
            ratio = (
                by_range[min(by_range)] / by_range[max(by_range)]
                if len(by_range) >= 2
                else math.nan
            )
            lines.append(
                f"| {map_label} | {robots} | " + " | ".join(cells) + f" | {_fmt(ratio, 2)} |"
            )
    return lines


def _summary_rows(
    records: Sequence[RunRecord], keep: Any, hue: Any, value: Any = None
) -> dict[str, list[Any]]:
    """Rows for :func:`mrexplore.viz.plots.plot_metric_vs`: robots, hue, mean, CI."""
    data: dict[str, list[Any]] = {
        "robots": [],
        "hue": [],
        "mean": [],
        "ci_low": [],
        "ci_high": [],
        "n": [],
    }
    for key, runs in sorted(group(records).items(), key=lambda i: (str(hue(i[0])), i[0][3])):
        if not keep(key):
            continue
        values = [r.time for r in runs] if value is None else [value(r) for r in runs]
        s = summarize_metric(values)
        data["robots"].append(key[3])
        data["hue"].append(hue(key))
        data["mean"].append(s.mean)
        data["ci_low"].append(s.ci_low)
        data["ci_high"].append(s.ci_high)
        data["n"].append(s.n)
    return data


def _figures(records: Sequence[RunRecord], out: Path) -> list[str]:
    from mrexplore.viz.plots import plot_metric_vs

    lines: list[str] = []
    figure = 6
    time_label = "time to complete the map (T100, ticks)"
    for map_label in MAPS:
        ranges = sorted({r.comm_range for r in records if r.map == map_label})
        for comm_range in COMM_RANGES_CELLS:
            number = figure
            figure += 1
            if comm_range not in ranges:
                continue
            data = _summary_rows(
                records,
                lambda k, m=map_label, c=comm_range: k[0] == m and k[1] == c,
                lambda k: k[2],
            )
            data["strategy"] = data.pop("hue")
            path = plot_metric_vs(
                data,
                out / f"fig{number}_{map_label}_{_fmt(comm_range)}cells.png",
                x="robots",
                hue="strategy",
                metric=time_label,
                title=f"Fig. {number}: {map_label} environment, range {metres(comm_range)} "
                f"({_fmt(comm_range)} cells); mean, 95% CI",
            )
            lines.append(f"![Fig. {number}]({path.name})")
    for map_label in MAPS:
        data = _summary_rows(
            records,
            lambda k, m=map_label: k[0] == m and k[2] == VAZQUEZ,
            lambda k: metres(k[1]),
        )
        if not data["robots"]:
            continue
        data["range"] = data.pop("hue")
        path = plot_metric_vs(
            data,
            out / f"fig12_{map_label}.png",
            x="robots",
            hue="range",
            metric=time_label,
            title=f"Fig. 12: vazquez-network by range, {map_label} environment; mean, 95% CI",
        )
        lines.append(f"![Fig. 12 {map_label}]({path.name})")
    for map_label in MAPS:
        data = _summary_rows(
            records,
            lambda k, m=map_label: k[0] == m,
            lambda k: f"{k[2]}, {metres(k[1])}",
            value=lambda r: r.connected_share,
        )
        if not data["robots"]:
            continue
        data["method, range"] = data.pop("hue")
        path = plot_metric_vs(
            data,
            out / f"connected_{map_label}.png",
            x="robots",
            hue="method, range",
            metric="share of the time in one sub-network",
            title=f"Connectivity (not a paper figure), {map_label} environment; mean, 95% CI",
        )
        lines.append(f"![connectivity {map_label}]({path.name})")
    return lines


def _rules() -> list[str]:
    return [
        "Rules (ours; the paper gives plots without numbers, so each claim is tested on "
        "the direction or size of an effect). All means are over seeds; vazquez-network "
        "and Yamauchi are compared on the seeds both ran (same map and start cells).",
        "",
        "- team-size trend: in every curve (map x range x method) the mean time at the "
        "largest team is below that at the smallest, and the drop from the smallest to the "
        "middle team size is at least the drop from the middle to the largest "
        "(diminishing returns). Reproduced: every curve; partly: at least half.",
        f"- faster: share of settings (map x range x team size) where vazquez-network's mean "
        f"time is lower. Reproduced: >= {FASTER_REPRODUCED:.0%}; partly: >= "
        f"{FASTER_PARTLY:.0%}; else not reproduced.",
        f"- Yamauchi worse above seven (small map): at a range, every team size above "
        f"{PAPER_YAMAUCHI_WORSE_ABOVE} has a higher mean time than the largest team size of at "
        "most 7. Reproduced: at every range; partly: at some.",
        f"- variance: share of settings where Yamauchi's standard deviation is the higher. "
        f"Reproduced: >= {VARIANCE_REPRODUCED:.0%}; partly: >= {VARIANCE_PARTLY:.0%}.",
        f"- range trade-off: vazquez-network's mean time at the shortest range over that at "
        f"the longest, per map and team size, at most {RANGE_SIMILAR_RATIO} ('similar "
        "performance'). Reproduced: everywhere; partly: in at least half.",
        "- range gap: the gap in mean time between the shortest and longest range, at the "
        "largest team against the smallest, in ticks and as a ratio (times fall with team "
        "size, so the gap in ticks alone shrinks almost by itself). Reproduced: both shrink "
        "on every map; partly: the gap in ticks shrinks on some map.",
        "- incremental: the ratio vazquez/Yamauchi of mean times is lower at the largest team "
        "than at the smallest. Reproduced: in every (map, range); partly: in at least half.",
        f"- network: mean share of the time the team is one sub-network (curves sampled every "
        f"{CURVES_EVERY} ticks), per setting. Reproduced: >= {CONNECTED_REPRODUCED} everywhere; "
        f"partly: >= {CONNECTED_PARTLY} everywhere.",
    ]


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Path:
    """Write ``out/report.md`` and its figures from the experiments' stores."""
    out = Path(out)
    records: list[RunRecord] = []
    for store in stores.values():
        records += _records_of_store(store)
    found = verdicts(records)
    n_incomplete = sum(not r.complete for r in records)
    statuses = sorted({r.status for r in records if not r.complete})
    lines = [f"# {REPRODUCTION.title}", "", REPRODUCTION.citation, ""]
    if quick:
        lines += [
            "**Quick run: its verdicts are indicative only.** It runs one reduced "
            f"environment (office {QUICK_MAP.size}, about half the paper's small one; "
            "its tables and figures are labelled small), ranges "
            f"{', '.join(metres(c) for c in QUICK_RANGES)}, "
            f"{', '.join(str(n) for n in QUICK_TEAM_SIZES)} robots and "
            f"{len(QUICK_SEEDS)} seeds. Run without `--quick` for the reproduction.",
            "",
        ]
    lines += [
        "The paper compares the time to a complete map of its network-keeping behaviours "
        "(`vazquez-network`) with Yamauchi's frontier method (`nearest-frontier`) for 2-10 "
        "Khepera robots, three radio ranges and two office-like environments (Figs. 6-11), "
        "and the behaviours across ranges (Fig. 12). Its figures are plots whose values are "
        "not in the text, so the paper's side below is its settings and the results its "
        "text states (quoted in the verdicts' rules and in `PAPER_STATEMENTS`).",
        "",
        "## Settings",
        "",
        *_settings_section(),
        "",
        "## Environments",
        "",
        "The paper's Fig. 5 (a structured office-like environment divided into parts of "
        "different sizes) is not in our text copy; we use the `office` generator (rooms "
        "on both sides of corridors, doors of 2 cells = 10 cm, walls 1 cell) at the "
        "size whose explorable area matches the paper's:",
        "",
        *_map_section(records, out),
        "",
        f"Runs: {len(records)} (failed runs excluded: none are counted); "
        f"{n_incomplete} did not complete"
        + (
            f" (status: {', '.join(statuses)}; they count with their last tick, marked >=)"
            if n_incomplete
            else ""
        )
        + ".",
        "",
    ]
    for map_label, spec in MAPS.items():
        if not any(r.map == map_label for r in records):
            continue
        lines += [
            f"## {spec.figures}: {map_label} environment ({spec.paper_area_m2} m^2), "
            "time to complete",
            "",
            "Ticks to a complete map (T100). Paper: plots only; its text says the "
            "network-keeping robots are faster at every setting"
            + (
                ", and Yamauchi's robots do worse above seven robots"
                if map_label == "small"
                else ""
            )
            + ". Each method's column uses all its seeds; the ratio and the paired "
            "difference use the seeds both ran.",
            "",
            *_comparison_table(records, map_label),
            "",
        ]
    yamauchi = _yamauchi_table(records)
    if yamauchi:
        lines += [
            "## Yamauchi in the small environment, every team size (Figs. 6-8)",
            "",
            f"Paper: worse above {PAPER_YAMAUCHI_WORSE_ABOVE} robots. Ours, mean +- sd ticks:",
            "",
            *yamauchi,
            "",
        ]
    lines += [
        "## Fig. 12: vazquez-network under the three ranges",
        "",
        "Paper: an acceptable trade-off, the difference diminishing with more robots. "
        "Ours, mean ticks:",
        "",
        *_range_section(records),
        "",
        "## Figures",
        "",
        *_figures(records, out),
        "",
        "## Verdicts",
        "",
        *_rules(),
        "",
        verdict_section(found),
        "",
    ]
    path = out / "report.md"
    path.write_text("\n".join(lines))
    return path


REPRODUCTION = Reproduction(
    id="vazquez2005",
    title="Vazquez & Malcolm: exploration maintaining a mobile network vs Yamauchi",
    citation=(
        'J. Vazquez, C. Malcolm, "Distributed multirobot exploration maintaining a mobile '
        "network\", Proc. 2nd IEEE International Conference on Intelligent Systems (IS'04), "
        "Varna, 2004, vol. 3, pp. 113-118, §4, Figs. 6-12."
    ),
    sweeps=sweeps,
    report=report,
)
