"""Reproduction of Wu, Puig and Garcia (2010; the id ``wu2011`` is historical), §V: KME
against Yamauchi (``nearest-frontier``), Burgard et al. (``burgard``) and Zlot et al.
(``zlot-market``) by the waiting-time variance WTV (eqs. 8-10) and the exploration-percentage
variance EPV of 8 equal regions. Figs. 6-8 are plots without numbers: the text's statements are
the :data:`CLAIMS`. One sweep per map type and strategy, so a re-plan-trigger reading
(:data:`INTERPRETATIONS`) takes whole sweeps.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyarrow as pa

from mrexplore.experiments.reproduce import claims, render
from mrexplore.experiments.reproduce.base import Reproduction
from mrexplore.experiments.store import Store

ID = "wu2011"
TITLE = (
    "Wu, Puig and Garcia, Balanced multi-robot exploration through a global optimization strategy"
)
CITATION = (
    'L. Wu, D. Puig, M. A. Garcia, "Balanced multi-robot exploration through a global '
    'optimization strategy", Journal of Physical Agents 4(1), 2010, §V.'
)
FloatArray = npt.NDArray[np.float64]

#: §V.A, Fig. 4: "blank map", "unstructured map", "cityblock map" (our generators, one
#: map each; their size, cells, is ours); the unstructured map first: Figs. 6-8 show it.
MAPS, MAP_SIZE, QUICK_MAP_SIZE, MAP_SEED = ("unstructured", "blank", "cityblock"), 80, 48, 1
SENSOR_RANGE = 8  # cells; not given in the paper (the simulator's default)
#: §V.A: "(a) all robots start from the same location, (b) robots start from random locations".
STARTS = ("together", "separate")
#: Figs. 6-8: "2, 4, 6, and 8 robots" (§V.A ran 2 to 8).
TEAM_SIZES, QUICK_TEAM_SIZES = (2, 4, 6, 8), (2, 4)
#: §V.A: "For every combination of robots, maps and starting schemes, 15 set-ups": a seed each.
SEEDS, QUICK_SEEDS = tuple(range(1, 16)), (1, 2)
#: §V.C: "YMC, Burgard, Zlot and KME represent Yamauchi [3], Burgard et al. [4], [5], Zlot ..."
STRATEGIES = ("kme", "nearest-frontier", "burgard", "zlot-market")
#: Figs. 6-8: "WTV of eight regions", "EPV for eight regions"; our curves every 10 ticks.
N_REGIONS, CURVES_EVERY, MAX_TICKS = 8, 10, 4000
CURVES, CURVE_METRICS = (f"wtv_{N_REGIONS}", f"epv_{N_REGIONS}"), ("wtv_time", "epv_time")

FIXED: dict[str, Any] = {
    "map_seed": MAP_SEED,
    "sensor_range": SENSOR_RANGE,
    "sensing": "moving",  # §V.B: a robot "arrives at a cell at step t and explores"
    "comm_range": "inf",  # the paper models no communication limit
    "coverage_threshold": 1.0,  # §V.B, eq. 10: at the end "every cell of the workspace is known"
    "max_ticks": MAX_TICKS,
}

#: §V.A: "15 set-ups of runs"; "630 different configurations (3 maps x 2 starting schemes
#: x 7 applied numbers of robots x 15 runs)"; §V.B: "the maps are divided into 2, 4, 8,
#: 16, 32, 64 equal-sized regions".
PAPER_RUNS_PER_CONFIGURATION, PAPER_CONFIGURATIONS = 15, 630
PAPER_TEAM_SIZES, PAPER_REGION_COUNTS = (2, 3, 4, 5, 6, 7, 8), (2, 4, 8, 16, 32, 64)
#: The team sizes of the §V.C sentences: KME lowest WTV "when more than two robots are
#: utilized" (Fig. 6, taken alike for Fig. 7 and the six combinations), final WTV
#: smallest "except for the two-robot case", EPV lowest "with 2, 4, 6, and 8 robots".
PAPER_KME_LOWEST, PAPER_KME_FINAL_NOT_LOWEST, PAPER_KME_LOWEST_EPV = (4, 6, 8), (2,), TEAM_SIZES


def experiments(quick: bool) -> list[render.Experiment]:
    """One experiment per map type and strategy; quick: the unstructured map, smaller."""
    size, seeds = (QUICK_MAP_SIZE, QUICK_SEEDS) if quick else (MAP_SIZE, SEEDS)
    fixed = {**FIXED, "size": f"{size}x{size}"}
    grid = {"start": list(STARTS), "robots": list(QUICK_TEAM_SIZES if quick else TEAM_SIZES)}
    return [
        render.Experiment(f"{m}-{s}", {**fixed, "map": m, **settings}, grid, seeds, CURVES_EVERY)
        for m in (MAPS[:1] if quick else MAPS)
        for s in STRATEGIES
        for settings in [{"strategy": s, **({"set": ON_ARRIVAL} if s in REPLANNING else {})}]
    ]


# ------------------------------------------------------------- per-run numbers


def time_mean(ticks: FloatArray, values: FloatArray, horizon: int, every: int) -> float:
    """Mean of a run's curve (``ticks`` increasing) at the ticks ``0, every, 2 every, ...
    <= horizon`` and at ``horizon``, each its last sample at or before the tick (carried
    past the run's end, none before its first): "the value during the exploration"."""
    grid = np.arange(0, horizon + 1, every, dtype=np.float64)
    grid = grid if grid[-1] == horizon else np.append(grid, horizon)
    at = np.searchsorted(ticks, grid, side="right") - 1
    sampled = values[at[at >= 0]]
    finite = sampled[np.isfinite(sampled)]
    return float(finite.mean()) if finite.size else math.nan


def curve_table(stores: Mapping[str, Store]) -> pa.Table | None:
    """``run_id``, ``tick``, ``wtv_8``, ``epv_8`` of every store's runs (``None``: none)."""
    tables = [store.tables()[1] for store in stores.values()]
    kept = [t.select(["run_id", "tick", *CURVES]) for t in tables if t is not None]
    return pa.concat_tables(kept, promote_options="default") if kept else None


def with_curve_means(rows: Sequence[render.Row], curves: pa.Table | None) -> list[dict[str, Any]]:
    """Each row with its ``horizon`` and ``wtv_time`` / ``epv_time``: :func:`time_mean` of
    its curves (:func:`curve_table`) up to the horizon of its map and team size, the last
    curve tick of their longest run (any strategy or scheme)."""
    runs: dict[str, dict[str, FloatArray]] = {}
    if curves is not None:
        ids = np.array(curves["run_id"].to_pylist(), dtype=object)
        data = {c: np.array(curves[c].to_pylist(), dtype=float) for c in ("tick", *CURVES)}
        for i in np.split(np.arange(ids.size), np.flatnonzero(ids[1:] != ids[:-1]) + 1):
            runs[ids[i[0]]] = {c: v[i] for c, v in data.items()}
    horizons: dict[tuple[str, int], int] = {}
    for r in (r for r in rows if r["run_id"] in runs):
        key = r["map"], r["robots"]
        horizons[key] = max(horizons.get(key, 0), int(runs[r["run_id"]]["tick"][-1]))
    none = dict.fromkeys(("tick", *CURVES), np.zeros(0))  # no curve: nan
    out = []
    for r in rows:
        run, horizon = runs.get(r["run_id"], none), horizons.get((r["map"], r["robots"]), 0)
        means = [time_mean(run["tick"], run[c], horizon, CURVES_EVERY) for c in CURVES]
        out.append({**r, "horizon": horizon, **dict(zip(CURVE_METRICS, means, strict=True))})
    return out


#: The numbers of a run the report and the claims read (nan when missing: not a count).
METRICS = {"wtv_time": render.measured("wtv_time"), "epv_time": render.measured("epv_time")}
METRICS |= {"wtv_final": render.measured(f"{CURVES[0]}_final"), "t100": render.measured("T100")}


def run_values(rows: Sequence[render.Row], by: str = "start", arm: str = "strategy") -> Any:
    """``metric -> (map, row[by], robots) -> row[arm] -> seed -> value`` in the report's
    order (``by="strategy", arm="start"`` compares the starting schemes)."""
    order = {v: i for i, v in enumerate((*MAPS, *STARTS, *STRATEGIES))}
    cell = lambda r: (r["map"], r[by], int(r["robots"]))  # noqa: E731 (a key, as below)
    rank = lambda c: (order.get(c[0], 99), order.get(c[1], 99), c[2])  # noqa: E731 (a key)
    return render.tabulate(rows, METRICS, cell, lambda r: str(r[arm]), rank)


# ------------------------------------------------------------ the paper's claims

FIG6, FIG7 = ("unstructured", "together"), ("unstructured", "separate")
LABELS = {
    "wtv_time": "WTV over time (ticks^2)",
    "wtv_final": "final WTV (ticks^2)",
    "epv_time": "EPV over time (percent^2)",
    "t100": "T100 (ticks until every explorable cell is known; not a claim, for context)",
    "wtv_epv_time": "WTV (ticks^2) and EPV (percent^2) over time",
}


def tables(stores: Mapping[str, Store], quick: bool) -> dict[str, claims.Values]:
    """What :data:`CLAIMS` read: ``<metric>/<panels> -> cell -> arm -> seed -> value``."""
    rows = with_curve_means(render.rows_of(stores)[0], curve_table(stores))
    values, schemes = run_values(rows), run_values(rows, by="strategy", arm="start")["wtv_time"]

    def part(m: str, scheme: Any, teams: Sequence[int] = TEAM_SIZES) -> claims.Values:
        return {c: v for c, v in values[m].items() if scheme in (None, c[:2]) and c[2] in teams}

    both = {(m[:3].upper(), *c): v for m in CURVE_METRICS for c, v in values[m].items()}
    return {
        "wtv_time/fig6": part("wtv_time", FIG6),
        "wtv_time/fig6/teams": part("wtv_time", FIG6, PAPER_KME_LOWEST),
        "wtv_final/fig6": part("wtv_final", FIG6),
        "wtv_time/schemes": {c: v for c, v in schemes.items() if c[0] == FIG6[0]},
        "wtv_time/fig7/teams": part("wtv_time", FIG7, PAPER_KME_LOWEST),
        "epv_time/fig8": part("epv_time", FIG7, PAPER_KME_LOWEST_EPV),
        "wtv_time/teams": part("wtv_time", None, PAPER_KME_LOWEST),
        "wtv_epv_time": both,
    }


#: ``id | where | our statement | the paper's sentence (§V.C)``, in the report's order.
CLAIM_WORDS = render.text_rows("""
fewer_robots | Fig. 6 | the more robots, the lower the WTV of every approach (unstructured,
  together) | The WTV curves show that the more robots, the lower the WTVs of all approaches.
fig6_lowest | Fig. 6 | with more than two robots KME has the lowest WTV (unstructured, together)
  | When more than two robots are utilized, KME has the lowest WTV during the exploration
fig6_final | Fig. 6 | the final WTV of KME is the smallest except with two robots (unstructured,
  together) | WTV_final of regions (the value where each curve terminates) with KME is also the
  smallest except for the two-robot case
separate_lower | Fig. 7 vs 6 | every technique's WTV is lower with separate starts than with
  starts together | The WTV curves of all techniques with the separate scheme are lower than the
  ones with the together scheme.
fig7_lowest | Fig. 7 | with separate starts KME again has the lowest WTV (unstructured, more than
  two robots) | With the separate scheme, KME is again superior to the other methods.
fig8_lowest | Fig. 8 | KME has the lowest EPV (most similar speeds) with 2-8 robots (unstructured,
  separate) | with 2, 4, 6, and 8 robots, the eight regions are explored at a similar speed with
  KME
six_combinations | §V.C | KME has the lowest WTV with more than two robots in all six maps x
  schemes | The same trend can be found in the six combinations of maps and starting schemes.
zlot | §V.C | Zlot's method is not superior to Yamauchi's and Burgard's in WTV and EPV | Zlot's
  algorithm behaves like [3]-[5] with respect to the WTV and EPV ... its solution is not
  superior to [3]-[5]
""")
_LOWEST = claims.Means("<", best=True)  # KME's mean the lowest of the strategies'
_FINAL = claims.Means("<", best=True, except_at=PAPER_KME_FINAL_NOT_LOWEST)
_UNPAIRED = claims.Means("<", seeds="unpaired", brief=True)  # one seed is not one set-up
#: Claim id -> the values read, the rule, the arms (the first against the others).
RULES: dict[str, tuple[str, claims.Rule, tuple[str, ...]]] = {
    "fewer_robots": ("wtv_time/fig6", claims.Trend("steps", needs=claims.EVERY_WEAK), STRATEGIES),
    "fig6_lowest": ("wtv_time/fig6/teams", _LOWEST, STRATEGIES),
    "fig6_final": ("wtv_final/fig6", _FINAL, STRATEGIES),
    "separate_lower": ("wtv_time/schemes", _UNPAIRED, STARTS[::-1]),
    "fig7_lowest": ("wtv_time/fig7/teams", _LOWEST, STRATEGIES),
    "fig8_lowest": ("epv_time/fig8", _LOWEST, STRATEGIES),
    "six_combinations": ("wtv_time/teams", claims.Means("<", best=True, brief=True), STRATEGIES),
    "zlot": ("wtv_epv_time", claims.NotBelowAll(brief=True), ("zlot-market", *STRATEGIES[1:3])),
}


def _claim(id_: str, where: str, statement: str, sentence: str) -> claims.Claim:
    values, rule, (first, second, *seconds) = RULES[id_]
    head = (id_, where, statement, sentence, values, LABELS[values.split("/")[0]], first, second)
    return claims.Claim(*head, rule, int(values.startswith("epv")), tuple(seconds))


CLAIMS = tuple(_claim(*words) for words in CLAIM_WORDS)

#: §IV.D step 11: a KME round when the first robot arrives; the paper names no trigger of the
#: baselines, so `nearest-frontier` and `burgard` re-plan on arrival too (one rule for every
#: arm); `zlot-market` drops a goal once it is explored (its own task rule).
_STEP_11 = '§IV.D step 11 "Robots move to their targets until one robot arrives at its target"'
ON_ARRIVAL = {"replan_on_target_explored": False}
REPLANNING = ("kme", "nearest-frontier", "burgard")
INTERPRETATIONS = render.readings(f"""
all-replan-when-explored | {_STEP_11}, read as one trigger among others | `kme`,
  `nearest-frontier` and `burgard` also re-plan once a target is explored
  (`replan_on_target_explored=true`, our earlier default; default: on arrival), KME and the
  baselines alike | replan_on_target_explored=true | kme, nearest-frontier, burgard
coordinator-assigns-requesting | §II (Burgard et al.: the robot-target tuple of highest utility,
  robot after robot) | `burgard`'s coordinator assigns only the robots that ask for a goal, the
  goals of the others fixed (`assign=requesting`, our earlier version; default: the whole team)
  | assign=requesting | burgard
""")

# ------------------------------------------------------------------------ report


def _settings(quick: bool) -> render.Lines:
    """The settings, the paper's (§V.A-B) beside ours, and our choices where it is silent."""
    size, seeds = (QUICK_MAP_SIZE, QUICK_SEEDS) if quick else (MAP_SIZE, SEEDS)
    teams = ", ".join(map(str, QUICK_TEAM_SIZES if quick else TEAM_SIZES))
    rows = f"""
maps | blank, unstructured, cityblock (Fig. 4); size not given | our generators, {size}x{size}
  cells, `map_seed = {MAP_SEED}`{" (quick: one)" * quick}
sensor range | not given | {SENSOR_RANGE} cells (a tenth of the side), line of sight
sensing | a robot "arrives at a cell at step t and explores" | every tick (`moving`)
strategies | YMC [3], Burgard [4, 5], Zlot [6], KME | `nearest-frontier`, `burgard`,
  `zlot-market`, `kme` at their defaults
team sizes | {PAPER_TEAM_SIZES[0]} to {PAPER_TEAM_SIZES[-1]} (figures: 2, 4, 6, 8) | {teams}
starting schemes | together / separate among 15 locations | placed by the seed, alike
runs per combination | {PAPER_RUNS_PER_CONFIGURATION} set-ups ({PAPER_CONFIGURATIONS}
  configurations) | {len(seeds)} seeds, one set-up each
end of a run | every cell known | every explorable cell, at most {MAX_TICKS} ticks
communication | not limited | unlimited range, latency 1 tick, `full` map sharing
regions | {N_REGIONS} equal regions (also {", ".join(map(str, PAPER_REGION_COUNTS))}) |
  {N_REGIONS} equal rectangles (4 x 2), `wtv_8`, `epv_8`
time; curves | steps; mean of 15 runs | ticks; every {CURVES_EVERY} ticks, 95% CI"""
    notes = (
        "*WTV and EPV* follow `mrexplore.metrics.regions` (eqs. 8-10), over the explorable "
        "cells only (the paper counts every cell). *WTV over time*, our one number per run for "
        '"the WTV during the exploration": its `wtv_8` curve carried at its final value to the '
        "last tick of the longest run of its map and team size, averaged over the samples "
        f"every {CURVES_EVERY} ticks; *EPV over time* likewise.",
        "*Start set-ups*: the paper's 15 locations (Fig. 5) are not in our copy. The seed places "
        "the team alike for every strategy (`together`: adjacent cells around a random free "
        "cell; `separate`: random free cells): comparisons are paired by seed.",
        "*Re-planning*: `kme` starts a round when a robot reaches its target (§IV.D step 11), "
        "and `nearest-frontier` and `burgard` re-plan on arrival too (the paper names no "
        "trigger of the baselines; one rule for every arm); `zlot-market` drops a goal once "
        "it is explored. `burgard` assigns the whole team whenever a robot needs a goal, "
        "discounting in line of sight. The readings of the robustness section differ.",
    )
    return render.settings_table(rows, notes)


#: The report's sections: where in the paper, title, the (map, scheme) of their cells
#: (``None``: all), the metrics tabulated, the curve plotted per team size.
SECTIONS = (
    ("Fig. 6", "WTV, unstructured map, start together", FIG6, ("wtv_time", "wtv_final"), "wtv_8"),
    ("Fig. 7", "WTV, unstructured map, start separately", FIG7, ("wtv_time", "wtv_final"), "wtv_8"),
    ("Fig. 8", "EPV, unstructured map, start separately", FIG7, ("epv_time",), "epv_8"),
    ("§V.C", "all maps and starting schemes", None, ("wtv_time", "epv_time", "t100"), None),
)


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> render.Lines:
    """The report's sections, its figures written into ``out``."""
    from mrexplore.viz.plots import plot_curves, strategy_colour

    curves = curve_table(stores)
    rows = with_curve_means(render.rows_of(stores)[0], curves)
    values, lines = run_values(rows), _settings(quick)
    for where, title, scheme, metrics, curve in SECTIONS:
        said = [f'Paper ({c.where}): "{c.sentence}"' for c in CLAIMS if c.where.startswith(where)]
        lines += [f"## {where}: {title}", "", *said, "(read from the text: no numbers)", ""]
        cut, columns = (2, ["robots"]) if scheme else (0, ["map", "scheme", "robots"])
        for metric in metrics:  # rows labelled by the cell's keys below the section's
            shown = {c[cut:]: v for c, v in values[metric].items() if c[:cut] in ((), scheme)}
            flags = {(c, str(claims.lowest_arm(v, STRATEGIES))): "*" for c, v in shown.items()}
            digits = int(metric == "epv_time")
            lines += [f"Ours: {LABELS[metric]}, mean (sd; 95% CI; n), `*` the lowest:", ""]
            table = render.arm_table(shown, STRATEGIES, columns, flags=flags, digits=digits)
            lines += [*table, ""]
        if curve == CURVES[1]:  # every region is explored at the end: the final EPV is 0
            lines += ["(The final EPV is 0 in every complete run: every region is at 100%.)", ""]
        if scheme is None or curve is None or curves is None:
            continue  # §V.C: every map, the figures below
        for robots in sorted({c[-1] for c in shown}):
            figure = f"{where}, {robots} robots"
            name = f"fig{where[-1]}_{curve[:3]}_{scheme[1]}_{robots}r.png"
            here = [r for r in rows if (r["map"], r["start"], r["robots"]) == (*scheme, robots)]
            members = pa.table({k: [r[k] for r in here] for k in ("run_id", "strategy")})
            plot_curves(curves, members, out / name, y=curve, title=f"{figure}: {title}")
            lines += [f"![{figure}]({name})", ""]
    axes = {"xlabel": "robots", "colours": {s: strategy_colour(s) for s in STRATEGIES}}
    for metric in () if quick else CURVE_METRICS:  # quick: one map, shown above
        panels = render.panels_of(values[metric], STRATEGIES, lambda c: f"{c[0]}, start {c[1]}")
        name, y = f"{metric[:3]}_all_combinations.png", LABELS[metric]
        lines += render.figure(out, name, panels, title=y, ylabel=y, **axes)
    return lines


QUICK_NOTE = f"the unstructured map, {QUICK_MAP_SIZE} cells a side"
REPRODUCTION = Reproduction(
    ID, TITLE, CITATION, experiments, report, tables, CLAIMS, INTERPRETATIONS, QUICK_NOTE
)
