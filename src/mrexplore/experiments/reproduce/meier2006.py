"""Meier, Stachniss and Burgard (ECMR 2005; the id says 2006): exploration over polygonal
maps sent through a link of limited bandwidth. Arms: ``SR <split rate>`` (``meier-polygon``,
``polygon`` sharing); with ``full`` sharing ``centralised`` (``burgard``) and
``no-approximation`` (``meier-polygon``). Raw scans are computed, not sent."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from operator import itemgetter
from pathlib import Path
from typing import Any

import numpy as np

from mrexplore.comm.bytes import HEADER_BYTES, SCAN_BEAM_BYTES
from mrexplore.experiments.reproduce import claims, render
from mrexplore.experiments.reproduce.base import Reproduction
from mrexplore.experiments.reproduce.claims import Claim, Values, cell_name, family, fmt, level
from mrexplore.experiments.reproduce.render import Experiment, Lines, Metric, Row, number
from mrexplore.experiments.stats import Summary, summarize_metric
from mrexplore.experiments.store import Store

ID = "meier2006"
TITLE = "Coordinating multiple robots during exploration under communication with limited bandwidth"
CITATION = (
    'D. Meier, C. Stachniss, W. Burgard, "Coordinating multiple robots during exploration '
    'under communication with limited bandwidth", Proc. of the European Conference on '
    "Mobile Robots (ECMR), 2005."
)

# ----------------------------------------------------------------- the paper's numbers

#: Table 1: share (%) of the network traffic of each package type per split rate SR.
PAPER_TABLE1: dict[float, dict[str, float]] = {
    0.04: {"TPT": 31.12, "ES": 19.82, "B": 11.32, "VP": 6.16, "EP": 31.58},
    0.05: {"TPT": 29.00, "ES": 23.06, "B": 13.51, "VP": 5.45, "EP": 28.97},
    0.07: {"TPT": 25.68, "ES": 26.89, "B": 15.25, "VP": 5.37, "EP": 26.81},
    0.1: {"TPT": 22.00, "ES": 36.09, "B": 16.02, "VP": 4.54, "EP": 21.35},
    0.2: {"TPT": 16.77, "ES": 52.52, "B": 14.24, "VP": 3.90, "EP": 12.58},
    1.0: {"TPT": 5.62, "ES": 78.95, "B": 3.46, "VP": 9.52, "EP": 2.45},
    5.0: {"TPT": 1.56, "ES": 79.90, "B": 0.26, "VP": 17.78, "EP": 0.50},
    10.0: {"TPT": 1.01, "ES": 78.57, "B": 0.04, "VP": 19.97, "EP": 0.41},
    15.0: {"TPT": 0.85, "ES": 78.14, "B": 0.03, "VP": 20.68, "EP": 0.29},
    20.0: {"TPT": 0.77, "ES": 77.99, "B": 0.02, "VP": 20.93, "EP": 0.28},
    25.0: {"TPT": 0.76, "ES": 77.88, "B": 0.02, "VP": 21.05, "EP": 0.30},
}
PACKAGE_TYPES = tuple(PAPER_TABLE1[0.04])
#: Table 2: average approximation error (%) per split rate.
PAPER_TABLE2 = {0.1: 8.92, 1.0: 0.86, 10.0: 0.19}
#: §5.2: "around 7.500 integers per second and robot" give a result similar to the
#: centralised approach's "about 200.000 integers per second" (Fig. 7 has no numbers).
PAPER_INTS_PER_S_ROBOT, PAPER_CENTRAL_INTS_PER_S = 7_500, 200_000
PAPER_RATIO = PAPER_CENTRAL_INTS_PER_S / PAPER_INTS_PER_S_ROBOT

# ----------------------------------------------------------------------- settings

MAP_SEED, SENSOR_RANGE, CELL_SIZE_M = 1, 10, 0.5  # not given; the cell size only for units
SCAN_BEAMS, SCAN_BEAMS_HALF = 360, 181  # raw scans: a beam per degree; a 180° SICK-like scan
SCAN_BYTES = HEADER_BYTES + SCAN_BEAMS * SCAN_BEAM_BYTES
LOW_SPLIT_RATE = 0.1  # §5.4 calls 0.1 splits/s "a low bandwidth connection"
FIXED: dict[str, Any] = {
    "map_seed": MAP_SEED,
    "sensor_range": SENSOR_RANGE,
    "start": "together",
    "sensing": "moving",
    "comm_range": "inf",
    "latency": 1,
    "loss": 0.0,
    "coverage_threshold": 0.99,
    # Algorithm 1 runs when a robot needs a new target: on arrival (or blocked), for
    # both arms (the meier-polygon default; burgard's is also re-planning when explored).
    "set": {"replan_on_target_explored": False},
}


def stores(quick: bool) -> dict[str, tuple[tuple[str, ...], int, tuple[float, ...], range]]:
    """Experiment prefix -> maps, team size, split rates, seeds (Fig. 6 rows 1, 2; Fig. 7)."""
    if quick:  # both maps in one store, Fig. 7 from the 3-robot unstructured runs
        return {"quick": (("unstructured", "corridor"), 3, (0.1, 1.0, 10.0), range(1, 2))}
    return {
        "unstructured3": (("unstructured",), 3, tuple(PAPER_TABLE1), range(1, 7)),
        "corridor5": (("corridor",), 5, (0.04, 0.1, 0.2, 1.0, 5.0, 10.0, 25.0), range(1, 7)),
        "two_robots": (("unstructured",), 2, (0.04, 0.1, 1.0, 10.0, 25.0), range(1, 5)),
    }


def roles(quick: bool) -> tuple[tuple[str, int], ...]:
    """The settings of Fig. 6 row 1 (also Tables 1 and 2), row 2 and Fig. 7."""
    return ("unstructured", 3), ("corridor", 3 if quick else 5), ("unstructured", 3 if quick else 2)


def experiments(quick: bool) -> list[Experiment]:
    """Per store: the split-rate sweep, then one sweep per baseline strategy."""
    size, max_ticks = ("40x40", 1000) if quick else ("100x100", 3000)
    out = []
    for store, (maps, robots, rates, seeds) in stores(quick).items():
        fixed = {"size": size, **FIXED, "robots": robots, "max_ticks": max_ticks}
        grid = {"map": list(maps)} if len(maps) > 1 else {}
        fixed |= {} if grid else {"map": maps[0]}
        polygon = {**fixed, "strategy": "meier-polygon", "sharing": "polygon"}
        shares = {**grid, "share": {"split_rate": list(rates)}}
        out.append(Experiment(f"{store}_polygon", polygon, shares, tuple(seeds)))
        for strategy in ("burgard", "meier-polygon"):
            baseline = {**fixed, "strategy": strategy, "sharing": "full"}
            out.append(Experiment(f"{store}_baselines-{strategy}", baseline, grid, tuple(seeds)))
    return out


# ------------------------------------------------------------------ arms and metrics

SR, CENTRALISED, EXACT, RAW, RAW_HALF = "SR", "centralised", "no-approximation", "raw", "raw-181"


def arm_of(row: Row) -> str:
    """``SR <rate>`` for polygon sharing, else ``centralised`` (burgard) or ``no-approximation``."""
    if row.get("sharing") == "polygon":
        return f"{SR} {float(row['share_split_rate']):g}"
    return CENTRALISED if row.get("strategy") == "burgard" else EXACT


def package_shares(row: Row) -> dict[str, float]:
    """Share (%) of a run's bytes in each package type of Table 1 and ``other`` (resync
    requests); nan without traffic."""
    total = number(row, "bytes_total")
    if not total > 0:
        return dict.fromkeys((*PACKAGE_TYPES, "other"), math.nan)
    shares = {t: 100.0 * number(row, f"bytes_by_type_{t}") / total for t in PACKAGE_TYPES}
    return {**shares, "other": max(0.0, 100.0 - sum(shares.values()))}


def team_error(text: Any) -> float:
    """Mean over robots of a per-robot JSON list (``polygon_approximation_error*``), in %."""
    values = [float(v) for v in json.loads(text) if v is not None] if text else []
    return 100 * float(np.mean(values)) if values else math.nan


def centralised_raw_bytes(row: Row, beams: int = SCAN_BEAMS) -> float:
    """The centralised approach as the paper runs it: a run's ``status`` and ``assign``
    messages, and every robot's raw scan at each tick ``0..ticks`` (a broadcast is sent once)."""
    scans = int(row["robots"]) * (int(row["ticks"]) + 1) * (HEADER_BYTES + beams * SCAN_BEAM_BYTES)
    return render.bytes_of(("status", "assign"))(row) + scans


def share(package: str) -> Metric:
    return lambda row: package_shares(row)[package]


_cell = itemgetter("map", "robots")  # the setting of a run
_COORDINATION = render.bytes_of(("TPT", "status", "assign"))  # all but map sharing
#: The numbers of a run; the ``raw*`` ones are meant for the centralised runs.
METRICS: dict[str, Metric] = {
    "time": render.measured("T99"),
    "reached": render.reached("T99"),
    "bytes": render.column("bytes_total"),
    "rate": lambda row: number(row, "bytes_total") / ((row["ticks"] + 1) * row["robots"]),
    "map_bytes": lambda row: number(row, "bytes_total") - _COORDINATION(row),
    RAW: centralised_raw_bytes,
    RAW_HALF: lambda row: centralised_raw_bytes(row, SCAN_BEAMS_HALF),
}
#: The numbers of a polygon run (Tables 1 and 2).
POLYGON_METRICS: dict[str, Metric] = {
    "error": lambda row: team_error(row.get("polygon_approximation_error_mean")),
    "error_end": lambda row: team_error(row.get("polygon_approximation_error")),
    **{f"share {t}": share(t) for t in (*PACKAGE_TYPES, "other")},
}

# ------------------------------------------------------------------ the paper's claims

#: ``id | where | the claim in our words | the paper's words``. Time claims read Fig. 6's
#: settings; Tables 1 and 2 the 3-robot unstructured runs.
CLAIM_WORDS = render.text_rows("""
decreasing | Fig. 6, §5.1 | exploration time decreases as the split rate (approximation
  quality) increases | exploration time ... decreases when the quality of the approximation
  ... increases
converge | Fig. 6, §5.1, §6 | with more bandwidth the polygon method converges to coordination
  without approximation | for an increasing communication link bandwidth the performance of
  our approach converges
slower | §4, §5.1 | decentralised coordination explores slower than centralised Burgard et al.
  | decentralized coordination leads to worse results than the original centralized approach
advantage | §5.1 | the advantage of centralised coordination grows with the team (the maps
  differ too) | The relative advantage ... increases with the number of robots.
similar | §5.2 | at a low split rate the polygon method explores about as fast as centralised
  coordination | even with low bandwidth connections ... a similar coordination result can be
  achieved
tpt | Table 1, §5.3 | TPT is a high share at low split rates (paper 31.12% at 0.04), negligible
  at high (0.76%) | the transmission of the goal points causes a high amount of the overall
  traffic (33.12%)
trends | Table 1 | each package type's share changes with the split rate as in the paper | The
  relative network traffic introduced by the different packages for different ... (SR)
error | Table 2, §5.4 | the higher the split rate, the lower the error (paper: 8.92, 0.86, 0.19%
  at 0.1, 1, 10) | the higher the SR the lower is the average approximation error
fragment | Fig. 7, §5.3 | polygons need only a fragment of the traffic of raw scans, even at high
  split rates | Even in the case of high ... refinement rates, our approach requires only a
  fragment
cheaper | §2 | polygonal approximations can be communicated more efficiently than the full map
  | these polygonal approximations ... can be more efficiently communicated
""")
_SOME, _T99, _LOW = claims.SOME_WEAK, ("time", "T99 (ticks)"), f"{SR} {LOW_SPLIT_RATE:g}"
_FALLS = claims.Trend("rank", along="family", rho=0.5, paired=True, needs=_SOME)
_GROWS = claims.Trend("ratio", "rises", along="cells", bound=1, digits=3, needs=claims.EVERY_WEAK)
_SIGNS = claims.SignsAsPaper(PAPER_TABLE1, 0.3, needs=claims.Needs(partly_holds=0.6))  # 3 of 5
_ONE_OR_ALL = claims.Needs(partly_holds=0, partly_weakly=1)  # one ratio holds, or all weakly
_FRAGMENT = claims.Ratio(
    "<=", 0.5, weak=1, members="each", shown=(RAW_HALF,), digits=3, needs=_ONE_OR_ALL
)
_CONVERGES = claims.Paired("=", tolerance=0.1, members="top", needs=_SOME)
_CHEAPER = claims.Ratio("<", 1, members="each", needs=_SOME)
#: Claim id -> the values read and their label, the arms, the rule, its digits.
JUDGED: dict[str, tuple[str, str, str, str, claims.Rule, int]] = {
    "decreasing": (*_T99, SR, "", _FALLS, 0),
    "converge": (*_T99, SR, EXACT, _CONVERGES, 0),
    "slower": (*_T99, EXACT, CENTRALISED, claims.Paired(">", needs=_SOME), 0),
    "advantage": (*_T99, EXACT, CENTRALISED, _GROWS, 0),
    "similar": (*_T99, _LOW, CENTRALISED, claims.Ratio("<=", 1.15, weak=1.30, needs=_SOME), 0),
    "tpt": ("shares", "share of bytes (%)", SR, "", claims.AtEnds("TPT", 20.0, 5.0), 1),
    "trends": ("shares", "share of bytes", SR, "", _SIGNS, 0),
    "error": ("error", "error (%)", SR, "", claims.NearPaper(PAPER_TABLE2, 2.0), 2),
    "fragment": ("traffic", "bytes", SR, RAW, _FRAGMENT, 0),
    "cheaper": ("map_bytes", "map bytes", SR, EXACT, _CHEAPER, 0),
}
CLAIMS = tuple(Claim(i, at, ours, paper, *JUDGED[i]) for i, at, ours, paper in CLAIM_WORDS)

#: Choices the paper leaves open (docs/reproductions/meier2006.md); claims are judged under
#: each. ``name | sentence | reading | overrides | strategies``.
INTERPRETATIONS = render.readings("""
epsilon-half-cell | §5.1 "Edge splits are not performed when the approximation of the robot is
  appropriate meaning that the approximation error is equal to zero" | splitting stops once
  every contour point is within half a cell of its edge (`epsilon=0.5`, our earlier default;
  default 0) | share.epsilon=0.5 | meier-polygon
replan-when-explored | §4 "Whenever a robot selects a new target location, it broadcasts its
  decision" | a robot also selects a new target once its target is explored, not only on
  arrival or blocked (`replan_on_target_explored=true`, both arms; default false) |
  replan_on_target_explored=true | meier-polygon, burgard
coordinator-assigns-requesting | §5.1 "Only a centralized coordination technique has the
  ability to choose that robot-target tuple that provides the (globally) highest expected
  utility" | the centralised coordinator assigns only the robots that ask for a goal, the goals
  of the others fixed (`assign=requesting`, our earlier version; default: the whole team) |
  assign=requesting | burgard
discount-within-range | Algorithm 1 step 5 "Reduce the utility of each target point t' in the
  visibility area" | every target within max_range is discounted, seen from the goal or not
  (`visibility_discount=false`, both arms, our earlier version) | visibility_discount=false |
  meier-polygon, burgard
every-target-discounts | §5.3 "target point transmissions (TPT) to publish chosen target
  locations to robots with lower priority" against Algorithm 1 "for all received targets" |
  every received target discounts, not only those of lower ids (`respect_priority=false`) |
  respect_priority=false | meier-polygon
raw-path-cost | §4 "V_t' refers to the cost of reaching target location t'" (traded by beta, no
  value) | V is the path length in cells, not scaled to [0, 1] (`normalize_cost=false`, both
  arms) | normalize_cost=false | meier-polygon, burgard
""")

# ------------------------------------------------------------------------ tables


def run_values(rows: Sequence[Row], quick: bool) -> dict[str, dict[Any, dict[str, Any]]]:
    """``metric -> (map, robots) -> arm -> seed -> value``, settings in the paper's order;
    ``bytes`` also with the raw-scan arms of the centralised runs."""
    order = list(dict.fromkeys(roles(quick)))
    polygon = [row for row in rows if row.get("sharing") == "polygon"]
    values = render.tabulate(rows, METRICS, _cell, arm_of, order.index)
    values |= render.tabulate(polygon, POLYGON_METRICS, _cell, arm_of, order.index)
    for arm in (RAW, RAW_HALF):
        for cell, arms in values[arm].items():
            values["bytes"][cell].update({arm: arms[CENTRALISED]} if CENTRALISED in arms else {})
    return values


def claim_tables(values: Mapping[str, Values], quick: bool) -> dict[str, Values]:
    """What :data:`CLAIMS` read, ``metric -> values``."""
    one, corridor, fig7 = roles(quick)
    return {
        "time": {c: v for c, v in values["time"].items() if c in (one, corridor)},
        "shares": {(t,): values[f"share {t}"].get(one, {}) for t in (*PACKAGE_TYPES, "other")},
        "error": {one: values["error"].get(one, {})},
        "traffic": {fig7: values["bytes"].get(fig7, {})},
        "map_bytes": values["map_bytes"],
    }


def tables(stores: Mapping[str, Store], quick: bool) -> dict[str, Values]:
    return claim_tables(run_values(render.rows_of(stores)[0], quick), quick)


# ------------------------------------------------------------------------ report

QUICK_NOTE = "40 x 40 maps, 1 seed, split rates 0.1, 1, 10, 3 robots on both maps, Fig. 7 from them"
NOTES = (
    "Tables 1, 2: the 3-robot unstructured runs (the paper does not say); shares count headers.",
    "Raw scans are computed, not sent; a scan per tick is a slow laser: it favours centralised.",
)
TRAFFIC = (
    f"Paper (§5.2): ~{PAPER_INTS_PER_S_ROBOT:,} integers/s per robot give a result like ~"
    f"{PAPER_CENTRAL_INTS_PER_S:,} centralised ({PAPER_RATIO:.1f} x). Ours (`raw`, `raw-181`: "
    f"raw scans of {SCAN_BEAMS}, {SCAN_BEAMS_HALF} beams; an integer is 4 B), team raw-scan rate "
    f"/ polygon rate per robot at SR {LOW_SPLIT_RATE:g}: "
)


def _settings(quick: bool) -> Lines:
    teams = "{}, {}; {}".format(*(robots for _, robots in roles(quick)))
    size, ticks = ("40 x 40", 1000) if quick else ("100 x 100", 3000)
    rates = "; ".join(", ".join(f"{r:g}" for r in x) for *_, x, _ in stores(quick).values())
    seeds = ", ".join(str(len(x)) for *_, x in stores(quick).values())
    rows = f"""maps (Fig. 6; Fig. 7) | unstructured, corridor; the same; no size | generators
  `unstructured`, `corridor`, {size} cells, map_seed {MAP_SEED}
team sizes | 3, 5; 2 | {teams}
split rates (splits/s) | 0.04 ... 25 (Table 1) | {rates}
sensor; 1 tick | laser, range not given; - | 360°, {SENSOR_RANGE} cells (5 m at 0.5 m); 1 s, 1 cell
Douglas-Peucker stop | approximation error zero | approximation error zero (`epsilon` 0)
communication | unlimited range, reliable | no loss, latency 1 tick, no bandwidth cap
baselines | Burgard et al.; theirs with our coordination | `burgard`, `meier-polygon`; `full` maps
centralised assignment | the "(globally) highest" robot-target tuple (§5.1) | the whole team
  re-assigned whenever a robot needs a goal; positions reported every tick
discount | "in the visibility area" (Alg. 1) | targets in line of sight of a goal, both arms
re-planning | when a robot "selects a new target location" (not said) | on arrival or blocked,
  both arms
raw scans (Fig. 7) | each robot sends its sweeps | {SCAN_BYTES} B/robot/tick + `status`, `assign`
approximation error | against a central map (%) | own cells own polygons get wrong (run mean)
runs | not given | {seeds} seeds, start `together`, at most {ticks} ticks"""
    return render.settings_table(rows, NOTES)


COLOURS = {"polygon": "#17becf", "ours": "#17becf", "paper": "#999999", CENTRALISED: "#1f77b4"}
COLOURS |= {EXACT: "#555555", RAW: "#d62728", RAW_HALF: "#ff7f0e"}
ARMS = [*(f"{SR} {r:g}" for r in PAPER_TABLE1), CENTRALISED, EXACT, RAW, RAW_HALF]


def _xs(arms: Mapping[str, Summary], flat: Sequence[str] = ()) -> dict[str, Any]:
    """A :func:`render.figure` panel: ``SR`` arms by rate, ``flat`` arms level."""
    xs = {level(a): arms[a] for a in family(arms, SR)}
    return {"polygon": xs, **{a: dict.fromkeys(xs, arms[a]) for a in flat if a in arms}}


def _with_paper(ours: Mapping[str, Summary], paper: Mapping[float, float]) -> dict[str, Any]:
    theirs = {f"{SR} {r:g}": summarize_metric([v]) for r, v in paper.items()}
    return {"ours": _xs(ours)["polygon"], "paper": _xs(theirs)["polygon"]}


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Lines:
    """The report's sections, its figures written into ``out``."""
    values = run_values(render.rows_of(stores)[0], quick)
    t = claim_tables(values, quick)
    s = {metric: render.summaries(v) for metric, v in {**values, **t}.items()}
    one, fig7, low = next(iter(t["error"])), next(iter(t["traffic"])), f"{SR} {LOW_SPLIT_RATE:g}"

    def table(cells: Values, columns: Sequence[str] = ("map", "robots"), **options: Any) -> Lines:
        return [*render.arm_table(cells, ARMS, list(columns), **options), ""]

    def figure(file: str, title: str, panels: Any, ylabel: str, log: bool = False) -> Lines:
        axes = {"xlabel": "split rate (splits/s)", "ylabel": ylabel, "colours": COLOURS, "log": log}
        return render.figure(out, file, panels, title=title, logx=True, **axes)

    ratios = [
        f"{cell_name(c)} {fmt(SCAN_BYTES * c[1] / x[low].mean, 1)}"
        for c, x in s["rate"].items()
        if c in t["time"] and low in x
    ]
    lines = [*_settings(quick), "## Fig. 6: exploration time vs split rate", ""]
    lines += ["Ours: T99 (ticks); `*`: some runs never reached 99% and are left out.", ""]
    lines += table(t["time"], flags=render.unfinished(values["reached"]))
    panels = {cell_name(c): _xs(x, (CENTRALISED, EXACT)) for c, x in s["time"].items()}
    lines += figure("fig6_exploration_time.png", "Fig. 6", panels, "T99 (ticks)")
    lines += ["## Traffic (§2, §5.2, §5.3, Fig. 7)", "", TRAFFIC + ", ".join(ratios), ""]
    for text, metric, digits in (
        ("Bytes per tick per robot", "rate", 1),
        ("Bytes per run", "bytes", 0),
        ("Map-sharing bytes per run (all but TPT, `status`, `assign`)", "map_bytes", 0),
    ):
        lines += [f"{text}:", "", *table(values[metric], digits=digits)]
    panels = {cell_name(fig7): _xs(s["traffic"][fig7], (RAW, RAW_HALF, EXACT, CENTRALISED))}
    lines += figure("fig7_traffic.png", "Fig. 7", panels, "bytes per run", log=True)
    paper1 = [[f"{r:g}", *(f"{v:.2f}" for v in row.values())] for r, row in PAPER_TABLE1.items()]
    lines += ["## Table 1: share (%) of the bytes by package type", "", "Paper:", ""]
    lines += [*render.table(["SR", *PACKAGE_TYPES], paper1), "", f"Ours ({cell_name(one)}):", ""]
    lines += table(t["shares"], ["package"], digits=2)
    panels = {
        p: _with_paper(s["shares"][(p,)], {r: row[p] for r, row in PAPER_TABLE1.items()})
        for p in PACKAGE_TYPES
    }
    lines += figure("table1_package_shares.png", "Table 1", panels, "share of bytes (%)")
    end = values["error_end"].get(one, {})
    errors = {("mean over the run",): t["error"][one], ("at the end",): end}
    paper2 = ", ".join(f"SR {r:g}: {v}" for r, v in PAPER_TABLE2.items())
    lines += ["## Table 2: approximation error (%)", "", f"Paper: {paper2}.", ""]
    lines += table(errors, ["error"], digits=2)
    panels = {"Table 2": _with_paper(s["error"][one], PAPER_TABLE2)}
    return lines + figure("table2_approximation_error.png", "Table 2", panels, "error (%)", True)


REPRODUCTION = Reproduction(
    ID, TITLE, CITATION, experiments, report, tables, CLAIMS, INTERPRETATIONS, QUICK_NOTE
)
