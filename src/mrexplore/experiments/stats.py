"""Statistics over a sweep's ``runs`` table: summaries, conditions, paired differences.

A sweep's results store holds one row per run. Its columns fall into four kinds,
and the store, this module and the report agree on them through
:data:`SCENARIO_COLUMNS`, :data:`SCENARIO_PREFIXES`, :data:`SEED_COLUMN` and
:data:`NON_METRIC_COLUMNS`:

=================  ==========================================================
kind               columns
=================  ==========================================================
scenario           the fields of :class:`~mrexplore.sim.scenario.Scenario`
                   under the CLI's option names (``map``, ``strategy``,
                   ``robots``, ``comm_range``, ...), see
                   :data:`SCENARIO_COLUMNS`; strategy parameters flattened as
                   ``param_<name>``, sharing parameters as ``share_<name>``
replicate          ``seed``: runs that differ only by seed are replicates of
                   one condition
bookkeeping        ``run_id``, ``status``, ``error``, ``wall_time_s``,
                   ``mrexplore_version``, ... (:data:`NON_METRIC_COLUMNS`)
metric             every other numeric column (``T99``, ``ticks``,
                   ``total_distance``, ``bytes_total``, ``wtv_8_final``, ...)
=================  ==========================================================

A **condition** is one combination of values of the scenario columns that vary in
the table (:func:`conditions`, :func:`group_conditions`). Runs whose ``status`` is
in :data:`EXCLUDED_STATUSES` (``failed``) carry no metrics and are left out of every
statistic (:func:`usable_rows`); runs that merely did not finish (``max_ticks``,
``stalled``) count, with their null metrics (``T99`` never reached) dropped and
counted as missing.

Formulas (``x_1..x_n`` the non-missing values, ``t_q(k)`` the ``q`` quantile of
Student's t with ``k`` degrees of freedom, ``scipy.stats.t.ppf``):

* mean ``m = (1/n) sum x_i``; sample standard deviation
  ``s = sqrt(sum (x_i - m)^2 / (n - 1))``;
* 95% confidence interval of the mean ``m -+ t_0.975(n - 1) * s / sqrt(n)``;
  undefined (nan) for ``n < 2``;
* paired difference of ``A`` and ``B`` on the same seeds: ``d_i = A_i - B_i``,
  summarized as above (so its CI is the paired t interval).

Everything here is a pure function of its arguments (numpy, scipy, pyarrow).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np
import numpy.typing as npt
import pyarrow as pa
import pyarrow.compute as pc
from scipy import stats as scipy_stats

from mrexplore.errors import MrexploreInputError
from mrexplore.sim.noise import ODOMETRY_PARAMS, SENSOR_PARAMS
from mrexplore.sim.scenario import Scenario

FloatArray = npt.NDArray[np.float64]

#: The column holding the replicate seed. Conditions never include it; paired
#: comparisons match runs on it.
SEED_COLUMN = "seed"

#: Scenario columns: the :class:`~mrexplore.sim.scenario.Scenario` fields under the
#: CLI's option names, without ``seed`` (:data:`SEED_COLUMN`) and without the
#: parameter dictionaries, which the store flattens: the strategy's, the sharing
#: mechanism's and the comm model's by prefix (:data:`SCENARIO_PREFIXES`), the sensor
#: and odometry models' as ``sensor_<name>`` and ``odometry_<name>`` for each of their
#: parameters (listed here: the prefix ``sensor_`` would take in
#: ``sensor_range_cells``, which ``result.json`` restates).
SCENARIO_COLUMNS: tuple[str, ...] = (
    *(
        field.name
        for field in fields(Scenario)
        if field.name
        not in (
            SEED_COLUMN,
            "params",
            "sharing_params",
            "comm_params",
            "sensor_params",
            "odometry_params",
        )
    ),
    *(f"sensor_{name}" for name in SENSOR_PARAMS),
    *(f"odometry_{name}" for name in ODOMETRY_PARAMS),
)

#: Prefixes of flattened scenario parameters: ``param_<name>`` for a strategy
#: parameter (``--set name=value``), ``share_<name>`` for a parameter of the
#: map-sharing mechanism (``--share name=value``), ``comm_<name>`` for one of the
#: communication model (``--comm name=value``; ``comm_range`` and ``comm_los`` are
#: scenario columns anyway).
SCENARIO_PREFIXES: tuple[str, ...] = ("param_", "share_", "comm_")

#: Columns that describe a run but are not outcomes to compare: ids, provenance,
#: machine-dependent timings, the limits in force, and scenario or map values
#: restated by ``result.json`` (team size, ranges in cells, map size).
NON_METRIC_COLUMNS: frozenset[str] = frozenset(
    {
        SEED_COLUMN,
        "run_id",
        "status",
        "error",
        "traceback",
        "wall_time_s",
        "decide_ms_per_plan",
        "mrexplore_version",
        "max_ticks_in_force",
        "n_robots",
        "sensor_range_cells",
        "comm_range_cells",
        "map_resolution_m",
        "explorable_cells",
    }
)

#: Statuses whose runs carry no metrics and are left out of every statistic.
EXCLUDED_STATUSES: tuple[str, ...] = ("failed",)

#: Confidence level of every interval in this module and in the report.
CONFIDENCE = 0.95


def is_scenario_column(name: str) -> bool:
    """Whether column ``name`` is part of a run's scenario (and so of its condition).

    >>> is_scenario_column("robots"), is_scenario_column("param_w3")
    (True, True)
    >>> is_scenario_column("seed"), is_scenario_column("T99")
    (False, False)
    """
    return name in SCENARIO_COLUMNS or name.startswith(SCENARIO_PREFIXES)


def metric_columns(runs: pa.Table) -> list[str]:
    """The metric columns of ``runs``, in table order.

    A metric is any integer or floating-point column that is neither a scenario
    column (:func:`is_scenario_column`) nor in :data:`NON_METRIC_COLUMNS`.
    """
    return [
        field.name
        for field in runs.schema
        if (pa.types.is_integer(field.type) or pa.types.is_floating(field.type))
        and not is_scenario_column(field.name)
        and field.name not in NON_METRIC_COLUMNS
    ]


# ------------------------------------------------------------------------ summaries


@dataclass(frozen=True)
class Summary:
    """Mean, spread and confidence interval of one metric over some runs.

    Attributes:
        n: values used (non-missing).
        mean: ``(1/n) sum x_i``; nan when ``n == 0``.
        sd: sample standard deviation (``n - 1`` in the denominator); nan when
            ``n < 2``.
        ci_low, ci_high: ``mean -+ t_0.975(n-1) * sd / sqrt(n)``; nan when ``n < 2``
            (one value says nothing about the spread).
        n_missing: values dropped because they were null, nan or infinite.
    """

    n: int
    mean: float
    sd: float
    ci_low: float
    ci_high: float
    n_missing: int = 0

    @property
    def half_width(self) -> float:
        """Half the width of the confidence interval (nan when it is undefined)."""
        return (self.ci_high - self.ci_low) / 2


def _finite(values: Iterable[Any]) -> tuple[FloatArray, int]:
    """The finite values as float64 and how many others (null, nan, inf) there were."""
    if isinstance(values, pa.Array | pa.ChunkedArray):
        arr = _as_float(values)
    elif isinstance(values, np.ndarray) and values.dtype.kind in "biuf":
        arr = values.astype(np.float64).ravel()
    else:
        items = values if isinstance(values, np.ndarray) else list(values)
        raw = np.asarray(items, dtype=object)
        arr = np.array([np.nan if v is None else v for v in raw.ravel()], dtype=np.float64)
    keep = np.isfinite(arr)
    return arr[keep], int(arr.size - np.count_nonzero(keep))


def summarize_metric(values: Iterable[Any], *, confidence: float = CONFIDENCE) -> Summary:
    """Summarize ``values``: ``n``, mean, sd and the t confidence interval of the mean.

    ``values``: numbers and ``None`` in any iterable, a numpy array or a pyarrow
    array. Nulls (``None``), nan and infinities are dropped and counted in
    ``n_missing``. With ``x_1..x_n`` the rest::

        mean = (1/n) sum x_i
        sd   = sqrt(sum (x_i - mean)^2 / (n - 1))
        CI   = mean -+ t_{(1+confidence)/2}(n - 1) * sd / sqrt(n)

    ``sd`` and the CI are nan when ``n < 2``; everything but ``n`` is nan when
    ``n == 0``.

    >>> s = summarize_metric([1, 2, 3, 4, 5, None])
    >>> s.n, s.mean, round(s.sd, 4), round(s.ci_low, 3), round(s.ci_high, 3), s.n_missing
    (5, 3.0, 1.5811, 1.037, 4.963, 1)
    """
    if not 0 < confidence < 1:
        raise MrexploreInputError(f"confidence must be in (0, 1), got {confidence}")
    x, n_missing = _finite(values)
    n = int(x.size)
    if n == 0:
        return Summary(0, math.nan, math.nan, math.nan, math.nan, n_missing)
    mean = float(x.mean())
    if n == 1:
        return Summary(1, mean, math.nan, math.nan, math.nan, n_missing)
    sd = float(x.std(ddof=1))
    half = float(scipy_stats.t.ppf((1 + confidence) / 2, n - 1)) * sd / math.sqrt(n)
    return Summary(n, mean, sd, mean - half, mean + half, n_missing)


# ----------------------------------------------------------------------- conditions


def _as_float(column: pa.Array | pa.ChunkedArray) -> FloatArray:
    """A numeric column as float64 with nulls as nan."""
    floats = pc.cast(column, pa.float64())
    arr: FloatArray = np.asarray(floats.to_numpy(zero_copy_only=False), dtype=np.float64)
    return arr


def _key(value: Any) -> Any:
    """A hashable, comparable stand-in for a cell value (nan and null become None)."""
    if isinstance(value, float) and math.isnan(value):
        return None
    if isinstance(value, list):
        return tuple(_key(v) for v in value)
    if isinstance(value, dict):
        return tuple(sorted((k, _key(v)) for k, v in value.items()))
    return value


def _sort_key(value: Any) -> tuple[int, str, Any]:
    """Order values of one column: numbers numerically, then strings, None last."""
    if value is None:
        return (2, "", 0)
    if isinstance(value, bool | int | float):
        return (0, "", value)
    return (1, type(value).__name__, str(value))


def _column_keys(runs: pa.Table, name: str) -> list[Any]:
    return [_key(v) for v in runs.column(name).to_pylist()]


def _determined_by(keys: Sequence[Any], by: Sequence[Any]) -> bool:
    """Whether ``keys`` takes one value for each value of ``by``."""
    seen: dict[Any, Any] = {}
    for key, group in zip(keys, by, strict=True):
        if seen.setdefault(group, key) != key:
            return False
    return True


def conditions(runs: pa.Table, *, exclude: Iterable[str] = (SEED_COLUMN, "run_id")) -> list[str]:
    """The scenario columns that vary across ``runs``, in table order.

    A column varies when it holds at least two distinct values (null and nan count
    as one value). Columns in ``exclude`` are left out; so is ``map_seed`` when it
    is a function of ``seed`` (one map per replicate, the default ``map_seed =
    seed``), since it is then part of the replicate and not of the condition.

    >>> t = pa.table({"strategy": ["a", "b"], "robots": [2, 2], "seed": [0, 1]})
    >>> conditions(t)
    ['strategy']
    """
    excluded = set(exclude)
    seeds = _column_keys(runs, SEED_COLUMN) if SEED_COLUMN in runs.column_names else None
    varying: list[str] = []
    for name in runs.column_names:
        if name in excluded or not is_scenario_column(name):
            continue
        keys = _column_keys(runs, name)
        if len(set(keys)) < 2:
            continue
        if name == "map_seed" and seeds is not None and _determined_by(keys, seeds):
            continue
        varying.append(name)
    return varying


@dataclass(frozen=True)
class Condition:
    """One combination of values of the varying scenario columns and its runs.

    Attributes:
        values: ``(column, value)`` for each grouping column, in column order
            (null and nan appear as ``None``).
        rows: indices into the table of the runs of this condition, ascending.
    """

    values: tuple[tuple[str, Any], ...]
    rows: tuple[int, ...]

    def as_dict(self) -> dict[str, Any]:
        """``values`` as a dict."""
        return dict(self.values)

    def label(self, *, skip: Iterable[str] = ()) -> str:
        """``"strategy=kme, robots=4"`` (``"all runs"`` when nothing varies)."""
        skipped = set(skip)
        parts = [f"{name}={format_value(v)}" for name, v in self.values if name not in skipped]
        return ", ".join(parts) if parts else "all runs"


def format_value(value: Any) -> str:
    """A scenario value as text: ``inf`` for infinity, ``-`` for null, ``4`` for 4.0.

    >>> format_value(float("inf")), format_value(None), format_value(4.0), format_value(0.25)
    ('inf', '-', '4', '0.25')
    """
    if value is None:
        return "-"
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        if value.is_integer():
            return str(int(value))
        return f"{value:g}"
    return str(value)


def group_conditions(
    runs: pa.Table, columns: Sequence[str] | None = None, *, rows: Sequence[int] | None = None
) -> list[Condition]:
    """Group the runs by ``columns`` (default: :func:`conditions` of ``runs``).

    ``rows`` restricts the grouping to these row indices (e.g. :func:`usable_rows`).
    Conditions come sorted by their values (numbers numerically, nulls last), so
    the order is the same whatever the order of the rows.
    """
    names = list(conditions(runs) if columns is None else columns)
    for name in names:
        if name not in runs.column_names:
            raise MrexploreInputError(f"runs table has no column {name!r}")
    keys = [_column_keys(runs, name) for name in names]
    selected = range(runs.num_rows) if rows is None else rows
    groups: dict[tuple[Any, ...], list[int]] = {}
    for row in selected:
        groups.setdefault(tuple(column[row] for column in keys), []).append(int(row))
    ordered = sorted(groups, key=lambda key: tuple(_sort_key(v) for v in key))
    return [
        Condition(tuple(zip(names, key, strict=True)), tuple(sorted(groups[key])))
        for key in ordered
    ]


def usable_rows(runs: pa.Table) -> list[int]:
    """Indices of the runs that count in statistics: status not in ``EXCLUDED_STATUSES``.

    Every row counts when there is no ``status`` column.
    """
    if "status" not in runs.column_names:
        return list(range(runs.num_rows))
    return [
        row
        for row, status in enumerate(runs.column("status").to_pylist())
        if status not in EXCLUDED_STATUSES
    ]


def metric_values(runs: pa.Table, metric: str) -> FloatArray:
    """Column ``metric`` as float64, nulls as nan; a clear error when it is absent."""
    if metric not in runs.column_names:
        raise MrexploreInputError(
            f"runs table has no metric column {metric!r}; metrics: "
            f"{', '.join(metric_columns(runs)) or 'none'}"
        )
    column = runs.column(metric)
    if pa.types.is_null(column.type):  # no run has a value (e.g. T99 never reached)
        return np.full(len(column), np.nan)
    if not (pa.types.is_integer(column.type) or pa.types.is_floating(column.type)):
        raise MrexploreInputError(f"column {metric!r} is {column.type}, not numeric")
    return _as_float(column)


def summarize_by_condition(
    runs: pa.Table,
    metric: str,
    columns: Sequence[str] | None = None,
    *,
    confidence: float = CONFIDENCE,
) -> list[tuple[Condition, Summary]]:
    """:func:`summarize_metric` of ``metric`` in every condition, failed runs left out.

    Conditions are grouped by ``columns`` (default :func:`conditions` of all runs,
    failed ones included, so a condition whose runs all failed still appears, with
    ``n == 0``).
    """
    values = metric_values(runs, metric)
    names = conditions(runs) if columns is None else columns
    usable = set(usable_rows(runs))
    out: list[tuple[Condition, Summary]] = []
    for condition in group_conditions(runs, names):
        rows = [row for row in condition.rows if row in usable]
        out.append((condition, summarize_metric(values[rows], confidence=confidence)))
    return out


def summary_table(
    runs: pa.Table,
    metric: str,
    columns: Sequence[str] | None = None,
    *,
    confidence: float = CONFIDENCE,
) -> pa.Table:
    """:func:`summarize_by_condition` as a table, the input of the metric plots.

    Columns: the grouping columns, then ``n``, ``n_missing``, ``mean``, ``sd``,
    ``ci_low``, ``ci_high``; the table's metadata holds ``metric``.
    """
    names = list(conditions(runs) if columns is None else columns)
    rows = summarize_by_condition(runs, metric, names, confidence=confidence)
    data: dict[str, list[Any]] = {name: [c.as_dict()[name] for c, _ in rows] for name in names}
    for stat in ("n", "n_missing", "mean", "sd", "ci_low", "ci_high"):
        data[stat] = [getattr(s, stat) for _, s in rows]
    arrays: dict[str, pa.Array] = {}
    for name, col in data.items():
        if name in names:
            try:
                arrays[name] = pa.array(col, type=runs.schema.field(name).type)
            except (pa.ArrowInvalid, pa.ArrowTypeError):  # nested values: keep them as text
                arrays[name] = pa.array([format_value(v) for v in col], type=pa.string())
        else:
            arrays[name] = pa.array(col)
    return pa.table(arrays).replace_schema_metadata({"metric": metric})


# -------------------------------------------------------------- paired differences


@dataclass(frozen=True)
class PairedDifference:
    """``A - B`` for one metric over the seeds both ran, in one condition.

    Attributes:
        condition: values of the other varying scenario columns.
        a, b: the two compared levels of the ``between`` column.
        summary: :func:`summarize_metric` of ``d_i = A_i - B_i`` over the paired
            seeds (``summary.n`` pairs; mean difference and its paired t CI).
        share_a_less: share of the pairs with ``A_i < B_i`` (nan with no pair).
        unpaired_seeds: seeds that only one of ``a`` and ``b`` ran (or whose run
            on the other side failed), dropped.
        missing_seeds: seeds both ran where the metric is null on at least one
            side (``T99`` never reached), dropped.
    """

    condition: tuple[tuple[str, Any], ...]
    a: Any
    b: Any
    summary: Summary
    share_a_less: float
    unpaired_seeds: tuple[Any, ...]
    missing_seeds: tuple[Any, ...]

    @property
    def n_pairs(self) -> int:
        """Pairs used."""
        return self.summary.n

    @property
    def mean(self) -> float:
        """Mean of ``A - B``."""
        return self.summary.mean


def _per_seed(values: FloatArray, seeds: Sequence[Any], rows: Iterable[int]) -> dict[Any, float]:
    """Metric per seed; duplicate runs of one seed are averaged (nan if any is null)."""
    collected: dict[Any, list[float]] = {}
    for row in rows:
        collected.setdefault(seeds[row], []).append(float(values[row]))
    return {seed: float(np.mean(vals)) for seed, vals in collected.items()}


def paired_differences(
    runs: pa.Table,
    metric: str,
    *,
    between: str = "strategy",
    baseline: Any = None,
    confidence: float = CONFIDENCE,
) -> list[PairedDifference]:
    """Compare the levels of ``between`` on the same seeds, in every condition.

    Runs are grouped by the varying scenario columns other than ``between`` (the
    condition); in each, the run of level ``A`` and the run of level ``B`` with the
    same seed form a pair, and::

        d_i  = A_i - B_i                          (i over the paired seeds)
        mean = (1/n) sum d_i
        CI   = mean -+ t_{(1+confidence)/2}(n - 1) * sd(d) / sqrt(n)

    Failed runs are left out; a seed without a usable run on both sides is
    dropped and listed in ``unpaired_seeds``, one whose metric is null on a side
    in ``missing_seeds``. Several runs of one level and seed (a re-run) are
    averaged first.

    With ``baseline`` every other level ``A`` is compared with ``B = baseline``;
    without, every pair of levels ``A < B`` in sorted order. Levels are those found
    in the condition; a condition without the baseline gives no comparison.

    >>> t = pa.table({"strategy": ["a"] * 3 + ["b"] * 3, "seed": [0, 1, 2] * 2,
    ...               "ticks": [11, 12, 13, 1, 2, 3]})
    >>> d = paired_differences(t, "ticks")[0]
    >>> d.a, d.b, d.n_pairs, d.mean, d.summary.ci_low, d.summary.ci_high, d.share_a_less
    ('a', 'b', 3, 10.0, 10.0, 10.0, 0.0)
    """
    for name in (between, SEED_COLUMN):
        if name not in runs.column_names:
            raise MrexploreInputError(f"paired differences need a {name!r} column in runs")
    values = metric_values(runs, metric)
    seeds = _column_keys(runs, SEED_COLUMN)
    levels_of = _column_keys(runs, between)
    usable = usable_rows(runs)
    other = [name for name in conditions(runs) if name != between]

    out: list[PairedDifference] = []
    # Group all runs (failed included) so that a seed failing on one side shows
    # up as unpaired rather than vanishing.
    usable_set = set(usable)
    for condition in group_conditions(runs, other):
        by_level: dict[Any, list[int]] = {}
        for row in condition.rows:
            by_level.setdefault(levels_of[row], []).append(row)
        levels = sorted(by_level, key=_sort_key)
        if baseline is None:
            pairs = [(a, b) for i, a in enumerate(levels) for b in levels[i + 1 :]]
        elif baseline in by_level:
            pairs = [(a, baseline) for a in levels if a != baseline]
        else:
            pairs = []
        for a, b in pairs:
            a_rows = [r for r in by_level[a] if r in usable_set]
            b_rows = [r for r in by_level[b] if r in usable_set]
            out.append(_pair(condition, a, b, values, seeds, a_rows, b_rows, by_level, confidence))
    return out


def _pair(
    condition: Condition,
    a: Any,
    b: Any,
    values: FloatArray,
    seeds: Sequence[Any],
    a_rows: Sequence[int],
    b_rows: Sequence[int],
    by_level: Mapping[Any, Sequence[int]],
    confidence: float,
) -> PairedDifference:
    a_by_seed = _per_seed(values, seeds, a_rows)
    b_by_seed = _per_seed(values, seeds, b_rows)
    all_seeds = {seeds[r] for r in (*by_level[a], *by_level[b])}
    common = sorted(set(a_by_seed) & set(b_by_seed), key=_sort_key)
    unpaired = tuple(sorted(all_seeds - set(common), key=_sort_key))
    diffs: list[float] = []
    missing: list[Any] = []
    for seed in common:
        d = a_by_seed[seed] - b_by_seed[seed]
        if math.isfinite(d):
            diffs.append(d)
        else:
            missing.append(seed)
    d_arr = np.asarray(diffs, dtype=np.float64)
    share = float(np.count_nonzero(d_arr < 0) / d_arr.size) if d_arr.size else math.nan
    return PairedDifference(
        condition=condition.values,
        a=a,
        b=b,
        summary=summarize_metric(d_arr, confidence=confidence),
        share_a_less=share,
        unpaired_seeds=unpaired,
        missing_seeds=tuple(missing),
    )
