"""The reproductions' shared report layer on hand-made rows and values."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pyarrow as pa
import pytest

from mrexplore.experiments.reproduce import render
from mrexplore.experiments.reproduce.base import Reproduction, write_report
from mrexplore.experiments.reproduce.claims import Claim, Means
from mrexplore.experiments.stats import summarize_metric
from mrexplore.viz.plots import plot_arm_lines


def _rows() -> list[dict[str, Any]]:
    rows = []
    for strategy, offset in (("a", 0.0), ("b", 10.0)):
        for robots in (2, 4):
            for seed in (1, 2, 3):
                rows.append(
                    {
                        "strategy": strategy,
                        "robots": robots,
                        "seed": seed,
                        "ticks": 100 + seed,
                        "T99": None if (strategy, seed) == ("b", 3) else offset + robots + seed,
                        "bytes_by_type_bid": 5 * seed,
                        "bytes_by_type_map": 100,
                        "messages_by_type_bid": seed,
                    }
                )
    return rows


def _values() -> dict[str, Any]:
    metrics = {
        "time": render.time_to("T99"),
        "reached": render.reached("T99"),
        "bid": render.bytes_of(["bid"]),
        "bids": render.bytes_of(["bid"], "messages"),
    }
    return render.tabulate(
        _rows(), metrics, lambda r: ("m", r["robots"]), lambda r: r["strategy"], lambda c: -c[1]
    )


def test_tabulate_reads_metric_functions_by_cell_arm_and_seed() -> None:
    values = _values()
    assert list(values["time"]) == [("m", 4), ("m", 2)]  # in the given order
    assert values["time"][("m", 2)]["a"] == {1: 3.0, 2: 4.0, 3: 5.0}
    assert values["time"][("m", 2)]["b"][3] == 103.0  # never reached: the run's length
    assert values["reached"][("m", 2)]["b"] == {1: 1.0, 2: 1.0, 3: 0.0}
    assert values["bid"][("m", 4)]["a"] == {1: 5.0, 2: 10.0, 3: 15.0}
    assert values["bids"][("m", 4)]["b"][2] == 2.0
    assert render.bytes_by_type(_rows()[0]) == {"bid": 5.0, "map": 100.0}
    skipped = render.tabulate(_rows(), {"t": render.column("ticks")}, lambda r: None, str)
    assert skipped == {"t": {}}


def test_text_rows_and_the_values_of_missing_columns() -> None:
    assert render.text_rows("a | b\n  c | d\ne | f") == [["a", "b c", "d"], ["e", "f"]]
    rows = ({"a": 3}, {"a": None}, {"a": math.nan}, {})
    assert [render.number(row, "a") for row in rows] == [3.0, 0.0, 0.0, 0.0]
    assert render.measured("a")(rows[0]) == 3.0 and math.isnan(render.measured("a")(rows[1]))


def test_arm_table_renders_every_cell_with_flags() -> None:
    values = _values()["time"]
    lines = render.arm_table(
        values, ["b", "a", "absent"], ["map", "robots"], digits=1, flags={(("m", 2), "b"): "*"}
    )
    assert lines[0] == "| map | robots | `b` | `a` |"
    assert lines[1] == "|---|---|---|---|"
    a2 = summarize_metric([3.0, 4.0, 5.0])
    expected = f"4.0 (sd 1.0; CI {render.fmt(a2.ci_low, 1)}..{render.fmt(a2.ci_high, 1)}; n 3)"
    assert lines[3].endswith(f"| {expected} |")
    assert lines[3].startswith("| m | 2 | ") and "* (sd" in lines[3]
    assert render.summary_cell(None) == "-"
    assert render.blocks("## A", lines[:2], [], "end") == ["## A", "", *lines[:2], "", "end", ""]


def test_settings_head_and_report(tmp_path: Path) -> None:
    settings = render.settings_table([("robots", "2-8", "2, 4")], ["*Maps*: ours."])
    assert settings[:4] == ["## Settings", "", "| setting | paper | ours |", "|---|---|---|"]
    assert "| robots | 2-8 | 2, 4 |" in settings and "- *Maps*: ours." in settings
    claim = Claim("c", "§1", "a is faster", "a is fast", "time", "T99", "a", "b", Means("<"))
    tables = {"time": _values()["time"]}
    paper = Reproduction("p", "T", "C", list, lambda *_: settings, lambda *_: tables, [claim])
    path = write_report(paper, {"default": {}}, tmp_path, quick=True)
    text = path.read_text()
    assert path == tmp_path / "report.md" and text.startswith("# Reproduction: T\n\nCitation: C\n")
    assert "Runs: none." in text and "Quick run" not in text  # no quick note to give
    assert "\n".join(settings) in text and "## Verdicts" in text
    assert "- **reproduced**: §1: a is faster" in text  # a < b in both cells
    assert text.endswith("Only the default reading was run (`--interpretations none`).\n")
    runs = pa.table({"run_id": ["a", "b", "c"], "status": ["complete", "failed", "complete"]})
    store = SimpleNamespace(query=lambda sql: runs)  # what rows_of reads of a store
    noted = replace(paper, quick_note="2 seeds")
    head = write_report(noted, {"default": {"e": store}}, tmp_path, quick=True).read_text()
    assert head.startswith("# Reproduction: T\n\n> **Quick run** (`--quick`): 2 seeds. Its")
    assert "Runs: complete 2, failed 1." in head
    slow = write_report(noted, {"default": {"e": store}}, tmp_path, quick=False).read_text()
    assert "Quick run" not in slow and "Runs: complete 2, failed 1." in slow


def test_experiment_builds_its_sweep() -> None:
    experiment = render.Experiment(
        "e", {"map": "office", "size": "30x30", "strategy": "kme"}, {"robots": [2, 3]}, (4, 5), 10
    )
    reproduction = Reproduction("paper", "T", "C", lambda quick: [experiment], list, dict)
    sweeps = reproduction.sweeps(False)
    assert list(sweeps) == ["e"]
    runs = sweeps["e"].runs()
    assert len(runs) == 4 and sweeps["e"].curves_every == 10


def test_arm_lines_hold_their_data_and_the_legend_is_outside(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from matplotlib.figure import Figure

    saved: list[Any] = []
    monkeypatch.setattr(Figure, "savefig", lambda fig, path, **kw: saved.append(fig))
    values = {
        ("p", 2): {"a": {1: 1.0, 2: 3.0}, "b": {1: 1e5, 2: 2e5}},
        ("p", 4): {"a": {1: 2.0, 2: 2.0}, "b": {1: 5e5, 2: 9e5}},
        ("q", 2): {"a": {1: 0.0, 2: 0.0}},  # zero: not drawn on a log axis
    }
    for log in (False, True):
        panels = render.panels_of(values, ["b", "a"])
        assert list(panels["p"]) == ["b", "a"]
        path = plot_arm_lines(
            panels, tmp_path / "f.png", xlabel="x", ylabel="y", title="T", colours={}, log=log
        )
        assert path == tmp_path / "f.png"
    assert (
        len(saved) == 2
        and plot_arm_lines({}, tmp_path / "g.png", xlabel="", ylabel="", title="", colours={})
        is None
    )
    for fig in saved:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        legend = fig.legends[0].get_window_extent(renderer)
        for ax in fig.axes:
            low, high = ax.get_ylim()
            for container in ax.containers:
                for line in container.lines[2]:  # the error bars
                    for segment in line.get_segments():
                        ys = np.asarray(segment)[:, 1]
                        assert low <= ys.min() and ys.max() <= high
            assert legend.x0 >= ax.get_window_extent(renderer).x1


def _drawn(monkeypatch: pytest.MonkeyPatch, panels: Any, title: str, **axes: Any) -> Any:
    """The figure :func:`render.figure` draws (not saved) and the report lines it returns."""
    from matplotlib.figure import Figure

    saved: list[Any] = []
    monkeypatch.setattr(Figure, "savefig", lambda fig, path, **kw: saved.append(fig))
    lines = render.figure(Path("/nowhere"), "f.png", panels, title=title, **axes)
    fig = saved[0]
    fig.canvas.draw()
    return fig, fig.canvas.get_renderer(), lines


def test_one_panel_keeps_its_title_clear_of_the_legend(monkeypatch: pytest.MonkeyPatch) -> None:
    long_arms = {f"an arm with a long name {i}": {1: summarize_metric([1.0 + i])} for i in range(3)}
    title = "Fig. 12: exploration time of every team size"
    axes = {"xlabel": "x", "ylabel": "y", "colours": {}}
    fig, renderer, lines = _drawn(monkeypatch, {"the panel": long_arms}, title, **axes)
    assert lines == [f"![{title}](f.png)", ""]
    assert not fig.texts or not fig.texts[0].get_text()  # no figure title: it is the axes'
    (ax,) = fig.axes
    assert " ".join(ax.get_title().split("\n")[:2]) == f"{title}: the panel"  # wrapped
    title = ax.title.get_window_extent(renderer)
    legend = fig.legends[0].get_window_extent(renderer)
    assert title.x1 <= legend.x0 or title.y1 <= legend.y0 or legend.y1 <= title.y0


def test_log_x_places_the_points_at_their_values(monkeypatch: pytest.MonkeyPatch) -> None:
    points = {x: summarize_metric([10.0 / x, 12.0 / x]) for x in (0.1, 1.0, 10.0)}
    panels = {"": {"a": points, "b": dict.fromkeys(points, summarize_metric([3.0]))}}
    fig, _, _ = _drawn(
        monkeypatch, panels, "A title", xlabel="x", ylabel="y", colours={}, logx=True
    )
    (ax,) = fig.axes
    assert ax.get_xscale() == "log" and ax.get_title().startswith("A title\n")
    xs = [x for line in ax.get_lines() for x in line.get_xdata()]
    assert min(xs) == pytest.approx(0.1, rel=0.05) and max(xs) == pytest.approx(10.0, rel=0.05)
    assert {t.get_text() for t in ax.get_xticklabels()} >= {"0.1", "1", "10"}
