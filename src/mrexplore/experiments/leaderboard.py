"""The leaderboard of a benchmark suite: ``mrexplore suite report DIR``.

:func:`write_leaderboard` turns the ``runs`` table of a suite's results folder (one
row per run, tagged with ``suite``, ``suite_version``, ``suite_hash`` and ``regime``
by :mod:`mrexplore.experiments.suite`) into ``leaderboard.md``, ``leaderboard.html``
(one self-contained page whose tables sort by a click on a column header),
``leaderboard.png`` (the critical-difference diagrams of every regime, stacked) and
``img/*.png`` (per regime, the critical-difference diagram and time against bytes).

Ranks and tests follow Demšar, "Statistical comparisons of classifiers over
multiple data sets", JMLR 7:1-30, 2006 (§3.2.2: Friedman test, Nemenyi test and the
critical-difference diagram), with "data set" read as *instance* and "classifier"
as *strategy*:

=========================  ==================  =======================================
Demšar's symbol            name in code        meaning
=========================  ==================  =======================================
``N``                      ``n_instances``     instances (map, team size, seed) of a
                                               regime on which every strategy ran
``k``                      ``n_strategies``    strategies of the regime
``r_i^j``                  ``ranks[i, j]``     rank of strategy ``j`` on instance ``i``
                                               by T99 ascending (1 = fastest)
``R_j``                    ``mean_ranks[j]``   ``(1/N) sum_i r_i^j``
``chi2_F``                 ``statistic``       ``12N/(k(k+1)) [sum_j R_j^2 - k(k+1)^2/4]``,
                                               chi-square with ``k - 1`` degrees of freedom
``q_alpha``                :func:`nemenyi_q`   studentized range quantile
                                               ``q(1 - alpha; k, inf) / sqrt(2)``
``CD``                     :func:`critical_difference`
                                               ``q_alpha sqrt(k(k+1)/(6N))``
``alpha``                  ``alpha``           0.05
=========================  ==================  =======================================

Choices, stated once:

* A run that did not reach 99% coverage (``T99`` null: ``max_ticks``, ``stalled``,
  ``failed``) is not dropped: it ranks after every run of the instance that reached
  it, and such runs tie with each other (fractional ranking, the average of the
  ranks they span, ``scipy.stats.rankdata``).
* An instance counts only when every strategy of the regime has a row for it (a
  results folder still being filled is reported, not guessed at); every statistic
  of a regime is over those instances, so the strategies are compared on the same
  runs. Several rows for one strategy and instance (a re-run) keep one: a non-failed
  one first, then the smallest ``run_id``.
* The Friedman statistic is Demšar's textbook ``chi2_F``, without correction for
  ties. ``scipy.stats.friedmanchisquare`` divides it by
  ``C = 1 - sum_i sum_t (t^3 - t) / (N k (k^2 - 1))`` (``t`` the sizes of the tie
  groups of instance ``i``), which is at most 1: the uncorrected statistic is the
  smaller, its p value the larger (conservative). :class:`Friedman` carries ``C``.
* The critical-difference diagram is drawn whenever the Friedman test is given; its
  groups are the maximal runs of consecutive strategies (in mean-rank order) whose
  mean ranks differ by less than ``CD``. When Friedman does not reject equal ranks
  the page says so: the groups are then descriptive only.
* Against the baseline, a strategy *wins* an instance when its T99 is lower; a run
  without T99 is infinitely slow, two such runs tie, and a tie counts half.

Drawing: the figures are :func:`mrexplore.viz.leaderboard.draw_cd_diagrams` and
:func:`~mrexplore.viz.leaderboard.draw_pareto` (only ``viz`` imports matplotlib), imported
when :func:`write_leaderboard` draws.
"""

from __future__ import annotations

import base64
import html
import logging
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyarrow as pa
import pyarrow.compute as pc
from scipy import stats as scipy_stats

from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.report import _escape, _slug, _table, format_number
from mrexplore.experiments.stats import CONFIDENCE, Summary, summarize_metric

logger = logging.getLogger(__name__)

FloatArray = npt.NDArray[np.float64]

#: Columns the leaderboard reads; a table without one of them is refused.
REQUIRED_COLUMNS: tuple[str, ...] = (
    "suite",
    "suite_version",
    "suite_hash",
    "regime",
    "strategy",
    "map",
    "robots",
    "seed",
    "status",
    "T99",
)

#: The columns that name an instance within a regime.
INSTANCE_COLUMNS: tuple[str, ...] = ("map", "robots", "seed")

#: Run statuses counted in the header, in this order (others follow, sorted).
STATUSES: tuple[str, ...] = ("complete", "max_ticks", "stalled", "failed")

#: Significance level of the Friedman and Nemenyi tests.
ALPHA = 0.05

#: Metrics summarized per strategy besides T99: (column, header).
SUMMARY_METRICS: tuple[tuple[str, str], ...] = (
    ("total_distance", "distance (cells)"),
    ("bytes_total", "bytes"),
    ("wtv_8_final", "final WTV, 8 regions (ticks²)"),
)

_MISSING = "—"


# ------------------------------------------------------------------ pure statistics


def rank_instances(t99: FloatArray) -> FloatArray:
    """Rank the strategies (columns) within each instance (row) by T99, 1 = fastest.

    ``nan`` (T99 never reached) ranks after every finite value; equal values,
    ``nan`` included, share the average of the ranks they span.

    >>> rank_instances(np.array([[30.0, 10.0, np.nan, np.nan], [5.0, 5.0, 7.0, 1.0]]))
    array([[2. , 1. , 3.5, 3.5],
           [2.5, 2.5, 4. , 1. ]])
    """
    values = np.asarray(t99, dtype=np.float64)
    if values.ndim != 2:
        raise MrexploreInputError(
            f"T99 matrix must be 2-D (instances x strategies), got {values.ndim}-D"
        )
    if values.size == 0:
        return np.zeros(values.shape)
    ranks: FloatArray = scipy_stats.rankdata(np.where(np.isnan(values), np.inf, values), axis=1)
    return ranks.astype(np.float64)


def mean_ranks(ranks: FloatArray) -> FloatArray:
    """``R_j = (1/N) sum_i r_i^j``: each strategy's mean rank over the instances.

    >>> mean_ranks(np.array([[1.0, 2.0], [2.0, 1.0], [1.0, 2.0]])).round(3)
    array([1.333, 1.667])
    """
    values = np.asarray(ranks, dtype=np.float64)
    if values.shape[0] == 0:
        return np.full(values.shape[1], np.nan)
    means: FloatArray = values.mean(axis=0)
    return means


def win_rate(t99: FloatArray, baseline_t99: FloatArray) -> float:
    """Share of instances where a strategy's T99 is lower than the baseline's.

    Paired by position. ``nan`` (never reached) is infinitely slow; two ``nan`` tie;
    a tie counts half. ``nan`` when there is no instance.

    >>> win_rate(np.array([1.0, 5.0, np.nan, np.nan]), np.array([2.0, 5.0, 3.0, np.nan]))
    0.5
    """
    a = np.where(np.isnan(t99), np.inf, np.asarray(t99, dtype=np.float64))
    b = np.where(np.isnan(baseline_t99), np.inf, np.asarray(baseline_t99, dtype=np.float64))
    if a.shape != b.shape:
        raise MrexploreInputError(f"win rate needs paired values, got {a.shape} and {b.shape}")
    if a.size == 0:
        return math.nan
    wins = np.count_nonzero(a < b) + 0.5 * np.count_nonzero(a == b)
    return float(wins / a.size)


def paired_difference(t99: FloatArray, baseline_t99: FloatArray) -> Summary:
    """Mean of ``T99 - T99_baseline`` and its 95% t CI over instances where both reached T99.

    >>> s = paired_difference(np.array([10.0, 12.0, np.nan]), np.array([11.0, 15.0, 9.0]))
    >>> s.n, s.mean, s.n_missing
    (2, -2.0, 1)
    """
    return summarize_metric(np.asarray(t99, dtype=np.float64) - np.asarray(baseline_t99))


@dataclass(frozen=True)
class Friedman:
    """Friedman's test of equal mean ranks (Demšar 2006, §3.2.2).

    Attributes:
        statistic: ``chi2_F = 12N/(k(k+1)) [sum_j R_j^2 - k(k+1)^2/4]``, no tie
            correction.
        df: ``k - 1``.
        p_value: ``P(chi2(k-1) >= statistic)``.
        n_instances, n_strategies: ``N`` and ``k``.
        tie_factor: ``C = 1 - sum (t^3 - t) / (N k (k^2 - 1))``; scipy's
            ``friedmanchisquare`` reports ``statistic / C``.
    """

    statistic: float
    df: int
    p_value: float
    n_instances: int
    n_strategies: int
    tie_factor: float

    @property
    def rejects(self) -> bool:
        """Whether equal mean ranks are rejected at :data:`ALPHA`."""
        return self.p_value < ALPHA


def friedman(ranks: FloatArray) -> Friedman:
    """Friedman's test over an ``N x k`` rank matrix (rows: instances, columns: strategies).

    Raises:
        MrexploreInputError: fewer than 3 strategies or 2 instances (the test is
            then not defined in Demšar's sense: two strategies take a sign test).

    >>> f = friedman(rank_instances(np.array([[1.0, 2, 3], [1, 3, 2], [1, 2, 3], [2, 1, 3]])))
    >>> round(f.statistic, 3), f.df, round(f.p_value, 4)
    (4.5, 2, 0.1054)
    """
    values = np.asarray(ranks, dtype=np.float64)
    n, k = values.shape
    if k < 3 or n < 2:
        raise MrexploreInputError(
            f"the Friedman test needs at least 3 strategies and 2 instances, got {k} and {n}"
        )
    r = values.mean(axis=0)
    statistic = 12 * n / (k * (k + 1)) * (float(np.sum(r**2)) - k * (k + 1) ** 2 / 4)
    statistic = max(statistic, 0.0)  # rounding can leave -1e-15 when every rank ties
    ties = 0.0
    for row in values:
        _, counts = np.unique(row, return_counts=True)
        ties += float(np.sum(counts.astype(np.float64) ** 3 - counts))
    tie_factor = 1 - ties / (n * k * (k * k - 1))
    p_value = float(scipy_stats.chi2.sf(statistic, k - 1))
    return Friedman(statistic, k - 1, p_value, n, k, tie_factor)


def nemenyi_q(k: int, alpha: float = ALPHA) -> float:
    """Nemenyi's ``q_alpha`` for ``k`` strategies: ``q(1 - alpha; k, inf) / sqrt(2)``.

    ``q`` is the studentized range quantile (``scipy.stats.studentized_range``) with
    infinite degrees of freedom; Demšar's Table 5(a) gives 3.164 for ``k = 10``.

    >>> round(nemenyi_q(10), 3), round(nemenyi_q(2), 3)
    (3.164, 1.96)
    """
    if k < 2:
        raise MrexploreInputError(f"the Nemenyi test needs at least 2 strategies, got {k}")
    if not 0 < alpha < 1:
        raise MrexploreInputError(f"alpha must be in (0, 1), got {alpha}")
    return float(scipy_stats.studentized_range.ppf(1 - alpha, k, np.inf)) / math.sqrt(2)


def critical_difference(k: int, n: int, alpha: float = ALPHA) -> float:
    """Nemenyi's critical difference ``CD = q_alpha sqrt(k(k+1)/(6N))`` of mean ranks.

    >>> round(critical_difference(4, 12), 3)
    1.354
    """
    if n < 1:
        raise MrexploreInputError(f"the critical difference needs at least 1 instance, got {n}")
    return nemenyi_q(k, alpha) * math.sqrt(k * (k + 1) / (6 * n))


def cd_groups(mean_rank: Mapping[str, float], cd: float) -> list[tuple[str, ...]]:
    """Groups of strategies not told apart: the bars of the critical-difference diagram.

    In mean-rank order (ties by name), each group is a run of consecutive strategies
    whose mean ranks differ by less than ``cd``, as long as it can be, of two or
    more strategies, and not contained in another group. Groups come in order of
    their best strategy.

    >>> cd_groups({"a": 1.0, "b": 1.5, "c": 2.2, "d": 3.9}, 1.0)
    [('a', 'b'), ('b', 'c')]
    """
    order = sorted(mean_rank, key=lambda name: (mean_rank[name], name))
    ranks = [mean_rank[name] for name in order]
    groups: list[tuple[str, ...]] = []
    last_end = 0
    for start in range(len(order)):
        end = start
        while end + 1 < len(order) and ranks[end + 1] - ranks[start] < cd:
            end += 1
        if end > start and end > last_end:
            groups.append(tuple(order[start : end + 1]))
            last_end = end
    return groups


def pareto_front(points: Mapping[str, tuple[float, float]]) -> list[str]:
    """The names whose point ``(bytes, time)`` no other point beats in both, sorted by bytes.

    A point is dominated when another has both a lower first and a lower second
    coordinate; points with a nan coordinate take no part.

    >>> pareto_front({"a": (0.0, 90.0), "b": (10.0, 50.0), "c": (20.0, 60.0)})
    ['a', 'b']
    """
    finite = {n: p for n, p in points.items() if math.isfinite(p[0]) and math.isfinite(p[1])}
    front = [
        name
        for name, (x, y) in finite.items()
        if not any(x2 < x and y2 < y for other, (x2, y2) in finite.items() if other != name)
    ]
    return sorted(front, key=lambda name: (finite[name], name))


# --------------------------------------------------------------- one regime's numbers


@dataclass(frozen=True)
class InstanceMatrix:
    """The runs of one regime laid out as instances x strategies.

    Attributes:
        strategies: the regime's strategies, sorted.
        instances: ``(map, robots, seed)`` of the instances every strategy ran, sorted.
        rows: ``N x k`` row indices into the regime's table: the run used per cell.
        t99: ``N x k`` T99 of those runs, nan where it was never reached.
        left_out: instances some strategy has no row for (not ranked).
        missing: strategy -> instances of the regime it has no row for.
        duplicates: rows not used because another run of the same strategy and
            instance was kept.
    """

    strategies: tuple[str, ...]
    instances: tuple[tuple[Any, ...], ...]
    rows: npt.NDArray[np.int64]
    t99: FloatArray
    left_out: int
    missing: Mapping[str, int]
    duplicates: int


def _floats(table: pa.Table, name: str) -> FloatArray:
    """Column ``name`` as float64 with nulls as nan; all nan when absent or all null."""
    if name not in table.column_names or pa.types.is_null(table.column(name).type):
        return np.full(table.num_rows, np.nan)
    column = pc.cast(table.column(name), pa.float64())
    values: FloatArray = np.array(column.to_numpy(zero_copy_only=False), dtype=np.float64)
    return values


def _sort_key(value: Any) -> tuple[int, str, Any]:
    if isinstance(value, bool | int | float):
        return (0, "", value)
    return (1, "", str(value))


def instance_matrix(runs: pa.Table) -> InstanceMatrix:
    """Lay out the runs of one regime as instances x strategies (see :class:`InstanceMatrix`)."""
    strategies_of = [str(s) for s in runs.column("strategy").to_pylist()]
    keys = list(zip(*(runs.column(c).to_pylist() for c in INSTANCE_COLUMNS), strict=True))
    statuses = runs.column("status").to_pylist()
    run_ids = (
        [str(r) for r in runs.column("run_id").to_pylist()]
        if "run_id" in runs.column_names
        else [""] * runs.num_rows
    )
    t99_all = _floats(runs, "T99")
    t99_all[[status == "failed" for status in statuses]] = np.nan  # never a time, whatever it says
    strategies = tuple(sorted(set(strategies_of)))
    chosen: dict[tuple[Any, ...], dict[str, int]] = {}
    duplicates = 0
    for row, (key, strategy) in enumerate(zip(keys, strategies_of, strict=True)):
        cell = chosen.setdefault(key, {})
        if strategy not in cell:
            cell[strategy] = row
            continue
        duplicates += 1
        kept = cell[strategy]
        if (statuses[row] == "failed", run_ids[row], row) < (
            statuses[kept] == "failed",
            run_ids[kept],
            kept,
        ):
            cell[strategy] = row
    complete = sorted(
        (key for key, cell in chosen.items() if len(cell) == len(strategies)),
        key=lambda key: tuple(_sort_key(v) for v in key),
    )
    rows = np.array(
        [[chosen[key][s] for s in strategies] for key in complete], dtype=np.int64
    ).reshape(len(complete), len(strategies))
    t99 = t99_all[rows] if rows.size else np.zeros(rows.shape)
    return InstanceMatrix(
        strategies=strategies,
        instances=tuple(complete),
        rows=rows,
        t99=t99,
        left_out=len(chosen) - len(complete),
        missing={s: sum(s not in cell for cell in chosen.values()) for s in strategies},
        duplicates=duplicates,
    )


@dataclass(frozen=True)
class Standing:
    """One strategy's line of a regime's leaderboard (over the instances used).

    Attributes:
        strategy: its id.
        mean_rank: ``R_j`` (nan with no instance).
        runs, reached: runs used and how many reached 99% coverage.
        t99: T99 over the runs that reached it.
        metrics: :data:`SUMMARY_METRICS` column -> summary (failed runs have nulls
            and so drop out).
        win_rate: paired win rate against the baseline (nan without one).
        difference: ``T99 - T99_baseline`` over instances both reached (``None``
            for the baseline itself or without one).
    """

    strategy: str
    mean_rank: float
    runs: int
    reached: int
    t99: Summary
    metrics: Mapping[str, Summary]
    win_rate: float
    difference: Summary | None


@dataclass(frozen=True)
class RegimeBoard:
    """Everything the leaderboard says about one regime.

    Attributes:
        regime: its name.
        matrix: the instances x strategies layout.
        ranks: ``N x k`` ranks (:func:`rank_instances`).
        standings: one per strategy, best mean rank first.
        statuses: status -> number of the regime's rows (every row counts).
        baseline: the baseline's id if it ran in this regime, else ``None``.
        friedman: the test, or ``None`` when ``k < 3`` or ``N < 2``.
        cd: Nemenyi's critical difference when Friedman is given, else nan.
        groups: :func:`cd_groups` of the mean ranks (empty without ``cd``).
    """

    regime: str
    matrix: InstanceMatrix
    ranks: FloatArray
    standings: tuple[Standing, ...]
    statuses: Mapping[str, int]
    baseline: str | None
    friedman: Friedman | None
    cd: float
    groups: tuple[tuple[str, ...], ...]

    @property
    def n_runs(self) -> int:
        """Rows of this regime in the table."""
        return sum(self.statuses.values())


def _status_counts(statuses: Iterable[Any]) -> dict[str, int]:
    counts = {status: 0 for status in STATUSES}
    for status in statuses:
        counts[str(status)] = counts.get(str(status), 0) + 1
    return counts


def regime_board(runs: pa.Table, regime: str, baseline: str | None) -> RegimeBoard:
    """Ranks, tests and per-strategy summaries of ``runs``, all of one regime."""
    matrix = instance_matrix(runs)
    ranks = rank_instances(matrix.t99)
    r = mean_ranks(ranks)
    k, n = len(matrix.strategies), len(matrix.instances)
    base = baseline if baseline in matrix.strategies else None
    base_t99 = matrix.t99[:, matrix.strategies.index(base)] if base is not None else None
    metric_values = {name: _floats(runs, name) for name, _ in SUMMARY_METRICS}
    standings = []
    for j, strategy in enumerate(matrix.strategies):
        rows = matrix.rows[:, j]
        t99 = matrix.t99[:, j]
        if base_t99 is not None and strategy != base:
            wins, difference = win_rate(t99, base_t99), paired_difference(t99, base_t99)
        else:
            wins, difference = math.nan, None
        standings.append(
            Standing(
                strategy=strategy,
                mean_rank=float(r[j]),
                runs=n,
                reached=int(np.count_nonzero(np.isfinite(t99))),
                t99=summarize_metric(t99),
                metrics={name: summarize_metric(v[rows]) for name, v in metric_values.items()},
                win_rate=wins,
                difference=difference,
            )
        )
    standings.sort(key=lambda s: (s.mean_rank if n else 0.0, s.strategy))
    test = friedman(ranks) if k >= 3 and n >= 2 else None
    cd = critical_difference(k, n) if test is not None else math.nan
    groups = tuple(cd_groups({s.strategy: s.mean_rank for s in standings}, cd)) if test else ()
    return RegimeBoard(
        regime=regime,
        matrix=matrix,
        ranks=ranks,
        standings=tuple(standings),
        statuses=_status_counts(runs.column("status").to_pylist()),
        baseline=base,
        friedman=test,
        cd=cd,
        groups=groups,
    )


# ------------------------------------------------------------------ the whole table


@dataclass(frozen=True)
class SuiteIdentity:
    """The one suite a leaderboard is about."""

    name: str
    version: int
    content_hash: str


def check_runs(runs: pa.Table) -> SuiteIdentity:
    """Refuse a table the leaderboard cannot describe; return its suite.

    Raises:
        MrexploreInputError: the table is empty, lacks a column of
            :data:`REQUIRED_COLUMNS`, has nulls where an instance is named, or mixes
            suites, versions or hashes.
    """
    if runs.num_rows == 0:
        raise MrexploreInputError("no runs: the leaderboard needs at least one run")
    missing = [name for name in REQUIRED_COLUMNS if name not in runs.column_names]
    if missing:
        raise MrexploreInputError(
            f"runs table has no column {', '.join(missing)}: not a suite's results "
            "(run `mrexplore suite run`)"
        )
    for name in ("suite", "suite_version", "suite_hash", "regime", "strategy", *INSTANCE_COLUMNS):
        nulls = runs.column(name).null_count
        if nulls:
            raise MrexploreInputError(f"runs table: {nulls} rows have no {name}")
    found: dict[str, list[str]] = {}
    for name in ("suite", "suite_version", "suite_hash"):
        values = sorted({str(v) for v in runs.column(name).to_pylist()})
        found[name] = values
    mixed = [name for name, values in found.items() if len(values) > 1]
    if mixed:
        parts = "; ".join(f"{name}: {', '.join(found[name])}" for name in mixed)
        raise MrexploreInputError(
            f"runs of several suites in one table ({parts}): report each suite version apart"
        )
    return SuiteIdentity(
        found["suite"][0], int(runs.column("suite_version")[0].as_py()), found["suite_hash"][0]
    )


def regimes(runs: pa.Table) -> list[str]:
    """The regimes of ``runs``, sorted by name (so row order never matters)."""
    return sorted({str(v) for v in runs.column("regime").to_pylist()})


def leaderboard(runs: pa.Table, *, baseline: str | None = "nearest-frontier") -> list[RegimeBoard]:
    """One :class:`RegimeBoard` per regime of ``runs`` (checked by :func:`check_runs`)."""
    check_runs(runs)
    regime_column = runs.column("regime")
    boards = []
    for regime in regimes(runs):
        subset = runs.filter(pc.equal(pc.cast(regime_column, pa.string()), regime))
        boards.append(regime_board(subset, regime, baseline))
    return boards


# ---------------------------------------------------------------- document blocks
#
# The Markdown and the HTML page are rendered from the same blocks, so that the
# two say the same thing.


@dataclass(frozen=True)
class Cell:
    """A table cell: its text and the value it sorts by (``None``: missing, last)."""

    text: str
    value: float | str | None


@dataclass(frozen=True)
class TableBlock:
    """A table with an id (HTML), a key per column and the index of its first number column."""

    table_id: str
    header: tuple[str, ...]
    keys: tuple[str, ...]
    rows: tuple[tuple[Cell, ...], ...]
    numeric_from: int


@dataclass(frozen=True)
class Heading:
    level: int
    text: str


@dataclass(frozen=True)
class Paragraph:
    text: str


@dataclass(frozen=True)
class Bullets:
    items: tuple[str, ...]


@dataclass(frozen=True)
class Image:
    """A PNG, relative to the output folder."""

    path: str
    alt: str


Block = Heading | Paragraph | Bullets | TableBlock | Image


def _number(value: float) -> Cell:
    return Cell(format_number(value), value if math.isfinite(value) else None)


def _summary_cell(summary: Summary) -> Cell:
    if summary.n == 0:
        return Cell(_MISSING, None)
    text = format_number(summary.mean)
    if math.isfinite(summary.half_width):
        text += f" ± {format_number(summary.half_width)}"
    return Cell(text, summary.mean)


def _difference_cell(summary: Summary | None) -> Cell:
    if summary is None:
        return Cell(_MISSING, None)
    cell = _summary_cell(summary)
    return Cell(f"{cell.text} (n={summary.n})", cell.value)


def _standings_table(board: RegimeBoard, index: int, baseline: str | None) -> TableBlock:
    against = board.baseline or baseline or "baseline"
    header = (
        "#",
        "strategy",
        "mean rank",
        "T99 reached",
        "T99 (ticks) ± 95% CI",
        *(f"{title} ± 95% CI" for _, title in SUMMARY_METRICS),
        f"wins vs {against}",
        f"T99 − {against} ± 95% CI",
    )
    keys = (
        "place",
        "strategy",
        "mean_rank",
        "t99_reached",
        "t99",
        *(name for name, _ in SUMMARY_METRICS),
        "win_rate",
        "t99_difference",
    )
    rows = []
    for place, s in enumerate(board.standings, start=1):
        if s.strategy == board.baseline:
            wins = Cell("baseline", None)
        elif math.isfinite(s.win_rate):
            wins = Cell(f"{100 * s.win_rate:.0f}%", s.win_rate)
        else:
            wins = Cell(_MISSING, None)
        rows.append(
            (
                Cell(str(place), place),
                Cell(s.strategy, s.strategy),
                _number(s.mean_rank),
                Cell(f"{s.reached}/{s.runs}", s.reached / s.runs if s.runs else None),
                _summary_cell(s.t99),
                *(_summary_cell(s.metrics[name]) for name, _ in SUMMARY_METRICS),
                wins,
                _difference_cell(s.difference),
            )
        )
    return TableBlock(
        f"leaderboard-{index + 1}-{_slug(board.regime)}", header, keys, tuple(rows), 2
    )


def _status_table(boards: Sequence[RegimeBoard]) -> TableBlock:
    statuses = list(STATUSES)
    for board in boards:
        statuses += sorted(s for s in board.statuses if s not in statuses)
    header = ("regime", "runs", "strategies", "instances ranked", "left out", *statuses)
    keys = ("regime", "runs", "strategies", "instances", "left_out", *statuses)
    rows = []
    for board in boards:
        m = board.matrix
        counts = [board.statuses.get(status, 0) for status in statuses]
        rows.append(
            (
                Cell(board.regime, board.regime),
                Cell(str(board.n_runs), board.n_runs),
                Cell(str(len(m.strategies)), len(m.strategies)),
                Cell(str(len(m.instances)), len(m.instances)),
                Cell(str(m.left_out), m.left_out),
                *(Cell(str(c), c) for c in counts),
            )
        )
    return TableBlock("statuses", header, keys, tuple(rows), 1)


def _regime_blocks(
    board: RegimeBoard, index: int, baseline: str | None, cd_image: str, pareto_image: str
) -> list[Block]:
    m = board.matrix
    k, n = len(m.strategies), len(m.instances)
    blocks: list[Block] = [Heading(2, f"Regime: {board.regime}")]
    used = (
        f"{n} instances (map, team size, seed) ranked, every one run by all {k} strategies"
        if n
        else f"No instance has been run by all {k} strategies yet: nothing is ranked"
    )
    if m.left_out:
        lacking = ", ".join(f"{s} {count}" for s, count in m.missing.items() if count)
        used += (
            f"; {m.left_out} left out because a strategy has no row for them yet "
            f"(instances without a row: {lacking})."
        )
    else:
        used += "; none left out."
    if m.duplicates:
        used += f" {m.duplicates} repeated runs of a strategy on an instance were not used."
    blocks.append(Paragraph(used))
    if baseline is not None and board.baseline is None:
        blocks.append(Paragraph(f"The baseline {baseline} has no runs in this regime."))
    if n == 0:
        return blocks
    blocks += [Heading(3, "Leaderboard"), _standings_table(board, index, baseline)]

    blocks.append(Heading(3, "Friedman test"))
    test = board.friedman
    if test is None:
        blocks.append(
            Paragraph(
                f"Not given: the test needs at least 3 strategies and 2 instances; "
                f"this regime has {k} and {n}. No critical-difference diagram either."
            )
        )
    else:
        blocks += _friedman_blocks(board, test, cd_image)
    front = pareto_front(_pareto_points(board))
    blocks += [
        Heading(3, "Time against bytes"),
        Image(pareto_image, f"mean T99 against mean bytes, {board.regime}"),
        Paragraph(
            "Means over the ranked instances with their 95% CIs (T99 over the runs that "
            "reached it). Pareto-optimal (no strategy both sends fewer bytes and is "
            f"faster): {', '.join(front) if front else 'none'}."
        ),
    ]
    return blocks


def _friedman_blocks(board: RegimeBoard, test: Friedman, cd_image: str) -> list[Block]:
    n, k = test.n_instances, test.n_strategies
    verdict = (
        "the strategies' mean ranks differ" if test.rejects else "equal mean ranks are not rejected"
    )
    groups = (
        "; ".join(", ".join(group) for group in board.groups)
        if board.groups
        else "none (every pair of strategies differs by at least CD)"
    )
    caution = (
        ""
        if test.rejects
        else " Friedman does not reject equal ranks here, so the groups are descriptive only."
    )
    return [
        Paragraph(
            f"chi²_F = {format_number(test.statistic)} with {test.df} degrees of freedom, "
            f"p = {_p_text(test.p_value)} (N = {n} instances, k = {k} strategies): at "
            f"α = {ALPHA:g}, {verdict}. Textbook statistic without tie correction; "
            f"scipy's tie-corrected value is chi²_F / C with C = {test.tie_factor:.4f}."
        ),
        Heading(3, "Critical-difference diagram"),
        Image(cd_image, f"critical-difference diagram, {board.regime}"),
        Paragraph(
            f"Nemenyi test at α = {ALPHA:g}: CD = {format_number(board.cd)} "
            f"(q = {nemenyi_q(k):.3f}). Strategies joined by a bar differ in mean rank "
            f"by less than CD. Groups: {groups}.{caution}"
        ),
    ]


def _p_text(p: float) -> str:
    return f"{p:.2e}" if p < 1e-3 else f"{p:.3f}"


def _pareto_points(board: RegimeBoard) -> dict[str, tuple[float, float]]:
    return {s.strategy: (s.metrics["bytes_total"].mean, s.t99.mean) for s in board.standings}


def _document(
    boards: Sequence[RegimeBoard],
    suite: SuiteIdentity,
    title: str,
    baseline: str | None,
    images: Sequence[tuple[str, str]],
) -> list[Block]:
    n_runs = sum(board.n_runs for board in boards)
    strategies = sorted({s for board in boards for s in board.matrix.strategies})
    blocks: list[Block] = [
        Heading(1, title),
        Bullets(
            (
                f"suite {suite.name}, version {suite.version}, hash {suite.content_hash}",
                f"{n_runs} runs, {len(strategies)} strategies ({', '.join(strategies)}), "
                f"{len(boards)} regimes",
                f"baseline for win rates and differences: {baseline or 'none'}",
            )
        ),
        _status_table(boards),
        Heading(2, "How to read the tables"),
        Paragraph(
            "Within each instance (map, team size, seed) the strategies are ranked by T99, "
            "the ticks to 99% coverage, lower is better; a run that never reached 99% "
            "(max_ticks, stalled, failed) ranks after every run that did, and such runs "
            "share the average of their ranks. Mean rank is over the instances every "
            "strategy ran, and so are all the columns. T99 reached: runs that reached 99% "
            "of those. Means carry "
            f"their {100 * CONFIDENCE:.0f}% t CI (± half-width, {_MISSING} when undefined); "
            "T99 is averaged over the runs that reached it. Wins: share of instances where "
            "the strategy's T99 is lower than the baseline's (not reaching 99% is "
            "infinitely slow, ties count half). T99 − baseline: paired mean difference "
            "over the instances both reached 99% (n of them). Friedman, Nemenyi and the "
            "critical-difference diagram follow Demšar (2006), JMLR 7:1-30."
        ),
    ]
    for index, (board, (cd_image, pareto_image)) in enumerate(zip(boards, images, strict=True)):
        blocks += _regime_blocks(board, index, baseline, cd_image, pareto_image)
    return blocks


# --------------------------------------------------------------------- rendering


def render_markdown(blocks: Sequence[Block]) -> str:
    """The blocks as Markdown (text escaped for tables and lists)."""
    lines: list[str] = []
    for block in blocks:
        if isinstance(block, Heading):
            lines += ["#" * block.level + " " + _escape(block.text), ""]
        elif isinstance(block, Paragraph):
            lines += [_escape(block.text), ""]
        elif isinstance(block, Bullets):
            lines += [*(f"- {_escape(item)}" for item in block.items), ""]
        elif isinstance(block, TableBlock):
            rows = [[_escape(cell.text) for cell in row] for row in block.rows]
            lines += [*_table(block.header, rows, block.numeric_from), ""]
        else:
            lines += [f"![{_escape(block.alt)}]({block.path})", ""]
    return "\n".join(lines).rstrip("\n") + "\n"


_CSS = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 75em; color: #222; }
table { border-collapse: collapse; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; white-space: nowrap; }
div.scroll { overflow-x: auto; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
th { background: #f3f3f3; cursor: pointer; user-select: none; white-space: nowrap; }
th[aria-sort="ascending"]::after { content: " \\25B2"; }
th[aria-sort="descending"]::after { content: " \\25BC"; }
img { max-width: 100%; }
"""

# Click a header: sort by that column (numbers numerically by data-value, missing
# values always last); click it again: the other way round.
_SCRIPT = """
(function () {
  try {
    function compare(a, b, numeric) {
      if (a === null || b === null) { return a === b ? 0 : (a === null ? 1 : -1); }
      if (numeric) { return a - b; }
      return a < b ? -1 : (a > b ? 1 : 0);
    }
    function valueOf(cell, numeric) {
      var raw = cell.getAttribute("data-value");
      if (raw === null || raw === "") { return null; }
      return numeric ? parseFloat(raw) : raw;
    }
    document.querySelectorAll("table.sortable").forEach(function (table) {
      var headers = table.querySelectorAll("thead th");
      headers.forEach(function (th, column) {
        th.addEventListener("click", function () {
          var ascending = th.getAttribute("aria-sort") !== "ascending";
          headers.forEach(function (h) { h.removeAttribute("aria-sort"); });
          th.setAttribute("aria-sort", ascending ? "ascending" : "descending");
          var numeric = th.getAttribute("data-type") === "number";
          var body = table.tBodies[0];
          var rows = Array.prototype.slice.call(body.rows);
          rows.sort(function (r, s) {
            var a = valueOf(r.cells[column], numeric), b = valueOf(s.cells[column], numeric);
            var order = (a === null || b === null) ? compare(a, b, numeric)
                : (ascending ? 1 : -1) * compare(a, b, numeric);
            return order || (r.dataset.index - s.dataset.index);
          });
          rows.forEach(function (row) { body.appendChild(row); });
        });
      });
    });
    document.body.dataset.ready = "1";
  } catch (error) {
    document.body.dataset.error = String(error);
  }
})();
"""


def _html_table(table: TableBlock) -> str:
    # A column sorts as numbers when every value it holds is a number.
    numeric = [
        all(isinstance(row[i].value, int | float) or row[i].value is None for row in table.rows)
        for i in range(len(table.header))
    ]
    head = "".join(
        f'<th data-key="{html.escape(key)}" data-type="{"number" if num else "text"}">'
        f"{html.escape(title)}</th>"
        for key, title, num in zip(table.keys, table.header, numeric, strict=True)
    )
    body = []
    for index, row in enumerate(table.rows):
        cells = []
        for cell, num in zip(row, numeric, strict=True):
            value = "" if cell.value is None else (repr(cell.value) if num else str(cell.value))
            css = ' class="num"' if num else ""
            cells.append(
                f'<td{css} data-value="{html.escape(value)}">{html.escape(cell.text)}</td>'
            )
        body.append(f'<tr data-index="{index}">{"".join(cells)}</tr>')
    return (
        f'<div class="scroll"><table class="sortable" id="{html.escape(table.table_id)}">'
        f"<thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table></div>"
    )


def render_html(blocks: Sequence[Block], out_dir: Path, title: str) -> str:
    """The blocks as one self-contained HTML page: images inlined as data URIs,
    inline CSS and script, every table sortable by a click on its header."""
    parts: list[str] = []
    for block in blocks:
        if isinstance(block, Heading):
            parts.append(f"<h{block.level}>{html.escape(block.text)}</h{block.level}>")
        elif isinstance(block, Paragraph):
            parts.append(f"<p>{html.escape(block.text)}</p>")
        elif isinstance(block, Bullets):
            items = "".join(f"<li>{html.escape(item)}</li>" for item in block.items)
            parts.append(f"<ul>{items}</ul>")
        elif isinstance(block, TableBlock):
            parts.append(_html_table(block))
        else:
            data = base64.b64encode((out_dir / block.path).read_bytes()).decode("ascii")
            parts.append(f'<img alt="{html.escape(block.alt)}" src="data:image/png;base64,{data}">')
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{html.escape(title)}</title><style>{_CSS}</style></head>\n<body>\n"
        + "\n".join(parts)
        + f"\n<script>{_SCRIPT}</script>\n</body></html>\n"
    )


@dataclass(frozen=True)
class LeaderboardFiles:
    """The files :func:`write_leaderboard` wrote.

    Attributes:
        markdown: ``leaderboard.md``.
        html: ``leaderboard.html``, self-contained.
        image: ``leaderboard.png``, the critical-difference diagrams stacked.
        figures: ``img/*.png``: per regime its CD diagram (when given) and its
            time-against-bytes plot (when anything was ranked).
    """

    markdown: Path
    html: Path
    image: Path
    figures: tuple[Path, ...]


def write_leaderboard(
    runs: pa.Table,
    out_dir: Path,
    *,
    baseline: str = "nearest-frontier",
    title: str | None = None,
) -> LeaderboardFiles:
    """Write the leaderboard of one suite's ``runs`` into ``out_dir`` (created if needed).

    Args:
        runs: one row per run with the columns of :data:`REQUIRED_COLUMNS` (and
            ``run_id``, ``total_distance``, ``bytes_total``, ``wtv_8_final`` when
            present).
        out_dir: folder for ``leaderboard.md``, ``leaderboard.html``,
            ``leaderboard.png`` and ``img/``; files of the same names are replaced.
        baseline: strategy the others are paired with; a regime without it shows
            no win rates.
        title: first heading; default ``"Leaderboard: SUITE (version V)"``.

    Raises:
        MrexploreInputError: see :func:`check_runs`.
    """
    from mrexplore.viz.leaderboard import draw_cd_diagrams, draw_pareto

    suite = check_runs(runs)
    boards = leaderboard(runs, baseline=baseline)
    if not any(baseline in board.matrix.strategies for board in boards):
        logger.warning("baseline %s has no runs in this suite's results", baseline)
    heading = title or f"Leaderboard: {suite.name} (version {suite.version})"
    out = Path(out_dir)
    img = out / "img"
    img.mkdir(parents=True, exist_ok=True)

    figures: list[Path] = []
    images: list[tuple[str, str]] = []
    for index, board in enumerate(boards):
        stem = f"{index + 1:02d}_{_slug(board.regime)}"
        cd_path, pareto_path = img / f"cd_{stem}.png", img / f"pareto_{stem}.png"
        if board.friedman is not None:
            figures.append(draw_cd_diagrams([board], cd_path))
        if board.matrix.instances:
            figures.append(draw_pareto(board, pareto_path))
        images.append((f"img/{cd_path.name}", f"img/{pareto_path.name}"))
    image = draw_cd_diagrams(boards, out / "leaderboard.png")

    blocks = _document(boards, suite, heading, baseline, images)
    markdown = out / "leaderboard.md"
    markdown.write_text(render_markdown(blocks), encoding="utf-8")
    page = out / "leaderboard.html"
    page.write_text(render_html(blocks, out, heading), encoding="utf-8")
    logger.info("wrote %s, %s and %s", markdown, page, image)
    return LeaderboardFiles(markdown, page, image, tuple(figures))
