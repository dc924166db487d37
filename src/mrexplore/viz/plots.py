"""Figures of a sweep: metrics against a scenario value, curves over time, bytes by type,
the means of a reproduction's arms.

Every function draws one PNG with matplotlib (``Figure`` + ``FigureCanvasAgg``,
never pyplot, so no global backend or figure state), imported inside the function,
and returns the path written.

Each strategy has one colour and one marker in every figure
(:data:`STRATEGY_COLOURS`, :func:`strategy_colour`, :func:`strategy_marker`): the
colours are matplotlib's ``tab10``, and the markers tell the strategies apart for
readers who cannot tell the colours apart. Strategy ids outside the registry get a
colour from the Okabe-Ito palette chosen by a stable hash of the id, the same in
every figure and every Python process.

Error bars and bands are 95% confidence intervals of the mean over seeds (Student's
t, see :mod:`mrexplore.experiments.stats`) unless a figure's legend says otherwise.
"""

from __future__ import annotations

import math
import os
import textwrap
import zlib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError

if TYPE_CHECKING:
    import pyarrow as pa

    from mrexplore.experiments.stats import Summary

FloatArray = npt.NDArray[np.float64]

#: One colour per registered strategy (hex, matplotlib ``tab10``): the two
#: frontier baselines in grey and brown, the coordinated methods in the rest.
STRATEGY_COLOURS: dict[str, str] = {
    "random-frontier": "#7f7f7f",
    "nearest-frontier": "#8c564b",
    "burgard": "#1f77b4",
    "simmons": "#ff7f0e",
    "zlot-market": "#2ca02c",
    "sheng-bidding": "#d62728",
    "vazquez-network": "#9467bd",
    "kme": "#e377c2",
    "market-occupancy": "#bcbd22",
    "meier-polygon": "#17becf",
}

#: One marker per registered strategy, so that lines differ without colour too.
STRATEGY_MARKERS: dict[str, str] = {
    "random-frontier": "o",
    "nearest-frontier": "s",
    "burgard": "^",
    "simmons": "v",
    "zlot-market": "D",
    "sheng-bidding": "P",
    "vazquez-network": "X",
    "kme": "*",
    "market-occupancy": "<",
    "meier-polygon": ">",
}

#: Okabe-Ito colour-blind-safe palette (without black), for unknown strategy ids,
#: levels of other hue columns and message types.
OKABE_ITO: tuple[str, ...] = (
    "#E69F00",
    "#56B4E9",
    "#009E73",
    "#F0E442",
    "#0072B2",
    "#D55E00",
    "#CC79A7",
    "#999999",
)
# Past eight message types the colours repeat with a hatch pattern.
_HATCHES: tuple[str, ...] = ("", "//", "..", "xx")
_FALLBACK_MARKERS: tuple[str, ...] = ("o", "s", "^", "v", "D", "P", "X", "*", "<", ">", "h")

#: Axis labels with units for known metrics and scenario columns.
LABELS: dict[str, str] = {
    "T90": "T90: ticks to 90% coverage (ticks)",
    "T99": "T99: ticks to 99% coverage (ticks)",
    "T100": "T100: ticks to full coverage (ticks)",
    "ticks": "run length (ticks)",
    "total_distance": "total distance travelled (cells)",
    "bytes_total": "bytes sent (bytes)",
    "explored_fraction": "explored fraction (of explorable cells)",
    "coverage": "coverage (fraction of explorable cells)",
    "overlap": "overlap (sensings per sensed cell)",
    "group_diameter_mean": "mean group diameter (cells)",
    "subnetworks_mean": "mean number of sub-networks",
    "robots": "team size (robots)",
    "comm_range": "communication range (cells)",
    "sensor_range": "sensor range (cells)",
    "bandwidth": "bandwidth (bytes per tick per robot)",
    "latency": "latency (ticks per hop)",
    "loss": "loss probability",
    "tick": "time (ticks)",
    "group_diameter": "group diameter (cells)",
    "subnetworks": "number of sub-networks",
}


def label_for(name: str) -> str:
    """Axis label with unit for a metric or column name (the name itself if unknown).

    >>> label_for("T99"), label_for("wtv_8")
    ('T99: ticks to 99% coverage (ticks)', 'wtv_8')
    """
    return LABELS.get(name, name)


def _stable_index(name: str, n: int) -> int:
    return zlib.crc32(name.encode("utf-8")) % n


def strategy_colour(name: str) -> str:
    """The colour of strategy ``name`` (hex), the same in every figure.

    Registered strategies use :data:`STRATEGY_COLOURS`; any other id gets an
    Okabe-Ito colour chosen by the CRC-32 of the id (deterministic across runs).

    >>> strategy_colour("burgard")
    '#1f77b4'
    >>> strategy_colour("my-plugin") == strategy_colour("my-plugin")
    True
    """
    colour = STRATEGY_COLOURS.get(name)
    return colour if colour is not None else OKABE_ITO[_stable_index(name, len(OKABE_ITO))]


def strategy_marker(name: str) -> str:
    """The marker of strategy ``name``, the same in every figure."""
    marker = STRATEGY_MARKERS.get(name)
    if marker is not None:
        return marker
    return _FALLBACK_MARKERS[_stable_index(name, len(_FALLBACK_MARKERS))]


def _hue_styles(hue: str, levels: Sequence[Any]) -> dict[Any, tuple[str, str]]:
    """``level -> (colour, marker)``: strategy colours for ``strategy``, else by order."""
    if hue == "strategy":
        return {
            level: (strategy_colour(str(level)), strategy_marker(str(level))) for level in levels
        }
    return {
        level: (OKABE_ITO[i % len(OKABE_ITO)], _FALLBACK_MARKERS[i % len(_FALLBACK_MARKERS)])
        for i, level in enumerate(levels)
    }


def _text(value: Any) -> str:
    """A level as text, as the sweep summaries write it (imported here: pyarrow, scipy)."""
    from mrexplore.experiments.stats import format_value

    return format_value(value)


def _order(values: Sequence[Any]) -> list[Any]:
    """Distinct values, numbers ascending (inf last among them), then text, None last."""

    def key(value: Any) -> tuple[int, Any]:
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return (2, "")
        if isinstance(value, bool | int | float):
            return (0, value)
        return (1, str(value))

    return sorted(set(values), key=key)


def _columns(table: pa.Table | Mapping[str, Sequence[Any]]) -> dict[str, list[Any]]:
    if isinstance(table, Mapping):
        return {name: list(values) for name, values in table.items()}
    data: dict[str, list[Any]] = table.to_pydict()
    return data


def _require(data: Mapping[str, Any], names: Sequence[str], what: str) -> None:
    missing = [name for name in names if name not in data]
    if missing:
        raise MrexploreInputError(f"{what} lacks column(s) {', '.join(missing)}")


def _new_figure(width: float, height: float, dpi: int) -> Any:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


#: Inches added to a figure's width for a legend right of its axes.
LEGEND_WIDTH_IN = 1.8


def legend_outside(ax: Any, **options: Any) -> None:
    """The legend right of the axes, top-aligned: it covers no data, whatever the data."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, **options)


def figure_legend_outside(fig: Any, axes: Sequence[Any], **options: Any) -> None:
    """One legend for panels that share their series, right of all of them (the
    figure must use the constrained layout). Each label once, in first-seen order."""
    handles: dict[str, Any] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(label, handle)
    if handles:
        fig.legend(list(handles.values()), list(handles), loc="outside right upper", **options)


def _save(fig: Any, path: str | os.PathLike[str], dpi: int) -> Path:
    out = Path(path)
    fig.savefig(out, format="png", dpi=dpi)
    return out


def _as_float_array(values: Sequence[Any]) -> FloatArray:
    return np.array([math.nan if v is None else float(v) for v in values], dtype=np.float64)


# --------------------------------------------------------------- metric vs a value


def plot_metric_vs(
    runs_summary: pa.Table | Mapping[str, Sequence[Any]],
    path: str | os.PathLike[str],
    *,
    x: str = "robots",
    metric: str = "",
    hue: str = "strategy",
    title: str = "",
    dpi: int = 110,
) -> Path:
    """Plot a metric's mean against scenario column ``x``, one line per ``hue`` level.

    ``runs_summary`` has one row per condition with columns ``x``, ``hue``,
    ``mean``, ``ci_low`` and ``ci_high`` (and optionally ``n``), as made by
    :func:`mrexplore.experiments.stats.summary_table`; ``metric`` names the metric
    for the axis label (default: the table's ``metric`` metadata). Error bars are
    the 95% CI of the mean; a point without one (a single run) has none. Rows must
    differ only in ``x`` and ``hue``: filter other varying columns out first.

    A numeric ``x`` gets a numeric axis (lines of different hues nudged sideways
    so that their error bars do not hide each other); text or infinite values
    (``comm_range = inf``) get evenly spaced categories in sorted order.

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    if not metric and not isinstance(runs_summary, Mapping):
        meta = runs_summary.schema.metadata or {}
        metric = meta.get(b"metric", b"").decode("utf-8")
    data = _columns(runs_summary)
    _require(data, [x, hue, "mean", "ci_low", "ci_high"], "runs_summary")
    xs = data[x]
    numeric = all(
        isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) for v in xs
    )
    x_levels = _order(xs)
    if numeric:
        positions = {level: float(level) for level in x_levels}
        finite_steps = np.diff(np.array(x_levels, dtype=np.float64))
        step = float(finite_steps.min()) if finite_steps.size else 1.0
    else:
        positions = {level: float(i) for i, level in enumerate(x_levels)}
        step = 1.0
    hue_levels = _order(data[hue])
    styles = _hue_styles(hue, hue_levels)
    dodge = 0.08 * step if len(hue_levels) > 1 else 0.0

    fig = _new_figure(6.4 + LEGEND_WIDTH_IN, 4.2, dpi)
    ax = fig.add_subplot()
    mean = _as_float_array(data["mean"])
    low = _as_float_array(data["ci_low"])
    high = _as_float_array(data["ci_high"])
    for i, level in enumerate(hue_levels):
        rows = [r for r, v in enumerate(data[hue]) if v == level]
        rows.sort(key=lambda r: positions[xs[r]])
        offset = (i - (len(hue_levels) - 1) / 2) * dodge
        px = np.array([positions[xs[r]] + offset for r in rows])
        m = mean[rows]
        # A missing interval (n = 1) draws no bar; matplotlib needs 0, not nan.
        below = np.where(np.isfinite(low[rows]), m - low[rows], 0.0)
        above = np.where(np.isfinite(high[rows]), high[rows] - m, 0.0)
        colour, marker = styles[level]
        ax.errorbar(
            px,
            m,
            yerr=np.vstack([np.nan_to_num(below), np.nan_to_num(above)]),
            color=colour,
            marker=marker,
            ms=6,
            lw=1.6,
            capsize=3,
            label=_text(level),
        )
    ax.set_xticks([positions[level] for level in x_levels])
    ax.set_xticklabels([_text(level) for level in x_levels])
    ax.set_xlabel(label_for(x))
    ax.set_ylabel(label_for(metric) if metric else "mean")
    ax.grid(True, alpha=0.3)
    ax.set_title(title or f"{metric or 'metric'} vs {x} (mean, error bars: 95% CI)", fontsize=10)
    legend_outside(ax, title=hue, fontsize=8, title_fontsize=8)
    return _save(fig, path, dpi)


# ------------------------------------------------------------------- curves in time


def _step_matrix(
    run_index: npt.NDArray[np.intp], ticks: FloatArray, values: FloatArray, n_runs: int
) -> tuple[FloatArray, FloatArray]:
    """Resample each run's samples onto the union of all ticks.

    At each grid tick a run has its last sample at or before that tick (so a run
    that ended keeps its last value) and nan before its first sample.
    """
    grid = np.unique(ticks)
    matrix = np.full((n_runs, grid.size), np.nan)
    order = np.lexsort((ticks, run_index))
    run_sorted, ticks_sorted, values_sorted = run_index[order], ticks[order], values[order]
    bounds = np.searchsorted(run_sorted, np.arange(n_runs + 1))
    for run in range(n_runs):
        start, stop = bounds[run], bounds[run + 1]
        if start == stop:
            continue
        at = np.searchsorted(ticks_sorted[start:stop], grid, side="right") - 1
        valid = at >= 0
        matrix[run, valid] = values_sorted[start:stop][at[valid]]
    return grid, matrix


def _band_stats(
    matrix: FloatArray, band: Literal["ci", "range"]
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per column: mean, and the band's low and high edges (nan where undefined)."""
    from scipy import stats as scipy_stats

    finite = np.isfinite(matrix)
    n = finite.sum(axis=0)
    filled = np.where(finite, matrix, 0.0)
    mean = np.divide(filled.sum(axis=0), n, out=np.full(n.shape, np.nan), where=n > 0)
    if band == "range":
        low = np.where(finite, matrix, np.inf).min(axis=0)
        high = np.where(finite, matrix, -np.inf).max(axis=0)
        low[n == 0] = np.nan
        high[n == 0] = np.nan
        return mean, low, high
    squares = np.where(finite, (matrix - np.where(n > 0, mean, 0.0)) ** 2, 0.0).sum(axis=0)
    many = n > 1
    var = np.divide(squares, n - 1, out=np.full(n.shape, np.nan), where=many)
    t = np.full(n.shape, np.nan)
    t[many] = scipy_stats.t.ppf(0.975, n[many] - 1)
    half = np.full(n.shape, np.nan)
    half[many] = t[many] * np.sqrt(var[many] / n[many])
    return mean, mean - half, mean + half


def plot_curves(
    curves: pa.Table,
    runs: pa.Table,
    path: str | os.PathLike[str],
    *,
    y: str = "coverage",
    hue: str = "strategy",
    band: Literal["ci", "range"] = "ci",
    title: str = "",
    dpi: int = 110,
) -> Path:
    """Plot column ``y`` of ``curves`` against tick: mean over the runs of each ``hue``.

    ``curves`` has ``run_id``, ``tick`` and ``y``; ``runs`` maps ``run_id`` to the
    ``hue`` column. Only runs listed in ``runs`` are drawn, so pass the runs of one
    condition (all other scenario columns equal) with failed runs filtered out.

    Runs are sampled at their own ticks and end at different times: each run is
    carried onto the union of all sampled ticks by holding its last sample (a run
    that finished keeps its final value), and the mean at a tick is over the runs
    with a sample at or before it. The shaded band is, with ``band="ci"``, the 95%
    t confidence interval of that mean (none where a single run is left), with
    ``band="range"`` the minimum to maximum over the runs; the legend says which.

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    import pyarrow.compute as pc

    if band not in ("ci", "range"):
        raise MrexploreInputError(f"band must be 'ci' or 'range', got {band!r}")
    for table, names, what in (
        (curves, ("run_id", "tick", y), "curves"),
        (runs, ("run_id", hue), "runs"),
    ):
        _require(dict.fromkeys(table.column_names), names, what)
    run_ids = runs.column("run_id").to_pylist()
    hues = runs.column(hue).to_pylist()
    position = {run_id: i for i, run_id in enumerate(run_ids)}
    kept = curves.filter(pc.is_in(curves.column("run_id"), value_set=runs.column("run_id")))
    run_index = np.array([position[r] for r in kept.column("run_id").to_pylist()], dtype=np.intp)
    ticks = np.asarray(
        pc.cast(kept.column("tick"), "float64").to_numpy(zero_copy_only=False), dtype=np.float64
    )
    values = np.asarray(
        pc.cast(kept.column(y), "float64").to_numpy(zero_copy_only=False), dtype=np.float64
    )

    fig = _new_figure(6.4 + LEGEND_WIDTH_IN, 4.2, dpi)
    ax = fig.add_subplot()
    levels = _order(hues)
    styles = _hue_styles(hue, levels)
    for level in levels:
        members = [i for i, h in enumerate(hues) if h == level]
        local = np.full(len(run_ids), -1, dtype=np.intp)
        local[members] = np.arange(len(members))
        mine = local[run_index] >= 0
        if not mine.any():
            continue
        grid, matrix = _step_matrix(local[run_index[mine]], ticks[mine], values[mine], len(members))
        mean, low, high = _band_stats(matrix, band)
        colour, _ = styles[level]
        n_with_data = int(np.count_nonzero(np.isfinite(matrix).any(axis=1)))
        ax.step(
            grid,
            mean,
            where="post",
            color=colour,
            lw=1.6,
            label=f"{_text(level)} (n={n_with_data})",
        )
        ax.fill_between(grid, low, high, step="post", color=colour, alpha=0.2, lw=0)
    band_text = "95% CI of the mean" if band == "ci" else "min-max over runs"
    ax.set_xlabel(label_for("tick"))
    ax.set_ylabel(label_for(y))
    ax.grid(True, alpha=0.3)
    ax.set_title(title or f"{y} over time (mean over seeds, band: {band_text})", fontsize=10)
    if levels:
        legend_outside(ax, title=f"{hue} (band: {band_text})", fontsize=8, title_fontsize=8)
    return _save(fig, path, dpi)


def plot_group_diameter(
    curves: pa.Table,
    runs: pa.Table,
    path: str | os.PathLike[str],
    *,
    hue: str = "strategy",
    band: Literal["ci", "range"] = "ci",
    title: str = "",
    dpi: int = 110,
) -> Path:
    """Group diameter over time (Sheng et al., Fig. 11): mean over the runs of each ``hue``.

    The group diameter is the largest distance in cells between two robots at a
    tick (``group_diameter`` in the ``curves`` table and in ``trace.npz``); it
    shows whether a strategy keeps the team together (a connected network) or
    spreads it out. Bands and the handling of runs of different lengths are those
    of :func:`plot_curves`.

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    band_text = "95% CI of the mean" if band == "ci" else "min-max over runs"
    return plot_curves(
        curves,
        runs,
        path,
        y="group_diameter",
        hue=hue,
        band=band,
        title=title or f"group diameter over time (mean over seeds, band: {band_text})",
        dpi=dpi,
    )


# --------------------------------------------------------------------- bytes by type


def plot_bytes_by_type(
    bytes_by_type_per_condition: Mapping[str, Mapping[str, float]],
    path: str | os.PathLike[str],
    *,
    title: str = "",
    xlabel: str = "",
    dpi: int = 110,
) -> Path:
    """Stacked bars: for each condition (one bar), the bytes sent per message type.

    ``bytes_by_type_per_condition`` maps a condition label (the bar's tick label)
    to ``{message type: bytes}``, typically the mean over the condition's seeds.
    Message types get Okabe-Ito colours in sorted order, the same in every bar
    (hatched after the eighth type).

    Every bar fits its axis (the top is set to 5% above the tallest stack) and the
    legend stands outside the axes, right of them, so it covers no bar.

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    fig = bytes_by_type_figure(bytes_by_type_per_condition, title=title, xlabel=xlabel, dpi=dpi)
    return _save(fig, path, dpi)


def bytes_by_type_figure(
    bytes_by_type_per_condition: Mapping[str, Mapping[str, float]],
    *,
    title: str = "",
    xlabel: str = "",
    dpi: int = 110,
) -> Any:
    """The figure of :func:`plot_bytes_by_type`, not yet saved."""
    if not bytes_by_type_per_condition:
        raise MrexploreInputError("plot_bytes_by_type needs at least one condition")
    labels = list(bytes_by_type_per_condition)
    types = sorted({t for by_type in bytes_by_type_per_condition.values() for t in by_type})
    heights = np.array(
        [[float(bytes_by_type_per_condition[c].get(t, 0.0)) for c in labels] for t in types],
        dtype=np.float64,
    ).reshape(len(types), len(labels))
    if not np.all(np.isfinite(heights)) or np.any(heights < 0):
        raise MrexploreInputError("bytes by type must be finite and non-negative")

    fig = _new_figure(max(5.0, 1.0 + 0.6 * len(labels)) + LEGEND_WIDTH_IN, 4.4, dpi)
    ax = fig.add_subplot()
    xs = np.arange(len(labels), dtype=np.float64)
    bottom = np.zeros(len(labels))
    for i, message_type in enumerate(types):
        ax.bar(
            xs,
            heights[i],
            bottom=bottom,
            color=OKABE_ITO[i % len(OKABE_ITO)],
            hatch=_HATCHES[(i // len(OKABE_ITO)) % len(_HATCHES)],
            edgecolor="white",
            lw=0.5,
            label=message_type,
        )
        bottom += heights[i]
    ax.set_xticks(xs)
    ax.set_xticklabels(
        labels,
        rotation=30 if len(labels) > 3 else 0,
        ha="right" if len(labels) > 3 else "center",
        fontsize=8,
    )
    if xlabel:
        ax.set_xlabel(xlabel)
    ax.set_ylabel("bytes sent (bytes)")
    ax.grid(True, axis="y", alpha=0.3)
    ax.set_title(title or "bytes sent by message type", fontsize=10)
    tallest = float(bottom.max()) if bottom.size else 0.0
    ax.set_ylim(0.0, 1.05 * tallest if tallest > 0 else 1.0)
    if types:
        legend_outside(ax, title="message type", fontsize=8, title_fontsize=8)
    return fig


# ----------------------------------------------------------- means of arms, by panel


_LINE_STYLE: dict[str, Any] = {"marker": "o", "ms": 4, "lw": 1.3, "capsize": 2}


def plot_arm_lines(
    panels: Mapping[str, Mapping[str, Mapping[Any, Summary]]],
    path: str | os.PathLike[str],
    *,
    xlabel: str,
    ylabel: str,
    title: str,
    colours: Mapping[str, str],
    log: bool = False,
    logx: bool = False,
) -> Path | None:
    """One subplot per panel (``panel -> arm -> x -> summary``): the mean against x, one
    line per arm, 95% CI bars, the legend right of the panels; ``log`` / ``logx``: a
    logarithmic y / x axis. With one panel the title stands above its axes, clear of the
    legend (the panel's name, if any, after it). ``None`` when there is no panel."""
    from matplotlib.ticker import FuncFormatter

    if not panels:
        return None
    fig = _new_figure(3.6 * len(panels) + LEGEND_WIDTH_IN, 3.6, 110)
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    for ax, (panel, arms) in zip(axes, panels.items(), strict=True):
        xs_all: set[Any] = set()
        for i, (arm, points) in enumerate(arms.items()):
            kept = [(x, s) for x, s in points.items() if math.isfinite(s.mean)]
            kept = [(x, s) for x, s in kept if s.mean > 0] if log else kept
            if not kept:
                continue
            xs_all |= {x for x, _ in kept}
            xs = np.array([x for x, _ in kept], dtype=np.float64)
            dodge = (i - len(arms) / 2) * 0.06  # arms side by side; on a log axis, in ratio
            xs = xs * 10 ** (dodge / 8) if logx else xs + dodge
            means = np.array([s.mean for _, s in kept])
            below = np.nan_to_num(np.array([s.mean - s.ci_low for _, s in kept]))
            above = np.nan_to_num(np.array([s.ci_high - s.mean for _, s in kept]))
            below = np.minimum(below, means * 0.999) if log else below
            yerr, colour = np.vstack([below, above]), colours.get(arm, "#000000")
            ax.errorbar(xs, means, yerr=yerr, color=colour, label=arm, **_LINE_STYLE)
        if log:
            ax.set_yscale("log")
        if logx:  # ticks at the decades, labelled as numbers
            ax.set_xscale("log")
            ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))
        else:
            ax.set_xticks(sorted(xs_all))
        ax.set_xlabel(xlabel, fontsize=8)
        ax.set_title(panel, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
    figure_legend_outside(fig, axes, fontsize=7)
    axes[0].set_ylabel(ylabel, fontsize=8)
    subtitle, panel = "(mean over seeds, error bars: 95% CI)", next(iter(panels))
    if len(panels) > 1:
        fig.suptitle(f"{title}\n{subtitle}", fontsize=10)
    else:  # above the axes, as wide as they are: clear of the legend at their right
        heading = f"{title}: {panel}" if panel not in ("", title) else title
        axes[0].set_title(f"{textwrap.fill(heading, 40)}\n{subtitle}", fontsize=9)
    return _save(fig, path, 110)
