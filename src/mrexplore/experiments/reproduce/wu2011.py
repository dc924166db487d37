"""Reproduction of Wu, Puig and Garcia, section V: balanced exploration (WTV and EPV).

L. Wu, D. Puig, M. A. Garcia, "Balanced multi-robot exploration through a global
optimization strategy", Journal of Physical Agents 4(1), 2010 (the reproduction
id ``wu2011`` is historical), §V: KME against Yamauchi (``nearest-frontier``),
Burgard et al. (``burgard``) and Zlot et al. (``zlot-market``), judged by the
regional waiting-time variance WTV (eqs. 8-10) and the exploration-percentage
variance EPV of 8 equal regions (:mod:`mrexplore.metrics.regions`).

Experiments (``mrexplore reproduce wu2011 --out DIR [--quick]``): one sweep per map
type (``unstructured``, ``blank``, ``cityblock``), each of

    4 strategies x 2 starting schemes (together, separate) x 2, 4, 6, 8 robots
    x 15 start set-ups (seeds 1-15)

on one map per type (``map_seed`` fixed, as the paper has one map per type),
80 x 80 cells, sensor range 8 cells, sensing every tick, unlimited
communication, runs until every explorable cell is known. The curves ``wtv_8`` and
``epv_8`` are sampled every 10 ticks.

Numbers compared (the paper gives Figs. 6-8 as plots only; the text's statements
are typed in as ``PAPER_*`` constants):

* **WTV over time** of a run: its ``wtv_8`` curve carried to a common horizon
  (the last tick of the longest run with the same map and team size, any strategy
  or start; a finished run keeps its final value, which no longer changes) and
  averaged over the samples every 10 ticks: :func:`time_mean`. This is "the WTV
  during the exploration" of Fig. 6 as one number per run, so that runs can be
  summarised over seeds and paired by seed.
* **final WTV**: ``wtv_8_final`` (eq. 10; the paper's "value where each curve
  terminates").
* **EPV over time** and final EPV likewise from ``epv_8``.

Verdicts follow the rules in :data:`RULES`; the helpers (:func:`time_mean`,
:func:`run_values`, :func:`panel_means`, :func:`paired`, the ``*_outcome``
functions) are pure functions of pyarrow tables and numbers.
"""

from __future__ import annotations

import itertools
import json
import math
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyarrow as pa

from mrexplore.experiments.reproduce.base import (
    Outcome,
    Reproduction,
    Verdict,
    rules_header,
    verdict_section,
)
from mrexplore.experiments.reproduce.claims import count_outcome, paired
from mrexplore.experiments.reproduce.claims import fmt as _fmt
from mrexplore.experiments.stats import Summary, summarize_metric
from mrexplore.experiments.store import Store
from mrexplore.experiments.sweep import Sweep, sweep_from_dict

ID = "wu2011"
TITLE = "Balanced multi-robot exploration through a global optimization strategy"
CITATION = (
    'L. Wu, D. Puig, M. A. Garcia, "Balanced multi-robot exploration through a global '
    'optimization strategy", Journal of Physical Agents 4(1), 2010, §V.'
)

FloatArray = npt.NDArray[np.float64]

# ----------------------------------------------------------------------- settings

#: §V.A, Fig. 4: "blank map", "unstructured map", "cityblock map"; our generators of
#: the same names. The unstructured map first: Figs. 6-8 show it.
MAPS = ("unstructured", "blank", "cityblock")
#: Not given in the paper: our choice (see the report's settings), cells.
MAP_SIZE = "80x80"
QUICK_MAP_SIZE = "48x48"
#: One map per type (§V.A shows one of each): the generator's seed, fixed.
MAP_SEED = 1
#: Not given in the paper: cells (the simulator's default).
SENSOR_RANGE = 8
#: §V.A: "(a) all robots start from the same location, (b) robots start from random
#: locations".
STARTS = ("together", "separate")
#: Figs. 6-8: "2, 4, 6, and 8 robots" (§V.A ran 2 to 8).
TEAM_SIZES = (2, 4, 6, 8)
QUICK_TEAM_SIZES = (2, 4)
#: §V.A: "For every combination of robots, maps and starting schemes, 15 set-ups of
#: runs have been performed": one seed per set-up.
SEEDS = tuple(range(1, 16))
QUICK_SEEDS = (1, 2)
#: §V.C: "YMC, Burgard, Zlot and KME represent Yamauchi [3], Burgard et al. [4], [5],
#: Zlot et al. [6] and the proposed algorithm".
STRATEGIES = ("kme", "nearest-frontier", "burgard", "zlot-market")
PAPER_NAMES = {
    "kme": "KME",
    "nearest-frontier": "YMC",
    "burgard": "Burgard",
    "zlot-market": "Zlot",
}
#: Figs. 6-8: "WTV of eight regions", "EPV for eight regions".
N_REGIONS = 8
#: Ticks between two samples of the curves.
CURVES_EVERY = 10
MAX_TICKS = 4000

FIXED: dict[str, Any] = {
    "map_seed": MAP_SEED,
    "sensor_range": SENSOR_RANGE,
    "sensing": "moving",  # §V.B: a robot "arrives at a cell at step t and explores"
    "comm_range": "inf",  # the paper models no communication limit
    "coverage_threshold": 1.0,  # §V.B: "When the exploration process terminates, every
    # cell of the workspace is known" (eq. 10 is defined then)
    "max_ticks": MAX_TICKS,
}

# ------------------------------------------------------------ the paper's numbers

#: §V.A: "15 set-ups of runs" per combination of robots, map and starting scheme.
PAPER_RUNS_PER_CONFIGURATION = 15
#: §V.A: "630 different configurations (3 maps x 2 starting schemes x 7 applied
#: numbers of robots x 15 runs)".
PAPER_CONFIGURATIONS = 630
PAPER_TEAM_SIZES = (2, 3, 4, 5, 6, 7, 8)
#: §V.B: "the maps are divided into 2, 4, 8, 16, 32, 64 equal-sized regions".
PAPER_REGION_COUNTS = (2, 4, 8, 16, 32, 64)

#: Fig. 6 (unstructured map, start together; plot only, no numbers; read from the
#: text): "the more robots, the lower the WTVs of all approaches".
PAPER_FIG6_FEWER_ROBOTS_HIGHER = "the more robots, the lower the WTVs of all approaches"
#: Fig. 6 (read from the text): "When more than two robots are utilized, KME has the
#: lowest WTV during the exploration" -> team sizes of the figure with KME lowest.
PAPER_FIG6_KME_LOWEST = (4, 6, 8)
#: Fig. 6 (read from the text): "WTV_final ... with KME is also the smallest except
#: for the two-robot case" -> KME smallest final WTV at 4, 6, 8, not at 2 robots.
PAPER_FIG6_KME_FINAL_LOWEST = (4, 6, 8)
PAPER_FIG6_KME_FINAL_NOT_LOWEST = (2,)
#: Fig. 7 vs 6 (read from the text): "The WTV curves of all techniques with the
#: separate scheme are lower than the ones with the together scheme."
PAPER_FIG7_SEPARATE_LOWER = "WTV with separate starts < WTV with starts together, all methods"
#: Fig. 7 (read from the text): "With the separate scheme, KME is again superior to
#: the other methods" (taken, like Fig. 6, for more than two robots).
PAPER_FIG7_KME_LOWEST = (4, 6, 8)
#: Fig. 8 (unstructured, separate; read from the text): "with 2, 4, 6, and 8 robots,
#: the eight regions are explored at a similar speed with KME, whereas ... the EPV
#: curves of the other three methods show a big difference".
PAPER_FIG8_KME_LOWEST = (2, 4, 6, 8)
#: §V.C (read from the text): "The same trend can be found in the six combinations of
#: maps and starting schemes" (KME lowest WTV, more than two robots).
PAPER_SIX_COMBINATIONS = "KME lowest WTV in all 3 maps x 2 starting schemes"
#: §V.C (read from the text): "Zlot's algorithm behaves like [3]-[5] with respect to
#: the WTV and EPV ... its solution is not superior to [3]-[5]".
PAPER_ZLOT_NOT_SUPERIOR = "Zlot's WTV and EPV are not better than Yamauchi's and Burgard's"

# ------------------------------------------------------------------ verdict rules

RULES: dict[str, str] = {
    "decreasing": (
        "for every strategy, the mean WTV over time falls at every step 2 -> 4 -> 6 -> 8 "
        "robots: reproduced; for every strategy the largest team's mean is below the "
        "smallest team's: partly; otherwise not reproduced."
    ),
    "lowest": (
        "in each panel named by the claim (map, starting scheme, team size), KME's mean "
        "(over the seeds) is the lowest of the four strategies; reproduced if this holds "
        "in every panel, partly if in at least half of them, not reproduced otherwise. "
        "No significance test: the paper compares means of 15 runs."
    ),
    "counted": (
        "the statement is checked in each cell named by the claim; reproduced if it holds "
        "in every cell, partly if in at least half, not reproduced otherwise."
    ),
    "zlot": (
        "Zlot is superior in a panel and metric if its paired (same seeds) 95% CI of "
        "Zlot - YMC and of Zlot - Burgard both lie below 0; the claim holds in a cell "
        "where Zlot is not superior; then as `counted` over every panel (all maps, "
        "schemes, team sizes) and both metrics (WTV and EPV over time)."
    ),
}


def decreasing_outcome(means: Mapping[str, Mapping[int, float]]) -> Outcome:
    """Rule ``decreasing``: ``strategy -> team size -> mean``.

    >>> decreasing_outcome({"a": {2: 9.0, 4: 5.0}, "b": {2: 8.0, 4: 6.0}})
    'reproduced'
    >>> decreasing_outcome({"a": {2: 9.0, 4: 5.0, 6: 6.0}, "b": {2: 8.0, 4: 6.0}})
    'partly'
    """
    if not means:
        return "not reproduced"
    monotone = overall = True
    for by_size in means.values():
        values = [by_size[n] for n in sorted(by_size)]
        monotone &= all(b < a for a, b in itertools.pairwise(values))
        overall &= len(values) > 1 and values[-1] < values[0]
    if monotone and overall:
        return "reproduced"
    return "partly" if overall else "not reproduced"


# ------------------------------------------------------------- per-run numbers


def step_values(ticks: FloatArray, values: FloatArray, grid: FloatArray) -> FloatArray:
    """A sampled curve at the ``grid`` ticks: the last sample at or before each tick
    (a run that ended keeps its last value; nan before the first sample).

    ``ticks`` must be increasing.

    >>> step_values(np.array([0.0, 10.0, 14.0]), np.array([1.0, 2.0, 3.0]),
    ...             np.array([0.0, 5.0, 10.0, 20.0]))
    array([1., 1., 2., 3.])
    """
    at = np.searchsorted(ticks, grid, side="right") - 1
    out = np.full(grid.shape, np.nan)
    valid = at >= 0
    out[valid] = values[at[valid]]
    return out


def horizon_grid(horizon: int, every: int) -> FloatArray:
    """Ticks ``0, every, 2 every, ... <= horizon``, and ``horizon`` itself.

    >>> horizon_grid(25, 10)
    array([ 0., 10., 20., 25.])
    """
    grid = np.arange(0, horizon + 1, every, dtype=np.float64)
    if grid[-1] != horizon:
        grid = np.append(grid, float(horizon))
    return grid


def time_mean(ticks: FloatArray, values: FloatArray, horizon: int, every: int) -> float:
    """Mean of a run's curve over the samples of :func:`horizon_grid` (carried forward
    past the run's end): "the value during the exploration" as one number.

    >>> time_mean(np.array([0.0, 10.0, 12.0]), np.array([4.0, 2.0, 1.0]), 30, 10)
    2.0
    """
    sampled = step_values(ticks, values, horizon_grid(horizon, every))
    finite = sampled[np.isfinite(sampled)]
    return float(finite.mean()) if finite.size else math.nan


@dataclass(frozen=True)
class RunValues:
    """One run's numbers for the report."""

    run_id: str
    map: str
    start: str
    robots: int
    strategy: str
    seed: int
    status: str
    starts: str
    t100: float
    wtv_final: float
    epv_final: float
    wtv_time: float
    epv_time: float

    @property
    def panel(self) -> Panel:
        return (self.map, self.start, self.robots)


Panel = tuple[str, str, int]
"""``(map, starting scheme, team size)``: one subfigure of Figs. 6-8."""


def _number(value: Any) -> float:
    return math.nan if value is None else float(value)


def _curve_arrays(curves: pa.Table | None, columns: Sequence[str]) -> dict[str, dict[str, Any]]:
    """``run_id -> {"tick": array, column: array, ...}``, ticks increasing."""
    if curves is None or curves.num_rows == 0:
        return {}
    run_ids = np.asarray(curves.column("run_id").to_pylist(), dtype=object)
    ticks = np.asarray(curves.column("tick").to_pylist(), dtype=np.float64)
    data = {
        c: np.array([_number(v) for v in curves.column(c).to_pylist()], dtype=np.float64)
        for c in columns
    }
    order = np.lexsort((ticks, run_ids.astype(str)))
    run_ids, ticks = run_ids[order], ticks[order]
    data = {c: v[order] for c, v in data.items()}
    out: dict[str, dict[str, Any]] = {}
    boundaries = np.flatnonzero(run_ids[1:] != run_ids[:-1]) + 1
    for chunk in np.split(np.arange(run_ids.size), boundaries):
        if chunk.size:
            out[str(run_ids[chunk[0]])] = {
                "tick": ticks[chunk],
                **{c: v[chunk] for c, v in data.items()},
            }
    return out


def run_values(
    runs: pa.Table, curves: pa.Table | None, every: int = CURVES_EVERY
) -> list[RunValues]:
    """The report's numbers of every usable run (status not ``failed``).

    WTV and EPV over time are :func:`time_mean` of ``wtv_8`` / ``epv_8`` up to the
    horizon of the run's map and team size: the last curve tick of the longest run
    with that map and team size (any strategy, any starting scheme), so every
    comparison inside a team size uses one horizon.

    >>> runs = pa.table({"run_id": ["a", "b"], "map": ["m", "m"], "start": ["together"] * 2,
    ...     "robots": [2, 2], "strategy": ["kme", "burgard"], "seed": [1, 1],
    ...     "status": ["complete"] * 2, "starts": ["[[1, 1]]"] * 2, "T100": [20, 10],
    ...     "wtv_8_final": [1.0, 3.0], "epv_8_final": [0.0, 0.0]})
    >>> curves = pa.table({"run_id": ["a", "a", "a", "b", "b"], "tick": [0, 10, 20, 0, 10],
    ...     "wtv_8": [5.0, 2.0, 1.0, 5.0, 3.0], "epv_8": [0.0, 9.0, 0.0, 0.0, 0.0]})
    >>> [(v.strategy, round(v.wtv_time, 3), v.epv_time) for v in run_values(runs, curves)]
    [('kme', 2.667, 3.0), ('burgard', 3.667, 0.0)]
    """
    arrays = _curve_arrays(curves, (f"wtv_{N_REGIONS}", f"epv_{N_REGIONS}"))
    rows = [row for row in runs.to_pylist() if row.get("status") != "failed"]
    horizons: dict[tuple[str, int], int] = {}
    for row in rows:
        curve = arrays.get(str(row["run_id"]))
        if curve is not None and curve["tick"].size:
            key = (str(row["map"]), int(row["robots"]))
            horizons[key] = max(horizons.get(key, 0), int(curve["tick"][-1]))
    out: list[RunValues] = []
    for row in rows:
        curve = arrays.get(str(row["run_id"]))
        horizon = horizons.get((str(row["map"]), int(row["robots"])), 0)
        wtv_time = epv_time = math.nan
        if curve is not None and curve["tick"].size:
            wtv_time = time_mean(curve["tick"], curve[f"wtv_{N_REGIONS}"], horizon, every)
            epv_time = time_mean(curve["tick"], curve[f"epv_{N_REGIONS}"], horizon, every)
        out.append(
            RunValues(
                run_id=str(row["run_id"]),
                map=str(row["map"]),
                start=str(row["start"]),
                robots=int(row["robots"]),
                strategy=str(row["strategy"]),
                seed=int(row["seed"]),
                status=str(row["status"]),
                starts=str(row.get("starts") or ""),
                t100=_number(row.get("T100")),
                wtv_final=_number(row.get(f"wtv_{N_REGIONS}_final")),
                epv_final=_number(row.get(f"epv_{N_REGIONS}_final")),
                wtv_time=wtv_time,
                epv_time=epv_time,
            )
        )
    return out


METRICS = ("wtv_time", "wtv_final", "epv_time", "epv_final", "t100")
"""Fields of :class:`RunValues` that the report summarises."""


def by_panel(values: Iterable[RunValues], metric: str) -> dict[Panel, dict[str, dict[int, float]]]:
    """``panel -> strategy -> seed -> value`` of one metric."""
    out: dict[Panel, dict[str, dict[int, float]]] = {}
    for v in values:
        out.setdefault(v.panel, {}).setdefault(v.strategy, {})[v.seed] = float(getattr(v, metric))
    return out


def panel_means(values: Iterable[RunValues], metric: str) -> dict[Panel, dict[str, Summary]]:
    """``panel -> strategy ->`` :func:`summarize_metric` of one metric over the seeds.

    >>> v = [RunValues("a", "m", "together", 2, "kme", s, "complete", "", 1.0, float(s),
    ...      0.0, 0.0, 0.0) for s in (1, 2, 3)]
    >>> panel_means(v, "wtv_final")[("m", "together", 2)]["kme"].mean
    2.0
    """
    return {
        panel: {s: summarize_metric(list(seeds.values())) for s, seeds in by_strategy.items()}
        for panel, by_strategy in by_panel(values, metric).items()
    }


def lowest(summaries: Mapping[str, Summary]) -> str | None:
    """The strategy with the lowest mean (``None`` when no mean is defined).

    >>> s = summarize_metric
    >>> lowest({"kme": s([1.0, 2.0]), "burgard": s([3.0]), "zlot-market": s([])})
    'kme'
    """
    finite = {k: v.mean for k, v in summaries.items() if math.isfinite(v.mean)}
    return min(finite, key=lambda k: (finite[k], k)) if finite else None


def zlot_superior(by_seed: Mapping[str, Mapping[int, float]]) -> bool:
    """Rule ``zlot`` in one panel: Zlot significantly below both YMC and Burgard.

    >>> zlot_superior({"zlot-market": {1: 1.0, 2: 2.0, 3: 1.5},
    ...                "nearest-frontier": {1: 5.0, 2: 6.0, 3: 5.5},
    ...                "burgard": {1: 5.0, 2: 2.5, 3: 9.0}})
    False
    """
    differences = [
        paired(by_seed, "zlot-market", other) for other in ("nearest-frontier", "burgard")
    ]
    return all(d.n >= 2 and d.ci_high < 0 for d in differences)


@dataclass(frozen=True)
class MeanCurve:
    """Mean over runs of a curve on a tick grid, with its 95% CI band."""

    ticks: FloatArray
    mean: FloatArray
    low: FloatArray
    high: FloatArray
    n: int


def mean_curve(series: Sequence[tuple[FloatArray, FloatArray]], grid: FloatArray) -> MeanCurve:
    """Mean of runs' curves (``(ticks, values)`` each) carried onto ``grid``.

    >>> c = mean_curve([(np.array([0.0, 10.0]), np.array([1.0, 3.0])),
    ...                 (np.array([0.0]), np.array([3.0]))], np.array([0.0, 10.0]))
    >>> c.mean.tolist(), c.n
    ([2.0, 3.0], 2)
    """
    from scipy import stats as scipy_stats

    if not series:
        empty = np.full(grid.shape, np.nan)
        return MeanCurve(grid, empty, empty, empty, 0)
    matrix = np.vstack([step_values(t, v, grid) for t, v in series])
    finite = np.isfinite(matrix)
    n = finite.sum(axis=0)
    filled = np.where(finite, matrix, 0.0)
    mean = np.divide(filled.sum(axis=0), n, out=np.full(grid.shape, np.nan), where=n > 0)
    squares = np.where(finite, (matrix - np.nan_to_num(mean)) ** 2, 0.0).sum(axis=0)
    var = np.divide(squares, n - 1, out=np.zeros(grid.shape), where=n > 1)
    t = np.zeros(grid.shape)
    t[n > 1] = scipy_stats.t.ppf(0.975, n[n > 1] - 1)
    half = t * np.sqrt(np.divide(var, n, out=np.zeros(grid.shape), where=n > 0))
    return MeanCurve(grid, mean, mean - half, mean + half, len(series))


# ------------------------------------------------------------------------ sweeps


def sweeps(quick: bool) -> dict[str, Sweep]:
    """One sweep per map type; quick: the unstructured map only, smaller, fewer runs."""
    maps = MAPS[:1] if quick else MAPS
    out: dict[str, Sweep] = {}
    for map_name in maps:
        data = {
            "sweep": {
                "name": map_name,
                "seeds": list(QUICK_SEEDS if quick else SEEDS),
                "curves_every": CURVES_EVERY,
            },
            "fixed": {
                **FIXED,
                "map": map_name,
                "size": QUICK_MAP_SIZE if quick else MAP_SIZE,
            },
            "grid": {
                "start": list(STARTS),
                "strategy": list(STRATEGIES),
                "robots": list(QUICK_TEAM_SIZES if quick else TEAM_SIZES),
            },
        }
        out[map_name] = sweep_from_dict(data, source=f"{ID}:{map_name}")
    return out


# ------------------------------------------------------------------------ report

Lines = list[str]


def _cell(s: Summary | None, digits: int = 0, bold: bool = False) -> str:
    """``mean (sd; CI low..high; n)``, bold mean for the panel's lowest."""
    if s is None:
        return "-"
    mean = _fmt(s.mean, digits)
    if bold:
        mean = f"**{mean}**"
    interval = f"{_fmt(s.ci_low, digits)}..{_fmt(s.ci_high, digits)}"
    text = f"{mean} (sd {_fmt(s.sd, digits)}; CI {interval}; n {s.n}"
    return text + (f", {s.n_missing} missing)" if s.n_missing else ")")


def _diff(s: Summary, digits: int = 0) -> str:
    return f"{_fmt(s.mean, digits)} [{_fmt(s.ci_low, digits)}, {_fmt(s.ci_high, digits)}]"


def _panel_name(panel: Panel) -> str:
    return f"{panel[0]}/{panel[1]}/{panel[2]}r"


def _metric_table(
    stats: Mapping[Panel, Mapping[str, Summary]],
    panels: Sequence[Panel],
    first_column: str,
    label: Any,
    digits: int = 0,
) -> Lines:
    lines = [
        f"| {first_column} | " + " | ".join(f"{PAPER_NAMES[s]} (`{s}`)" for s in STRATEGIES) + " |",
        "|---|" + "---|" * len(STRATEGIES),
    ]
    for panel in panels:
        by_strategy = stats.get(panel, {})
        best = lowest(by_strategy)
        cells = [_cell(by_strategy.get(s), digits, bold=s == best) for s in STRATEGIES]
        lines.append(f"| {label(panel)} | " + " | ".join(cells) + " |")
    return lines


def _lowest_evidence(
    stats: Mapping[Panel, Mapping[str, Summary]],
    seeds: Mapping[Panel, Mapping[str, Mapping[int, float]]],
    panels: Sequence[Panel],
    digits: int = 0,
) -> tuple[int, int, str]:
    """How many of ``panels`` have KME lowest, and the evidence text."""
    holds, parts = 0, []
    for panel in panels:
        by_strategy = stats.get(panel, {})
        best = lowest(by_strategy)
        kme = by_strategy.get("kme")
        if kme is None or best is None:
            parts.append(f"{_panel_name(panel)}: no runs")
            continue
        others = {s: v for s, v in by_strategy.items() if s != "kme"}
        runner = lowest(others)
        holds += best == "kme"
        if runner is None:
            parts.append(f"{_panel_name(panel)}: KME {_fmt(kme.mean, digits)}")
            continue
        difference = paired(seeds.get(panel, {}), "kme", runner)
        parts.append(
            f"{_panel_name(panel)}: KME {_fmt(kme.mean, digits)} vs best other "
            f"{PAPER_NAMES[runner]} {_fmt(others[runner].mean, digits)}, paired KME-"
            f"{PAPER_NAMES[runner]} {_diff(difference, digits)}"
        )
    return holds, len(panels), f"KME lowest in {holds}/{len(panels)} panels; " + "; ".join(parts)


def _curve_figure(
    values: Sequence[RunValues],
    arrays: Mapping[str, Mapping[str, Any]],
    panels: Sequence[Panel],
    column: str,
    path: Path,
    title: str,
    ylabel: str,
) -> Path | None:
    """One subplot per panel: the mean curve of each strategy with its 95% CI band."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from mrexplore.viz.plots import LEGEND_WIDTH_IN, figure_legend_outside, strategy_colour

    present = [p for p in panels if any(v.panel == p for v in values)]
    if not present:
        return None
    horizons: dict[tuple[str, int], int] = {}
    for v in values:
        arrays_of_run = arrays.get(v.run_id)
        if arrays_of_run is not None and arrays_of_run["tick"].size:
            key = (v.map, v.robots)
            horizons[key] = max(horizons.get(key, 0), int(arrays_of_run["tick"][-1]))
    fig = Figure(figsize=(3.3 * len(present) + LEGEND_WIDTH_IN, 3.4), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(present), squeeze=False)[0]
    for ax, panel in zip(axes, present, strict=True):
        grid = horizon_grid(horizons.get((panel[0], panel[2]), 0), CURVES_EVERY)
        for strategy in STRATEGIES:
            series = [
                (arrays[v.run_id]["tick"], arrays[v.run_id][column])
                for v in values
                if v.panel == panel and v.strategy == strategy and v.run_id in arrays
            ]
            if not series:
                continue
            curve = mean_curve(series, grid)
            colour = strategy_colour(strategy)
            ax.plot(
                curve.ticks,
                curve.mean,
                color=colour,
                lw=1.5,
                label=f"{PAPER_NAMES[strategy]} (n={curve.n})",
            )
            ax.fill_between(curve.ticks, curve.low, curve.high, color=colour, alpha=0.18, lw=0)
        ax.set_ylim(bottom=0.0)  # a variance: the band's lower edge may dip below 0
        ax.set_title(f"{panel[2]} robots", fontsize=9)
        ax.set_xlabel("time (ticks)", fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.tick_params(labelsize=7)
    figure_legend_outside(fig, axes, fontsize=7)
    axes[0].set_ylabel(ylabel, fontsize=8)
    fig.suptitle(f"{title}\n(mean of the runs, band: 95% CI)", fontsize=10)
    fig.savefig(path, format="png")
    return path


def _combinations_figure(
    stats: Mapping[Panel, Mapping[str, Summary]], path: Path, ylabel: str, title: str
) -> Path | None:
    """A grid (starting scheme x map) of mean-vs-team-size plots, one line per strategy."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from mrexplore.viz.plots import (
        LEGEND_WIDTH_IN,
        figure_legend_outside,
        strategy_colour,
        strategy_marker,
    )

    maps = [m for m in MAPS if any(p[0] == m for p in stats)]
    starts = [s for s in STARTS if any(p[1] == s for p in stats)]
    if not maps or not starts:
        return None
    fig = Figure(
        figsize=(3.4 * len(maps) + LEGEND_WIDTH_IN, 3.0 * len(starts)),
        dpi=110,
        layout="constrained",
    )
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(starts), len(maps), squeeze=False)
    for row, start in enumerate(starts):
        for col, map_name in enumerate(maps):
            ax = axes[row][col]
            sizes = sorted({p[2] for p in stats if p[0] == map_name and p[1] == start})
            for i, strategy in enumerate(STRATEGIES):
                points = [(n, stats[(map_name, start, n)].get(strategy)) for n in sizes]
                kept = [(n, s) for n, s in points if s is not None]
                if not kept:
                    continue
                xs = np.array([n for n, _ in kept], dtype=np.float64) + (i - 1.5) * 0.12
                means = np.array([s.mean for _, s in kept])
                below = np.array([s.mean - s.ci_low for _, s in kept])
                above = np.array([s.ci_high - s.mean for _, s in kept])
                ax.errorbar(
                    xs,
                    means,
                    yerr=np.vstack([np.nan_to_num(below), np.nan_to_num(above)]),
                    color=strategy_colour(strategy),
                    marker=strategy_marker(strategy),
                    ms=4,
                    lw=1.2,
                    capsize=2,
                    label=PAPER_NAMES[strategy],
                )
            ax.set_title(f"{map_name}, start {start}", fontsize=9)
            ax.set_xticks(sizes)
            ax.set_xlabel("robots", fontsize=8)
            ax.set_ylabel(ylabel, fontsize=8)
            ax.tick_params(labelsize=7)
            ax.grid(True, alpha=0.3)
    figure_legend_outside(fig, fig.axes, fontsize=7)
    fig.suptitle(f"{title} (mean, error bars: 95% CI)", fontsize=10)
    fig.savefig(path, format="png")
    return path


def _status_note(values: Sequence[RunValues], failed: int) -> str:
    counts: dict[str, int] = {}
    for v in values:
        counts[v.status] = counts.get(v.status, 0) + 1
    if failed:
        counts["failed"] = failed
    return ", ".join(f"{n} runs {s}" for s, n in sorted(counts.items())) or "no runs"


def start_check(values: Sequence[RunValues]) -> list[tuple[str, str, int, int, int, int]]:
    """Per (map, scheme, team size): distinct start sets over the seeds, seeds, and
    seeds whose four strategies started from the same cells (paired comparisons).

    >>> v = [RunValues(str(i), "m", "separate", 2, s, seed, "complete", f"[[{seed}, 1]]",
    ...      0.0, 0.0, 0.0, 0.0, 0.0) for i, (s, seed) in
    ...      enumerate([("kme", 1), ("burgard", 1), ("kme", 2), ("burgard", 2)])]
    >>> start_check(v)
    [('m', 'separate', 2, 2, 2, 2)]
    """
    groups: dict[Panel, dict[int, set[str]]] = {}
    for v in values:
        groups.setdefault(v.panel, {}).setdefault(v.seed, set()).add(v.starts)
    out = []
    for panel in sorted(groups):
        by_seed = groups[panel]
        paired_seeds = sum(len(starts) == 1 for starts in by_seed.values())
        distinct = len({json.dumps(sorted(s)) for s in by_seed.values()})
        out.append((*panel, distinct, len(by_seed), paired_seeds))
    return out


def _settings_section(quick: bool) -> Lines:
    rows = [
        (
            "maps",
            "blank, unstructured, cityblock (Fig. 4), one map each; size not given",
            f"generators `blank`, `unstructured`, `cityblock`, "
            f"{QUICK_MAP_SIZE if quick else MAP_SIZE} cells, `map_seed = {MAP_SEED}`"
            + (" (quick: unstructured only)" if quick else ""),
        ),
        ("sensor range", "not given", f"{SENSOR_RANGE} cells, line of sight"),
        (
            "sensing",
            'a robot "arrives at a cell at step t and explores its surrounding area"',
            "every tick (`sensing = moving`): each step arrives at a cell",
        ),
        (
            "strategies",
            "YMC [3], Burgard [4, 5], Zlot [6], KME",
            "`nearest-frontier`, `burgard`, `zlot-market`, `kme`, all at their defaults",
        ),
        (
            "team sizes",
            "2 to 8 (figures: 2, 4, 6, 8)",
            ", ".join(str(n) for n in (QUICK_TEAM_SIZES if quick else TEAM_SIZES)),
        ),
        (
            "starting schemes",
            "together: from one of 15 locations (Fig. 5 right); separate: robots at "
            "random among those 15 locations",
            "together: adjacent free cells around a random free cell drawn from the seed; "
            "separate: each robot at a random free cell (of the largest free region) drawn "
            "from the seed",
        ),
        (
            "runs per combination",
            f"{PAPER_RUNS_PER_CONFIGURATION} set-ups ({PAPER_CONFIGURATIONS} configurations "
            "in all)",
            f"{len(QUICK_SEEDS if quick else SEEDS)} seeds "
            f"({min(QUICK_SEEDS if quick else SEEDS)}-{max(QUICK_SEEDS if quick else SEEDS)}); "
            "the seed places the starts, the same for the four strategies",
        ),
        ("time", "exploration steps", "ticks: one cell of path per tick"),
        (
            "end of a run",
            "every cell known",
            f"every explorable cell known (`coverage_threshold = 1`), at most {MAX_TICKS} ticks",
        ),
        ("communication", "not limited", "unlimited range, latency 1 tick, `full` map sharing"),
        (
            "regions",
            f"{N_REGIONS} equal-sized regions (also {', '.join(map(str, PAPER_REGION_COUNTS))})",
            f"{N_REGIONS} equal rectangles (4 x 2 on a square map), `wtv_8`, `epv_8`",
        ),
        (
            "curves",
            "mean of 15 runs over exploration steps",
            f"sampled every {CURVES_EVERY} ticks; mean over seeds, 95% CI band",
        ),
    ]
    lines = ["## Settings", "", "| setting | paper (§V.A-B) | ours |", "|---|---|---|"]
    lines += [f"| {name} | {paper} | {ours} |" for name, paper, ours in rows]
    lines += [
        "",
        "Choices where the paper is silent or our world differs:",
        "",
        f"- *Map size and sensor range* are not given. We use {MAP_SIZE} cells (the "
        "generators' default is 100 x 100, whose runs cost about 1.5 times the CPU time; "
        "80 x 80 keeps the 1440 runs near 16 CPU minutes) and the simulator's default "
        "sensor range of 8 cells (a tenth "
        "of the map side). The maps are ours: Fig. 4 is not in our text copy.",
        "- *WTV and EPV* follow `mrexplore.metrics.regions` (eqs. 8-10): `w'` of an unknown "
        "cell = now + straight-line distance to the closest robot / speed; only explorable "
        "cells count (the paper counts every cell, free or occupied); the variance is the "
        "population variance, WTV in ticks^2, EPV in percent^2.",
        '- *WTV over time* (our one number per run for "the WTV during the exploration"): '
        "the run's `wtv_8` curve, carried past the run's end at its final value up to the "
        "last tick of the longest run with the same map and team size, averaged over the "
        f"samples every {CURVES_EVERY} ticks. *EPV over time* likewise. The paper compares "
        "the plotted mean curves by eye.",
        "- *Start set-ups*: the paper draws starts from 15 fixed locations (Fig. 5 right, "
        "not in our copy); we draw them from the seed over all free cells, so each seed "
        "is one set-up and the four strategies start from the same cells (checked below).",
        "- *Sensing every tick*: our `kme` re-plans when a robot reaches its target "
        "(§IV.D step 11) and also when its target stops being a frontier "
        "(`replan_on_target_explored`, its documented default).",
        "",
    ]
    return lines


def _start_section(values: Sequence[RunValues]) -> Lines:
    checks = start_check(values)
    lines = [
        "## Start set-ups",
        "",
        "Each seed places the robots; all strategies of a seed start from the same cells.",
        "",
        "| map | scheme | robots | distinct start sets | seeds | seeds with equal starts "
        "for all strategies |",
        "|---|---|---|---|---|---|",
    ]
    lines += [f"| {m} | {s} | {n} | {d} | {k} | {p} |" for m, s, n, d, k, p in checks]
    return [*lines, ""]


def _curve_section(
    title: str,
    paper: Sequence[str],
    values: Sequence[RunValues],
    arrays: Mapping[str, Mapping[str, Any]],
    panels: Sequence[Panel],
    stats: Mapping[str, Mapping[Panel, Mapping[str, Summary]]],
    column: str,
    figure: str,
    out: Path,
    digits: int,
) -> Lines:
    """A section for one of Figs. 6-8: the paper's text, our tables and figure."""
    kind = "WTV" if column.startswith("wtv") else "EPV"
    unit = "ticks^2" if kind == "WTV" else "percent^2"
    time_key, final_key = f"{kind.lower()}_time", f"{kind.lower()}_final"
    lines = [f"## {title}", ""]
    lines += [f"Paper: {text}." for text in paper]
    lines += [
        "",
        f"Ours: {kind} of {N_REGIONS} regions over time ({unit}; mean over the run, see "
        "Settings), mean (sd; 95% CI; n) over the seeds; the lowest mean in bold.",
        "",
    ]
    lines += _metric_table(stats[time_key], panels, "robots", lambda p: p[2], digits)
    if kind == "WTV":
        lines += ["", f"Final WTV (eq. 10, the value where each curve ends; {unit}):", ""]
        lines += _metric_table(stats[final_key], panels, "robots", lambda p: p[2], digits)
    else:  # every region is fully explored at the end: the final EPV is 0 by definition
        lines += ["", "(The final EPV is 0 in every complete run: every region is at 100%.)"]
    lines.append("")
    path = _curve_figure(values, arrays, panels, column, out / figure, title, f"{kind} ({unit})")
    if path is not None:
        lines += [f"![{title}]({figure})", ""]
    return lines


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Path:
    """Write ``out/report.md`` and its figures from the experiments' stores."""
    out = Path(out)
    values: list[RunValues] = []
    arrays: dict[str, dict[str, Any]] = {}
    failed = 0
    for store in stores.values():
        runs, curves = store.tables()
        values += run_values(runs, curves)
        failed += sum(s == "failed" for s in runs.column("status").to_pylist())
        arrays.update(_curve_arrays(curves, (f"wtv_{N_REGIONS}", f"epv_{N_REGIONS}")))
    stats = {metric: panel_means(values, metric) for metric in METRICS}
    seeds = {metric: by_panel(values, metric) for metric in METRICS}
    sizes = sorted({v.robots for v in values})
    more_than_two = [n for n in sizes if n > 2]

    lines: Lines = [f"# Reproduction: Wu, Puig and Garcia, {TITLE}", ""]
    if quick:
        lines += [
            f"> **Quick run** (`--quick`): unstructured map only, {QUICK_MAP_SIZE} cells, "
            f"{len(QUICK_SEEDS)} seeds, {', '.join(map(str, QUICK_TEAM_SIZES))} robots. Its "
            "verdicts are indicative only; run without `--quick` for the paper's settings.",
            "",
        ]
    lines += [
        f"Citation: {CITATION}",
        "",
        f"Written {time.strftime('%Y-%m-%d %H:%M')}. Runs: {_status_note(values, failed)}.",
        "",
    ]
    lines += _settings_section(quick)
    lines += _start_section(values)

    unstructured = "unstructured"
    together = [(unstructured, "together", n) for n in sizes]
    separate = [(unstructured, "separate", n) for n in sizes]
    lines += _curve_section(
        "Fig. 6: WTV of eight regions, unstructured map, robots start together",
        [
            f'"{PAPER_FIG6_FEWER_ROBOTS_HIGHER}" (read from the text)',
            '"When more than two robots are utilized, KME has the lowest WTV during the '
            f'exploration": KME lowest with {PAPER_FIG6_KME_LOWEST} robots (read from the text)',
            '"WTV_final ... with KME is also the smallest except for the two-robot case": '
            f"smallest with {PAPER_FIG6_KME_FINAL_LOWEST}, not with "
            f"{PAPER_FIG6_KME_FINAL_NOT_LOWEST} robots (read from the text; Fig. 6 gives the "
            f"curves, mean of {PAPER_RUNS_PER_CONFIGURATION} runs, without numbers)",
        ],
        values,
        arrays,
        together,
        stats,
        f"wtv_{N_REGIONS}",
        "fig6_wtv_together.png",
        out,
        0,
    )
    lines += _curve_section(
        "Fig. 7: WTV of eight regions, unstructured map, robots start separately",
        [
            f'"{PAPER_FIG7_SEPARATE_LOWER}" (read from the text)',
            '"With the separate scheme, KME is again superior to the other methods": KME '
            f"lowest with {PAPER_FIG7_KME_LOWEST} robots (read from the text; no numbers)",
        ],
        values,
        arrays,
        separate,
        stats,
        f"wtv_{N_REGIONS}",
        "fig7_wtv_separate.png",
        out,
        0,
    )
    lines += _curve_section(
        "Fig. 8: EPV of eight regions, unstructured map, robots start separately",
        [
            '"with 2, 4, 6, and 8 robots, the eight regions are explored at a similar speed '
            f'with KME": KME lowest EPV with {PAPER_FIG8_KME_LOWEST} robots (read from the '
            "text; no numbers)",
        ],
        values,
        arrays,
        separate,
        stats,
        f"epv_{N_REGIONS}",
        "fig8_epv_separate.png",
        out,
        1,
    )

    all_panels = sorted(
        stats["wtv_time"],
        key=lambda p: (
            MAPS.index(p[0]) if p[0] in MAPS else 9,
            STARTS.index(p[1]) if p[1] in STARTS else 9,
            p[2],
        ),
    )
    lines += [
        '## All maps and starting schemes (§V.C: "the same trend")',
        "",
        f'Paper: "{PAPER_SIX_COMBINATIONS}"; "{PAPER_ZLOT_NOT_SUPERIOR}" (read from the '
        "text; the other combinations are only on the authors' web page).",
        "",
        "WTV of eight regions over time (ticks^2), mean (sd; 95% CI; n), lowest in bold:",
        "",
    ]
    lines += _metric_table(stats["wtv_time"], all_panels, "map / scheme / robots", _panel_name)
    lines += ["", "EPV of eight regions over time (percent^2):", ""]
    lines += _metric_table(stats["epv_time"], all_panels, "map / scheme / robots", _panel_name, 1)
    lines += [
        "",
        "Exploration time T100 (ticks until every explorable cell is known; not a claim of "
        "the paper, for context):",
        "",
    ]
    lines += _metric_table(stats["t100"], all_panels, "map / scheme / robots", _panel_name)
    lines.append("")
    for metric, name, label in (
        ("wtv_time", "wtv_all_combinations.png", "WTV over time (ticks^2)"),
        ("epv_time", "epv_all_combinations.png", "EPV over time (percent^2)"),
    ):
        if quick:  # one map: the figures above show it all
            continue
        path = _combinations_figure(stats[metric], out / name, label, f"{label}, 8 regions")
        if path is not None:
            lines += [f"![{label}, all combinations]({name})", ""]

    # ------------------------------------------------------------------ verdicts
    verdicts: list[Verdict] = []
    means_by_strategy = {
        s: {
            p[2]: stats["wtv_time"][p][s].mean
            for p in together
            if s in stats["wtv_time"].get(p, {})
        }
        for s in STRATEGIES
    }
    verdicts.append(
        Verdict(
            "Fig. 6: the more robots, the lower the WTV of every approach (unstructured, together)",
            decreasing_outcome({s: m for s, m in means_by_strategy.items() if m}),
            "; ".join(
                f"{PAPER_NAMES[s]} "
                + ", ".join(f"{n}:{_fmt(m)}" for n, m in sorted(means_by_strategy[s].items()))
                for s in STRATEGIES
                if means_by_strategy[s]
            )
            + " (robots:mean WTV over time, ticks^2)",
        )
    )
    fig6 = [p for p in together if p[2] in more_than_two]
    holds, total, evidence = _lowest_evidence(stats["wtv_time"], seeds["wtv_time"], fig6)
    verdicts.append(
        Verdict(
            "Fig. 6: with more than two robots KME has the lowest WTV during the exploration "
            "(unstructured, together)",
            count_outcome(holds, total),
            evidence + "; WTV over time, ticks^2",
        )
    )
    final_holds, final_parts = 0, []
    for panel in together:
        best = lowest(stats["wtv_final"].get(panel, {}))
        expected_lowest = panel[2] > 2
        ok = (best == "kme") == expected_lowest
        final_holds += ok
        kme_final = stats["wtv_final"].get(panel, {}).get("kme")
        final_parts.append(
            f"{panel[2]}r: lowest {PAPER_NAMES.get(best or '', '-')} "
            f"(KME {_fmt(kme_final.mean if kme_final is not None else math.nan)})"
        )
    verdicts.append(
        Verdict(
            "Fig. 6: the final WTV of KME is the smallest except with two robots "
            "(unstructured, together)",
            count_outcome(final_holds, len(together)),
            f"statement holds at {final_holds}/{len(together)} team sizes: "
            + "; ".join(final_parts)
            + " (final WTV, ticks^2)",
        )
    )
    lower_holds, lower_total, lower_parts = 0, 0, []
    for n in sizes:
        for s in STRATEGIES:
            a = stats["wtv_time"].get((unstructured, "separate", n), {}).get(s)
            b = stats["wtv_time"].get((unstructured, "together", n), {}).get(s)
            if a is None or b is None:
                continue
            lower_total += 1
            lower_holds += a.mean < b.mean
            if not a.mean < b.mean:
                lower_parts.append(f"{PAPER_NAMES[s]} {n}r: {_fmt(a.mean)} vs {_fmt(b.mean)}")
    verdicts.append(
        Verdict(
            "Fig. 7 vs Fig. 6: the WTV of every technique is lower with separate starts than "
            "with starts together (unstructured)",
            count_outcome(lower_holds, lower_total),
            f"separate < together in {lower_holds}/{lower_total} strategy x team size cells"
            + (
                "; exceptions (separate vs together, WTV over time): " + "; ".join(lower_parts)
                if lower_parts
                else ""
            ),
        )
    )
    fig7 = [p for p in separate if p[2] in more_than_two]
    holds, total, evidence = _lowest_evidence(stats["wtv_time"], seeds["wtv_time"], fig7)
    verdicts.append(
        Verdict(
            "Fig. 7: with separate starts KME again has the lowest WTV (unstructured, more than "
            "two robots)",
            count_outcome(holds, total),
            evidence + "; WTV over time, ticks^2",
        )
    )
    holds, total, evidence = _lowest_evidence(stats["epv_time"], seeds["epv_time"], separate, 1)
    verdicts.append(
        Verdict(
            "Fig. 8: KME explores the eight regions at the most similar speed (lowest EPV) "
            "with 2, 4, 6 and 8 robots (unstructured, separate)",
            count_outcome(holds, total),
            evidence + "; EPV over time, percent^2",
        )
    )
    six = [p for p in all_panels if p[2] > 2]
    holds, total, _ = _lowest_evidence(stats["wtv_time"], seeds["wtv_time"], six)
    misses = [
        f"{_panel_name(p)} ({PAPER_NAMES.get(lowest(stats['wtv_time'][p]) or '', '-')} lowest)"
        for p in six
        if lowest(stats["wtv_time"][p]) != "kme"
    ]
    combos = sorted({(p[0], p[1]) for p in six})
    verdicts.append(
        Verdict(
            "§V.C: the same trend (KME lowest WTV with more than two robots) holds in all six "
            "combinations of maps and starting schemes",
            count_outcome(holds, total),
            f"KME lowest in {holds}/{total} panels over {len(combos)} map x scheme "
            "combination(s)" + (f"; not lowest in {', '.join(misses)}" if misses else ""),
        )
    )
    zlot_cells, zlot_holds, superior = 0, 0, []
    for metric in ("wtv_time", "epv_time"):
        for panel in all_panels:
            by_seed = seeds[metric].get(panel, {})
            if not all(s in by_seed for s in ("zlot-market", "nearest-frontier", "burgard")):
                continue
            zlot_cells += 1
            if zlot_superior(by_seed):
                superior.append(f"{metric[:3].upper()} {_panel_name(panel)}")
            else:
                zlot_holds += 1
    verdicts.append(
        Verdict(
            "§V.C: Zlot's method is not superior to Yamauchi's and Burgard's in WTV and EPV",
            count_outcome(zlot_holds, zlot_cells),
            f"Zlot not significantly below both in {zlot_holds}/{zlot_cells} panel x metric "
            "cells" + (f"; superior in {', '.join(superior)}" if superior else ""),
        )
    )

    lines += rules_header(RULES)
    lines += [
        "",
        "Which rule decides which claim: the first `decreasing`; the KME-lowest claims "
        "`lowest`; the final-WTV and separate-vs-together claims `counted`; the last `zlot`. "
        "Panels with more than two robots are those of the run's team sizes above 2.",
        "",
        verdict_section(verdicts),
        "",
    ]
    path = out / "report.md"
    path.write_text("\n".join(lines))
    return path


REPRODUCTION = Reproduction(
    id=ID,
    title=TITLE,
    citation=CITATION,
    sweeps=sweeps,
    report=report,
)
