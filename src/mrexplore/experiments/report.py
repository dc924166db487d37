"""The Markdown report of a sweep: ``mrexplore report DIR``.

:func:`write_report` turns a sweep's ``runs`` table (one row per run) and, when
given, its ``curves`` table (one row per run per sampled tick) into
``report.md`` with PNG figures beside it:

1. a header: number of runs by status, the failed runs with the first line of
   their error, the scenario settings shared by every run and the ones that vary,
   the package versions;
2. per metric, a table of ``n``, mean, sd and the 95% CI of the mean in every
   condition (:func:`mrexplore.experiments.stats.summarize_by_condition`);
3. with two strategies or more, per metric, the paired differences between
   strategies over the same seeds (:func:`~mrexplore.experiments.stats.paired_differences`);
4. figures: each metric against team size when ``robots`` varies, coverage curves
   over time (and ``wtv_8`` / ``epv_8`` curves when the curves table has them),
   and bytes sent by message type when ``runs`` has ``bytes_by_type_<type>``
   columns (:data:`BYTES_BY_TYPE_PREFIX`).

Columns are classified as in :mod:`mrexplore.experiments.stats` (scenario columns,
seed, bookkeeping, metrics). The report has no timestamp: the same tables give the
same ``report.md``.
"""

from __future__ import annotations

import logging
import math
import platform
import re
from collections.abc import Callable, Sequence
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from mrexplore import __version__
from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.stats import (
    CONFIDENCE,
    EXCLUDED_STATUSES,
    SEED_COLUMN,
    Condition,
    PairedDifference,
    Summary,
    conditions,
    format_value,
    group_conditions,
    is_scenario_column,
    metric_columns,
    metric_values,
    paired_differences,
    summarize_by_condition,
    summary_table,
    usable_rows,
)

logger = logging.getLogger(__name__)

#: Metrics reported when the caller names none (those absent from ``runs`` are
#: skipped): time to 99% coverage, run length, distance, bytes, and the 8-region
#: WTV at the end of the run.
DEFAULT_METRICS: tuple[str, ...] = ("T99", "ticks", "total_distance", "bytes_total", "wtv_8_final")

#: ``runs`` columns ``bytes_by_type_<type>`` hold the bytes a run sent in messages of
#: ``<type>``; when present the report draws them as stacked bars.
BYTES_BY_TYPE_PREFIX = "bytes_by_type_"

#: Curves drawn over time when the ``curves`` table has them.
CURVE_COLUMNS: tuple[str, ...] = ("coverage", "wtv_8", "epv_8")

#: Figures of one kind beyond this number are not drawn (the report says so).
MAX_FIGURES_PER_KIND = 24

#: Conditions drawn as bars in the bytes-by-type figure at most.
MAX_BARS = 48

#: Failed runs listed by name in the header; the rest are counted.
MAX_FAILED_LISTED = 20

_PACKAGES: tuple[str, ...] = ("numpy", "scipy", "pyarrow", "matplotlib")
_MISSING = "—"


# ------------------------------------------------------------------------ formatting


def format_number(value: float | int | None) -> str:
    """A number for a Markdown table: 4 significant digits, thousands separated.

    >>> [format_number(v) for v in (3, 1.58114, 0.01234, 1234567.8, None, float("inf"))]
    ['3.000', '1.581', '0.01234', '1,234,568', '—', 'inf']
    """
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return _MISSING
    x = float(value)
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    magnitude = abs(x)
    if magnitude == 0:
        return "0"
    if magnitude >= 1000:
        return f"{x:,.0f}"
    if magnitude < 1e-3:
        return f"{x:.3e}"
    decimals = 3 - math.floor(math.log10(magnitude))
    return f"{x:.{decimals}f}"


def _format_ci(summary: Summary) -> str:
    if not (math.isfinite(summary.ci_low) and math.isfinite(summary.ci_high)):
        return _MISSING
    return f"[{format_number(summary.ci_low)}, {format_number(summary.ci_high)}]"


def _escape(text: str) -> str:
    """Text safe inside a Markdown table cell or list item, on one line."""
    flat = " ".join(text.split())
    return re.sub(r"([\\`*\[\]<>|#])", r"\\\1", flat)


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], numeric_from: int) -> list[str]:
    """A Markdown table; columns from ``numeric_from`` on are right-aligned."""
    align = ["---" if i < numeric_from else "---:" for i in range(len(header))]
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join(align) + " |"]
    lines.extend("| " + " | ".join(row) + " |" for row in rows)
    return lines


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9.]+", "_", text).strip("_") or "x"


def _seed_list(seeds: Sequence[Any], limit: int = 5) -> str:
    if not seeds:
        return "0"
    shown = ", ".join(format_value(s) for s in seeds[:limit])
    more = ", ..." if len(seeds) > limit else ""
    return f"{len(seeds)} ({shown}{more})"


# ---------------------------------------------------------------------- the sections


def _versions(runs: pa.Table) -> list[str]:
    lines = []
    if "mrexplore_version" in runs.column_names:
        used = sorted({str(v) for v in runs.column("mrexplore_version").to_pylist() if v})
        if used:
            lines.append(f"- runs made with mrexplore {', '.join(used)}")
    written = [f"mrexplore {__version__}", f"Python {platform.python_version()}"]
    for package in _PACKAGES:
        try:
            written.append(f"{package} {metadata.version(package)}")
        except metadata.PackageNotFoundError:
            continue
    lines.append(f"- report written with {', '.join(written)}")
    return lines


def _header(runs: pa.Table, varying: Sequence[str], usable: Sequence[int]) -> list[str]:
    n_runs = runs.num_rows
    lines = [f"{n_runs} runs, {len(usable)} used in the statistics."]
    if "status" in runs.column_names:
        counts: dict[str, int] = {}
        for status in runs.column("status").to_pylist():
            counts[str(status)] = counts.get(str(status), 0) + 1
        parts = ", ".join(f"{status}: {count}" for status, count in sorted(counts.items()))
        lines[0] += f" Status: {parts}."
    if SEED_COLUMN in runs.column_names:
        seeds = sorted({s for s in runs.column(SEED_COLUMN).to_pylist() if s is not None})
        if seeds:
            lines[0] += (
                f" {len(seeds)} seeds ({format_value(seeds[0])} to {format_value(seeds[-1])})."
            )
    lines.append("")
    fixed = [
        f"{name}={format_value(values[0])}"
        for name in runs.column_names
        if is_scenario_column(name)
        and name not in varying
        and len(values := runs.column(name).to_pylist()) > 0
        and len({repr(v) for v in values}) == 1
    ]
    lines.append(f"- varying: {', '.join(varying) if varying else 'nothing but the seed'}")
    if fixed:
        lines.append(f"- fixed: {_escape(', '.join(fixed))}")
    lines.extend(_versions(runs))
    return lines


def _failed_section(runs: pa.Table, varying: Sequence[str]) -> list[str]:
    if "status" not in runs.column_names:
        return []
    statuses = runs.column("status").to_pylist()
    failed = [row for row, status in enumerate(statuses) if status in EXCLUDED_STATUSES]
    if not failed:
        return []
    lines = [
        "## Failed runs",
        "",
        f"{len(failed)} {'run' if len(failed) == 1 else 'runs'} failed: no metrics, left "
        "out of every statistic below.",
        "",
    ]
    columns = runs.to_pydict()
    errors = columns.get("error", [None] * runs.num_rows)
    ids = columns.get("run_id", [None] * runs.num_rows)
    shown_columns = [*varying, SEED_COLUMN] if SEED_COLUMN in columns else list(varying)
    for row in failed[:MAX_FAILED_LISTED]:
        name = f"`{ids[row]}`" if ids[row] is not None else f"row {row}"
        where = ", ".join(f"{c}={format_value(columns[c][row])}" for c in shown_columns)
        error = str(errors[row]).strip().splitlines()[0] if errors[row] else "no error message"
        if len(error) > 160:
            error = error[:157] + "..."
        lines.append(f"- {name} ({_escape(where)}): {_escape(error)}")
    if len(failed) > MAX_FAILED_LISTED:
        lines.append(f"- ... and {len(failed) - MAX_FAILED_LISTED} more")
    lines.append("")
    return lines


def _condition_cells(condition: Condition) -> list[str]:
    return [_escape(format_value(value)) for _, value in condition.values]


def _metric_section(runs: pa.Table, metric: str, varying: Sequence[str]) -> list[str]:
    from mrexplore.viz.plots import label_for

    header = [*varying] if varying else ["condition"]
    header += ["n", "missing", "mean", "sd", "95% CI"]
    rows = []
    for condition, summary in summarize_by_condition(runs, metric, varying):
        cells = _condition_cells(condition) if varying else ["all runs"]
        rows.append(
            [
                *cells,
                str(summary.n),
                str(summary.n_missing),
                format_number(summary.mean),
                format_number(summary.sd),
                _format_ci(summary),
            ]
        )
    label = label_for(metric)
    heading = "### " + (label if label.startswith(metric) else f"{metric}: {label}")
    return [heading, "", *_table(header, rows, numeric_from=len(header) - 5), ""]


def _paired_section(
    runs: pa.Table, metric: str, varying: Sequence[str], baseline: str | None
) -> list[str]:
    diffs = paired_differences(runs, metric, between="strategy", baseline=baseline)
    if not diffs:
        return []
    other = [name for name in varying if name != "strategy"]
    header = [*other, "A", "B", "pairs", "mean A − B", "95% CI", "A < B", "unpaired", "missing"]
    rows = []
    for diff in diffs:
        values = dict(diff.condition)
        rows.append(
            [
                *(_escape(format_value(values[name])) for name in other),
                _escape(str(diff.a)),
                _escape(str(diff.b)),
                str(diff.n_pairs),
                format_number(diff.mean),
                _format_ci(diff.summary),
                _share(diff),
                _seed_list(diff.unpaired_seeds),
                _seed_list(diff.missing_seeds),
            ]
        )
    return [f"### {metric}", "", *_table(header, rows, numeric_from=len(other) + 2), ""]


def _share(diff: PairedDifference) -> str:
    if not math.isfinite(diff.share_a_less):
        return _MISSING
    return f"{100 * diff.share_a_less:.0f}%"


# ------------------------------------------------------------------------- figures


def _subgroups(runs: pa.Table, varying: Sequence[str], skip: Sequence[str]) -> list[Condition]:
    """Groups of usable runs equal in every varying column but those in ``skip``."""
    others = [name for name in varying if name not in skip]
    return group_conditions(runs, others, rows=usable_rows(runs))


def _with_hue(table: pa.Table) -> tuple[pa.Table, str]:
    """``table`` and its hue column: ``strategy``, or a constant one when absent."""
    if "strategy" in table.column_names:
        return table, "strategy"
    return table.append_column("runs", pa.array(["all"] * table.num_rows)), "runs"


def _figure_paths(
    groups: Sequence[Condition],
    stem: str,
    out_dir: Path,
    draw: Callable[[Condition, Path, str], Path | None],
    skip_in_label: Sequence[str],
) -> list[str]:
    """Draw one figure per group and return the Markdown lines that show them."""
    lines: list[str] = []
    for index, group in enumerate(groups[:MAX_FIGURES_PER_KIND]):
        name = f"{stem}.png" if len(groups) == 1 else f"{stem}_{index + 1:02d}.png"
        label = group.label(skip=skip_in_label)
        written = draw(group, out_dir / name, label)
        if written is None:
            continue
        caption = _escape(label if len(groups) > 1 else stem.replace("_", " "))
        lines.extend([f"![{caption}]({written.name})", ""])
    if len(groups) > MAX_FIGURES_PER_KIND:
        lines.extend(
            [f"({len(groups) - MAX_FIGURES_PER_KIND} more groups not drawn for {stem}.)", ""]
        )
    return lines


def _metric_figures(
    runs: pa.Table, metrics: Sequence[str], varying: Sequence[str], out_dir: Path
) -> list[str]:
    from mrexplore.viz.plots import plot_metric_vs

    if "robots" not in varying:
        return []
    groups = _subgroups(runs, varying, ["robots", "strategy"])
    lines = ["### Metrics against team size", ""]
    for metric in metrics:

        def draw(group: Condition, path: Path, label: str, metric: str = metric) -> Path:
            subset, hue = _with_hue(runs.take(list(group.rows)))
            summary = summary_table(subset, metric, ["robots", hue])
            title = f"{metric} vs team size" + (f" ({label})" if label != "all runs" else "")
            return plot_metric_vs(summary, path, x="robots", metric=metric, hue=hue, title=title)

        lines += _figure_paths(groups, f"{_slug(metric)}_vs_robots", out_dir, draw, [])
    return lines


def _curve_figures(
    runs: pa.Table, curves: pa.Table, varying: Sequence[str], out_dir: Path
) -> list[str]:
    from mrexplore.viz.plots import plot_curves

    if "run_id" not in runs.column_names or not {"run_id", "tick"} <= set(curves.column_names):
        return ["Curves not drawn: `run_id` or `tick` column missing.", ""]
    groups = _subgroups(runs, varying, ["strategy"])
    lines = []
    for y in CURVE_COLUMNS:
        if y not in curves.column_names:
            continue
        lines += [f"### {y} over time", ""]

        def draw(group: Condition, path: Path, label: str, y: str = y) -> Path:
            subset, hue = _with_hue(runs.take(list(group.rows)))
            title = f"{y} over time" + (f" ({label})" if label != "all runs" else "")
            return plot_curves(curves, subset, path, y=y, hue=hue, band="ci", title=title)

        lines += _figure_paths(groups, f"curves_{_slug(y)}", out_dir, draw, [])
    if lines:
        lines[0:0] = [
            "Mean over seeds; the shaded band is the 95% CI of the mean. A run that "
            "ended keeps its last value.",
            "",
        ]
    return lines


def _bytes_figure(runs: pa.Table, varying: Sequence[str], out_dir: Path) -> list[str]:
    from mrexplore.viz.plots import plot_bytes_by_type

    columns = [name for name in runs.column_names if name.startswith(BYTES_BY_TYPE_PREFIX)]
    if not columns:
        return []
    usable = usable_rows(runs)
    every_group = group_conditions(runs, varying, rows=usable)
    groups = every_group[:MAX_BARS]
    per_type = {name: metric_values(runs, name) for name in columns}
    per_condition: dict[str, dict[str, float]] = {}
    for group in groups:
        by_type = {}
        for name in columns:
            values = per_type[name][list(group.rows)]
            values = values[np.isfinite(values)]
            by_type[name[len(BYTES_BY_TYPE_PREFIX) :]] = (
                float(values.mean()) if values.size else 0.0
            )
        label = ", ".join(format_value(value) for _, value in group.values) or "all runs"
        per_condition[label] = by_type
    if not per_condition:
        return []
    path = plot_bytes_by_type(
        per_condition,
        out_dir / "bytes_by_type.png",
        title="mean bytes sent per run, by message type",
        xlabel=f"condition ({', '.join(varying)})" if varying else "",
    )
    lines = ["### Bytes by message type", "", f"![bytes by message type]({path.name})", ""]
    if len(every_group) > MAX_BARS:
        lines += [f"(First {MAX_BARS} of {len(every_group)} conditions shown.)", ""]
    return lines


# ---------------------------------------------------------------------------- entry


def _choose_metrics(runs: pa.Table, metrics: Sequence[str] | None) -> tuple[list[str], list[str]]:
    """The metrics to report and the default ones absent from the table."""
    if metrics is None:
        present = [m for m in DEFAULT_METRICS if m in runs.column_names]
        return present, [m for m in DEFAULT_METRICS if m not in runs.column_names]
    numeric = set(metric_columns(runs)) | {
        name
        for name in runs.column_names
        if pa.types.is_integer(runs.schema.field(name).type)
        or pa.types.is_floating(runs.schema.field(name).type)
    }
    unknown = [m for m in metrics if m not in numeric]
    if unknown:
        raise MrexploreInputError(
            f"no numeric column {', '.join(map(repr, unknown))} in runs; metrics: "
            f"{', '.join(metric_columns(runs)) or 'none'}"
        )
    return list(metrics), []


def check_baseline(runs: pa.Table, baseline: Any, where: str = "these runs") -> None:
    """Refuse a ``baseline`` that is not one of the strategies of ``runs``.

    ``where`` names the runs in the message (the results folder, on the command line).

    Raises:
        MrexploreInputError: ``baseline`` is not a strategy of ``runs``; the message
            lists the strategies there are.
    """
    if baseline is None:
        return
    found = (
        sorted({str(s) for s in runs.column("strategy").to_pylist() if s is not None})
        if "strategy" in runs.column_names
        else []
    )
    if str(baseline) not in found:
        raise MrexploreInputError(
            f"--baseline {baseline}: not a strategy of the runs in {where}; "
            f"strategies: {', '.join(found) or 'none'}"
        )


def write_report(
    runs: pa.Table,
    curves: pa.Table | None,
    out_dir: Path,
    *,
    metrics: Sequence[str] | None = None,
    title: str = "Sweep report",
    baseline: str | None = None,
) -> Path:
    """Write ``out_dir/report.md`` and its PNG figures; return the report's path.

    Args:
        runs: one row per run (see :mod:`mrexplore.experiments.stats` for the
            columns); failed runs are listed and left out of the statistics.
        curves: one row per run per sampled tick (``run_id``, ``tick``,
            ``coverage``, optionally ``wtv_8``, ``epv_8``); ``None`` = no curves.
        out_dir: folder of the report, created if needed; files of the same names
            are overwritten.
        metrics: metric columns to report; default :data:`DEFAULT_METRICS` that
            are present.
        title: the report's first heading.
        baseline: compare every strategy with this one; default every pair.

    Raises:
        MrexploreInputError: a named metric is not a numeric column of ``runs``, or
            ``baseline`` is not one of its strategies.
    """
    check_baseline(runs, baseline)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    chosen, absent = _choose_metrics(runs, metrics)
    varying = conditions(runs)
    usable = usable_rows(runs)

    lines = [f"# {_escape(title)}", ""]
    lines += _header(runs, varying, usable)
    lines.append("")
    lines += _failed_section(runs, varying)

    lines += [
        "## Metrics by condition",
        "",
        f"Per condition: n = runs with a value; missing = runs whose value is null (e.g. "
        f"T99 never reached, so n undercounts slow strategies); sd with n − 1; "
        f"{100 * CONFIDENCE:.0f}% CI of the mean from Student's t; {_MISSING} = undefined "
        "(CI and sd need n ≥ 2).",
        "",
    ]
    if absent:
        lines += [f"Not in this sweep: {', '.join(absent)}.", ""]
    for metric in chosen:
        lines += _metric_section(runs, metric, varying)

    strategies = (
        set(runs.column("strategy").take(usable).to_pylist())
        if "strategy" in runs.column_names
        else set()
    )
    if len(strategies) >= 2 and SEED_COLUMN in runs.column_names:
        lines += [
            "## Paired comparisons between strategies",
            "",
            "Same condition and same seed (same map and start): d = A − B per seed; "
            f"mean of d with its {100 * CONFIDENCE:.0f}% paired t CI. A < B: share of seeds "
            "where A's value is lower. Unpaired: seeds without a usable run of both "
            "(dropped); missing: seeds where the metric is null on a side (dropped).",
            "",
        ]
        for metric in chosen:
            lines += _paired_section(runs, metric, varying, baseline)

    figures = _metric_figures(runs, chosen, varying, out)
    if curves is not None and curves.num_rows:
        figures += _curve_figures(runs, curves, varying, out)
    figures += _bytes_figure(runs, varying, out)
    if figures:
        lines += ["## Figures", "", *figures]

    report = out / "report.md"
    report.write_text("\n".join(lines).rstrip("\n") + "\n", encoding="utf-8")
    logger.info("wrote %s", report)
    return report
