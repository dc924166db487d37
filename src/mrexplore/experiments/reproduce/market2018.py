"""Reproduction of the decentralised market paper (§IV): market-occupancy vs a centralised
market (``burgard``, the paper's [3]), with and without event-based communication and the
frontier occupancy, on three indoor maps (:data:`MAPS`), 1-3 robots, one experiment per map and
arm (:data:`ARM_LABELS`). Our copy of §IV has no numbers and no figure: the claims come from
the abstract and §I-III (``PAPER_*``).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mrexplore.comm import messages
from mrexplore.experiments.reproduce import render
from mrexplore.experiments.reproduce.base import Reproduction
from mrexplore.experiments.reproduce.claims import CellKey, Claim, Means, Values
from mrexplore.experiments.reproduce.render import Experiment, Lines, Metric, Row, bytes_by_type
from mrexplore.experiments.store import Store
from mrexplore.strategies.market_occupancy import WEIGHT_REQUEST, WEIGHTS

ID = "market2018"
TITLE = "Decentralised market-based strategy for cooperative multi-robot exploration"
CITATION = (
    '"Decentralised market-based strategy for cooperative multi-robot exploration", §IV '
    "(our plain-text copy names no authors or venue; the id says 2018)."
)

TEAM_SIZES, QUICK_TEAM_SIZES = (1, 2, 3), (2, 3)  # §IV: "from one to three"
SEEDS, QUICK_SEEDS = tuple(range(1, 11)), (1, 2)  # not given in the paper: ours
#: Metres per cell of the real maps (their files have 0.05 m): a robot-sized cell; the sensor
#: range is not given in the paper: a Kinect-like range, the project's usual 3 m.
CELL_SIZE_M, SENSOR_RANGE_M = 0.2, 3.0
SENSOR_RANGE_CELLS = SENSOR_RANGE_M / CELL_SIZE_M
#: Periods of the time-triggered ablation (ticks = cells of travel): 2 m and 6 m.
TIMER_PERIODS = (10, 30)
#: Umari & Mukhopadhyay's frontier filter, the paper's pipeline [20]: a point is dropped when
#: under 0.2 m² is unknown within half its 1 m ``info_radius``; in our cells.
FILTER = {"filter_radius": 0.5 / CELL_SIZE_M, "filter_min_gain": round(0.2 / CELL_SIZE_M**2, 6)}
#: The occupancy ablation: ``lambda_f = 0`` means "default" (= r_f), so a negligible peak.
NO_OCCUPANCY_LAMBDA_F = 1e-9
#: A robot waiting for its clock is idle: the stall rule must wait longer than a period.
IDLE_TICKS = 2 * max(TIMER_PERIODS) + 10

FIXED: dict[str, Any] = {
    "start": "together",  # the robots of a ROS launch start side by side
    "comm_range": "inf",  # §I: "communication ... is modelled by fully connected graph"
    "latency": 1,
    "coverage_threshold": 0.99,
    "idle_ticks": IDLE_TICKS,
}


#: The environments, ``key (sweep names) | map | label | what it is``: two real indoor maps of
#: the catalogue and the ``office`` generator.
MAPS = render.text_rows(f"""
intel | intel | Intel Research Lab | catalogue map `intel` (real SLAM map, ring corridor and small
  rooms)
house | aws-small-house | AWS small house | catalogue map `aws-small-house` (a Gazebo house mapped
  in ROS)
office | office | office generator | our `office` generator (rooms on both sides of corridors), one
  map (`map_seed = 1`), cells read as {CELL_SIZE_M} m
""")
MAP_LABELS = {key: label for key, _, label, _ in MAPS}


def map_settings(quick: bool) -> dict[str, dict[str, Any]]:
    """``map key -> scenario settings``, in the order of :data:`MAPS`."""
    real = {"cell_size": CELL_SIZE_M, "sensor_range": f"{SENSOR_RANGE_M:g}m", "max_ticks": 10000}
    size, ticks = ("80x56", 3000) if quick else ("120x80", 10000)
    office = {"size": size, "map_seed": 1, "sensor_range": SENSOR_RANGE_CELLS, "max_ticks": ticks}
    return {key: {"map": name, **(office if key == "office" else real)} for key, name, *_ in MAPS}


CENTRALISED, DECENTRALISED = "centralised", "decentralised"
RRT, NO_OCCUPANCY = "rrt", "no-occupancy"


def timer_arm(period: int) -> str:
    return f"timer-{period}"


ARMS = (CENTRALISED, DECENTRALISED, RRT, *(timer_arm(p) for p in TIMER_PERIODS), NO_OCCUPANCY)
ARM_LABELS = {
    CENTRALISED: "centralised market (`burgard`)",
    DECENTRALISED: "decentralised, event-based (`market-occupancy`)",
    RRT: "decentralised, event-based, RRT frontiers",
    **{timer_arm(p): f"decentralised, time-triggered every {p} ticks" for p in TIMER_PERIODS},
    NO_OCCUPANCY: "decentralised, event-based, no occupancy (lambda_f ~ 0)",
}
_PALETTE = ("#1f77b4", "#bcbd22", "#8c564b", "#d62728", "#ff7f0e", "#7f7f7f")
ARM_COLOURS = dict(zip(ARMS, _PALETTE, strict=True))


def arm_of(row: Mapping[str, Any]) -> str:
    """The arm of a run from its strategy and parameter columns."""
    if row.get("strategy") == "burgard":
        return CENTRALISED
    if row.get("param_frontier_detector") == "rrt":
        return RRT
    if row.get("param_event_based") is False:
        return timer_arm(int(row.get("param_replan_every") or 0))
    lambda_f = row.get("param_lambda_f")
    if lambda_f is not None and 0 < float(lambda_f) < 1e-6:
        return NO_OCCUPANCY
    return DECENTRALISED


#: Message types of map sharing; every other type is coordination traffic.
MAP_TYPES = tuple(
    getattr(messages, t)
    for t in ("MAP_UPDATE", "MAP_FULL", "MAP_MULTICAST", "MAP_DELTA", "SEQ_TABLE", "MAP_SYNC")
)
#: The negotiation of Algorithm 1: the request with the frontier list and the rows.
NEGOTIATION_TYPES = (WEIGHT_REQUEST, WEIGHTS)
#: The numbers of a run the report and the claims read. ``time`` is T99, or the run's
#: length if it never reached 99% (a lower bound; ``reached`` says which).
METRICS: dict[str, Metric] = {
    "time": render.time_to("T99"),
    "reached": render.reached("T99"),
    "negotiation_bytes": render.bytes_of(NEGOTIATION_TYPES),
    "negotiation_messages": render.bytes_of(NEGOTIATION_TYPES, "messages"),
    "coordination_bytes": lambda r: sum(
        b for t, b in bytes_by_type(r).items() if t not in MAP_TYPES
    ),
    "bytes_total": render.column("bytes_total"),
    "diameter": render.column("group_diameter_mean"),
}


def map_key(row: Row) -> str:
    """The map of a run, from its experiment's name (``<map>-<arm>``)."""
    return str(row.get("experiment", "")).split("-")[0]


def run_values(rows: Iterable[Row]) -> dict[str, dict[CellKey, Any]]:
    """``metric -> (map, robots) -> arm -> seed -> value``, maps in the report's order."""
    order = {key: i for i, key in enumerate(MAP_LABELS)}
    cell = lambda r: (map_key(r), int(r["robots"]))  # noqa: E731 (a key, as the order)
    return render.tabulate(rows, METRICS, cell, arm_of, lambda c: (order.get(c[0], 99), c[1]))


#: Abstract: "The proposed strategy has been implemented in simulation environment and
#: compared with a centralised market model method. The results of exploration
#: demonstrate that the strategy distributes the mobile robots over an unknown area
#: and enables quick mission accomplishment." (no numbers in our copy)
PAPER_QUICK = "the decentralised strategy enables quick mission accomplishment"
#: Abstract: "Introduction of the frontier occupancy function in the weight causes
#: mobile robots ... to be more dispersed in the environment."
PAPER_DISPERSED = "the frontier occupancy function makes the robots more dispersed"
#: Abstract: "Other factor the[at] speeds up exploration process is related to the
#: presented event-based communication that reduces amount of information exchange
#: in negotiation process."
PAPER_EVENT_LESS_DATA = "event-based communication reduces the information exchanged"
PAPER_EVENT_FASTER = "event-based communication speeds up the exploration"
#: §I: "Although achieving tight coordination typically requires that the mobile robots
#: exchange large quantities of information ..., decentralised strategy proposed herein
#: uses minimal information to ensure the negotiation"; §III.B: "Accordingly the amount
#: of exchanging data is reduced".
PAPER_MINIMAL = "the decentralised negotiation uses minimal information"
#: §IV: "Experiments were performed in the different indoor environments (Fig. 9) with
#: the number of robots from one to three."
PAPER_ENVIRONMENTS, PAPER_TEAM_SIZES = 3, (1, 2, 3)

#: Every claim compares means over seeds cell by cell (map x team size, teams of 2 and 3, where
#: robots negotiate; for the event-based claims also x timer period, pooled).
#: ``id | where | the paper's words | metric | its label | the first arm, how its mean compares
#: and the arms it is compared with (their cells pooled) | our statement``, in the report's order.
_TIMERS = " ".join(timer_arm(p) for p in TIMER_PERIODS)
_CLAIMS = f"""
quick | Abstract | {PAPER_QUICK} | time | T99 | decentralised <= centralised | the decentralised
  market-occupancy explores at least as fast as the centralised market (2-3 robots)
quick_rrt | Abstract | {PAPER_QUICK} | time | T99 | rrt <= centralised | the same with the
  paper's RRT frontier detector (2-3 robots)
dispersed | Abstract | {PAPER_DISPERSED} | diameter | group diameter (cells) | decentralised >
  no-occupancy | the frontier occupancy function makes the robots more dispersed
event_data | Abstract | {PAPER_EVENT_LESS_DATA} | negotiation_bytes | negotiation bytes |
  decentralised < {_TIMERS} | event-based communication reduces the information exchanged in
  the negotiation (vs time-triggered rounds)
event_time | Abstract | {PAPER_EVENT_FASTER} | time | T99 | decentralised <= {_TIMERS} |
  event-based communication speeds up the exploration (vs time-triggered rounds)
minimal | §I | {PAPER_MINIMAL} | coordination_bytes | coordination bytes | decentralised <=
  centralised | the decentralised negotiation needs no more information than the centralised
  market's coordination
"""
CLAIMS = tuple(
    Claim(i, at, ours, paper, metric, label, first, arms[0], Means(how), digits, tuple(arms[1:]))
    for i, at, paper, metric, label, compared, ours in render.text_rows(_CLAIMS)
    for first, how, *arms in [compared.split()]
    for digits in [int(metric == "diameter")]
)

#: Fig. 4: market-occupancy re-plans on arrival only; the comparison is fair only with one
#: trigger for both arms, and the paper does not say which its centralised baseline used:
#: `burgard` re-plans on arrival too (its own default also re-plans once its target is explored).
_ARRIVAL = (
    '§III.B "at the moment when the mobile robot reach the goal, mission is over and a '
    'weight calculation request is sent to the others"'
)
BASELINE = {"replan_on_target_explored": False}
#: A low-rate robot radio, for the limited-link reading: 9600 bit/s (an XBee's default serial
#: rate) for a robot at 0.25 m/s, i.e. 0.8 s per tick of 0.2 m: 960 bytes per tick.
LINK_BYTES_PER_TICK = 960
INTERPRETATIONS = render.readings(f"""
both-replan-when-explored | {_ARRIVAL}, read as one re-plan trigger among others | both arms
  also re-plan once their target is explored (`replan_on_target_explored=true`; default: both
  on arrival only) | replan_on_target_explored=true | burgard, market-occupancy
unfiltered-frontiers | the RRT detector of [20] with its filter, whose threshold the paper does
  not restate | every reachable frontier cluster is a point, however little it would reveal
  (`filter_radius=0`, our earlier version) | filter_radius=0 | market-occupancy
path-cost | §III.A "the cost is the estimated distance traveled by robot to reach the target
  frontier point. The estimated distance is approximated using Euclidean distance" | C_ij is
  the shortest-path length on the robot's map, the distance it estimates (`cost=path`; default
  Euclidean, eq. 3): how much of the gap to the baseline, which plans on path costs, the
  approximation explains | cost=path | market-occupancy
timer-does-not-idle | Abstract "event-based communication ... speeds up the exploration" (the
  paper names no alternative) | in the time-triggered arms a robot that needs a goal also opens
  a round at once instead of idling until its clock (`idle_until_clock=false`; it changes no
  event-based run) | idle_until_clock=false | market-occupancy
coordinator-assigns-requesting | the centralised market of [3] (Burgard et al.: the robot-target
  tuple of highest utility, robot after robot, over the team) | the baseline's coordinator
  assigns only the robots that ask for a goal, the goals of the others fixed
  (`assign=requesting`, our earlier version; default: the whole team) | assign=requesting |
  burgard
centralised-bids | §II "every robot constructs its bids and sends them to a central executive,
  that tries to maximize the total expected utility ... by assigning them tasks, based on their
  bids" | the centralised market's robots send their path cost to every frontier cell they reach
  when the coordinator calls (`protocol=bids`; default: positions, the coordinator computes the
  costs on the shared map, Burgard et al.'s setting) | protocol=bids | burgard
limited-link | §I "centralised task assignment for a multi-robot system is often not practical
  due to communication limits" against "modelled by fully connected graph" | every robot may send
  {LINK_BYTES_PER_TICK} bytes per tick, a 9600 bit/s radio at 0.25 m/s, both arms, map sharing
  included (`scenario.bandwidth`; default unlimited) | scenario.bandwidth={LINK_BYTES_PER_TICK} | *
""")


def experiments(quick: bool) -> list[Experiment]:
    """One experiment per map and arm (``<map>-<arm>``); the RRT detector costs most: one
    seed in a quick run."""
    seeds = QUICK_SEEDS if quick else SEEDS
    robots = {"robots": list(QUICK_TEAM_SIZES if quick else TEAM_SIZES)}
    market = {**FIXED, "strategy": "market-occupancy", "set": FILTER}
    arms: dict[str, tuple[dict[str, Any], dict[str, Any]]] = {
        CENTRALISED: ({**FIXED, "strategy": "burgard", "set": BASELINE}, robots),
        DECENTRALISED: (market, {**robots, "set": {"lambda_f": [0.0, NO_OCCUPANCY_LAMBDA_F]}}),
        RRT: ({**market, "set": {**FILTER, "frontier_detector": "rrt"}}, robots),
        "timer": (
            {**market, "set": {**FILTER, "event_based": False}},
            {**robots, "set": {"replan_every": list(TIMER_PERIODS)}},
        ),
    }
    return [
        Experiment(f"{key}-{arm}", {**fixed, **settings}, grid, chosen, curves_every=10)
        for key, settings in map_settings(quick).items()
        for arm, (fixed, grid) in arms.items()
        for chosen in [seeds[:1] if quick and arm == RRT else seeds]
    ]


#: Our choices where the paper is silent, as the report's settings section lists them.
_NOTES = f"""
*Maps*: the paper's Fig. 9 environments are not in our copy. We take two real indoor maps (Intel
  lab: corridors and small rooms; the AWS small house, a ROS/Gazebo world) and one generated office.
  Their SLAM files are at 0.05 m; cells of 0.2 m (the size of a small robot) keep the runs short.
*Exploration time* is T99, ticks until 99% of the explorable cells are known: SLAM maps leave a few
  pockets that only a visit next to them reveals.
*Event-based communication* (§III.B, Fig. 4): a robot that reaches its goal sends a
  weight-calculation request with its frontier list; the others answer with their weights. The paper
  names no alternative; ours is time-triggered negotiation (`event_based=false`, added to
  `market-occupancy` for this reproduction): the same rounds, opened by each robot's clock instead
  of its arrival; a robot that arrived waits for the next round.
*Occupancy ablation*: `lambda_f = 0` means "the default" in our parameters, so `no-occupancy` sets
  `lambda_f = {NO_OCCUPANCY_LAMBDA_F:g}`.
*Traffic*: negotiation = `weight_request` + `weights` bytes; coordination = every message type
  except map sharing (`map_update`, ...), i.e. `status` + `assign` for `burgard`. The byte model is
  ours (a frontier point two float32, a weight one float32, a 7-byte header); the paper gives none.
*Dispersion* is the mean group diameter (largest distance between two robots, cells, averaged over
  the run).
"""
NOTES = [note for (note,) in render.text_rows(_NOTES)]


def _settings(quick: bool) -> Lines:
    seeds, sizes = (QUICK_SEEDS, QUICK_TEAM_SIZES) if quick else (SEEDS, TEAM_SIZES)
    maps = "; ".join(f"{label}: {note}" for _, _, label, note in MAPS)
    periods = ", ".join(map(str, TIMER_PERIODS))
    travel = ", ".join(f"{p * CELL_SIZE_M:g} m" for p in TIMER_PERIODS)
    rows = f"""
environments | {PAPER_ENVIRONMENTS} indoor environments in ROS simulation (Fig. 9, not in our
  copy) | {maps}
cell size, sensor | not given (ROS, laser and odometry SLAM) | real maps resampled to
  {CELL_SIZE_M} m per cell, sensor range {SENSOR_RANGE_M:g} m = {SENSOR_RANGE_CELLS:g} cells with
  line of sight; office: {SENSOR_RANGE_CELLS:g} cells
team sizes | 1 to 3 robots | {", ".join(map(str, sizes))}
runs | not given | {len(seeds)} seeds ({min(seeds)}-{max(seeds)}) per map, team size and arm; the
  seed places the team (adjacent cells), the same for every arm
compared method | centralised market model of [3] (Burgard et al. 2005) | `burgard`: utility
  discounting in line of sight, the whole team assigned greedily whenever a robot needs a goal;
  re-plans on arrival, as the paper's method
the paper's method | weights C - U + F (eqs. 3-6), Hungarian (eq. 8), event-based rounds, RRT
  frontier detector [20] | `market-occupancy` at its defaults, no values in the paper: lambda_u
  0.1 per unknown cell (0.5 m of travel per m² unknown at {CELL_SIZE_M} m cells), lambda_f = r_f,
  r = the sensor range ({SENSOR_RANGE_M:g} m), r_f = {2 * SENSOR_RANGE_M:g} m; frontier points:
  grid clusters (`decentralised`) and the RRT detector (`rrt`)
frontier filter | Umari's pipeline [20]: points with under 0.2 m² unknown within 0.5 m dropped |
  the same in cells: under {FILTER["filter_min_gain"]:g} unknown cells within
  {FILTER["filter_radius"]:g} cells (`filter_min_gain`, `filter_radius`)
without event-based communication | not described | `--set event_based=false replan_every=P`:
  each robot opens a round every P ticks, P = {periods} ticks (= {travel} of travel), not when it
  reaches its goal
communication | fully connected graph | unlimited range, latency 1 tick, no loss; `full` map
  sharing; idle limit {IDLE_TICKS} ticks
time | seconds of ROS simulation | ticks: one cell (0.2 m) of path per tick; exploration time =
  T99
"""
    return render.settings_table(rows, NOTES)


def tables(stores: Mapping[str, Store], quick: bool) -> dict[str, Values]:
    """``metric -> (map, robots) -> arm -> seed -> value`` over the teams (2+ robots, where
    robots negotiate), in the report's order: what :data:`CLAIMS` read."""
    values = run_values(render.rows_of(stores)[0])
    return {m: {c: v for c, v in cells.items() if c[1] >= 2} for m, cells in values.items()}


def _bytes_figure(rows: Sequence[Row], cells: Sequence[CellKey], out: Path) -> Lines:
    """The mean bytes per run by message type of each map and arm, in the largest teams."""
    from mrexplore.viz.plots import plot_bytes_by_type

    largest = max((c[1] for c in cells), default=0)
    runs = [((map_key(r), r["robots"], arm_of(r)), bytes_by_type(r)) for r in rows]
    bars: dict[str, dict[str, float]] = {}
    for (key, robots), arm in ((c, a) for c in cells if c[1] == largest for a in ARMS):
        if here := [by_type for run, by_type in runs if run == (key, robots, arm)]:
            types = sorted({t for by_type in here for t in by_type})
            bars[f"{key} {arm}"] = {t: float(np.mean([b.get(t, 0.0) for b in here])) for t in types}
    if not bars:
        return []
    title = f"Bytes per run by message type, {largest} robots (mean over seeds)"
    plot_bytes_by_type(bars, out / "bytes_by_type.png", title=title, xlabel="map, arm")
    return ["![bytes by message type](bytes_by_type.png)", ""]


QUICK_NOTE = (
    f"the three maps (the office 80 x 56 cells), {len(QUICK_SEEDS)} seeds (the RRT arm "
    f"1), {', '.join(map(str, QUICK_TEAM_SIZES))} robots"
)


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Lines:
    """The report's sections, its figures written into ``out``."""
    rows = render.rows_of(stores)[0]
    values = run_values(rows)
    teams, arms = tables(stores, quick), render.arms_in(values["time"], ARMS)

    def named(cell: CellKey) -> CellKey:
        return MAP_LABELS.get(cell[0], cell[0]), cell[1]

    def arm_tab(metric_values: Values, digits: int = 0, marks: Any = None) -> Lines:
        return render.arm_table(metric_values, ARMS, ["map", "robots"], named, digits, marks)

    def figure(metric_values: Values, name: str, ylabel: str, title: str, log: bool) -> Lines:
        panels = render.panels_of(metric_values, arms, lambda c: MAP_LABELS.get(c[0], str(c[0])))
        axes = {"xlabel": "robots", "ylabel": ylabel, "colours": ARM_COLOURS, "log": log}
        return render.figure(out, name, panels, title=title, **axes)

    coordination = ("coordination bytes per run", "Coordination traffic (all but map sharing)")
    return render.blocks(
        _settings(quick),
        "## Arms",
        render.table(["arm", "what"], [(f"`{a}`", ARM_LABELS[a]) for a in arms]),
        "## Exploration time (§IV, abstract)",
        f'Paper: "{PAPER_QUICK}" compared with the centralised market; "{PAPER_EVENT_FASTER}" '
        f"(abstract; §IV of our copy gives no numbers; {PAPER_ENVIRONMENTS} environments, "
        f"{PAPER_TEAM_SIZES[0]} to {PAPER_TEAM_SIZES[-1]} robots).",
        "Ours: T99 (ticks), mean (sd; 95% CI; n); `*` = some runs never reached 99% and "
        "count with their length.",
        arm_tab(values["time"], 0, render.unfinished(values["reached"])),
        figure(values["time"], "time.png", "T99 (ticks)", "Exploration time", False),
        "## Negotiation traffic (abstract, §I, §III.B)",
        f'Paper: "{PAPER_EVENT_LESS_DATA}"; "{PAPER_MINIMAL}" (read from the text; no numbers).',
        "Ours: bytes of `weight_request` + `weights` per run, mean (sd; 95% CI; n):",
        arm_tab(teams["negotiation_bytes"]),
        "Negotiation messages per run (`weight_request` + `weights`):",
        arm_tab(teams["negotiation_messages"]),
        "Coordination bytes per run (every type but map sharing; `burgard`: `status` + `assign`):",
        arm_tab(teams["coordination_bytes"]),
        "All bytes per run (with map sharing):",
        arm_tab(teams["bytes_total"]),
        figure(teams["coordination_bytes"], "coordination_bytes.png", *coordination, True),
        _bytes_figure(rows, list(values["time"]), out),
        "## Dispersion (abstract)",
        f'Paper: "{PAPER_DISPERSED}" (read from the text; no numbers).',
        "Ours: mean group diameter (cells), mean (sd; 95% CI; n):",
        arm_tab(teams["diameter"], 1),
    )


REPRODUCTION = Reproduction(
    ID, TITLE, CITATION, experiments, report, tables, CLAIMS, INTERPRETATIONS, QUICK_NOTE
)
