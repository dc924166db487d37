"""Reproduction of Sheng, Yang, Tan and Xi (2006), section 5: five sweeps (``fig11``,
``fig12_13_random``, ``fig12_13_bidding``, ``table4``, ``fig17``), 352 runs, 28 with
``--quick``. The paper's numbers, the experiments, the claims and our readings follow.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from mrexplore.comm.bytes import CELL_UPDATE_BYTES
from mrexplore.experiments.reproduce import claims, render
from mrexplore.experiments.reproduce.base import Reproduction
from mrexplore.experiments.reproduce.claims import Claim, Values, fmt
from mrexplore.experiments.reproduce.render import Experiment, Lines, Metric, Row, number
from mrexplore.experiments.store import Store

ID = "sheng2006"
TITLE = "Sheng et al. (2006), Distributed multi-robot coordination in area exploration"
CITATION = (
    'W. Sheng, Q. Yang, J. Tan, N. Xi, "Distributed multi-robot coordination in area '
    'exploration", Robotics and Autonomous Systems 54 (2006) 945-955.'
)

# ------------------------------------------------------------ settings (§5)
MAP = "sheng40"  # "a square of 40 by 40, with two obstacles in it" (their shape: ours)
SENSOR_RANGE = 4  # "the sensor range radius is 4 cell units (r_s = 4)"
COMM_RANGE = 16  # "the communication range is 16 cell units (r_c = 16)"
W3_WITHOUT, W3_WITH = 0.0, 1.5  # Figs. 9 and 10 (1.5: also the strategy's default)
TABLE4_W3 = (0.0, 1.0, 2.0)  # Table 4 cases (i), (ii), (iii)
SPEED = 0.25  # cells of travel per tick (see FIXED)
#: Table 4: "by varying the starting time of each robot": each robot starts at a tick
#: drawn from 0..16, the time to travel the sensor radius (r_s / speed): later, the
#: first robot would have left the others' sensing disks (no longer a start together);
#: much less, every start would fall in the first bidding session (2 ticks).
START_DELAY = round(SENSOR_RANGE / SPEED)
FIG17_RANGES = (4, 8, 12, 16, 20, 24)  # Fig. 17 (the text says "five values", lists six)
TEAM_SIZES = tuple(range(1, 9))  # Figs. 12-13: "ranges from 1 to 8"
SEEDS = {"fig11": 8, "fig12_13": 6, "table4": 20, "fig17": 6}  # the paper's run counts
QUICK_SEEDS = {"fig11": 2, "fig12_13": 2, "table4": 1, "fig17": 1}
QUICK_TEAM_SIZES, QUICK_RANGES = (2, 5), (4, 16, 24)

FIXED: dict[str, Any] = {
    "map": MAP,
    "sensor_range": SENSOR_RANGE,
    "comm_range": COMM_RANGE,
    "sensing": "arrival",  # §2.1: "When the robot is travelling, it does not carry out sensing"
    "start": "together",  # §3: "initial positions which are close to each other"
    "coverage_threshold": 1.0,  # §3.3: "All the robots stop when no new frontier cell is ..."
    "sharing": "sheng-sync",  # §4, the paper's own map synchronisation
    # §5 "T_bid = 1.5 s", long against a LAN's delay: a tick is a hop's latency and a
    # quarter cell of travel, so a session (t_bid = T_grace = 2 ticks) is half a cell.
    "speed": SPEED,
}

#: Table 4 (bytes, 5 robots, 20 runs per case): w3 -> (mean without tracking, mean
#: with tracking, sd without, sd with). Figs. 11-13 and 17 give no numbers.
PAPER_TABLE4: dict[float, tuple[float, float, float, float]] = {
    0.0: (23034.0, 4893.0, 976.0, 393.0),  # case (i)
    1.0: (11855.0, 2126.0, 685.0, 130.0),  # case (ii)
    2.0: (7075.0, 812.0, 367.0, 82.0),  # case (iii)
}

# --------------------------------------------------------------- what is measured
#: Table 4's bytes, the map data sent when sub-networks merge: with tracking
#: (``sheng-sync``, §4.2 steps 4-10) sequence-number tables, the missing deltas and their
#: multicast; without (``full``, §4's brute force) whole maps both ways and the multicast.
SYNC_TYPES = {
    "sheng-sync": ("seq_table", "map_sync", "map_multicast"),
    "full": ("map_full", "map_multicast"),
}
#: Updates broadcast in a sub-network after each sensing (§3.1): alike in both, not counted.
BROADCAST_TYPES = ("map_delta", "map_update")

CASE_RANDOM, CASE_WITHOUT, CASE_WITH = "random", "bidding w3=0", "bidding w3=1.5"
CASES = (CASE_RANDOM, CASE_WITHOUT, CASE_WITH)
COLOURS = {CASE_RANDOM: "#7f7f7f", CASE_WITHOUT: "#1f77b4", CASE_WITH: "#d62728"}
#: Table 4's columns (its arms): a run's sharing mechanism, then numbers of the runs with
#: tracking: partition events, merges, cells per merge, broadcast bytes (not counted).
TRACKING = {"full": "without tracking", "sheng-sync": "with tracking"}
WITHOUT, WITH = TRACKING.values()
PARTITIONS, MERGES, PER_MERGE, BROADCAST = "partitions", "merges", "cells per merge", "broadcast"
#: The paper's measure: both volumes from the same `sheng-sync` runs, each message once
#: (its "volumes of map data that are supposed to be exchanged if the map update
#: tracking scheme is not used"), in our byte model (5 bytes a cell) and at 1 byte a cell.
SAME_WITHOUT, SAME_WITH = "without, same run", "with, same run"
ONE_BYTE = {f"{arm}, 1 B/cell": arm for arm in (SAME_WITHOUT, SAME_WITH)}
SAME_RUN = (SAME_WITHOUT, SAME_WITH, *ONE_BYTE)
ARMS = (*CASES, *SAME_RUN, WITHOUT, WITH, PARTITIONS, MERGES, PER_MERGE, BROADCAST)


def case_of(row: Row) -> str:
    """The paper's case of a run; ``w3`` not set is the strategy's default, 1.5."""
    if row["strategy"] == "random-frontier":
        return CASE_RANDOM
    w3 = row.get("param_w3")
    return f"bidding w3={W3_WITH if w3 is None or math.isnan(w3) else float(w3):g}"


def sync_bytes(row: Row) -> float:
    """Table 4's bytes of one run: the :data:`SYNC_TYPES` of its sharing mechanism."""
    return render.bytes_of(SYNC_TYPES[row["sharing"]])(row)  # KeyError: not a Table 4 run


BOTH = {"time": render.measured("T100"), "distance": render.measured("total_distance")}


def same_run(kind: str, cell_bytes: int = CELL_UPDATE_BYTES) -> Metric:
    """A `sheng-sync` run's volume ``kind`` (with or without tracking), cells at ``cell_bytes``."""
    volume, cells = (f"sync_{what}_{kind}_tracking" for what in ("bytes", "cells"))
    return lambda row: number(row, volume) - (CELL_UPDATE_BYTES - cell_bytes) * number(row, cells)


TABLE4_METRICS: dict[str, Metric] = {
    "bytes": sync_bytes,
    SAME_WITHOUT: same_run("without"),
    SAME_WITH: same_run("with"),
    **{arm: same_run(of.split(",")[0], 1) for arm, of in ONE_BYTE.items()},
    BROADCAST: render.bytes_of(BROADCAST_TYPES),
    PARTITIONS: render.measured("partition_events"),
    MERGES: render.measured("sync_merges"),
    PER_MERGE: render.measured("sync_cells_per_merge"),
    "ticks": render.column("ticks"),
    "diameter": render.measured("group_diameter_mean"),
    **BOTH,
    **{t: render.bytes_of([t]) for types in SYNC_TYPES.values() for t in types},
}


def tables(stores: Mapping[str, Store], quick: bool) -> dict[str, Values]:
    """``table -> cell -> arm -> seed -> value``: what :data:`RULES`, :data:`FIGURES` and
    :data:`TABLES` read."""
    rows = render.rows_of(stores)[0]

    def of(prefix: str, metrics: Mapping[str, Metric], cell: Any, arm: Any = case_of) -> Any:
        runs = [r for r in rows if str(r["experiment"]).startswith(prefix)]
        return render.tabulate(runs, metrics, cell, arm, lambda c: c)  # w3 = 0, 1, 2 as text

    fig11 = {"diameter": render.measured("group_diameter_mean")}
    figs = of("fig12_13", BOTH, lambda r: (r["robots"],))
    fig17 = of("fig17", BOTH, lambda r: (int(r["comm_range"]),))  # whole cells in Fig. 17
    w3 = lambda r: (f"w3={r['param_w3']:g}",)  # noqa: E731 (a cell key, as those above)
    table4 = of("table4", TABLE4_METRICS, w3, lambda r: TRACKING[r["sharing"]])
    with_only = (*SAME_RUN, PARTITIONS, MERGES, PER_MERGE, BROADCAST)  # of the sheng-sync runs
    return {
        **of("fig11", fig11, lambda r: (r["robots"],)),
        "diameter_runs": of("fig11", fig11, lambda r: (r["seed"],))["diameter"],
        **figs,
        **{f"{k}_teams": {c: v for c, v in figs[k].items() if c[0] >= 2} for k in figs},
        "table4": {
            c: {**arms, **{k: table4[k][c].get(WITH, {}) for k in with_only}}
            for c, arms in table4["bytes"].items()
        },
        "fig17": {(k, *c): arms for k in fig17 for c, arms in fig17[k].items()},
        **{f"fig17 {k}": v for k, v in fig17.items()},
        **{f"table4 {k}": v for k, v in table4.items()},
    }


# ------------------------------------------------------------------- the claims
#: ``id | our statement | the paper's sentence (§5)``; the id names the figure or table.
CLAIM_WORDS = render.text_rows("""
fig11 | with the nearness measure the robots stay closer together (smaller diameter) | by
  including the nearness measure ..., the robots tend to stay close to each other
fig12_team | the exploration time decreases as the number of robots increases | as the robot
  number increases, the total exploration time decreases
fig12_bidding | bidding (w3=0) explores faster than random frontiers | The bidding algorithm
  effectively reduces the time compared with a random exploration algorithm
fig12_nearness | the nearness measure further reduces the exploration time | When the nearness
  measure is considered in the algorithm, the total exploration time is further reduced
fig13_bidding | bidding (w3=0) travels less than random frontiers | similar saving in total
  distance traveled is achieved as the bidding algorithm is adopted
fig13_nearness | the nearness measure further reduces the total distance | similar saving in
  total distance traveled is achieved as ... the nearness measure is used
table4_tracking | map update tracking reduces the map data exchanged, for w3 = 0, 1, 2 | in all
  three cases, the map synchronization algorithm effectively reduces the communication volumes
table4_w3 | the more weight on nearness (w3 = 0, 1, 2), the less map data is exchanged | as the
  nearness measure has more weight ..., less communication volume
fig17_falls | without nearness, exploration time and distance fall as r_c grows | for case 1, as
  the communication range increases, the exploration time and traveled distance decrease
fig17_below16 | without nearness, the gain from a larger r_c is larger below r_c = 16 | the
  efficiency gain ... is more significant when the ... range is below 16
fig17_nearness | with nearness, the gain from a larger r_c is smaller than without | For case 2
  ... the magnitude of the gain is not so significant ...
""")
LABELS = {
    "diameter": "mean group diameter (cells)",
    "time": "T100 (ticks)",
    "distance": "total distance (cells)",
    "table4": "merge bytes per run",
    "fig17": "time (ticks) and distance (cells)",
}
PAPER_RATIOS = {(f"w3={w3:g}",): p[0] / p[1] for w3, p in PAPER_TABLE4.items()}
_COLUMNS = list(zip(*PAPER_TABLE4.values(), strict=True))  # by w3: without, with, their sds
PAPER_COLUMNS = {SAME_WITHOUT: _COLUMNS[0], SAME_WITH: _COLUMNS[1]}
_W3, _EVERY_WEAK = (CASE_WITH, CASE_WITHOUT), claims.EVERY_WEAK
#: The paired difference's mean below 0 in every cell and its CI in at least half of them.
_LOWER = claims.Paired("<", needs=claims.Needs(0.5, 1, partly_holds=None, partly_weakly=0.5))
_STEPS = claims.Trend("steps", needs=_EVERY_WEAK)
_TRACKING = claims.Ratio(">", 1, paper=PAPER_RATIOS, digits=1, needs=_EVERY_WEAK)
_ALONG_W3 = claims.Needs(partly_holds=0, partly_weakly=1)  # or one falls at every step
_W3_STEPS = claims.Trend(
    "steps", along="cells", paper=PAPER_COLUMNS, shown=(WITHOUT, PARTITIONS), needs=_ALONG_W3
)
_BELOW_16 = claims.FallsFasterBelow(COMM_RANGE, "cell")  # 16: the paper's own r_c
#: Claim id -> (values read, first arm, second arm, rule, further arms, digits).
RULES: dict[str, tuple[str, str, str, claims.Rule, tuple[str, ...], int]] = {
    "fig11": ("diameter", *_W3, claims.Paired("<"), (), 2),
    "fig12_team": ("time", CASE_RANDOM, CASE_WITHOUT, _STEPS, (CASE_WITH,), 0),
    "fig12_bidding": ("time", CASE_WITHOUT, CASE_RANDOM, _LOWER, (), 0),
    "fig12_nearness": ("time_teams", *_W3, _LOWER, (), 0),
    "fig13_bidding": ("distance", CASE_WITHOUT, CASE_RANDOM, _LOWER, (), 0),
    "fig13_nearness": ("distance_teams", *_W3, _LOWER, (), 0),
    "table4_tracking": ("table4", SAME_WITHOUT, SAME_WITH, _TRACKING, (), 0),
    "table4_w3": ("table4", SAME_WITH, SAME_WITHOUT, _W3_STEPS, (), 0),
    "fig17_falls": ("fig17", CASE_WITHOUT, "", claims.Trend("rank", rho=0.6), (), 0),
    "fig17_below16": ("fig17", CASE_WITHOUT, "", _BELOW_16, (), 2),
    "fig17_nearness": ("fig17", *_W3, claims.FallsLess(), (), 0),
}


def _claim(id: str, statement: str, sentence: str) -> Claim:
    metric, first, second, rule, seconds, digits = RULES[id]
    figure = id.split("_")[0]
    where = f"Fig. {figure[3:]}" if figure.startswith("fig") else f"Table {figure[5:]}"
    label = LABELS[metric.removesuffix("_teams")] + (", 2+ robots" if "_teams" in metric else "")
    args = (metric, label, first, second, rule, digits, seconds)
    return Claim(id, where, statement, sentence, *args)


CLAIMS = tuple(_claim(*words) for words in CLAIM_WORDS)

# ------------------------------------------------------------ readings of the paper
_EQ2 = (
    '§3.2 "The net gain g_i for frontier cell i is the weighted combination of the three measures"'
)
INTERPRETATIONS = render.readings(f"""
both-replan-when-explored | §3.3 "The winning robot then moves to its target frontier cell" and
  §5 case (1) "all the robots randomly pick frontier cells as next targets" | a robot stops and
  picks again once its target is no longer a frontier cell (`replan_on_target_explored=true`),
  bidding robots and the random baseline alike (default: each travels to its target) |
  replan_on_target_explored=true | sheng-bidding, random-frontier
alpha-0.1 | §2.2 "α is a positive fading factor, which is smaller than 1. The use of the fading
  factor will help to disperse the robots ..., since the nearness measure mainly depends on the
  closest neighbor" | alpha = 0.1: the closest neighbour counts almost alone (default 0.5) |
  alpha=0.1 | sheng-bidding
long-sessions | §5 "The bidding time used in the coordination algorithm is T_bid = 1.5 s" |
  t_bid = 8 ticks (two cells of travel), a session long against the delays as 1.5 s was on a
  LAN: T_win = 6 ticks with one hop (default: t_bid = T_grace, 2 ticks with one hop, T_win =
  0) | bid_time=8 | sheng-bidding
tick-per-cell | §5 "The bidding time used in the coordination algorithm is T_bid = 1.5 s" (the
  robots' speed is not given) | a tick is one cell of travel (`speed` 1; default 0.25): a
  session of two ticks is two cells, and one winner per session can hold the team back |
  scenario.speed=1 | *
negative-window | §3.4 "The relationship between Send-Map-Window, bidding time and the grace
  window is illustrated in Fig. 6" (t_bid drawn as T_win + T_grace) | t_bid = max(bid_time,
  t_d) as in earlier versions, so T_win = -1 with one hop: no robot ever joins a running
  session (`session_floor=delay`; default `grace`, T_win >= 0) | session_floor=delay |
  sheng-bidding
same-start-times | §5 "For each case, by varying the starting time of each robot, we run the
  programs eight times" | Table 4's robots all start at tick 0 and the seed places them (the
  runs of Figs. 11-13 and 17; default: the same cells in every run, start ticks drawn from
  0..16) | scenario.start_delay=0 scenario.start=together | sheng-bidding
varied-places | §5 (Table 4) "by varying the starting time of each robot" | the seed places the
  robots as well as it draws their start ticks (default: the same cells in every run) |
  scenario.start=together | sheng-bidding
nearness-over-known | §2.2 "in Fig. 2, robot 6 has the least nearness measure because its
  distances to other robots are all bigger than the communication range r_c" | eq. (1) measures
  to every robot last heard of, not only the n_k of the sub-network (`nearness_over=known`;
  default `subnetwork`, eq. (1)'s literal n_k) | nearness_over=known | sheng-bidding
eq2-raw | {_EQ2} (eq. 2; no unit given) | the literal sum: I_i and D_i in cells, lambda_i
  unscaled, so w3 lambda_i is worth at most 3 cells (`eq2_units=raw`; default: lambda_i in
  units of r_c cells) | eq2_units=raw | sheng-bidding
eq2-unit-free | {_EQ2} (eq. 2; no unit given) | every term unit-free: I_i over the cells of the
  sensor disk, D_i over r_c, lambda_i as it is (`eq2_units=unit-free`; default: lambda_i in
  units of r_c cells) | eq2_units=unit-free | sheng-bidding
""")


# ------------------------------------------------------------------ experiments
def table4_starts() -> list[list[int]]:
    """Table 4's start cells, the same in every run (its runs vary the start times): the
    five robots placed together as seed 1 places them."""
    from mrexplore.seeding import make_streams
    from mrexplore.sim import Scenario
    from mrexplore.sim.world import build_world

    scenario = Scenario(map=MAP, robots=5, seed=1, sensor_range=SENSOR_RANGE)
    return [list(cell) for cell in build_world(scenario, make_streams(1, 5).starts).starts]


def experiments(quick: bool) -> list[Experiment]:
    """The five sweeps, each at :data:`FIXED` but for its grid."""
    seeds = QUICK_SEEDS if quick else SEEDS
    sizes, ranges = (QUICK_TEAM_SIZES, QUICK_RANGES) if quick else (TEAM_SIZES, FIG17_RANGES)
    both_w3, bidding = {"set": {"w3": [W3_WITHOUT, W3_WITH]}}, "sheng-bidding"

    def sweep(name: str, runs: str, grid: dict[str, Any], **fixed: Any) -> Experiment:
        fixed = {k: v for k, v in {**FIXED, **fixed}.items() if k not in grid}
        return Experiment(name, fixed, grid, tuple(range(1, seeds[runs] + 1)), curves_every=10)

    table4 = {"sharing": ["sheng-sync", "full"], "set": {"w3": list(TABLE4_W3)}}
    places = {"start": table4_starts(), "start_delay": START_DELAY}
    fig17 = {"comm_range": list(ranges), **both_w3}
    return [
        sweep("fig11", "fig11", both_w3, strategy=bidding, robots=4),
        sweep("fig12_13_random", "fig12_13", {"robots": list(sizes)}, strategy="random-frontier"),
        sweep("fig12_13_bidding", "fig12_13", {"robots": list(sizes), **both_w3}, strategy=bidding),
        sweep("table4", "table4", table4, strategy=bidding, robots=5, **places),
        sweep("fig17", "fig17", fig17, strategy=bidding, robots=5),
    ]


# ------------------------------------------------------------------------ report
def _settings(quick: bool) -> str:
    seeds = {k: f"{n} seed{'s' * (n > 1)}" for k, n in (QUICK_SEEDS if quick else SEEDS).items()}
    ranges = ", ".join(map(str, QUICK_RANGES if quick else FIG17_RANGES))
    sizes = ", ".join(map(str, QUICK_TEAM_SIZES)) if quick else "1..8"
    return f"""
map | 40 x 40, two obstacles (not drawn) | `{MAP}`: obstacles 8 x 12 and 12 x 6
sensor range r_s | 4 cell units | 4 cells, line of sight
communication r_c | 16 cell units | 16 cells, multi-hop, through walls
sensing | not while travelling (§2.1) | `sensing = arrival`
start | close together (§3); varied places (Fig. 11) / times (Table 4) | adjacent, placed by
  the seed; Table 4: seed 1's cells, start ticks drawn from 0..{START_DELAY}
time | seconds | ticks: a hop's latency, {SPEED:g} cell of path
bidding time | t_bid = 1.5 s | t_bid = T_grace = t_d + 1 ticks (T_win = 0)
eq. (2) units | not given | I_i, D_i in cells; lambda_i in units of r_c cells
omega1, omega2; omega3 off / on | 1.0, 1.0; 0 / 1.5 (Figs. 9-10) | the same
alpha (eq. 1) | positive, < 1 (value not given) | 0.5 (strategy default)
map sharing | §4 synchronisation | `sheng-sync` (Table 4: also `full`)
random baseline | random frontier cells (case 1) | each kept until reached
exploration time | until no frontier is left (§3.3) | `T100` (unfinished: missing)
Fig. 11 | 4 robots, 8 runs | 4 robots, {seeds["fig11"]}
Figs. 12-13 | 1..8 robots, 6 runs | {sizes} robots, {seeds["fig12_13"]}
Table 4 | 5 robots, w3 = 0, 1, 2, 20 runs | the same, {seeds["table4"]}
Fig. 17 | 5 robots, r_c = 4..24, 6 runs | 5 robots, r_c = {ranges}, {seeds["fig17"]}
error bars | "the deviation" | 95% CI of the mean; the tables give the sd too"""


#: The report's sections: heading -> where in the paper its claims stand.
SECTIONS = {
    "Fig. 11: mean group diameter with and without nearness (4 robots)": ("Fig. 11",),
    "Figs. 12 and 13: exploration time and total distance, 1..8 robots": ("Fig. 12", "Fig. 13"),
    "Table 4: map data exchanged with and without tracking (5 robots)": ("Table 4",),
    "Fig. 17: exploration time and distance vs communication range (5 robots)": ("Fig. 17",),
}
#: Line figures: file -> (title, table of :func:`tables`, x label, y label).
FIGURES = {
    "fig11_diameter.png": ("Fig. 11: diameter of each run", "diameter_runs", "seed", "cells"),
    "fig12_time.png": ("Fig. 12: exploration time", "time", "robots", "T100 (ticks)"),
    "fig13_distance.png": ("Fig. 13: total distance", "distance", "robots", "cells"),
    "fig17a_time.png": ("Fig. 17(a): exploration time", "fig17 time", "r_c", "T100 (ticks)"),
    "fig17b_distance.png": ("Fig. 17(b): total distance", "fig17 distance", "r_c", "cells"),
}
#: Cell columns and digits of the report's tables (others: team sizes, 0 digits).
TABLES = {"diameter": (["robots"], 1), "table4": (["w3"], 0), "fig17": (["metric", "r_c"], 0)}


def _table4(values: Mapping[str, Values], out: Path) -> Lines:
    """The paper's Table 4, the identical pairs and the bytes by message type."""
    from mrexplore.viz.plots import plot_bytes_by_type

    ticks, distance, pairs = values["table4 ticks"], values["table4 distance"], []
    by_type: dict[str, dict[str, float]] = {}
    for cell, arms in ticks.items():
        seeds, both = set(arms.get(WITH, {})) & set(arms.get(WITHOUT, {})), (arms, distance[cell])
        alike = sum(all(v[WITH][s] == v[WITHOUT][s] for v in both) for s in seeds)
        pairs.append(f"{cell[0]} {alike}/{len(seeds)}")
        for sharing, arm in TRACKING.items():
            stats = {t: render.summaries(values[f"table4 {t}"])[cell] for t in SYNC_TYPES[sharing]}
            means = {t: s[arm].mean for t, s in stats.items() if arm in s}
            by_type[f"{cell[0]} {arm.split()[0]}"] = means
    paper = "; ".join(
        f"w3={w3:g} {fmt(a)} (sd {fmt(sd_a)}) / {fmt(b)} (sd {fmt(sd_b)}), ratio {fmt(a / b, 1)}"
        for w3, (a, b, sd_a, sd_b) in PAPER_TABLE4.items()
    )
    types = {k: "`, `".join(v) for k, v in SYNC_TYPES.items()}
    acts = {k: render.summaries(values[f"table4 {k}"]) for k in (*BOTH, "diameter", PARTITIONS)}
    with_runs = [c for c, arms in ticks.items() if WITH in arms]
    rows = [[c[0], *(fmt(a[c][WITH].mean, 1) for a in acts.values())] for c in with_runs]
    lines = render.blocks(
        f"The paper's bytes, mean (sd) over 20 runs, without / with tracking: {paper}. It "
        "measured both in the same runs, as our *same run* columns do: at each merge of a "
        "`sheng-sync` run, the bytes of steps 4-10 as sent and what §4's brute force (whole maps "
        "both ways, then multicast) would have sent then, each message once; *1 B/cell* counts a "
        "cell as one byte instead of five (the paper states no layout). The claims read the "
        "same-run columns. Beside them, `full` runs on the seeds of `sheng-sync` (*without "
        "tracking*, every hop counted, like *with tracking*). Identical pairs (the same length "
        f"and distance): {', '.join(pairs)}. Only merge messages count (the paper's 812 bytes is "
        f"half a byte per cell of the map): with tracking `{types['sheng-sync']}`, without "
        f"`{types['full']}`; *broadcast* (`{'`, `'.join(BROADCAST_TYPES)}`, inside a sub-network) "
        "is not counted. Our byte model is not the paper's (unknown): ratios compare.",
        "Where nearness acts: the `sheng-sync` runs' means by w3 (time in ticks, distance and "
        "diameter in cells, partition events):",
        render.table(["w3", *acts], rows),
    )
    if any(by_type.values()):
        title = "Table 4: map synchronisation bytes per run (mean), 5 robots"
        plot_bytes_by_type(by_type, out / "table4_bytes.png", title=title, xlabel="w3, tracking")
        lines += ["![Table 4: bytes by message type](table4_bytes.png)", ""]
    return lines


QUICK_NOTE = (
    f"{QUICK_SEEDS['fig11']} seeds for Figs. 11-13 and {QUICK_SEEDS['table4']} for Table 4 "
    f"and Fig. 17, team sizes {' and '.join(map(str, QUICK_TEAM_SIZES))}, r_c = "
    + ", ".join(map(str, QUICK_RANGES))
)


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Lines:
    """The report's sections, its figures written into ``out``."""
    values, lines = tables(stores, quick), render.settings_table(_settings(quick))
    for heading, wheres in SECTIONS.items():
        here = [c for c in CLAIMS if c.where in wheres]
        quotes = " ".join(f'"{c.sentence}."' for c in here)
        lines += [f"## {heading}", "", f"Paper: {quotes}", "", "Ours: mean (sd; 95% CI; n).", ""]
        for key in dict.fromkeys(c.metric.removesuffix("_teams") for c in here):
            columns, digits = TABLES.get(key, (["robots"], 0))
            table = render.arm_table(values[key], ARMS, columns, digits=digits)
            lines += [f"**{LABELS[key]}**", "", *table, ""]
        for name, (caption, key, xlabel, ylabel) in FIGURES.items():
            if caption.startswith(wheres):
                panels = render.panels_of(values[key], CASES, lambda c: "")  # one panel
                axes = {"xlabel": xlabel, "ylabel": ylabel, "colours": COLOURS}
                lines += render.figure(out, name, panels, title=caption, **axes)
        lines += _table4(values, out) if "Table 4" in wheres else []
    return lines


REPRODUCTION = Reproduction(
    ID, TITLE, CITATION, experiments, report, tables, CLAIMS, INTERPRETATIONS, QUICK_NOTE
)
