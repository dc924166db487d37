"""Vazquez & Malcolm (§4): time to map an office while keeping a mobile network, vs Yamauchi.

Khepera robots in Webots map two offices with radio ranges of 1-2 m and 2-10 robots: the
network-keeping behaviours (``vazquez-network``) against Yamauchi's (``nearest-frontier``).
Figs. 6-12 are plots without numbers in the text: the paper's side is its settings
(``PAPER_*``, :data:`SETTINGS_ROWS`) and the results its text states (:data:`CLAIMS`).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from mrexplore.experiments.reproduce import claims, render
from mrexplore.experiments.reproduce.base import Reproduction
from mrexplore.experiments.reproduce.claims import CellKey, Claim, Means, Needs, Rule, Values
from mrexplore.experiments.reproduce.render import Experiment, Lines, Row
from mrexplore.experiments.store import Store, StoreError

ID = "vazquez2005"
TITLE = "Vazquez & Malcolm: exploration maintaining a mobile network vs Yamauchi"
CITATION = (
    'J. Vazquez, C. Malcolm, "Distributed multirobot exploration maintaining a mobile '
    "network\", Proc. 2nd IEEE International Conference on Intelligent Systems (IS'04), "
    "Varna, 2004, vol. 3, pp. 113-118, §4, Figs. 6-12."
)

#: §4: "The robots have a diameter of 5 cm and their sensor range diameter is 45cm".
PAPER_ROBOT_DIAMETER_M, PAPER_SENSOR_DIAMETER_M = 0.05, 0.45
#: §4: "The communication ranges compared were 1m, 1.5 m and 2m" (Figs. 6-11).
PAPER_COMM_RANGES_M: tuple[float, ...] = (1.0, 1.5, 2.0)
#: §4: "The team sizes range from 2 to 10 robots"; "ten trials were run and averaged".
PAPER_TEAM_SIZES, PAPER_TRIALS = tuple(range(2, 11)), 10
#: §4: "The total space to explore in the environments were 10.2m2 and 23.5m2".
PAPER_AREAS_M2: dict[str, float] = {"small": 10.2, "large": 23.5}
#: §1, §4: position known "with an error margin of +-5%"; data broadcast "every half second".
PAPER_POSITION_ERROR, PAPER_BROADCAST_PERIOD_S = 0.05, 0.5
#: §3.1.2: d1 = 3/2 of the sensor diameter, d2 = 0.9 d3.
PAPER_D1_SENSOR_DIAMETERS, PAPER_D2_FRACTION = 1.5, 0.9
#: §4 (Figs. 6-8): above seven robots, Yamauchi's robots "perform worse".
PAPER_YAMAUCHI_WORSE_ABOVE = 7

CELL_SIZE_M = 0.05  # one Khepera per cell
SENSOR_RANGE_CELLS = PAPER_SENSOR_DIAMETER_M / 2 / CELL_SIZE_M  # 4.5
COMM_RANGES_CELLS: tuple[int, ...] = tuple(round(r / CELL_SIZE_M) for r in PAPER_COMM_RANGES_M)
MAP_SEED = 1
VAZQUEZ, YAMAUCHI = "vazquez-network", "nearest-frontier"
STRATEGIES = {VAZQUEZ: "vazquez", YAMAUCHI: "yamauchi"}  # -> the experiments' names


@dataclass(frozen=True)
class OfficeMap:
    """One of the paper's two environments as a generated office (one cell: 5 cm, a robot)."""

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
#: The quick run's stand-in for the small environment (1958 explorable cells = 4.9 m^2).
QUICK_MAP = OfficeMap("small", "50x50", PAPER_AREAS_M2["small"], 6_000, "Figs. 6-8, reduced")
SPEC_OF_SIZE = {spec.size: spec for spec in (*MAPS.values(), QUICK_MAP)}
#: The paper's grid: every team size of 2-10 robots, 10 trials each, both methods, both
#: environments, the three ranges (1 080 runs).
FULL_TEAM_SIZES, FULL_SEEDS = list(PAPER_TEAM_SIZES), list(range(1, PAPER_TRIALS + 1))
QUICK_TEAM_SIZES, QUICK_SEEDS = [4, 8], [1, 2]
QUICK_RANGES = [COMM_RANGES_CELLS[0], COMM_RANGES_CELLS[-1]]
CURVES_EVERY = 10
T100 = "T100 (ticks)"
FIXED = {"map": "office", "map_seed": MAP_SEED, "sensor_range": SENSOR_RANGE_CELLS}
FIXED.update({"start": "together", "coverage_threshold": 1.0})
#: §4 "The information arrives by multi hops to all the members of the team": new cells
#: relayed through the sub-network, for both methods; runs go on until one robot holds
#: the whole map, so both completion times are measured.
FIXED.update({"sharing": "broadcast", "complete_when": "robot"})
#: Fig. 2 "If the robot arrives at the current frontier the exploration algorithm its
#: executed"; Yamauchi's robots head for a frontier until they reach it: both methods.
FIXED["set"] = {"replan_on_target_explored": False}


_SETTINGS = f"""
simulator | Webots, Khepera robots | mrexplore occupancy grid, one robot per cell
robot diameter | {PAPER_ROBOT_DIAMETER_M * 100:g} cm | 1 cell (cells of {CELL_SIZE_M * 100:g} cm)
sensor | range diameter {PAPER_SENSOR_DIAMETER_M * 100:g} cm (infrared/sonar) | disk of radius
  {SENSOR_RANGE_CELLS:g} cells with line of sight, sensing while moving
communication range d3 | {", ".join(f"{r:g} m" for r in PAPER_COMM_RANGES_M)} |
  {", ".join(f"{r} cells" for r in COMM_RANGES_CELLS)} (the strategy takes d3 from the run's range)
comfort zone | d1 = 3/2 sensor diameter, d2 = 0.9 d3 |
  d1 = {PAPER_D1_SENSOR_DIAMETERS * 2 * SENSOR_RANGE_CELLS:g} cells,
  d2 = {", ".join(f"{PAPER_D2_FRACTION * r:g}" for r in COMM_RANGES_CELLS)} cells (strategy
  defaults; the d1 cap 0.75 d2 never binds here)
radio model | signal decays with the square of distance, walls do not block | disk of radius
  d3, walls do not block (comm_los off), multi-hop, 1 tick per hop
environments | structured office-like, {" and ".join(f"{a} m^2" for a in PAPER_AREAS_M2.values())}
  (Fig. 5, not in our copy) | generator office, {" and ".join(m.size for m in MAPS.values())}
  cells, map_seed {MAP_SEED} for every run; quick: one reduced office, {QUICK_MAP.size}
team sizes | 2-10 | full: 2-10, as the paper; quick: 4, 8
trials | {PAPER_TRIALS} per team size | full: seeds 1-{len(FULL_SEEDS)}; quick: {len(QUICK_SEEDS)}
start | relative positions to a known location | adjacent cells around a free cell of the seed
localisation | known within +-{PAPER_POSITION_ERROR:.0%} | perfect; the reading
  `localisation-error` adds odometry drift of {PAPER_POSITION_ERROR:.0%} per step
information sharing | sensor data every {PAPER_BROADCAST_PERIOD_S} s, multi-hop to the team |
  `broadcast` sharing (new cells relayed to the sub-network each tick, nothing exchanged when
  sub-networks join); positions every 2 ticks
Yamauchi | closest frontier, no coordination, common map | nearest-frontier with the same
  range and sharing; both re-plan on arrival only
time | seconds (Webots) | ticks; a robot moves 1 cell (5 cm) per tick
time to complete | time to a complete map | T100, the team's union knows every explorable
  cell; and T100 of one robot, the first tick one robot's own map holds them all (runs go on
  until then)
run limit | - | max_ticks {MAPS["small"].max_ticks} (small), {MAPS["large"].max_ticks} (large),
  {QUICK_MAP.max_ticks} (quick); a run that stops early counts with its last tick (a lower bound)
"""
#: The settings, the paper's (§4) beside ours.
SETTINGS_ROWS = [(name, paper, ours) for name, paper, ours in render.text_rows(_SETTINGS)]


def experiments(quick: bool) -> list[Experiment]:
    """Figs. 6-11 (and 12, from the same runs): one experiment per map and method."""
    out = []
    for spec in [QUICK_MAP] if quick else MAPS.values():
        for strategy, key in STRATEGIES.items():
            robots = QUICK_TEAM_SIZES if quick else FULL_TEAM_SIZES
            seeds = QUICK_SEEDS if quick else FULL_SEEDS
            fixed = {**FIXED, "size": spec.size, "max_ticks": spec.max_ticks, "strategy": strategy}
            ranges = QUICK_RANGES if quick else COMM_RANGES_CELLS
            grid = {"robots": list(robots), "comm_range": list(ranges)}
            out.append(Experiment(f"{spec.label}-{key}", fixed, grid, seeds, CURVES_EVERY))
    return out


class Metres(float):
    """A radio range in metres, printed with its unit (in the names of cells)."""

    def __str__(self) -> str:
        return f"{self:g} m"


def run_rows(stores: Mapping[str, Store]) -> tuple[list[dict[str, Any]], dict[str, int]]:
    """:func:`~render.rows_of` with each run's ``connected_share``: the share of its curve
    samples (every :data:`CURVES_EVERY` ticks) at which the team was one sub-network."""
    share = "avg(CASE WHEN subnetworks <= 1 THEN 1 ELSE 0 END) AS share"
    rows, statuses = render.rows_of(stores)
    shares: dict[tuple[str, str], float] = {}
    for name, store in stores.items():
        with contextlib.suppress(StoreError):  # no run finished, so there are no curves
            found = store.query(f"SELECT run_id, {share} FROM curves GROUP BY run_id").to_pylist()
            shares |= {(name, r["run_id"]): r["share"] for r in found}
    for row in rows:
        row["connected_share"] = shares.get((row["experiment"], row["run_id"]), math.nan)
    return rows, statuses


#: The numbers of a run: ``time`` is T100, or the run's length if it never completed.
METRICS: dict[str, render.Metric] = {
    "time": render.time_to("T100"),
    "complete": render.reached("T100"),
    "T99": render.measured("T99"),
    "one_map": render.time_to("T100_first_robot"),
    "connected": lambda r: float(r["connected_share"]),
}


def _cell(row: Row) -> CellKey:  # (map, range, robots)
    comm_range = Metres(round(float(row["comm_range"]) * CELL_SIZE_M, 6))
    return (SPEC_OF_SIZE[str(row["size"])].label, comm_range, int(row["robots"]))


def by_range(values: Values, arms: Sequence[str]) -> dict[CellKey, dict[str, Any]]:
    """``(map, robots) -> "<arm>, <range>" -> seed -> value``: one curve per arm and range."""
    out: dict[CellKey, dict[str, Any]] = {}
    for (map_label, comm_range, robots), by_arm in values.items():
        for arm in (a for a in arms if a in by_arm):
            out.setdefault((map_label, robots), {})[f"{arm}, {comm_range}"] = by_arm[arm]
    return out


def run_values(rows: Sequence[Row]) -> dict[str, Values]:
    """``metric -> (map, range, robots) -> strategy -> seed -> value``; ``time`` also has
    arms ``<strategy> T99``; ``ranges``: vazquez-network's time :func:`by_range`."""
    order = list(MAPS)
    values = render.tabulate(
        rows, METRICS, _cell, lambda r: str(r["strategy"]), lambda c: (order.index(c[0]), *c[1:])
    )
    for cell, arms in values["time"].items():
        arms.update({f"{a} T99": by_seed for a, by_seed in values["T99"][cell].items()})
    return {**values, "ranges": by_range(values["time"], [VAZQUEZ])}


def tables(stores: Mapping[str, Store], quick: bool) -> dict[str, Values]:
    return run_values(run_rows(stores)[0])


#: ``id | where | the claim in our words | the paper's sentence``, in the report's order.
_CLAIM_WORDS = """
trend | Figs. 6-11 | completion time drops with team size, with diminishing returns | the time
  of completition drops in a linear fashion with respect to the number of robots up to some
  maximum number of robots ... After the threshold there are diminishing returns for more robots
faster | Figs. 6-11 | vazquez-network is faster than Yamauchi (also on T99) | The robots
  maintaining the network perform better than the robots in Yamauchi's approach
above_7 | Figs. 6-8 | in the small environment Yamauchi's robots do worse above seven robots
  | in the case of the small environment when the number of robots is above seven robots
  in Yamauchis approach the robots perform worse
variance | Figs. 6-11, esp. Fig. 7 (small, 1.5 m) | Yamauchi's times vary much more than
  vazquez-network's | the varianze of the results [of Yamauchi's approach] is significantly
  higher than the varianze in the proposed approach, this is more notorious on Figure 7 when
  there are larger number of robots
range_tradeoff | Fig. 12 | a shorter range costs vazquez-network little time: similar
  performance | the effect of the communication range presents an acceptable trade-off with
  respect to the time of completion ... robots are able to maintain a similar performance
range_gap | Fig. 12 | the difference between ranges diminishes as robots are added | as the
  number of robots increases the difference is diminished
incremental | §1 | the approach does incrementally better (relative to Yamauchi) with larger
  teams | the approach performs incrementally better with larger teams of robots
network | abstract, §3 | the robots keep one mobile network while exploring | The robots are
  encouraged to move together forming a mobile network
faster_one_map | Figs. 6-11 | the same, timed until one robot holds the whole map | The
  comparision is based on the time required to generate a complete map of the environment
"""
SHORTEST, LONGEST = (f"{VAZQUEZ}, {r:g} m" for r in PAPER_COMM_RANGES_M[::2])
T99_ARMS = (f"{VAZQUEZ} T99", f"{YAMAUCHI} T99")
#: How each claim is judged (our thresholds: the paper gives plots without numbers):
#: ``id -> (rule, metric, first arm, second arm)``; cells are map x range x team size.
ONE_MAP = Means("<", seeds="common", summary=True, needs=Needs(0.9, partly_holds=1 / 3))
FASTER = replace(ONE_MAP, also=T99_ARMS)
VARIANCE = replace(ONE_MAP, relation=">", statistic="sd", min_seeds=2, needs=Needs(0.75))
ABOVE_7 = claims.RisesAbove(PAPER_YAMAUCHI_WORSE_ABOVE, within=("small",))
_RULES: dict[str, tuple[Rule, str, str, str]] = {
    "trend": (claims.Trend("diminishing"), "time", VAZQUEZ, YAMAUCHI),
    "faster": (FASTER, "time", VAZQUEZ, YAMAUCHI),
    "above_7": (ABOVE_7, "time", YAMAUCHI, ""),
    "variance": (VARIANCE, "time", YAMAUCHI, VAZQUEZ),
    "range_tradeoff": (claims.Ratio("<=", 1.25, seeds="common"), "ranges", SHORTEST, LONGEST),
    "range_gap": (claims.Trend("gap", needs=claims.SOME_WEAK), "ranges", SHORTEST, LONGEST),
    "incremental": (claims.Trend("ratio"), "time", VAZQUEZ, YAMAUCHI),
    "network": (claims.Level(">=", 0.95, 0.8, shown=(YAMAUCHI,)), "connected", VAZQUEZ, ""),
    "faster_one_map": (ONE_MAP, "one_map", VAZQUEZ, YAMAUCHI),
}
_LABELS = {"time": (T100, 0), "ranges": (T100, 0), "connected": ("share in one sub-network", 2)}
_LABELS["one_map"] = ("T100 of one robot (ticks)", 0)
CLAIMS = tuple(
    Claim(name, where, ours, said, metric, label, a, b, rule, digits)
    for name, where, ours, said in render.text_rows(_CLAIM_WORDS)
    for rule, metric, a, b in [_RULES[name]]
    for label, digits in [_LABELS[metric]]
)

_BRIDGE = (
    '§3.1 "A pair of robots impose mutual motion constraints only if they constitute a '
    "solitary bridge connection according to the current network topology and if the signal "
    'strength among the pair of robots falls below a threshold"'
)
_RETURN = (
    '§3.3.1 "When the connectivity behaviour is triggered the pair of robots that are out of the '
    'comfort zone in a bridge connection are encouraged to return"'
)
#: ``name | the sentence it reads | how it reads it | overrides | strategies`` (the
#: strategy's page lists each reading with its default).
INTERPRETATIONS = render.readings(f"""
both-replan-when-explored | §3.3 "When P(x, y) = f(x, y) ... the robot had arrived to the
  frontier. In this case the exploration algorithm its executed"; §2.1 (Yamauchi) "Each robot
  heads for its closest frontier" | both methods also choose a new frontier as soon as theirs
  is seen from afar (`replan_on_target_explored=true` for both; default false for both) |
  replan_on_target_explored=true | {VAZQUEZ}, {YAMAUCHI}
positions-every-tick | §4 "each broadcasts its sensorial information every half second" | half
  a second is one body length of travel (one tick), not two: `vazquez-network` broadcasts its
  position every tick (`position_period=1`; default 2) | position_period=1 | {VAZQUEZ}
maps-on-reconnection | §4 "The information arrives by multi hops to all the members of the
  team" | robots also exchange their whole maps when sub-networks join (`full` sharing, for
  both methods), as in Yamauchi's common map | scenario.sharing=full | *
every-bridge-constrains | {_BRIDGE} | every bridge neighbour constrains, stretched or not
  (`constrain_bridges=always`) | constrain_bridges=always | {VAZQUEZ}
convoy | §3.3.1 "When no frontier cells are found the robot computes a path to the current
  position of the other robot in the bridge connection" | the end nearer the root leads and
  the others follow it, a convoy (`no_frontier_rule=convoy`) | no_frontier_rule=convoy |
  {VAZQUEZ}
zone-around-partner | §3.3.1 "the search of frontier cells is constrained to the comfort zone
  between the pair of robots" | a stretched robot searches around the other robot only, not
  between the two (`zone_between_pair=False`) | zone_between_pair=false | {VAZQUEZ}
destination-zone | {_BRIDGE} | the destination must also lie in the comfort zone of the
  partner's destination (not in the paper) (`zone_includes_targets=True`) |
  zone_includes_targets=true | {VAZQUEZ}
discount-destinations | §3.2 "The utility expected by a robot considering moving to a
  particular frontier is lessened if there are any robots near that destination" | only other
  robots' announced destinations lessen the utility (Simmons)
  (`discount_around=destinations`) | discount_around=destinations | {VAZQUEZ}
utility-in-cells | §3.2, after Simmons: information gain minus cost | one unknown cell is
  worth one cell of travel, U in cells rather than ticks (`utility_unit=cells`) |
  utility_unit=cells | {VAZQUEZ}
replan-on-connectivity-change | Fig. 2 "When a change in behaviour is detected the robot will
  reevaluate its current plan" | only a change into or out of achieve-connectivity makes it
  re-plan (`replan_on_behaviour=connectivity`) | replan_on_behaviour=connectivity | {VAZQUEZ}
collision-replans | Fig. 2 "When a change in behaviour is detected the robot will reevaluate
  its current plan", read without §3.3.2 "The avoid-collision behaviour causes a re-evaluation of
  paths to the current goal" | entering or leaving avoid-collision chooses a new frontier too
  (`replan_on_behaviour=any`; default: it re-routes to the current goal) |
  replan_on_behaviour=any | {VAZQUEZ}
both-leave-on-break | {_RETURN} | when a bridge breaks, both robots leave their frontiers to
  the others as they go back (`broken_bridge_frontier=both-leave`; default: the lower id keeps
  its frontier and resumes it, as a stretched pair's lower id does) |
  broken_bridge_frontier=both-leave | {VAZQUEZ}
localisation-error | §4 "The position of each robot its assumed to be known with an error
  margin of +-5%" | each robot's estimate of where it is drifts by 5% of every step (standard
  deviation, `--odometry-noise 0.05`, never reset: they "start off relative positions to a
  known location"), for both methods alike; it senses, plans and shares at the estimate
  (default: perfect localisation) | scenario.odometry_noise=0.05 | *
""")


def _map_table(rows: Sequence[Row], out: Path) -> Lines:
    """The offices run: explorable area against the paper's, and a picture (walls black)."""
    from PIL import Image

    from mrexplore.grid import generate_map

    cells = {str(r["size"]): int(r.get("explorable_cells") or 0) for r in rows}
    body = []
    for size, spec in ((s, m) for s, m in SPEC_OF_SIZE.items() if s in cells):
        width, height = (int(v) for v in size.split("x"))
        free = ~generate_map("office", width, height, seed=MAP_SEED).occupied
        name = f"map_{spec.label}_{size}.png"
        Image.fromarray(np.uint8(255 * free)).resize((3 * width, 3 * height), 0).save(out / name)
        area = cells[size] * CELL_SIZE_M**2
        ours = f"office {size}, map_seed {MAP_SEED}: {cells[size]} cells = {area:.2f} m^2"
        off = f"{area / spec.paper_area_m2 - 1:+.1%}"
        body.append((f"{spec.label} ({spec.figures})", spec.paper_area_m2, ours, off, name))
    header = ["map", "paper area (m^2)", "ours", "ours vs paper", "picture"]
    return render.table(header, [(*row[:4], f"![{row[0]}]({row[4]})") for row in body])


#: Each curve of the figures: a method, or a method at one range.
CURVES = [f"{a}, {r:g} m" for a in (VAZQUEZ, YAMAUCHI) for r in PAPER_COMM_RANGES_M]
PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f")
COLOURS = dict(zip([VAZQUEZ, YAMAUCHI, *CURVES], PALETTE, strict=True))


QUICK_NOTE = (
    f"one office of {QUICK_MAP.size} cells (about half the paper's small one), ranges "
    f"{' and '.join(f'{r * CELL_SIZE_M:g} m' for r in QUICK_RANGES)}, "
    f"{' and '.join(map(str, QUICK_TEAM_SIZES))} robots, {len(QUICK_SEEDS)} seeds"
)


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Lines:
    """The report's sections, its figures written into ``out``."""
    rows = run_rows(stores)[0]
    values, arms, cells = run_values(rows), list(STRATEGIES), ["map", "range", "robots"]
    figure = partial(render.figure, out, xlabel="robots", ylabel=T100, colours=COLOURS)
    lines = render.blocks(
        f"The paper compares the time to a complete map of `{VAZQUEZ}` with Yamauchi's "
        f"`{YAMAUCHI}` (Figs. 6-11) and of `{VAZQUEZ}` across ranges (Fig. 12) in plots whose "
        "values are not in the text: its side is its settings and the results its text states.",
        render.settings_table(SETTINGS_ROWS),
        "## Environments",
        "The paper's Fig. 5 is not in our copy; our `office` generator (rooms on both sides of "
        "corridors, doors 10 cm, walls 5 cm) at the size whose explorable area is the paper's:",
        _map_table(rows, out),
        "## Figs. 6-11: time to complete",
        "T100 (ticks), mean (sd; 95% CI; n) over each method's seeds (`*`: a run did not "
        "complete and counts with its last tick, a lower bound). Paper: plots only.",
        render.arm_table(values["time"], arms, cells, flags=render.unfinished(values["complete"])),
        "Share of the time the team was one sub-network (not in the paper):",
        render.arm_table(values["connected"], arms, cells, digits=2),
        "## Fig. 12: vazquez-network under the three ranges, T100 (ticks)",
        render.arm_table(values["ranges"], CURVES, ["map", "robots"]),
        "## Figures",
    )
    for label, spec in MAPS.items():  # Figs. 6-11: a panel per range
        part = {c: by_arm for c, by_arm in values["time"].items() if c[0] == label}
        panels = render.panels_of(part, arms, lambda c: f"range {c[1]}")
        lines += figure(f"time_{label}.png", panels, title=f"{spec.figures}: {label} environment")
    panels = render.panels_of(values["ranges"], CURVES)  # a panel per map
    lines += figure("fig12.png", panels, title="Fig. 12: vazquez-network by range")
    panels = render.panels_of(by_range(values["connected"], arms), CURVES)
    return lines + figure(
        "connected.png", panels, title="One sub-network (not in the paper)", ylabel="share"
    )


REPRODUCTION = Reproduction(
    ID, TITLE, CITATION, experiments, report, tables, CLAIMS, INTERPRETATIONS, QUICK_NOTE
)
