"""Sweep statistics, plots and the Markdown report, on hand-made tables."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.report import format_number, write_report
from mrexplore.experiments.stats import (
    SCENARIO_COLUMNS,
    conditions,
    group_conditions,
    is_scenario_column,
    metric_columns,
    metric_values,
    paired_differences,
    summarize_by_condition,
    summarize_metric,
    summary_table,
)
from mrexplore.viz.plots import (
    STRATEGY_COLOURS,
    plot_bytes_by_type,
    plot_curves,
    plot_metric_vs,
    strategy_colour,
    strategy_marker,
)

T_975_4 = 2.7764451051977987  # scipy.stats.t.ppf(0.975, 4), checked against tables
SEEDS = range(5)


def _row(strategy: str, robots: int, seed: int, ticks: float | None, **extra: Any) -> dict:
    row: dict[str, Any] = {
        "run_id": f"{strategy}-{robots}-{seed}",
        "map": "office",
        "strategy": strategy,
        "robots": robots,
        "comm_range": math.inf,
        "seed": seed,
        "status": "complete",
        "error": None,
        "ticks": ticks,
        "T99": ticks,
        "total_distance": None if ticks is None else 3.0 * ticks,
        "bytes_total": None if ticks is None else 1000.0 * ticks,
        "wall_time_s": 0.5,
        "mrexplore_version": "0.1.0",
    }
    row.update(extra)
    return row


def _sweep_rows() -> list[dict]:
    """kme ticks 1..5 (2 robots) and 2..10 (4 robots); burgard = kme + 10 on each seed.

    kme with 4 robots never reaches 99% on seed 4 (T99 null); burgard with 2 robots
    has an extra seed 5 that failed.
    """
    rows = []
    for robots, scale in ((2, 1), (4, 2)):
        for seed in SEEDS:
            kme = float(scale * (seed + 1))
            extra = {"T99": None, "status": "max_ticks"} if (robots, seed) == (4, 4) else {}
            rows.append(_row("kme", robots, seed, kme, **extra))
            rows.append(_row("burgard", robots, seed, kme + 10))
    failed = _row("burgard", 2, 5, None, status="failed", error="RuntimeError: boom\nline 2")
    failed.update(ticks=None, T99=None)
    rows.append(failed)
    return rows


@pytest.fixture
def runs() -> pa.Table:
    return pa.Table.from_pylist(_sweep_rows())


@pytest.fixture
def curves(runs: pa.Table) -> pa.Table:
    """Coverage rising linearly to 1 at each run's last tick, sampled every tick."""
    data: dict[str, list[Any]] = {"run_id": [], "tick": [], "coverage": [], "wtv_8": []}
    for row in runs.to_pylist():
        if row["status"] == "failed":
            continue
        last = int(row["ticks"])
        for tick in range(last + 1):
            data["run_id"].append(row["run_id"])
            data["tick"].append(tick)
            data["coverage"].append(tick / last)
            data["wtv_8"].append(1.0 - tick / last)
    return pa.table(data)


# ------------------------------------------------------------------------ summaries


def test_summary_matches_hand_computation() -> None:
    s = summarize_metric([1, 2, 3, 4, 5])
    sd = math.sqrt(10 / 4)
    half = T_975_4 * sd / math.sqrt(5)
    assert (s.n, s.n_missing) == (5, 0)
    assert s.mean == pytest.approx(3.0)
    assert s.sd == pytest.approx(1.5811, abs=1e-4)
    assert half == pytest.approx(1.963, abs=1e-3)
    assert (s.ci_low, s.ci_high) == pytest.approx((3 - half, 3 + half))


def test_summary_drops_and_counts_missing_values() -> None:
    s = summarize_metric([None, 1.0, float("nan"), 3.0, float("inf")])
    assert (s.n, s.n_missing, s.mean) == (2, 3, 2.0)
    assert s.ci_low < 2.0 < s.ci_high


def test_summary_of_one_value_has_no_interval() -> None:
    s = summarize_metric([7])
    assert (s.n, s.mean) == (1, 7.0)
    assert math.isnan(s.sd) and math.isnan(s.ci_low) and math.isnan(s.ci_high)
    empty = summarize_metric([None])
    assert (empty.n, empty.n_missing) == (0, 1) and math.isnan(empty.mean)


def test_summary_accepts_arrays() -> None:
    a = summarize_metric(np.array([1, 2, 3, 4, 5]))
    b = summarize_metric(pa.array([1, 2, 3, 4, 5, None]))
    assert (a.mean, a.sd) == (b.mean, b.sd) and b.n_missing == 1


def test_summary_rejects_bad_confidence() -> None:
    with pytest.raises(MrexploreInputError, match="confidence"):
        summarize_metric([1, 2], confidence=95)


@settings(max_examples=60, deadline=None)
@given(
    data=st.lists(
        st.floats(min_value=-1e3, max_value=1e3, allow_nan=False), min_size=2, max_size=20
    ),
    copies=st.integers(min_value=2, max_value=6),
)
def test_ci_contains_mean_and_shrinks_when_data_repeats(data: list[float], copies: int) -> None:
    once = summarize_metric(data)
    repeated = summarize_metric(data * copies)
    for s in (once, repeated):
        assert s.ci_low <= s.mean <= s.ci_high
    assert repeated.mean == pytest.approx(once.mean, abs=1e-9)
    assert repeated.half_width <= once.half_width * (1 + 1e-9) + 1e-9


# ----------------------------------------------------------------------- conditions


def test_column_classification(runs: pa.Table) -> None:
    assert "robots" in SCENARIO_COLUMNS and "seed" not in SCENARIO_COLUMNS
    assert is_scenario_column("param_w3") and is_scenario_column("share_split_rate")
    assert metric_columns(runs) == ["ticks", "T99", "total_distance", "bytes_total"]


def test_conditions_are_the_varying_scenario_columns(runs: pa.Table) -> None:
    assert conditions(runs) == ["strategy", "robots"]
    groups = group_conditions(runs)
    assert [g.label() for g in groups] == [
        "strategy=burgard, robots=2",
        "strategy=burgard, robots=4",
        "strategy=kme, robots=2",
        "strategy=kme, robots=4",
    ]
    assert [len(g.rows) for g in groups] == [6, 5, 5, 5]


def test_map_seed_following_the_seed_is_not_a_condition() -> None:
    table = pa.table({"strategy": ["a", "a", "b", "b"], "seed": [0, 1, 0, 1]})
    per_seed = table.append_column("map_seed", pa.array([10, 11, 10, 11]))
    assert conditions(per_seed) == ["strategy"]
    crossed = table.append_column("map_seed", pa.array([10, 10, 11, 11]))
    assert conditions(crossed) == ["strategy", "map_seed"]


def test_failed_runs_are_left_out_of_summaries(runs: pa.Table) -> None:
    by_label = {c.label(): s for c, s in summarize_by_condition(runs, "ticks")}
    kme2 = by_label["strategy=kme, robots=2"]
    assert (kme2.n, kme2.mean) == (5, 3.0)
    assert kme2.sd == pytest.approx(1.5811, abs=1e-4)
    burgard2 = by_label["strategy=burgard, robots=2"]
    assert (burgard2.n, burgard2.n_missing, burgard2.mean) == (5, 0, 13.0)
    t99 = {c.label(): s for c, s in summarize_by_condition(runs, "T99")}
    assert (t99["strategy=kme, robots=4"].n, t99["strategy=kme, robots=4"].n_missing) == (4, 1)


def test_summary_table_columns(runs: pa.Table) -> None:
    table = summary_table(runs, "ticks", ["robots", "strategy"])
    assert table.column_names == [
        "robots",
        "strategy",
        "n",
        "n_missing",
        "mean",
        "sd",
        "ci_low",
        "ci_high",
    ]
    assert table.schema.metadata == {b"metric": b"ticks"}
    assert table.column("robots").to_pylist() == [2, 2, 4, 4]


def test_unknown_metric_is_an_input_error(runs: pa.Table) -> None:
    with pytest.raises(MrexploreInputError, match="no metric column 'T42'"):
        summarize_by_condition(runs, "T42")


# -------------------------------------------------------------- paired differences


def test_constant_offset_gives_exact_difference(runs: pa.Table) -> None:
    diffs = paired_differences(runs, "ticks")
    assert [(dict(d.condition), d.a, d.b) for d in diffs] == [
        ({"robots": 2}, "burgard", "kme"),
        ({"robots": 4}, "burgard", "kme"),
    ]
    for d in diffs:
        assert d.n_pairs == 5
        assert (d.mean, d.summary.ci_low, d.summary.ci_high) == (10.0, 10.0, 10.0)
        assert d.share_a_less == 0.0
    # The failed burgard run on seed 5 has no kme partner: dropped and reported.
    assert diffs[0].unpaired_seeds == (5,)
    assert diffs[1].unpaired_seeds == ()


def test_baseline_reverses_the_difference(runs: pa.Table) -> None:
    diffs = paired_differences(runs, "ticks", baseline="burgard")
    assert [(d.a, d.b, d.mean, d.share_a_less) for d in diffs] == [
        ("kme", "burgard", -10.0, 1.0),
        ("kme", "burgard", -10.0, 1.0),
    ]
    assert paired_differences(runs, "ticks", baseline="simmons") == []


def test_unpaired_and_missing_seeds_are_dropped(runs: pa.Table) -> None:
    keep = [r for r in _sweep_rows() if not (r["strategy"] == "kme" and r["seed"] == 0)]
    diffs = paired_differences(pa.Table.from_pylist(keep), "T99")
    two, four = diffs
    assert (two.n_pairs, two.unpaired_seeds, two.missing_seeds) == (4, (0, 5), ())
    # robots=4: seed 0 unpaired, seed 4 has no kme T99 (never reached).
    assert (four.n_pairs, four.unpaired_seeds, four.missing_seeds) == (3, (0,), (4,))
    assert four.mean == 10.0


def test_paired_differences_with_noise() -> None:
    a = [3.0, 5.0, 4.0, 8.0]
    b = [1.0, 4.0, 4.5, 2.0]
    table = pa.table({"strategy": ["a"] * 4 + ["b"] * 4, "seed": [0, 1, 2, 3] * 2, "ticks": a + b})
    (d,) = paired_differences(table, "ticks")
    expected = summarize_metric(np.subtract(a, b))
    assert d.summary == expected
    assert d.share_a_less == 0.25


def test_paired_differences_need_seeds() -> None:
    with pytest.raises(MrexploreInputError, match="'seed'"):
        paired_differences(pa.table({"strategy": ["a"], "ticks": [1]}), "ticks")


# --------------------------------------------------------------------------- plots


def test_strategy_colours_are_fixed_and_distinct() -> None:
    assert len(STRATEGY_COLOURS) == 10
    assert len(set(STRATEGY_COLOURS.values())) == 10
    assert strategy_colour("kme") == STRATEGY_COLOURS["kme"]
    assert strategy_colour("plugin-x") == strategy_colour("plugin-x")
    assert strategy_colour("plugin-x").startswith("#")
    assert strategy_marker("plugin-x") == strategy_marker("plugin-x")


def _is_png(path: Path) -> bool:
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_functions_write_pngs(tmp_path: Path, runs: pa.Table, curves: pa.Table) -> None:
    summary = summary_table(runs, "T99", ["robots", "strategy"])
    written = [
        plot_metric_vs(summary, tmp_path / "m.png", x="robots"),
        plot_metric_vs(
            {
                "comm_range": [5.0, math.inf],
                "strategy": ["kme", "kme"],
                "mean": [1, 2],
                "ci_low": [0.5, math.nan],
                "ci_high": [1.5, math.nan],
            },
            tmp_path / "categorical.png",
            x="comm_range",
            metric="T99",
        ),
        plot_curves(curves, runs.filter(pc.equal(runs["robots"], 2)), tmp_path / "c.png"),
        plot_curves(curves, runs, tmp_path / "r.png", y="wtv_8", band="range"),
        plot_bytes_by_type(
            {"kme": {"map": 500.0, "bid": 20.0}, "burgard": {"map": 400.0, "assign": 5.0}},
            tmp_path / "b.png",
        ),
        plot_bytes_by_type(  # more types than colours: hatched
            {f"c{i}": {f"type{t}": float(t + i) for t in range(11)} for i in range(6)},
            tmp_path / "many.png",
            xlabel="condition",
        ),
    ]
    for path in written:
        assert path.exists() and _is_png(path)


def test_every_figure_holds_its_data_and_no_legend_covers_it(
    tmp_path: Path, runs: pa.Table, curves: pa.Table, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each figure type from hand-made tables: every plotted point lies inside its
    axis limits and the legend stands outside the axes (issue 14, item 4)."""
    from mrexplore.viz import plots

    figures: list[Any] = []
    monkeypatch.setattr(plots, "_save", lambda fig, path, dpi: figures.append(fig) or Path(path))
    summary = summary_table(runs, "T99", ["robots", "strategy"])
    plot_metric_vs(summary, tmp_path / "m.png", x="robots")
    plot_curves(curves, runs, tmp_path / "r.png", y="wtv_8", band="range")
    plot_bytes_by_type({"a": {"map": 9e5, "bid": 1e5}, "b": {"map": 1e5}}, tmp_path / "b.png")
    assert len(figures) == 3
    for fig in figures:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        ax = fig.axes[0]
        low, high = ax.get_ylim()
        for line in ax.get_lines():
            ys = np.asarray(line.get_ydata(), dtype=np.float64)
            ys = ys[np.isfinite(ys)]
            assert ys.size == 0 or (low <= ys.min() and ys.max() <= high)
        for bar in ax.patches:
            assert low <= bar.get_y() + bar.get_height() <= high
        legend = ax.get_legend()
        assert legend is not None
        assert legend.get_window_extent(renderer).x0 >= ax.get_window_extent(renderer).x1


def test_curves_hold_the_last_value_of_finished_runs() -> None:
    from mrexplore.viz.plots import _step_matrix

    run = np.array([0, 0, 1, 1, 1], dtype=np.intp)
    ticks = np.array([0.0, 10.0, 0.0, 10.0, 20.0])
    values = np.array([0.1, 0.5, 0.2, 0.4, 0.9])
    grid, matrix = _step_matrix(run, ticks, values, 2)
    assert grid.tolist() == [0.0, 10.0, 20.0]
    assert matrix.tolist() == [[0.1, 0.5, 0.5], [0.2, 0.4, 0.9]]


def test_plots_reject_missing_columns(tmp_path: Path) -> None:
    with pytest.raises(MrexploreInputError, match="ci_low"):
        plot_metric_vs({"robots": [1], "strategy": ["a"], "mean": [1.0]}, tmp_path / "x.png")


# -------------------------------------------------------------------------- report


def test_format_number() -> None:
    assert format_number(3) == "3.000"
    assert format_number(10.0) == "10.00"
    assert format_number(123456.0) == "123,456"
    assert format_number(float("nan")) == "—"


def test_write_report(tmp_path: Path, runs: pa.Table, curves: pa.Table) -> None:
    report = write_report(runs, curves, tmp_path / "out", title="Test sweep")
    assert report == tmp_path / "out" / "report.md"
    text = report.read_text(encoding="utf-8")
    assert text.startswith("# Test sweep\n")
    assert "21 runs, 20 used in the statistics" in text
    assert "complete: 19, failed: 1, max_ticks: 1" in text
    # The failed run is listed with its error's first line, and left out of the stats.
    assert "`burgard-2-5`" in text and "RuntimeError: boom" in text and "line 2" not in text
    # kme, 2 robots, ticks 1..5: mean 3, sd 1.581, CI [1.037, 4.963].
    assert "| kme | 2 | 5 | 0 | 3.000 | 1.581 | [1.037, 4.963] |" in text
    # burgard = kme + 10 on every seed: difference exactly 10, zero-width CI.
    assert "| 2 | burgard | kme | 5 | 10.00 | [10.00, 10.00] | 0% | 1 (5) | 0 |" in text
    assert "| 4 | burgard | kme | 4 | 10.00 | [10.00, 10.00] | 0% | 0 | 1 (4) |" in text
    assert "Not in this sweep: wtv_8_final." in text
    pngs = sorted(p.name for p in report.parent.glob("*.png"))
    assert pngs == [
        "T99_vs_robots.png",
        "bytes_total_vs_robots.png",
        "curves_coverage_01.png",
        "curves_coverage_02.png",
        "curves_wtv_8_01.png",
        "curves_wtv_8_02.png",
        "ticks_vs_robots.png",
        "total_distance_vs_robots.png",
    ]
    for name in pngs:
        assert f"]({name})" in text
        assert _is_png(report.parent / name)


def test_report_without_curves_or_second_strategy(tmp_path: Path) -> None:
    rows = [_row("kme", 4, seed, float(seed + 1)) for seed in SEEDS]
    report = write_report(pa.Table.from_pylist(rows), None, tmp_path, metrics=["ticks"])
    text = report.read_text(encoding="utf-8")
    assert "| all runs | 5 | 0 | 3.000 | 1.581 | [1.037, 4.963] |" in text
    assert "Paired comparisons" not in text and "Failed runs" not in text
    assert not list(tmp_path.glob("*.png"))


def test_report_bytes_by_type_and_several_groups(tmp_path: Path) -> None:
    rows = [
        _row(s, r, seed, float(seed + r), comm_range=c, bytes_by_type_map=100.0 * r)
        for s in ("kme", "burgard")
        for r in (2, 4)
        for c in (10.0, math.inf)
        for seed in SEEDS
    ]
    report = write_report(pa.Table.from_pylist(rows), None, tmp_path, metrics=["ticks"])
    text = report.read_text(encoding="utf-8")
    assert "![comm_range=10](ticks_vs_robots_01.png)" in text
    assert "![comm_range=inf](ticks_vs_robots_02.png)" in text
    assert (tmp_path / "bytes_by_type.png").exists()


def test_report_rejects_unknown_metric(tmp_path: Path, runs: pa.Table) -> None:
    with pytest.raises(MrexploreInputError, match="'T42'"):
        write_report(runs, None, tmp_path, metrics=["T42"])


def test_a_metric_no_run_reached_is_all_nan_not_an_error() -> None:
    # A sweep whose runs all stop before 99% coverage stores T99 as a null column.
    runs = pa.table({"strategy": ["a", "b"], "T99": pa.array([None, None], type=pa.null())})
    assert np.isnan(metric_values(runs, "T99")).all()


def test_bytes_by_type_bars_fit_their_axis_and_the_legend_covers_none() -> None:
    """Table 4 of sheng2006 --quick cut its tallest bars and put the legend on them."""
    from mrexplore.viz.plots import bytes_by_type_figure

    table = {
        "w3=0 without": {"map_full": 9.0e5, "map_update": 1.2e5},
        "w3=0 with": {"map_sync": 2.0e5, "seq_table": 1.0e4},
        "w3=1 without": {"map_full": 1.4e6, "map_update": 2.0e5},
        "w3=1 with": {"map_sync": 3.0e5, "seq_table": 2.0e4},
    }
    fig = bytes_by_type_figure(table)
    fig.canvas.draw()
    ax = fig.axes[0]
    tallest = max(sum(v.values()) for v in table.values())
    assert ax.get_ylim()[0] == 0 and ax.get_ylim()[1] >= tallest
    renderer = fig.canvas.get_renderer()
    legend = ax.get_legend().get_window_extent(renderer)
    for bar in ax.patches:
        assert not legend.overlaps(bar.get_window_extent(renderer))
    assert legend.x0 >= ax.get_window_extent(renderer).x1  # right of the axes
