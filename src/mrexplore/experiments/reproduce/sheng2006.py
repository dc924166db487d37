"""Reproduction of Sheng, Yang, Tan and Xi (2006), section 5.

W. Sheng, Q. Yang, J. Tan, N. Xi, "Distributed multi-robot coordination in area
exploration", *Robotics and Autonomous Systems* 54 (2006) 945-955.

Experiments (``mrexplore reproduce sheng2006 --out DIR [--quick]``), all on the
paper's 40 x 40 square with two obstacles (our generator ``sheng40``), sensor
range ``r_s = 4`` cells, sensing only on arrival (§2.1), robots starting next to
each other (§3), the paper's map synchronisation ``sheng-sync``:

============  ================================================  ======================
experiment    what                                              runs (full)
============  ================================================  ======================
fig11         mean group diameter, w3 = 0 vs 1.5, 4 robots      2 x 8 seeds
fig12_13_*    exploration time and total distance, random,      3 cases x 8 sizes x 6
              bidding w3 = 0, bidding w3 = 1.5, 1..8 robots
table4        map synchronisation bytes with / without          3 w3 x 2 x 20 seeds
              tracking (``sheng-sync`` / ``full``), 5 robots
fig17         time and distance vs r_c = 4..24 (step 4),        2 cases x 6 x 6 seeds
              w3 = 0 / 1.5, 5 robots
============  ================================================  ======================

Exploration time is ``T100``: runs end when every explorable cell is known
(``coverage_threshold = 1``), the paper's "all the robots stop when no new
frontier cell is available". The report (``report.md``) lists every setting and
every choice, the paper's numbers (Table 4; the text's statements for the
figures, which give no numbers) beside ours, the figures, and one verdict per
claim decided by the rules in :data:`RULES`.

The helpers (:func:`case_of`, :func:`collect`, :func:`sync_bytes`, the ``*_outcome``
rules) are pure functions of pyarrow tables and numbers.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from mrexplore.experiments.reproduce.base import (
    Outcome,
    Reproduction,
    Verdict,
    rules_header,
    verdict_section,
)
from mrexplore.experiments.reproduce.claims import fmt as _fmt
from mrexplore.experiments.stats import Summary, summarize_metric
from mrexplore.experiments.store import Store
from mrexplore.experiments.sweep import Sweep, sweep_from_dict

ID = "sheng2006"
TITLE = "Distributed multi-robot coordination in area exploration"
CITATION = (
    'W. Sheng, Q. Yang, J. Tan, N. Xi, "Distributed multi-robot coordination in area '
    'exploration", Robotics and Autonomous Systems 54 (2006) 945-955.'
)

# ----------------------------------------------------------------------- settings

#: §5: "a square of 40 by 40, with two obstacles in it" (geometry unknown: ours).
MAP = "sheng40"
#: §5: "the sensor range radius is 4 cell units (r_s = 4)".
SENSOR_RANGE = 4
#: §5: "the communication range is 16 cell units (r_c = 16)".
COMM_RANGE = 16
#: §5 Fig. 9: "When no nearness measure is concerned ... omega_3 = 0".
W3_WITHOUT = 0.0
#: §5 Fig. 10: "When the nearness measure is considered ... omega_3 = 1.5" (also
#: the strategy's default); used for every "with nearness" case.
W3_WITH = 1.5
#: §5 Table 4 cases (i), (ii), (iii): omega_3 = 0, 1.0, 2.0.
TABLE4_W3 = (0.0, 1.0, 2.0)
#: §5 Fig. 17: "4, 8, 12, 16, 20, and 24" (the text says "five values", lists six).
FIG17_RANGES = (4, 8, 12, 16, 20, 24)
#: §5 Figs. 12-13: "The number of robots used in the testing ranges from 1 to 8".
TEAM_SIZES = tuple(range(1, 9))

FIXED: dict[str, Any] = {
    "map": MAP,
    "sensor_range": SENSOR_RANGE,
    "comm_range": COMM_RANGE,
    "sensing": "arrival",  # §2.1: "When the robot is travelling, it does not carry out sensing"
    "start": "together",  # §3: "initial positions which are close to each other"
    "coverage_threshold": 1.0,  # the run ends when no explorable cell is unknown
    "sharing": "sheng-sync",  # §4, the paper's own map synchronisation
}

# ------------------------------------------------------------ the paper's numbers

#: Table 4: "The mean and standard deviation of the data exchange volume in bytes",
#: 5 robots, 20 runs per case; w3 -> (mean without tracking, mean with tracking,
#: sd without tracking, sd with tracking).
PAPER_TABLE4: dict[float, tuple[float, float, float, float]] = {
    0.0: (23034.0, 4893.0, 976.0, 393.0),  # case (i)
    1.0: (11855.0, 2126.0, 685.0, 130.0),  # case (ii)
    2.0: (7075.0, 812.0, 367.0, 82.0),  # case (iii)
}

#: Fig. 11 (no numbers in the text; the plot's values cannot be read from the text):
#: "by including the nearness measure in the coordination algorithm, the robots tend
#: to stay close to each other" -- 4 robots, 8 runs varying the start locations.
PAPER_FIG11 = (
    "with nearness (w3 = 1.5) the mean group diameter is smaller than without "
    "(w3 = 0) (read from the text; Fig. 11's values are not given in numbers)"
)
#: Fig. 12 (read from the text): "as the robot number increases, the total
#: exploration time decreases. The bidding algorithm effectively reduces the time
#: compared with a random exploration algorithm. When the nearness measure is
#: considered in the algorithm, the total exploration time is further reduced."
PAPER_FIG12 = (
    "time decreases as the team grows (1..8 robots); bidding < random; "
    "bidding with nearness < bidding without (read from the text)"
)
#: Fig. 13 (read from the text): "similar saving in total distance traveled is
#: achieved as the bidding algorithm is adopted and the nearness measure is used".
PAPER_FIG13 = "distance: bidding < random; with nearness < without (read from the text)"
#: Fig. 17 (read from the text): "for case 1, as the communication range increases,
#: the exploration time and traveled distance decrease ... the efficiency gain ...
#: is more significant when the communication range is below 16 ... For case 2 ...
#: the magnitude of the gain is not so significant compared to case 1."
PAPER_FIG17 = (
    "w3 = 0: time and distance fall as r_c grows, more below r_c = 16; "
    "w3 = 1.5: smaller gain (read from the text)"
)

# ------------------------------------------------------------------ message types

#: Map data exchanged when sub-networks merge, with tracking (``sheng-sync``, §4.2
#: steps 4-10): last-sequence-number tables, the missing deltas, their multicast.
SYNC_TYPES_WITH_TRACKING = ("seq_table", "map_sync", "map_multicast")
#: The same without tracking (``full``, §4's brute force): whole explored maps
#: both ways on a merge, then multicast to the old sub-networks.
SYNC_TYPES_WITHOUT_TRACKING = ("map_full", "map_multicast")
#: Map updates broadcast inside a sub-network after each sensing (§3.1); the same
#: cells under both mechanisms, not part of Table 4.
BROADCAST_TYPES = ("map_delta", "map_update")

# ------------------------------------------------------------------------ cases

CASE_RANDOM = "random"
CASE_WITHOUT = "bidding w3=0"
CASE_WITH = "bidding w3=1.5"
CASES = (CASE_RANDOM, CASE_WITHOUT, CASE_WITH)


def case_of(strategy: str, w3: float | None) -> str:
    """The paper's case of a run: ``random``, or ``bidding w3=<value>``.

    ``w3 = None`` (not set) is the strategy's default, :data:`W3_WITH`.

    >>> case_of("random-frontier", None), case_of("sheng-bidding", 0.0)
    ('random', 'bidding w3=0')
    >>> case_of("sheng-bidding", None), case_of("sheng-bidding", 2.0)
    ('bidding w3=1.5', 'bidding w3=2')
    """
    if strategy == "random-frontier":
        return CASE_RANDOM
    value = W3_WITH if w3 is None or (isinstance(w3, float) and math.isnan(w3)) else w3
    return f"bidding w3={float(value):g}"


def _rows(runs: pa.Table) -> list[dict[str, Any]]:
    """The usable rows (status not ``failed``) of a runs table, as dicts."""
    return [row for row in runs.to_pylist() if row.get("status") != "failed"]


def _number(value: Any) -> float:
    return math.nan if value is None else float(value)


Collected = dict[str, dict[Any, dict[int, float]]]
"""``case -> x value -> seed -> metric`` (nan where the metric is null)."""


def collect(runs: pa.Table, metric: str, x: str) -> Collected:
    """The metric of every usable run, by case, by value of column ``x`` and by seed.

    Failed runs are left out; a null metric (``T100`` never reached) is nan, so a
    summary counts it as missing.

    >>> t = pa.table({"strategy": ["sheng-bidding"] * 2, "param_w3": [0.0, 0.0],
    ...               "robots": [2, 2], "seed": [1, 2], "status": ["complete"] * 2,
    ...               "T100": [10, None]})
    >>> collect(t, "T100", "robots")
    {'bidding w3=0': {2: {1: 10.0, 2: nan}}}
    """
    out: Collected = {}
    for row in _rows(runs):
        case = case_of(str(row["strategy"]), row.get("param_w3"))
        out.setdefault(case, {}).setdefault(row[x], {})[int(row["seed"])] = _number(row[metric])
    return out


def summaries(collected: Collected) -> dict[str, dict[Any, Summary]]:
    """:func:`summarize_metric` of every case and x value."""
    return {
        case: {x: summarize_metric(list(by_seed.values())) for x, by_seed in by_x.items()}
        for case, by_x in collected.items()
    }


def paired(collected: Collected, a: str, b: str) -> dict[Any, Summary]:
    """Summary of ``A - B`` over the seeds both cases ran, at every x value both have.

    >>> c = {"a": {1: {1: 5.0, 2: 7.0}}, "b": {1: {1: 4.0, 2: 4.0, 3: 1.0}}}
    >>> s = paired(c, "a", "b")[1]
    >>> s.n, s.mean
    (2, 2.0)
    """
    out: dict[Any, Summary] = {}
    for x, a_by_seed in collected.get(a, {}).items():
        b_by_seed = collected.get(b, {}).get(x)
        if b_by_seed is None:
            continue
        seeds = sorted(set(a_by_seed) & set(b_by_seed))
        out[x] = summarize_metric([a_by_seed[s] - b_by_seed[s] for s in seeds])
    return out


def sync_bytes(row: Mapping[str, Any]) -> float:
    """Bytes of map synchronisation on merges in one run (Table 4's quantity).

    ``sheng-sync`` runs ("with tracking") count :data:`SYNC_TYPES_WITH_TRACKING`,
    ``full`` runs ("without tracking") :data:`SYNC_TYPES_WITHOUT_TRACKING`; a type
    the run never sent has no column or a null and counts 0.

    >>> sync_bytes({"sharing": "full", "bytes_by_type_map_full": 100,
    ...             "bytes_by_type_map_multicast": 50, "bytes_by_type_map_update": 9})
    150.0
    >>> sync_bytes({"sharing": "sheng-sync", "bytes_by_type_seq_table": 37,
    ...             "bytes_by_type_map_sync": None, "bytes_by_type_map_delta": 9})
    37.0
    """
    sharing = row.get("sharing") or row.get("sharing_in_force")
    types: tuple[str, ...]
    if sharing == "full":
        types = SYNC_TYPES_WITHOUT_TRACKING
    elif sharing == "sheng-sync":
        types = SYNC_TYPES_WITH_TRACKING
    else:
        raise ValueError(f"sync_bytes: sharing {sharing!r} is neither 'full' nor 'sheng-sync'")
    return float(sum(_number(row.get(f"bytes_by_type_{t}")) for t in types if _ok(row, t)))


def broadcast_bytes(row: Mapping[str, Any]) -> float:
    """Bytes of the map updates broadcast inside sub-networks (§3.1) in one run."""
    return float(
        sum(_number(row.get(f"bytes_by_type_{t}")) for t in BROADCAST_TYPES if _ok(row, t))
    )


def _ok(row: Mapping[str, Any], message_type: str) -> bool:
    value = row.get(f"bytes_by_type_{message_type}")
    return value is not None and not (isinstance(value, float) and math.isnan(value))


@dataclass(frozen=True)
class Table4Row:
    """Our Table 4 numbers for one w3: bytes per run, with and without tracking."""

    w3: float
    without: Summary
    with_: Summary
    broadcast: Summary
    partitions: Summary
    identical_pairs: int
    pairs: int

    @property
    def ratio(self) -> float:
        """Mean without tracking / mean with tracking."""
        return self.without.mean / self.with_.mean if self.with_.mean > 0 else math.inf


def table4_rows(runs: pa.Table) -> list[Table4Row]:
    """Table 4 from the ``table4`` runs: per w3, sync bytes of ``full`` and
    ``sheng-sync`` runs, broadcast bytes and partition events (``sheng-sync``),
    and how many seed pairs had identical trajectories (same ticks and distance).

    >>> t = pa.table({"strategy": ["sheng-bidding"] * 2, "param_w3": [0.0, 0.0],
    ...     "sharing": ["full", "sheng-sync"], "seed": [1, 1], "status": ["complete"] * 2,
    ...     "ticks": [9, 9], "total_distance": [5.0, 5.0], "partition_events": [2, 2],
    ...     "bytes_by_type_map_full": [300, None], "bytes_by_type_map_multicast": [100, 20],
    ...     "bytes_by_type_seq_table": [None, 37], "bytes_by_type_map_sync": [None, 43],
    ...     "bytes_by_type_map_update": [50, None], "bytes_by_type_map_delta": [None, 55]})
    >>> r = table4_rows(t)[0]
    >>> r.w3, r.without.mean, r.with_.mean, r.ratio, r.identical_pairs
    (0.0, 400.0, 100.0, 4.0, 1)
    """
    by_w3: dict[float, dict[str, dict[int, dict[str, Any]]]] = {}
    for row in _rows(runs):
        w3 = W3_WITH if row.get("param_w3") is None else float(row["param_w3"])
        sharing = row.get("sharing") or row.get("sharing_in_force")
        by_w3.setdefault(w3, {}).setdefault(str(sharing), {})[int(row["seed"])] = row
    out: list[Table4Row] = []
    for w3 in sorted(by_w3):
        full = by_w3[w3].get("full", {})
        sync = by_w3[w3].get("sheng-sync", {})
        common = sorted(set(full) & set(sync))
        identical = sum(
            full[s]["ticks"] == sync[s]["ticks"]
            and _number(full[s]["total_distance"]) == _number(sync[s]["total_distance"])
            for s in common
        )
        out.append(
            Table4Row(
                w3=w3,
                without=summarize_metric([sync_bytes(r) for r in full.values()]),
                with_=summarize_metric([sync_bytes(r) for r in sync.values()]),
                broadcast=summarize_metric([broadcast_bytes(r) for r in sync.values()]),
                partitions=summarize_metric(
                    [_number(r.get("partition_events")) for r in sync.values()]
                ),
                identical_pairs=int(identical),
                pairs=len(common),
            )
        )
    return out


# ------------------------------------------------------------------ verdict rules

RULES: dict[str, str] = {
    "fig11": (
        "paired over seeds, d = diameter(w3=1.5) - diameter(w3=0): reproduced if the mean "
        "of d < 0 and its 95% CI lies below 0; partly if only the mean of d < 0; "
        "not reproduced otherwise."
    ),
    "lower": (
        "A < B over team sizes (paired over seeds at each size): reproduced if mean(A) < "
        "mean(B) at every size and the paired 95% CI of A - B lies below 0 at at least half "
        "of them; partly if mean(A) < mean(B) at at least half of the sizes; not reproduced "
        "otherwise. Nearness is compared from 2 robots on (one robot has no neighbour, "
        "so w3 changes nothing)."
    ),
    "decreasing": (
        "time falls with team size: reproduced if in every case the mean falls at every "
        "step 1 -> 2 -> ... -> 8; partly if in every case the largest team's mean is below "
        "the smallest team's; not reproduced otherwise."
    ),
    "table4_tracking": (
        "reproduced if the mean with tracking is below the mean without tracking for every "
        "w3 and our ratio without/with is within a factor 2 of the paper's for every w3; "
        "partly if only the first holds; not reproduced otherwise (absolute bytes are not "
        "compared: map, obstacles and byte layout differ)."
    ),
    "table4_w3": (
        "reproduced if both columns (with and without tracking) fall strictly from w3 = 0 "
        "to 1 to 2; partly if both are lower at w3 = 2 than at w3 = 0, or one column falls "
        "strictly; not reproduced otherwise."
    ),
    "fig17_falls": (
        "w3 = 0: reproduced if, for both time and distance, the mean at the largest r_c is "
        "below the mean at the smallest and Spearman's rho between r_c and the mean is "
        "<= -0.6; partly if this holds for one of the two; not reproduced otherwise."
    ),
    "fig17_below16": (
        "w3 = 0, per cell of range: gain below 16 = (m(r_min) - m(16)) / (16 - r_min), gain "
        "above = (m(16) - m(r_max)) / (r_max - 16); reproduced if the gain below 16 is "
        "positive and larger than the gain above, for both time and distance; partly for "
        "one of the two; not reproduced otherwise."
    ),
    "fig17_nearness": (
        "gain m(r_min) - m(r_max): reproduced if it is smaller with w3 = 1.5 than with "
        "w3 = 0 for both time and distance (a gain at or below zero counts as smaller); "
        "partly for one of the two; not reproduced otherwise."
    ),
}


def fig11_outcome(difference: Summary) -> Outcome:
    """Rule ``fig11`` on the paired difference (with - without nearness).

    >>> fig11_outcome(summarize_metric([-3.0, -2.0, -4.0]))
    'reproduced'
    >>> fig11_outcome(summarize_metric([-3.0, 2.0, -4.0]))
    'partly'
    """
    if not difference.mean < 0:
        return "not reproduced"
    return "reproduced" if difference.ci_high < 0 else "partly"


def lower_outcome(differences: Mapping[Any, Summary]) -> Outcome:
    """Rule ``lower`` on paired differences ``A - B`` by team size.

    >>> s = summarize_metric
    >>> lower_outcome({1: s([-5.0, -6.0, -7.0]), 2: s([-1.0, 1.0, -3.0])})
    'reproduced'
    >>> lower_outcome({1: s([-5.0, -6.0]), 2: s([1.0, 1.0]), 3: s([3.0, 1.0])})
    'not reproduced'
    """
    if not differences:
        return "not reproduced"
    lower = sum(d.mean < 0 for d in differences.values())
    significant = sum(d.ci_high < 0 for d in differences.values())
    if lower == len(differences) and 2 * significant >= len(differences):
        return "reproduced"
    return "partly" if 2 * lower >= len(differences) else "not reproduced"


def decreasing_outcome(means_by_case: Mapping[str, Mapping[Any, float]]) -> Outcome:
    """Rule ``decreasing``: each case maps team size -> mean time.

    >>> decreasing_outcome({"a": {1: 9.0, 2: 5.0, 3: 4.0}, "b": {1: 8.0, 2: 6.0, 3: 7.0}})
    'partly'
    """
    monotone = overall = True
    for by_size in means_by_case.values():
        sizes = sorted(by_size)
        values = [by_size[n] for n in sizes]
        monotone &= all(b < a for a, b in itertools.pairwise(values))
        overall &= len(values) > 1 and values[-1] < values[0]
    if monotone and overall:
        return "reproduced"
    return "partly" if overall else "not reproduced"


def table4_tracking_outcome(rows: Sequence[Table4Row]) -> Outcome:
    """Rule ``table4_tracking``."""
    if not rows or not all(r.with_.mean < r.without.mean for r in rows):
        return "not reproduced"
    within = all(r.w3 in PAPER_TABLE4 and 0.5 <= r.ratio / _paper_ratio(r.w3) <= 2.0 for r in rows)
    return "reproduced" if within else "partly"


def _paper_ratio(w3: float) -> float:
    without, with_, _, _ = PAPER_TABLE4[w3]
    return without / with_


def table4_w3_outcome(rows: Sequence[Table4Row]) -> Outcome:
    """Rule ``table4_w3`` (rows in increasing w3)."""
    columns = [[r.with_.mean for r in rows], [r.without.mean for r in rows]]
    strictly = [all(b < a for a, b in itertools.pairwise(c)) for c in columns]
    if len(rows) >= 2 and all(strictly):
        return "reproduced"
    ends = len(rows) >= 2 and all(c[-1] < c[0] for c in columns)
    return "partly" if ends or (len(rows) >= 2 and any(strictly)) else "not reproduced"


def spearman(x: Sequence[float], y: Sequence[float]) -> float:
    """Spearman's rank correlation (average ranks for ties); 0 if either is constant.

    >>> spearman([4, 8, 12], [30.0, 20.0, 10.0])
    -1.0
    """
    from scipy.stats import rankdata

    rx, ry = rankdata(np.asarray(x, dtype=float)), rankdata(np.asarray(y, dtype=float))
    if rx.std() == 0 or ry.std() == 0:
        return 0.0
    return float(np.corrcoef(rx, ry)[0, 1])


def count_outcome(holds: int, total: int = 2) -> Outcome:
    """``total`` sub-claims (time, distance): all hold, some hold, none."""
    if holds >= total:
        return "reproduced"
    return "partly" if holds > 0 else "not reproduced"


def falls_with_range(means: Mapping[float, float]) -> bool:
    """Part of rule ``fig17_falls`` for one metric: ``r_c -> mean``.

    >>> falls_with_range({4: 300.0, 16: 250.0, 24: 240.0})
    True
    """
    ranges = sorted(means)
    values = [means[r] for r in ranges]
    return values[-1] < values[0] and spearman(ranges, values) <= -0.6


def gains_around(means: Mapping[float, float], pivot: float = COMM_RANGE) -> tuple[float, float]:
    """Per-cell-of-range gains below and above ``pivot`` (rule ``fig17_below16``).

    >>> gains_around({4: 400.0, 16: 280.0, 24: 272.0})
    (10.0, 1.0)
    """
    low, high = min(means), max(means)
    if pivot not in means or not low < pivot < high:
        return math.nan, math.nan
    below = (means[low] - means[pivot]) / (pivot - low)
    above = (means[pivot] - means[high]) / (high - pivot)
    return float(below), float(above)


def total_gain(means: Mapping[float, float]) -> float:
    """``m(r_min) - m(r_max)``."""
    return float(means[min(means)] - means[max(means)])


# ------------------------------------------------------------------------ sweeps


def _sweep(name: str, seeds: Iterable[int], fixed: dict[str, Any], grid: dict[str, Any]) -> Sweep:
    data = {
        "sweep": {"name": name, "seeds": list(seeds), "curves_every": 10},
        "fixed": {k: v for k, v in {**FIXED, **fixed}.items() if k not in grid},
        "grid": grid,
    }
    return sweep_from_dict(data, source=f"{ID}:{name}")


def sweeps(quick: bool) -> dict[str, Sweep]:
    """The experiments: full (the paper's run counts: 352 runs) or quick (28 runs:
    2 seeds for Figs. 11-13 at 2 and 5 robots, 1 seed for Table 4 and for Fig. 17 at
    r_c = 4, 16, 24)."""
    seeds_fig11 = range(1, 3) if quick else range(1, 9)
    seeds_fig12 = range(1, 3) if quick else range(1, 7)
    seeds_table4 = range(1, 2) if quick else range(1, 21)
    seeds_fig17 = range(1, 2) if quick else range(1, 7)
    sizes = [2, 5] if quick else list(TEAM_SIZES)
    ranges = [4, 16, 24] if quick else list(FIG17_RANGES)
    both_w3 = {"set": {"w3": [W3_WITHOUT, W3_WITH]}}
    bidding = {"strategy": "sheng-bidding"}
    return {
        "fig11": _sweep("fig11", seeds_fig11, {**bidding, "robots": 4}, dict(both_w3)),
        "fig12_13_random": _sweep(
            "fig12_13_random", seeds_fig12, {"strategy": "random-frontier"}, {"robots": sizes}
        ),
        "fig12_13_bidding": _sweep(
            "fig12_13_bidding", seeds_fig12, bidding, {"robots": sizes, **both_w3}
        ),
        "table4": _sweep(
            "table4",
            seeds_table4,
            {**bidding, "robots": 5},
            {"sharing": ["sheng-sync", "full"], "set": {"w3": list(TABLE4_W3)}},
        ),
        "fig17": _sweep(
            "fig17",
            seeds_fig17,
            {**bidding, "robots": 5},
            {"comm_range": ranges, **both_w3},
        ),
    }


# ------------------------------------------------------------------------ report

Lines = list[str]


def _cell(s: Summary, digits: int = 0) -> str:
    """``mean (sd; CI low..high; n)``."""
    text = f"{_fmt(s.mean, digits)} (sd {_fmt(s.sd, digits)}; "
    text += f"CI {_fmt(s.ci_low, digits)}..{_fmt(s.ci_high, digits)}; n {s.n}"
    return text + (f", {s.n_missing} missing)" if s.n_missing else ")")


def _diff_cell(s: Summary, digits: int = 0) -> str:
    """``mean [CI low, high] n`` of a paired difference."""
    return f"{_fmt(s.mean, digits)} [{_fmt(s.ci_low, digits)}, {_fmt(s.ci_high, digits)}] n {s.n}"


def _runs(store: Store) -> pa.Table:
    return store.query("SELECT * FROM runs ORDER BY run_id")


def _concat_rows(*tables: pa.Table) -> pa.Table:
    """Stack runs tables that may have different columns (missing ones are null).

    >>> a, b = pa.table({"x": [1]}), pa.table({"x": [2], "param_w3": [0.0]})
    >>> _concat_rows(a, b).to_pydict()
    {'x': [1, 2], 'param_w3': [None, 0.0]}
    """
    names = list(dict.fromkeys(name for table in tables for name in table.column_names))
    rows = [row for table in tables for row in table.to_pylist()]
    return pa.Table.from_pylist([{name: row.get(name) for name in names} for row in rows])


def _status_note(table: pa.Table) -> str:
    counts: dict[str, int] = {}
    for status in table.column("status").to_pylist() if table.num_rows else []:
        counts[str(status)] = counts.get(str(status), 0) + 1
    return ", ".join(f"{n} runs {status}" for status, n in sorted(counts.items())) or "no runs"


def _plot_data(
    stats: Mapping[str, Mapping[Any, Summary]], x: str, cases: Sequence[str]
) -> dict[str, list[Any]]:
    """Input of :func:`~mrexplore.viz.plots.plot_metric_vs`: one row per case and x."""
    data: dict[str, list[Any]] = {x: [], "case": [], "mean": [], "ci_low": [], "ci_high": []}
    for case in cases:
        for value, s in sorted(stats.get(case, {}).items()):
            for column, item in zip(data, (value, case, s.mean, s.ci_low, s.ci_high), strict=True):
                data[column].append(item)
    return data


def _means(stats: Mapping[str, Mapping[Any, Summary]]) -> dict[str, dict[Any, float]]:
    return {case: {x: s.mean for x, s in by_x.items()} for case, by_x in stats.items()}


def _series(means: Mapping[Any, float]) -> str:
    """``4:310, 8:290`` (x:mean in increasing x)."""
    return ", ".join(f"{x:g}:{_fmt(m)}" for x, m in sorted(means.items()))


def _fig11_section(store: Store, out: Path) -> tuple[Lines, list[Verdict]]:
    from mrexplore.viz.plots import plot_curves, plot_metric_vs

    runs = _runs(store)
    diameter = collect(runs, "group_diameter_mean", "robots")
    stats = summaries(diameter)
    difference = paired(diameter, CASE_WITH, CASE_WITHOUT).get(4, summarize_metric([]))
    lines = [
        "## Fig. 11: mean group diameter with and without nearness (4 robots)",
        "",
        f"Paper (Fig. 11, 8 runs): {PAPER_FIG11}.",
        "",
        f"Ours ({_status_note(runs)}). Group diameter = the largest Euclidean distance between "
        "two robots (cells), averaged over every tick of the run.",
        "",
        "| case | mean group diameter (cells): mean (sd; 95% CI; n) |",
        "|---|---|",
    ]
    for case in (CASE_WITHOUT, CASE_WITH):
        lines += [f"| {case} | {_cell(s, 1)} |" for _, s in sorted(stats.get(case, {}).items())]
    lines += [
        "",
        f"Paired difference w3=1.5 minus w3=0 (same seeds): {_diff_cell(difference, 2)} cells.",
        "",
    ]
    per_run: dict[str, list[Any]] = {
        "run (seed)": [],
        "case": [],
        "mean": [],
        "ci_low": [],
        "ci_high": [],
    }
    for case in (CASE_WITHOUT, CASE_WITH):
        for seed, value in sorted(diameter.get(case, {}).get(4, {}).items()):
            for column, item in zip(per_run, (seed, case, value, math.nan, math.nan), strict=True):
                per_run[column].append(item)
    if per_run["case"]:
        plot_metric_vs(
            per_run,
            out / "fig11_diameter.png",
            x="run (seed)",
            metric="group_diameter_mean",
            hue="case",
            title="Fig. 11: mean group diameter of each run, 4 robots",
        )
        usable = _rows(runs)
        cases = pa.table(
            {
                "run_id": [r["run_id"] for r in usable],
                "case": [case_of(r["strategy"], r.get("param_w3")) for r in usable],
            }
        )
        plot_curves(
            store.query("SELECT run_id, tick, group_diameter FROM curves"),
            cases,
            out / "fig11_diameter_curve.png",
            y="group_diameter",
            hue="case",
            title="group diameter over time, 4 robots (mean over runs, 95% CI)",
        )
        lines += [
            "![Fig. 11: mean group diameter per run](fig11_diameter.png)",
            "",
            "![group diameter over time](fig11_diameter_curve.png)",
            "",
        ]
    verdict = Verdict(
        "Fig. 11: with the nearness measure the robots stay closer together "
        "(smaller mean group diameter, 4 robots)",
        fig11_outcome(difference),
        f"mean diameter w3=0 {_fmt(_mean(stats, CASE_WITHOUT, 4), 1)} vs w3=1.5 "
        f"{_fmt(_mean(stats, CASE_WITH, 4), 1)} cells, paired difference "
        f"{_diff_cell(difference, 2)}; paper: smaller with nearness (no numbers given)",
    )
    return lines, [verdict]


def _fig12_13_section(
    random_store: Store, bidding_store: Store, out: Path
) -> tuple[Lines, list[Verdict]]:
    from mrexplore.viz.plots import plot_metric_vs

    runs = _concat_rows(_runs(random_store), _runs(bidding_store))
    time_runs = collect(runs, "T100", "robots")
    distance_runs = collect(runs, "total_distance", "robots")
    time_stats, distance_stats = summaries(time_runs), summaries(distance_runs)
    lines = [
        "## Figs. 12 and 13: exploration time and total distance, 1..8 robots",
        "",
        f"Paper (Fig. 12, 6 runs per point): {PAPER_FIG12}.",
        "",
        f"Paper (Fig. 13, 6 runs per point): {PAPER_FIG13}.",
        "",
        f"Ours ({_status_note(runs)}): exploration time = `T100`, the ticks until every "
        "explorable cell is known; distance = the team's total path length (cells). "
        "Mean (sd; 95% CI; n).",
        "",
    ]
    for label, stats in (
        ("Exploration time T100 (ticks)", time_stats),
        ("Total distance (cells)", distance_stats),
    ):
        lines += [f"**{label}**", "", "| robots | " + " | ".join(CASES) + " |"]
        lines.append("|---|" + "---|" * len(CASES))
        for n in sorted({n for by_size in stats.values() for n in by_size}):
            cells = [_cell(stats[c][n]) if n in stats.get(c, {}) else "-" for c in CASES]
            lines.append(f"| {n} | " + " | ".join(cells) + " |")
        lines.append("")
    comparisons = {
        "time: w3=0 - random": paired(time_runs, CASE_WITHOUT, CASE_RANDOM),
        "time: w3=1.5 - w3=0": _from_two(paired(time_runs, CASE_WITH, CASE_WITHOUT)),
        "distance: w3=0 - random": paired(distance_runs, CASE_WITHOUT, CASE_RANDOM),
        "distance: w3=1.5 - w3=0": _from_two(paired(distance_runs, CASE_WITH, CASE_WITHOUT)),
    }
    lines += [
        "Paired differences on the same seeds, mean [95% CI] n (negative = the first is lower):",
        "",
        "| robots | " + " | ".join(comparisons) + " |",
        "|---|" + "---|" * len(comparisons),
    ]
    for n in sorted({n for d in comparisons.values() for n in d}):
        cells = [_diff_cell(d[n]) if n in d else "-" for d in comparisons.values()]
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    lines.append("")
    for stats, metric, name, title in (
        (time_stats, "T100", "fig12_time.png", "Fig. 12: exploration time"),
        (distance_stats, "total_distance", "fig13_distance.png", "Fig. 13: total distance"),
    ):
        plot_metric_vs(
            _plot_data(stats, "robots", CASES),
            out / name,
            x="robots",
            metric=metric,
            hue="case",
            title=f"{title} (mean, error bars: 95% CI)",
        )
        lines += [f"![{title}]({name})", ""]
    time_means = _means(time_stats)
    verdicts = [
        Verdict(
            "Fig. 12: the exploration time decreases as the number of robots increases",
            decreasing_outcome(time_means),
            "; ".join(f"{c} {_series(time_means[c])}" for c in CASES if c in time_means)
            + " (team size:mean ticks)",
        )
    ]
    for claim, key in (
        ("Fig. 12: bidding (w3=0) explores faster than random frontiers", "time: w3=0 - random"),
        (
            "Fig. 12: the nearness measure further reduces the exploration time",
            "time: w3=1.5 - w3=0",
        ),
        ("Fig. 13: bidding (w3=0) travels less than random frontiers", "distance: w3=0 - random"),
        (
            "Fig. 13: the nearness measure further reduces the total distance",
            "distance: w3=1.5 - w3=0",
        ),
    ):
        differences = comparisons[key]
        verdicts.append(
            Verdict(claim, lower_outcome(differences), _lower_evidence(key, differences))
        )
    return lines, verdicts


def _table4_section(store: Store, out: Path) -> tuple[Lines, list[Verdict]]:
    from mrexplore.viz.plots import plot_bytes_by_type

    runs = _runs(store)
    rows = table4_rows(runs)
    with_types = ", ".join(f"`{t}`" for t in SYNC_TYPES_WITH_TRACKING)
    without_types = ", ".join(f"`{t}`" for t in SYNC_TYPES_WITHOUT_TRACKING)
    lines = [
        "## Table 4: map data exchanged with and without tracking (5 robots)",
        "",
        f"Ours ({_status_note(runs)}): bytes per run of the map data exchanged when "
        f"sub-networks merge: with tracking (`sheng-sync`) the message types {with_types}; "
        f"without tracking (`full`) {without_types}. The map updates broadcast inside a "
        "sub-network after each sensing (`map_delta`, `map_update`) carry the same cells in "
        "both and are not counted (the broadcast column shows them for reference).",
        "",
        "| case | w3 | paper without | paper with | paper ratio | ours without (`full`) "
        "| ours with (`sheng-sync`) | our ratio | broadcast | partition events "
        "| identical pairs |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for number, row in zip(("i", "ii", "iii"), rows, strict=False):
        paper = PAPER_TABLE4.get(row.w3)
        paper_cells = (
            [
                f"{_fmt(paper[0])} (sd {_fmt(paper[2])})",
                f"{_fmt(paper[1])} (sd {_fmt(paper[3])})",
                _fmt(paper[0] / paper[1], 1),
            ]
            if paper
            else ["-", "-", "-"]
        )
        lines.append(
            f"| {number} | {row.w3:g} | "
            + " | ".join(paper_cells)
            + f" | {_cell(row.without)} | {_cell(row.with_)} | {_fmt(row.ratio, 1)} "
            f"| {_fmt(row.broadcast.mean)} | {_fmt(row.partitions.mean, 1)} "
            f"| {row.identical_pairs}/{row.pairs} |"
        )
    lines += [
        "",
        "Paper: Table 4, mean (sd) bytes over 20 runs per case; ratio = without / with. "
        "Ours: mean (sd; 95% CI; n). *Partition events*: mean per `sheng-sync` run. "
        "*Identical pairs*: seeds whose `full` and `sheng-sync` runs had the same length and "
        "distance, i.e. the same exploration counted two ways, as in the paper, which "
        "measured both volumes in the same runs.",
        "",
    ]
    if rows:
        bars: dict[str, dict[str, float]] = {}
        for row in rows:
            bars[f"w3={row.w3:g} without"] = _mean_bytes_by_type(
                runs, row.w3, "full", SYNC_TYPES_WITHOUT_TRACKING
            )
            bars[f"w3={row.w3:g} with"] = _mean_bytes_by_type(
                runs, row.w3, "sheng-sync", SYNC_TYPES_WITH_TRACKING
            )
        plot_bytes_by_type(
            bars,
            out / "table4_bytes.png",
            title="Table 4: map synchronisation bytes per run (mean), 5 robots",
            xlabel="w3, with or without tracking",
        )
        lines += ["![Table 4: bytes by message type](table4_bytes.png)", ""]
    verdicts = [
        Verdict(
            "Table 4: map update tracking reduces the map data exchanged, for w3 = 0, 1 and 2",
            table4_tracking_outcome(rows),
            "; ".join(
                f"w3={r.w3:g}: {_fmt(r.without.mean)} without vs {_fmt(r.with_.mean)} with "
                f"bytes, ratio {_fmt(r.ratio, 1)} (paper {_fmt(_paper_ratio(r.w3), 1)})"
                for r in rows
            ),
        ),
        Verdict(
            "Table 4: the more weight on nearness (w3 = 0, 1, 2), the less map data is exchanged",
            table4_w3_outcome(rows),
            "with tracking "
            + ", ".join(_fmt(r.with_.mean) for r in rows)
            + "; without "
            + ", ".join(_fmt(r.without.mean) for r in rows)
            + " bytes (paper 4 893, 2 126, 812; 23 034, 11 855, 7 075); largest w3 vs w3=0: "
            + _change(rows)
            + "; partition events "
            + ", ".join(_fmt(r.partitions.mean, 1) for r in rows),
        ),
    ]
    return lines, verdicts


def _fig17_section(store: Store, out: Path) -> tuple[Lines, list[Verdict]]:
    from mrexplore.viz.plots import plot_metric_vs

    runs = _runs(store)
    cases = (CASE_WITHOUT, CASE_WITH)
    stats = {
        "time": summaries(collect(runs, "T100", "comm_range")),
        "distance": summaries(collect(runs, "total_distance", "comm_range")),
    }
    lines = [
        "## Fig. 17: exploration time and distance vs communication range (5 robots)",
        "",
        f"Paper (Fig. 17, 6 runs per point): {PAPER_FIG17}.",
        "",
        f"Ours ({_status_note(runs)}), time = `T100` (ticks), distance = total (cells); "
        "mean (sd; 95% CI; n):",
        "",
        "| r_c | time w3=0 | time w3=1.5 | distance w3=0 | distance w3=1.5 |",
        "|---|---|---|---|---|",
    ]
    ranges = sorted({rc for by_case in stats.values() for c in by_case.values() for rc in c})
    for rc in ranges:
        cells = [
            _cell(by_case[c][rc]) if rc in by_case.get(c, {}) else "-"
            for by_case in stats.values()
            for c in cases
        ]
        lines.append(f"| {rc:g} | " + " | ".join(cells) + " |")
    lines.append("")
    for metric, column, name, title in (
        ("time", "T100", "fig17a_time.png", "Fig. 17(a): exploration time vs r_c"),
        ("distance", "total_distance", "fig17b_distance.png", "Fig. 17(b): distance vs r_c"),
    ):
        plot_metric_vs(
            _plot_data(stats[metric], "comm_range", cases),
            out / name,
            x="comm_range",
            metric=column,
            hue="case",
            title=f"{title}, 5 robots (mean, error bars: 95% CI)",
        )
        lines += [f"![{title}]({name})", ""]
    means = {metric: _means(by_case) for metric, by_case in stats.items()}
    without = {metric: means[metric].get(CASE_WITHOUT, {}) for metric in means}
    with_ = {metric: means[metric].get(CASE_WITH, {}) for metric in means}
    falls = sum(bool(m) and falls_with_range(m) for m in without.values())
    gains = {
        metric: gains_around(m) if m else (math.nan, math.nan) for metric, m in without.items()
    }
    larger_below = sum(below > 0 and below > above for below, above in gains.values())
    total = {
        metric: (total_gain(with_[metric]), total_gain(without[metric]))
        for metric in means
        if with_[metric] and without[metric]
    }
    verdicts = [
        Verdict(
            "Fig. 17: without nearness, exploration time and distance fall as r_c grows",
            count_outcome(falls),
            "; ".join(
                f"{metric} {_series(m)} (Spearman rho {_fmt(_rho(m), 2)})"
                for metric, m in without.items()
            )
            + " (r_c:mean)",
        ),
        Verdict(
            "Fig. 17: without nearness, the gain from a larger r_c is larger below r_c = 16",
            count_outcome(larger_below),
            "; ".join(
                f"{metric}: {_fmt(below, 2)} per cell of r_c below 16 vs {_fmt(above, 2)} above"
                for metric, (below, above) in gains.items()
            ),
        ),
        Verdict(
            "Fig. 17: with nearness, the gain from a larger r_c is smaller than without",
            count_outcome(sum(w < wo for w, wo in total.values())),
            "; ".join(
                f"{metric}: gain from the smallest to the largest r_c {_fmt(w)} with nearness "
                f"vs {_fmt(wo)} without"
                for metric, (w, wo) in total.items()
            ),
        ),
    ]
    return lines, verdicts


def _change(rows: Sequence[Table4Row]) -> str:
    """Relative change of both Table 4 columns from the first to the last w3.

    >>> s = summarize_metric
    >>> r = [Table4Row(0.0, s([200.0]), s([100.0]), s([1.0]), s([1.0]), 1, 1),
    ...      Table4Row(2.0, s([150.0]), s([97.0]), s([1.0]), s([1.0]), 1, 1)]
    >>> _change(r)
    '-3% with, -25% without tracking'
    """
    if len(rows) < 2:
        return "-"
    first, last = rows[0], rows[-1]
    with_ = 100 * (last.with_.mean / first.with_.mean - 1)
    without = 100 * (last.without.mean / first.without.mean - 1)
    return f"{with_:+.0f}% with, {without:+.0f}% without tracking"


def _rho(means: Mapping[float, float]) -> float:
    ranges = sorted(means)
    return spearman(ranges, [means[r] for r in ranges]) if len(ranges) > 1 else math.nan


def _from_two(differences: dict[Any, Summary]) -> dict[Any, Summary]:
    """Team sizes of 2 or more (with one robot, w3 changes nothing)."""
    return {n: s for n, s in differences.items() if n >= 2}


def _mean(stats: Mapping[str, Mapping[Any, Summary]], case: str, x: Any) -> float:
    s = stats.get(case, {}).get(x)
    return s.mean if s is not None else math.nan


def _lower_evidence(key: str, differences: Mapping[Any, Summary]) -> str:
    lower = sum(d.mean < 0 for d in differences.values())
    significant = sum(d.ci_high < 0 for d in differences.values())
    detail = ", ".join(f"{n}:{_fmt(d.mean)}" for n, d in sorted(differences.items()))
    return (
        f"paired mean {key} by team size {detail}; lower at {lower}/{len(differences)} "
        f"sizes, 95% CI below 0 at {significant}/{len(differences)}"
    )


def _mean_bytes_by_type(
    runs: pa.Table, w3: float, sharing: str, types: Sequence[str]
) -> dict[str, float]:
    """Mean bytes per run of each of ``types`` in the runs of one w3 and mechanism."""
    rows = [
        r for r in _rows(runs) if r.get("sharing") == sharing and _number(r.get("param_w3")) == w3
    ]
    out: dict[str, float] = {}
    for message_type in types:
        values = [_number(r.get(f"bytes_by_type_{message_type}")) for r in rows]
        out[message_type] = float(np.mean(np.nan_to_num(values))) if values else 0.0
    return out


def _settings_section(quick: bool) -> Lines:
    seeds = "2 seeds (1-2)" if quick else ""
    rows = [
        (
            "map",
            "40 x 40 square with two obstacles (their shape is not given)",
            f"`{MAP}`: 40 x 40 free square in a wall ring, obstacles of 8 x 12 and 12 x 6 "
            "cells (our choice, `SHENG40_OBSTACLES`)",
        ),
        ("sensor range r_s", "4 cell units", "4 cells, line of sight"),
        (
            "communication range r_c",
            "16 cell units (Fig. 17: 4..24)",
            "16 cells, multi-hop sub-networks, walls do not block (Fig. 17: "
            + ("4, 16, 24" if quick else "4, 8, 12, 16, 20, 24")
            + ")",
        ),
        ("sensing", "not while travelling (§2.1)", "`sensing = arrival`"),
        (
            "start",
            "close to each other (§3); Fig. 11 varies the start locations, Table 4 the start times",
            "`start = together`: adjacent cells at a random place drawn from the seed; the "
            "seed varies the start place (we have no per-robot start times)",
        ),
        (
            "time",
            "seconds (Java, one computer per robot; t_bid = 1.5 s)",
            "ticks: 1 cell of path per tick, t_bid = 1 tick, latency 1 tick per hop",
        ),
        (
            "exploration time",
            "total exploration time",
            "`T100`: ticks until every explorable cell is known (runs end there, "
            "`coverage_threshold = 1`)",
        ),
        ("omega1, omega2", "1.0, 1.0", "1.0, 1.0 (defaults)"),
        ("omega3 without / with nearness", "0 / 1.5 (§5, Figs. 9-10)", "0 / 1.5"),
        ("alpha (eq. 1)", "positive, < 1 (value not given)", "0.5 (strategy default)"),
        ("map sharing", "§4 synchronisation", "`sheng-sync` (Table 4: also `full`)"),
        ("Fig. 11", "4 robots, 8 runs", "4 robots, " + (seeds or "8 seeds (1-8)")),
        (
            "Figs. 12-13",
            "1..8 robots, 6 runs each, 3 cases",
            f"2 and 5 robots, {seeds}" if quick else "1..8 robots, 6 seeds (1-6), 3 cases",
        ),
        (
            "Table 4",
            "5 robots, w3 = 0, 1, 2, 20 runs",
            "5 robots, w3 = 0, 1, 2, "
            + ("1 seed (1)" if quick else "20 seeds (1-20)")
            + "; with tracking = `sheng-sync`, without = `full`, same seeds",
        ),
        (
            "Fig. 17",
            "5 robots, 6 runs, without / with nearness",
            "5 robots, w3 = 0 / 1.5, " + ("1 seed (1)" if quick else "6 seeds (1-6)"),
        ),
    ]
    lines = ["## Settings", "", "| setting | paper (§5) | ours |", "|---|---|---|"]
    lines += [f"| {name} | {paper} | {ours} |" for name, paper, ours in rows]
    lines += [
        "",
        "Choices where the paper is silent or our world differs:",
        "",
        "- *Exploration time* is `T100`: the paper's robots \"stop when no new frontier cell "
        'is available" (§3.3), i.e. when the reachable area is fully known, so every run '
        "goes to full coverage. A run that did not complete would count as missing (the "
        "tables say how many).",
        "- *With nearness* is w3 = 1.5, the value §5 gives for the nearness case (Fig. 10); "
        "the paper does not repeat it for Figs. 11-13 and 17.",
        "- *Random baseline* (`random-frontier`): each robot draws a uniformly random "
        "reachable frontier cell and keeps it until it arrives; it shares maps with "
        "`sheng-sync` like the bidding robots.",
        "- *Without tracking* is our `full` sharing, §4's brute force: \"robot R_a sends all "
        "the explored map data to robot R_b and vice versa. After that, R_a and R_b send the "
        'received map data, through multi-cast, to all the other robots". The paper measured '
        'both volumes in the same runs (the "without" one as what would have been sent); we '
        "run both mechanisms on the same seeds. With unlimited bandwidth both leave every "
        "robot with the same map, so most pairs explore identically (Table 4 says how many).",
        "- *Map data bytes* (Table 4) are the synchronisation messages sent when "
        "sub-networks merge. The paper's smallest volume (812 bytes, case iii, with "
        "tracking) is about half a byte per cell of the 1600-cell map, so it cannot include "
        "the map updates broadcast inside a sub-network after each sensing, which are the "
        "same with and without tracking. The last-sequence-number tables count as tracking "
        "overhead.",
        "- *Byte model*: header 7 bytes, a cell 5 bytes (2 x uint16 + value), a delta "
        "header 6 bytes, a sequence-number entry 6 bytes. The paper gives no layout, so its "
        "absolute bytes are not comparable with ours; ratios are.",
        '- *Deviation*: the paper\'s figures draw "the deviation" as bars; ours draw 95% '
        "confidence intervals of the mean (Student's t), and the tables give the sd too.",
        "- *Figures 11-13 and 17* have no numbers in the paper's text; their claims are "
        "typed in from the text (`PAPER_FIG*` in the module) and compared qualitatively.",
        "",
    ]
    return lines


def report(stores: Mapping[str, Store], out: Path, quick: bool) -> Path:
    """Write ``out/report.md`` and its figures from the experiments' stores."""
    out = Path(out)
    lines: Lines = [f"# Reproduction: Sheng et al. (2006), {TITLE}", ""]
    if quick:
        lines += [
            "> **Quick run** (`--quick`: 2 seeds for Figs. 11-13 and 1 for Table 4 and Fig. 17, "
            "team sizes 2 and 5, r_c = 4, 16, 24): its verdicts are indicative only. Run "
            "without `--quick` for the paper's run counts.",
            "",
        ]
    lines += [f"Citation: {CITATION}", "", f"Written {time.strftime('%Y-%m-%d %H:%M')}.", ""]
    lines += _settings_section(quick)
    verdicts: list[Verdict] = []
    for section, verdict_list in (
        _fig11_section(stores["fig11"], out),
        _fig12_13_section(stores["fig12_13_random"], stores["fig12_13_bidding"], out),
        _table4_section(stores["table4"], out),
        _fig17_section(stores["fig17"], out),
    ):
        lines += section
        verdicts += verdict_list
    lines += rules_header(RULES)
    lines += [
        "",
        "Which rule decides which claim: Fig. 11 `fig11`; Fig. 12 team size `decreasing`; "
        "the orderings of Figs. 12-13 `lower`; Table 4 `table4_tracking`, `table4_w3`; "
        "Fig. 17 `fig17_falls`, `fig17_below16`, `fig17_nearness`, in this order.",
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
