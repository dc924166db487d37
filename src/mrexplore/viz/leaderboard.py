"""Figures of a suite's leaderboard (:mod:`mrexplore.experiments.leaderboard`).

:func:`draw_cd_diagrams` draws Demšar's (2006) critical-difference diagram of one or
more regimes, :func:`draw_pareto` a regime's mean T99 against mean bytes with the
Pareto-optimal strategies joined. Matplotlib is imported inside the functions.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mrexplore.experiments.leaderboard import _p_text, _pareto_points, pareto_front

if TYPE_CHECKING:
    from mrexplore.experiments.leaderboard import RegimeBoard

_CD_MIN_WIDTH_IN = 8.0
_CD_ROW_IN = 0.27
_CD_GROUP_IN = 0.12
_CD_DPI = 120


def _cd_height(k: int, n_groups: int) -> float:
    return 1.25 + _CD_GROUP_IN * n_groups + _CD_ROW_IN * math.ceil(k / 2)


def _text_space(names: Iterable[str]) -> float:
    """Inches beside the axis for the longest ``name (1.23)`` label."""
    longest = max((len(f"{name} (0.00)") for name in names), default=0)
    return max(0.3 + 0.07 * longest, 1.2)


def _cd_width(boards: Sequence[RegimeBoard]) -> float:
    """One width for every panel: room for the names and 0.6 inch per rank."""
    widths = [
        2 * _text_space(board.matrix.strategies) + 0.6 * (len(board.matrix.strategies) - 1)
        for board in boards
        if board.friedman is not None
    ]
    return max([_CD_MIN_WIDTH_IN, *widths])


def _draw_cd(
    ax: Any,
    width: float,
    mean_rank: Mapping[str, float],
    cd: float,
    groups: Sequence[Sequence[str]],
    title: str,
    height: float,
) -> None:
    """Demšar's diagram on ``ax``, whose data coordinates are inches from the top left."""
    ax.set_xlim(0, width)
    ax.set_ylim(height, 0)
    ax.set_axis_off()
    ax.text(width / 2, 0.18, title, ha="center", va="center", fontsize=10, parse_math=False)
    order = sorted(mean_rank, key=lambda name: (mean_rank[name], name))
    k = len(order)
    text_space = _text_space(order)

    def x_of(rank: float) -> float:
        return text_space + (rank - 1) / (k - 1) * (width - 2 * text_space)

    axis_y = 1.0
    ax.plot([x_of(1), x_of(k)], [axis_y, axis_y], color="black", linewidth=1)
    for tick in np.arange(1, k + 0.01, 0.5):
        big = float(tick).is_integer()
        ax.plot([x_of(tick)] * 2, [axis_y, axis_y - (0.1 if big else 0.05)], color="black", lw=1)
        if big:
            ax.text(x_of(tick), axis_y - 0.14, str(int(tick)), ha="center", va="bottom", fontsize=9)
    # The critical difference, above the axis, from rank 1.
    cd_end = x_of(min(1 + cd, k))
    cd_y = 0.5
    ax.plot([x_of(1), cd_end], [cd_y, cd_y], color="black", linewidth=1.5)
    for x in (x_of(1), cd_end):
        ax.plot([x, x], [cd_y - 0.05, cd_y + 0.05], color="black", linewidth=1.5)
    longer = "" if 1 + cd <= k else ", longer than the axis"
    ax.text(
        (x_of(1) + cd_end) / 2, cd_y - 0.08, f"CD = {cd:.2f}{longer}", ha="center", va="bottom",
        fontsize=9,
    )  # fmt: skip
    # Groups not told apart: thick bars under the axis.
    for index, group in enumerate(groups):
        y = axis_y + 0.12 + _CD_GROUP_IN * index
        lo, hi = mean_rank[group[0]], mean_rank[group[-1]]
        ax.plot([x_of(lo) - 0.05, x_of(hi) + 0.05], [y, y], color="black", linewidth=4)
    # Names on leader lines: the better half on the left, the worse on the right,
    # each side nearest the axis at its outer end so that no lines cross.
    first_row = axis_y + 0.12 + _CD_GROUP_IN * len(groups) + 0.15
    half = math.ceil(k / 2)
    sides = [(order[:half], "left"), (order[half:][::-1], "right")]
    for names, side in sides:
        for row, name in enumerate(names):
            x, y = x_of(mean_rank[name]), first_row + _CD_ROW_IN * row
            end = text_space - 0.1 if side == "left" else width - text_space + 0.1
            ax.plot([x, x, end], [axis_y, y, y], color="#444444", linewidth=0.9)
            label = f"{name} ({mean_rank[name]:.2f})"
            ax.text(
                end - 0.05 if side == "left" else end + 0.05, y, label, va="center",
                ha="right" if side == "left" else "left", fontsize=9, parse_math=False,
            )  # fmt: skip


def _cd_panel(ax: Any, board: RegimeBoard, width: float, height: float) -> None:
    if board.friedman is None:
        ax.set_xlim(0, width)
        ax.set_ylim(height, 0)
        ax.set_axis_off()
        k, n = len(board.matrix.strategies), len(board.matrix.instances)
        ax.text(
            width / 2, height / 2,
            f"{board.regime}: no critical-difference diagram ({k} strategies, {n} instances; "
            "it needs 3 and 2)",
            ha="center", va="center", fontsize=10, parse_math=False,
        )  # fmt: skip
        return
    title = (
        f"{board.regime}: mean rank by T99 over {board.friedman.n_instances} instances "
        f"(Friedman p = {_p_text(board.friedman.p_value)})"
    )
    _draw_cd(
        ax,
        width,
        {s.strategy: s.mean_rank for s in board.standings},
        board.cd,
        board.groups,
        title,
        height,
    )


def _panel_height(board: RegimeBoard) -> float:
    if board.friedman is None:
        return 0.8
    return _cd_height(len(board.matrix.strategies), len(board.groups))


def draw_cd_diagrams(boards: Sequence[RegimeBoard], path: Path) -> Path:
    """The critical-difference diagrams of ``boards``, stacked in one PNG at ``path``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    heights = [_panel_height(board) for board in boards]
    total = sum(heights)
    width = _cd_width(boards)
    fig = Figure(figsize=(width, total), dpi=_CD_DPI)
    FigureCanvasAgg(fig)
    top = total
    for board, height in zip(boards, heights, strict=True):
        top -= height
        ax = fig.add_axes((0.0, top / total, 1.0, height / total))
        _cd_panel(ax, board, width, height)
    fig.savefig(path, format="png", dpi=_CD_DPI)
    return path


def draw_pareto(board: RegimeBoard, path: Path) -> Path:
    """Mean T99 against mean bytes per strategy, 95% CI error bars, Pareto front joined."""
    from mrexplore.viz.plots import _new_figure, _save, strategy_colour, strategy_marker

    fig = _new_figure(7.0, 4.8, _CD_DPI)
    ax = fig.add_subplot(1, 1, 1)
    points = _pareto_points(board)
    drawn = {name: p for name, p in points.items() if all(map(math.isfinite, p))}
    xs = [x for x, _ in drawn.values()]
    positive = [x for x in xs if x > 0]
    log = bool(positive) and max(positive) / min(positive) > 100
    for s in board.standings:
        if s.strategy not in drawn:
            continue
        x, y = drawn[s.strategy]
        x_half = s.metrics["bytes_total"].half_width
        y_half = s.t99.half_width
        x_half = x_half if math.isfinite(x_half) else 0.0
        y_half = y_half if math.isfinite(y_half) else 0.0
        # On a log axis a bar may not reach zero or below.
        x_low = min(x_half, 0.99 * x) if log and x > 0 else x_half
        ax.errorbar(
            [x], [y], xerr=[[x_low], [x_half]], yerr=[[y_half], [y_half]],
            fmt=strategy_marker(s.strategy), color=strategy_colour(s.strategy), capsize=3,
            markersize=7,
        )  # fmt: skip
        # Neighbours along x put their names on alternate sides so they do not overlap.
        above = sorted(drawn, key=lambda name: (drawn[name], name)).index(s.strategy) % 2 == 0
        ax.annotate(
            s.strategy, (x, y), xytext=(6, 5 if above else -11), textcoords="offset points",
            fontsize=8, parse_math=False,
        )  # fmt: skip
    front = pareto_front(drawn)
    if front:
        ax.plot(
            [drawn[n][0] for n in front], [drawn[n][1] for n in front], linestyle="--",
            color="black", linewidth=1, marker="o", markersize=14, markerfacecolor="none",
            label="Pareto-optimal",
        )  # fmt: skip
        ax.legend(loc="upper right", fontsize=8)
    if log:
        if min(xs) > 0:
            ax.set_xscale("log")
        else:  # a strategy that sends nothing: linear near zero
            ax.set_xscale("symlog", linthresh=min(positive))
    missing = [name for name in points if name not in drawn]
    if missing:
        ax.text(
            0.01, 0.01, f"not drawn (no T99 or no bytes): {', '.join(missing)}",
            transform=ax.transAxes, fontsize=7, va="bottom", parse_math=False,
        )  # fmt: skip
    ax.set_xlabel("mean bytes sent per run (bytes)")
    ax.set_ylabel("mean T99 (ticks)")
    ax.set_title(f"{board.regime}: time against bytes (95% CI)", fontsize=10)
    ax.grid(True, alpha=0.3)
    return _save(fig, path, _CD_DPI)


# ------------------------------------------------------------------------- entry
