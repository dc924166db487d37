"""Reproduction of the decentralised market paper (§IV): market-occupancy vs a
centralised market, with and without event-based communication.

"Decentralised market-based strategy for cooperative multi-robot exploration"
(authors, venue and year not named in our copy of the paper; the id says 2018).
§IV: the strategy (``market-occupancy``) was "compared with coordinated
centralized market model described in [3]" (Burgard et al. 2005, our
``burgard``) "in the different indoor environments (Fig. 9) with the number of
robots from one to three", in ROS simulation. Our copy
of §IV has no numbers and no figure; the claims come from the abstract and §I-III
and are typed in as ``PAPER_*`` constants.

Experiments (``mrexplore reproduce market2018 --out DIR [--quick]``), on each of
three indoor maps (the Intel Research Lab and the AWS small house, which ship
with the package as ``intel`` and ``aws-small-house``, at 0.2 m per cell with a
3 m sensor, and our ``office`` generator with a 15-cell sensor), 1, 2 and 3
robots, 10 seeds, these arms:

====================  ==========================================================
arm                   what
====================  ==========================================================
``centralised``       ``burgard``: the centralised market of [3]
``decentralised``     ``market-occupancy`` as in the paper: event-based rounds
                      (a robot that reaches its goal opens a negotiation)
``rrt``               the same with the paper's RRT frontier detector
``timer-10``,         ``market-occupancy`` without event-based communication:
``timer-30``          ``event_based=false``, a round every 10 or 30 ticks per robot
``no-occupancy``      ``market-occupancy`` with the occupancy peak ``lambda_f``
                      negligible (``1e-9``): the frontier occupancy ablated
====================  ==========================================================

One sweep per map and arm (``<map>-<arm>``). ``--quick`` keeps the three maps
(the office smaller) with 2 seeds (the RRT arm 1) and 2 and 3 robots.
Exploration time is ``T99`` (ticks to 99% of the explorable cells); a run that
ended without reaching it counts with its length (a lower bound), flagged in the
tables. The helpers (:func:`arm_of`, :func:`run_numbers`, :func:`cell_summaries`,
:func:`count_outcome`) are pure functions of rows and numbers.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from mrexplore.comm.messages import (
    MAP_DELTA,
    MAP_FULL,
    MAP_MULTICAST,
    MAP_SYNC,
    MAP_UPDATE,
    SEQ_TABLE,
)
from mrexplore.experiments.reproduce.base import (
    Reproduction,
)
from mrexplore.experiments.reproduce.claims import (
    Claim,
    Counted,
    Interpretation,
    Values,
    claims_section,
    fmt,
)
from mrexplore.experiments.stats import Summary, summarize_metric
from mrexplore.experiments.store import Store
from mrexplore.experiments.sweep import Sweep, sweep_from_dict
from mrexplore.strategies.market_occupancy import WEIGHT_REQUEST, WEIGHTS

ID = "market2018"
TITLE = "Decentralised market-based strategy for cooperative multi-robot exploration"
CITATION = (
    '"Decentralised market-based strategy for cooperative multi-robot exploration", §IV '
    "(our plain-text copy names no authors or venue; the id says 2018)."
)

# ----------------------------------------------------------------------- settings

#: §IV: "with the number of robots from one to three".
TEAM_SIZES = (1, 2, 3)
QUICK_TEAM_SIZES = (2, 3)
#: Not given in the paper: ours.
SEEDS = tuple(range(1, 11))
QUICK_SEEDS = (1, 2)
#: Metres per cell of the real maps (their files have 0.05 m): a robot-sized cell.
CELL_SIZE_M = 0.2
#: Not given in the paper: a Kinect-like range, the project's usual 3 m.
SENSOR_RANGE_M = 3.0
#: Periods of the time-triggered ablation (ticks = cells of travel): 2 m and 6 m.
TIMER_PERIODS = (10, 30)
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


@dataclass(frozen=True)
class MapSetup:
    """One environment: a short key (sweep names), a label and its scenario settings."""

    key: str
    label: str
    settings: dict[str, Any] = field(default_factory=dict)
    note: str = ""


def map_setups(quick: bool) -> list[MapSetup]:
    """The environments: two real indoor maps of the catalogue and the ``office`` generator.

    >>> [m.key for m in map_setups(True)]
    ['intel', 'house', 'office']
    """
    office = MapSetup(
        "office",
        "office generator",
        {
            "map": "office",
            "size": "80x56" if quick else "120x80",
            "map_seed": 1,
            "sensor_range": SENSOR_RANGE_M / CELL_SIZE_M,
            "max_ticks": 3000 if quick else 10000,
        },
        "our `office` generator (rooms on both sides of corridors), one map "
        f"(`map_seed = 1`), cells read as {CELL_SIZE_M} m",
    )
    real = {"cell_size": CELL_SIZE_M, "sensor_range": f"{SENSOR_RANGE_M:g}m", "max_ticks": 10000}
    return [
        MapSetup(
            "intel",
            "Intel Research Lab",
            {"map": "intel", **real},
            "catalogue map `intel` (real SLAM map, ring corridor and small rooms)",
        ),
        MapSetup(
            "house",
            "AWS small house",
            {"map": "aws-small-house", **real},
            "catalogue map `aws-small-house` (a Gazebo house mapped in ROS)",
        ),
        office,
    ]


# ------------------------------------------------------------------------ arms

CENTRALISED = "centralised"
DECENTRALISED = "decentralised"
RRT = "rrt"
NO_OCCUPANCY = "no-occupancy"


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
ARM_COLOURS = {
    CENTRALISED: "#1f77b4",
    DECENTRALISED: "#bcbd22",
    RRT: "#8c564b",
    timer_arm(TIMER_PERIODS[0]): "#d62728",
    timer_arm(TIMER_PERIODS[1]): "#ff7f0e",
    NO_OCCUPANCY: "#7f7f7f",
}


def arm_of(row: Mapping[str, Any]) -> str:
    """The arm of a run from its strategy and parameter columns.

    >>> arm_of({"strategy": "burgard"})
    'centralised'
    >>> arm_of({"strategy": "market-occupancy", "param_event_based": False,
    ...         "param_replan_every": 30})
    'timer-30'
    >>> arm_of({"strategy": "market-occupancy", "param_lambda_f": 1e-9})
    'no-occupancy'
    >>> arm_of({"strategy": "market-occupancy", "param_frontier_detector": "rrt"})
    'rrt'
    """
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
MAP_TYPES = (MAP_UPDATE, MAP_FULL, MAP_MULTICAST, MAP_DELTA, SEQ_TABLE, MAP_SYNC)
#: The negotiation of Algorithm 1: the request with the frontier list and the rows.
NEGOTIATION_TYPES = (WEIGHT_REQUEST, WEIGHTS)


def _value(row: Mapping[str, Any], key: str) -> float:
    value = row.get(key)
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return 0.0
    return float(value)


@dataclass(frozen=True)
class RunNumbers:
    """One run's numbers for the report."""

    map_key: str
    arm: str
    robots: int
    seed: int
    status: str
    time: float
    """T99, or the run's length if it never reached 99% (a lower bound)."""
    reached: bool
    negotiation_bytes: float
    negotiation_messages: float
    coordination_bytes: float
    bytes_total: float
    diameter: float
    bytes_by_type: dict[str, float]


def run_numbers(runs: pa.Table, map_key: str) -> list[RunNumbers]:
    """The numbers of every usable run (status not ``failed``) of one map.

    >>> t = pa.table({"strategy": ["burgard"], "robots": [2], "seed": [1],
    ...     "status": ["max_ticks"], "T99": [None], "ticks": [500], "bytes_total": [90],
    ...     "bytes_by_type_map_update": [60], "bytes_by_type_status": [30],
    ...     "messages_by_type_status": [3], "group_diameter_mean": [4.5]})
    >>> n = run_numbers(t, "office")[0]
    >>> n.arm, n.time, n.reached, n.coordination_bytes, n.negotiation_bytes
    ('centralised', 500.0, False, 30.0, 0.0)
    """
    out: list[RunNumbers] = []
    for row in runs.to_pylist():
        if row.get("status") == "failed":
            continue
        t99 = row.get("T99")
        by_type = {
            key[len("bytes_by_type_") :]: _value(row, key)
            for key in row
            if key.startswith("bytes_by_type_") and _value(row, key) > 0
        }
        out.append(
            RunNumbers(
                map_key=map_key,
                arm=arm_of(row),
                robots=int(row["robots"]),
                seed=int(row["seed"]),
                status=str(row["status"]),
                time=float(t99) if t99 is not None else float(row["ticks"]),
                reached=t99 is not None,
                negotiation_bytes=sum(by_type.get(t, 0.0) for t in NEGOTIATION_TYPES),
                negotiation_messages=sum(
                    _value(row, f"messages_by_type_{t}") for t in NEGOTIATION_TYPES
                ),
                coordination_bytes=sum(b for t, b in by_type.items() if t not in MAP_TYPES),
                bytes_total=_value(row, "bytes_total"),
                diameter=_value(row, "group_diameter_mean"),
                bytes_by_type=by_type,
            )
        )
    return out


Cell = tuple[str, int]
"""``(map key, team size)``."""

METRICS = (
    "time",
    "negotiation_bytes",
    "negotiation_messages",
    "coordination_bytes",
    "bytes_total",
    "diameter",
)


def by_cell(numbers: Iterable[RunNumbers], metric: str) -> dict[Cell, dict[str, dict[int, float]]]:
    """``(map, robots) -> arm -> seed -> value``."""
    out: dict[Cell, dict[str, dict[int, float]]] = {}
    for n in numbers:
        out.setdefault((n.map_key, n.robots), {}).setdefault(n.arm, {})[n.seed] = float(
            getattr(n, metric)
        )
    return out


def cell_summaries(numbers: Iterable[RunNumbers], metric: str) -> dict[Cell, dict[str, Summary]]:
    """``(map, robots) -> arm ->`` :func:`summarize_metric` over the seeds.

    >>> n = [RunNumbers("m", "centralised", 2, s, "complete", 10.0 * s, True, 0.0, 0.0,
    ...      0.0, 0.0, 1.0, {}) for s in (1, 2, 3)]
    >>> cell_summaries(n, "time")[("m", 2)]["centralised"].mean
    20.0
    """
    return {
        cell: {arm: summarize_metric(list(s.values())) for arm, s in arms.items()}
        for cell, arms in by_cell(numbers, metric).items()
    }


# ------------------------------------------------------------ the paper's claims

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
PAPER_ENVIRONMENTS = 3
PAPER_TEAM_SIZES = (1, 2, 3)

#: Every claim is judged cell by cell (map x team size, teams of 2 and 3, where robots
#: negotiate; for the event-based claims also x timer period, pooled) on the means over
#: seeds. Exploration time is T99; a run that never reached 99% counts with its length
#: (a lower bound of its T99).
CLAIMS = (
    Claim(
        "quick",
        "Abstract",
        "the decentralised market-occupancy explores at least as fast as the centralised "
        "market (2-3 robots)",
        PAPER_QUICK,
        "time",
        "T99",
        DECENTRALISED,
        CENTRALISED,
        Counted("<="),
    ),
    Claim(
        "quick_rrt",
        "Abstract",
        "the same with the paper's RRT frontier detector (2-3 robots)",
        PAPER_QUICK,
        "time",
        "T99",
        RRT,
        CENTRALISED,
        Counted("<="),
    ),
    Claim(
        "dispersed",
        "Abstract",
        "the frontier occupancy function makes the robots more dispersed",
        PAPER_DISPERSED,
        "diameter",
        "group diameter (cells)",
        DECENTRALISED,
        NO_OCCUPANCY,
        Counted(">"),
        digits=1,
    ),
    Claim(
        "event_data",
        "Abstract",
        "event-based communication reduces the information exchanged in the negotiation "
        "(vs time-triggered rounds)",
        PAPER_EVENT_LESS_DATA,
        "negotiation_bytes",
        "negotiation bytes",
        DECENTRALISED,
        timer_arm(TIMER_PERIODS[0]),
        Counted("<"),
        seconds=tuple(timer_arm(p) for p in TIMER_PERIODS[1:]),
    ),
    Claim(
        "event_time",
        "Abstract",
        "event-based communication speeds up the exploration (vs time-triggered rounds)",
        PAPER_EVENT_FASTER,
        "time",
        "T99",
        DECENTRALISED,
        timer_arm(TIMER_PERIODS[0]),
        Counted("<="),
        seconds=tuple(timer_arm(p) for p in TIMER_PERIODS[1:]),
    ),
    Claim(
        "minimal",
        "§I",
        "the decentralised negotiation needs no more information than the centralised "
        "market's coordination",
        PAPER_MINIMAL,
        "coordination_bytes",
        "coordination bytes",
        DECENTRALISED,
        CENTRALISED,
        Counted("<="),
    ),
)

#: §III.B: "at the moment when the mobile robot reach the goal, mission is over and a
#: weight calculation request is sent to the others (Fig. 4)": market-occupancy
#: re-plans on arrival only. Our `burgard` also re-plans once its target is explored
#: (its default). The comparison is fair only with one trigger for both arms, and the
#: paper does not say which its centralised baseline used.
_ARRIVAL = (
    '§III.B "at the moment when the mobile robot reach the goal, mission is over and a '
    'weight calculation request is sent to the others"'
)
INTERPRETATIONS = (
    Interpretation(
        "baseline-replans-on-arrival",
        f"{_ARRIVAL}, as the rule of the centralised baseline too",
        "the centralised baseline also re-plans on arrival only "
        "(`burgard` `replan_on_target_explored=false`), the trigger of the paper's method",
        {"replan_on_target_explored": False},
        ("burgard",),
    ),
    Interpretation(
        "both-replan-when-explored",
        f"{_ARRIVAL}, as one re-plan trigger among the baseline's",
        "market-occupancy also re-plans once its target is explored "
        "(`replan_on_target_explored=true`), the trigger of the baseline",
        {"replan_on_target_explored": True},
        ("market-occupancy",),
    ),
)


# ------------------------------------------------------------------------ sweeps


def _sweep(name: str, seeds: Sequence[int], fixed: dict[str, Any], grid: dict[str, Any]) -> Sweep:
    data = {
        "sweep": {"name": name, "seeds": list(seeds), "curves_every": 10},
        "fixed": {**FIXED, **fixed},
        "grid": grid,
    }
    return sweep_from_dict(data, source=f"{ID}:{name}")


def sweeps(quick: bool) -> dict[str, Sweep]:
    """One sweep per map and arm (``<map>-<arm>``)."""
    seeds = QUICK_SEEDS if quick else SEEDS
    robots = {"robots": list(QUICK_TEAM_SIZES if quick else TEAM_SIZES)}
    market = {"strategy": "market-occupancy"}
    out: dict[str, Sweep] = {}
    for setup in map_setups(quick):
        base = dict(setup.settings)
        arms: dict[str, tuple[dict[str, Any], dict[str, Any]]] = {
            CENTRALISED: ({**base, "strategy": "burgard"}, robots),
            DECENTRALISED: (
                {**base, **market},
                {**robots, "set": {"lambda_f": [0.0, NO_OCCUPANCY_LAMBDA_F]}},
            ),
            RRT: ({**base, **market, "set": {"frontier_detector": "rrt"}}, robots),
            "timer": (
                {**base, **market, "set": {"event_based": False}},
                {**robots, "set": {"replan_every": list(TIMER_PERIODS)}},
            ),
        }
        for arm, (fixed, grid) in arms.items():
            name = f"{setup.key}-{arm}"
            # The RRT detector costs most: one seed in a quick run.
            out[name] = _sweep(name, seeds[:1] if quick and arm == RRT else seeds, fixed, grid)
    return out


# ------------------------------------------------------------------------ report

Lines = list[str]


def _cell(s: Summary | None, digits: int = 0, flag: str = "") -> str:
    if s is None:
        return "-"
    interval = f"{fmt(s.ci_low, digits)}..{fmt(s.ci_high, digits)}"
    return f"{fmt(s.mean, digits)}{flag} (sd {fmt(s.sd, digits)}; CI {interval}; n {s.n})"


def _arms_present(stats: Mapping[Cell, Mapping[str, Summary]]) -> list[str]:
    present = {arm for arms in stats.values() for arm in arms}
    return [arm for arm in ARMS if arm in present]


def _table(
    stats: Mapping[Cell, Mapping[str, Summary]],
    cells: Sequence[Cell],
    labels: Mapping[str, str],
    digits: int = 0,
    flags: Mapping[tuple[Cell, str], str] | None = None,
) -> Lines:
    arms = _arms_present(stats)
    lines = [
        "| map | robots | " + " | ".join(f"`{a}`" for a in arms) + " |",
        "|---|---|" + "---|" * len(arms),
    ]
    for cell in cells:
        row = stats.get(cell, {})
        values = [_cell(row.get(arm), digits, (flags or {}).get((cell, arm), "")) for arm in arms]
        lines.append(f"| {labels[cell[0]]} | {cell[1]} | " + " | ".join(values) + " |")
    return lines


def _panels_figure(
    stats: Mapping[Cell, Mapping[str, Summary]],
    setups: Sequence[MapSetup],
    path: Path,
    ylabel: str,
    title: str,
    arms: Sequence[str],
    log: bool = False,
) -> Path | None:
    """One subplot per map: mean against team size, one line per arm, 95% CI bars."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from mrexplore.viz.plots import LEGEND_WIDTH_IN, figure_legend_outside

    keys = [s for s in setups if any(c[0] == s.key for c in stats)]
    if not keys:
        return None
    fig = Figure(figsize=(3.6 * len(keys) + LEGEND_WIDTH_IN, 3.6), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(keys), squeeze=False)[0]
    for ax, setup in zip(axes, keys, strict=True):
        sizes = sorted({c[1] for c in stats if c[0] == setup.key})
        for i, arm in enumerate(arms):
            points = [(n, stats[(setup.key, n)].get(arm)) for n in sizes]
            kept = [(n, s) for n, s in points if s is not None and math.isfinite(s.mean)]
            if log:
                kept = [(n, s) for n, s in kept if s.mean > 0]
            if not kept:
                continue
            xs = np.array([n for n, _ in kept], dtype=np.float64) + (i - len(arms) / 2) * 0.06
            means = np.array([s.mean for _, s in kept])
            below = np.nan_to_num(np.array([s.mean - s.ci_low for _, s in kept]))
            above = np.nan_to_num(np.array([s.ci_high - s.mean for _, s in kept]))
            if log:
                below = np.minimum(below, means * 0.999)
            ax.errorbar(
                xs,
                means,
                yerr=np.vstack([below, above]),
                color=ARM_COLOURS.get(arm, "#000000"),
                marker="o",
                ms=4,
                lw=1.3,
                capsize=2,
                label=arm,
            )
        if log:
            ax.set_yscale("log")
        ax.set_xticks(sizes)
        ax.set_xlabel("robots", fontsize=8)
        ax.set_title(setup.label, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
    figure_legend_outside(fig, axes, fontsize=7)
    axes[0].set_ylabel(ylabel, fontsize=8)
    fig.suptitle(f"{title}\n(mean over seeds, error bars: 95% CI)", fontsize=10)
    fig.savefig(path, format="png")
    return path


def _settings_section(quick: bool, setups: Sequence[MapSetup]) -> Lines:
    seeds = QUICK_SEEDS if quick else SEEDS
    sizes = QUICK_TEAM_SIZES if quick else TEAM_SIZES
    rows = [
        (
            "environments",
            f"{PAPER_ENVIRONMENTS} indoor environments in ROS simulation (Fig. 9, not in our copy)",
            "; ".join(f"{s.label}: {s.note}" for s in setups),
        ),
        (
            "cell size, sensor",
            "not given (ROS, laser and odometry SLAM)",
            f"real maps resampled to {CELL_SIZE_M} m per cell, sensor range "
            f"{SENSOR_RANGE_M:g} m = {SENSOR_RANGE_M / CELL_SIZE_M:g} cells with line of "
            f"sight; office: {SENSOR_RANGE_M / CELL_SIZE_M:g} cells",
        ),
        (
            "team sizes",
            "1 to 3 robots",
            ", ".join(str(n) for n in sizes),
        ),
        (
            "runs",
            "not given",
            f"{len(seeds)} seeds ({min(seeds)}-{max(seeds)}) per map, team size and arm; the "
            "seed places the team (adjacent cells), the same for every arm",
        ),
        (
            "compared method",
            "centralised market model of [3] (Burgard et al. 2005)",
            "`burgard` at its defaults (utility discounting, central greedy assignment)",
        ),
        (
            "the paper's method",
            "weights C - U + F (eqs. 3-6), Hungarian (eq. 8), event-based rounds, RRT "
            "frontier detector [20]",
            "`market-occupancy` at its defaults (lambda_u 0.1, lambda_f = r_f, r = sensor "
            "range, r_f = 2 x sensor range; no values in the paper); frontier points: grid "
            "clusters (`decentralised`) and the RRT detector (`rrt`)",
        ),
        (
            "without event-based communication",
            "not described",
            "`--set event_based=false replan_every=P`: each robot opens a round every P "
            f"ticks, P = {', '.join(map(str, TIMER_PERIODS))} ticks (= "
            + ", ".join(f"{p * CELL_SIZE_M:g} m" for p in TIMER_PERIODS)
            + " of travel), not when it reaches its goal",
        ),
        (
            "communication",
            "fully connected graph",
            f"unlimited range, latency 1 tick, no loss; `full` map sharing; idle limit "
            f"{IDLE_TICKS} ticks",
        ),
        (
            "time",
            "seconds of ROS simulation",
            "ticks: one cell (0.2 m) of path per tick; exploration time = T99",
        ),
    ]
    lines = ["## Settings", "", "| setting | paper | ours |", "|---|---|---|"]
    lines += [f"| {name} | {paper} | {ours} |" for name, paper, ours in rows]
    lines += [
        "",
        "Choices where the paper is silent or our world differs:",
        "",
        "- *Maps*: the paper's Fig. 9 environments are not in our copy. We take two real "
        "indoor maps (Intel lab: corridors and small rooms; the AWS small house, a ROS/Gazebo "
        "world) and one generated office. Their SLAM files are at 0.05 m; cells of 0.2 m "
        "(the size of a small robot) keep the runs short.",
        "- *Exploration time* is T99, ticks until 99% of the explorable cells are known: "
        "SLAM maps leave a few pockets that only a visit next to them reveals.",
        "- *Event-based communication* (§III.B, Fig. 4): a robot that reaches its goal sends "
        "a weight-calculation request with its frontier list; the others answer with their "
        "weights. The paper names no alternative; ours is time-triggered negotiation "
        "(`event_based=false`, added to `market-occupancy` for this reproduction): the same "
        "rounds, opened by each robot's clock instead of its arrival; a robot that arrived "
        "waits for the next round.",
        '- *Occupancy ablation*: `lambda_f = 0` means "the default" in our parameters, so '
        f"`no-occupancy` sets `lambda_f = {NO_OCCUPANCY_LAMBDA_F:g}`.",
        "- *Traffic*: negotiation = `weight_request` + `weights` bytes; coordination = every "
        "message type except map sharing (`map_update`, ...), i.e. `status` + `assign` for "
        "`burgard`. The byte model is ours (a frontier point two float32, a weight one "
        "float32, a 7-byte header); the paper gives none.",
        "- *Dispersion* is the mean group diameter (largest distance between two robots, "
        "cells, averaged over the run).",
        "",
    ]
    return lines


def _numbers(stores: Mapping[str, Store], quick: bool) -> tuple[list[RunNumbers], int]:
    """Every usable run's numbers, and the number of failed runs."""
    setups = map_setups(quick)
    numbers: list[RunNumbers] = []
    failed = 0
    for name, store in stores.items():
        key = next((s.key for s in setups if name.startswith(f"{s.key}-")), name)
        runs = store.query("SELECT * FROM runs ORDER BY run_id")
        failed += sum(s == "failed" for s in runs.column("status").to_pylist())
        numbers += run_numbers(runs, key)
    return numbers, failed


def _ordered_cells(cells: Iterable[Cell], quick: bool) -> list[Cell]:
    order = {s.key: i for i, s in enumerate(map_setups(quick))}
    return sorted(cells, key=lambda c: (order.get(c[0], 99), c[1]))


def tables(stores: Mapping[str, Store], quick: bool) -> dict[str, Values]:
    """``metric -> (map, robots) -> arm -> seed -> value`` over the teams (2+ robots),
    in the report's order: what :data:`CLAIMS` read."""
    numbers, _ = _numbers(stores, quick)
    out: dict[str, Values] = {}
    for metric in METRICS:
        values = by_cell(numbers, metric)
        out[metric] = {c: values[c] for c in _ordered_cells(values, quick) if c[1] >= 2}
    return out


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Path:
    """Write ``out/report.md`` and its figures from the experiments' stores."""
    from mrexplore.viz.plots import plot_bytes_by_type

    out = Path(out)
    setups = map_setups(quick)
    labels = {s.key: s.label for s in setups}
    numbers, failed = _numbers(stores, quick)
    labels.update({n.map_key: n.map_key for n in numbers if n.map_key not in labels})
    stats = {metric: cell_summaries(numbers, metric) for metric in METRICS}
    cells = _ordered_cells(stats["time"], quick)
    teams = [c for c in cells if c[1] >= 2]
    flags = {((n.map_key, n.robots), n.arm): "*" for n in numbers if not n.reached}
    statuses: dict[str, int] = {}
    for n in numbers:
        statuses[n.status] = statuses.get(n.status, 0) + 1
    if failed:
        statuses["failed"] = failed

    lines: Lines = [f"# Reproduction: {TITLE}", ""]
    if quick:
        lines += [
            "> **Quick run** (`--quick`): the three maps (the office 80 x 56 cells), "
            f"{len(QUICK_SEEDS)} seeds (the RRT arm 1), {', '.join(map(str, QUICK_TEAM_SIZES))} "
            "robots. Its "
            "verdicts are indicative only; run without `--quick` for the full settings.",
            "",
        ]
    lines += [
        f"Citation: {CITATION}",
        "",
        f"Written {time.strftime('%Y-%m-%d %H:%M')}. Runs: "
        + ", ".join(f"{k} {v}" for k, v in sorted(statuses.items()))
        + ".",
        "",
    ]
    lines += _settings_section(quick, setups)
    lines += ["## Arms", "", "| arm | what |", "|---|---|"]
    lines += [f"| `{arm}` | {ARM_LABELS[arm]} |" for arm in _arms_present(stats["time"])]
    lines += [
        "",
        "## Exploration time (§IV, abstract)",
        "",
        f'Paper: "{PAPER_QUICK}" compared with the centralised market; '
        f'"{PAPER_EVENT_FASTER}" (abstract; §IV of our copy gives no numbers; '
        f"{PAPER_ENVIRONMENTS} environments, {PAPER_TEAM_SIZES[0]} to {PAPER_TEAM_SIZES[-1]} "
        "robots).",
        "",
        "Ours: T99 (ticks), mean (sd; 95% CI; n); `*` = some runs never reached 99% and "
        "count with their length.",
        "",
    ]
    lines += _table(stats["time"], cells, labels, 0, flags)
    lines.append("")
    arms_all = _arms_present(stats["time"])
    path = _panels_figure(
        stats["time"], setups, out / "time.png", "T99 (ticks)", "Exploration time", arms_all
    )
    if path is not None:
        lines += ["![exploration time](time.png)", ""]
    lines += [
        "## Negotiation traffic (abstract, §I, §III.B)",
        "",
        f'Paper: "{PAPER_EVENT_LESS_DATA}"; "{PAPER_MINIMAL}" (read from the text; no numbers).',
        "",
        "Ours: bytes of `weight_request` + `weights` per run, mean (sd; 95% CI; n):",
        "",
    ]
    lines += _table(stats["negotiation_bytes"], teams, labels)
    lines += ["", "Negotiation messages per run (`weight_request` + `weights`):", ""]
    lines += _table(stats["negotiation_messages"], teams, labels)
    lines += [
        "",
        "Coordination bytes per run (every type but map sharing; `burgard`: `status` + `assign`):",
        "",
    ]
    lines += _table(stats["coordination_bytes"], teams, labels)
    lines += ["", "All bytes per run (with map sharing):", ""]
    lines += _table(stats["bytes_total"], teams, labels)
    lines.append("")
    path = _panels_figure(
        stats["coordination_bytes"],
        setups,
        out / "coordination_bytes.png",
        "coordination bytes per run",
        "Coordination traffic (all but map sharing)",
        arms_all,
        log=True,
    )
    if path is not None:
        lines += ["![coordination bytes](coordination_bytes.png)", ""]
    largest = max((c[1] for c in cells), default=0)
    bars: dict[str, dict[str, float]] = {}
    for cell in cells:
        if cell[1] != largest:
            continue
        for arm in arms_all:
            runs_here = [n for n in numbers if (n.map_key, n.robots) == cell and n.arm == arm]
            if not runs_here:
                continue
            types = sorted({t for n in runs_here for t in n.bytes_by_type})
            bars[f"{cell[0]} {arm}"] = {
                t: float(np.mean([n.bytes_by_type.get(t, 0.0) for n in runs_here])) for t in types
            }
    if bars:
        plot_bytes_by_type(
            bars,
            out / "bytes_by_type.png",
            title=f"Bytes per run by message type, {largest} robots (mean over seeds)",
            xlabel="map, arm",
        )
        lines += ["![bytes by message type](bytes_by_type.png)", ""]
    lines += [
        "## Dispersion (abstract)",
        "",
        f'Paper: "{PAPER_DISPERSED}" (read from the text; no numbers).',
        "",
        "Ours: mean group diameter (cells), mean (sd; 95% CI; n):",
        "",
    ]
    lines += _table(stats["diameter"], teams, labels, 1)
    lines.append("")

    lines += claims_section(CLAIMS, tables(stores, quick))
    lines.append("")
    path = out / "report.md"
    path.write_text("\n".join(lines))
    return path


REPRODUCTION = Reproduction(
    id=ID,
    title=TITLE,
    citation=CITATION,
    sweeps=sweeps,
    report=report,
    claims=CLAIMS,
    tables=tables,
    interpretations=INTERPRETATIONS,
)
