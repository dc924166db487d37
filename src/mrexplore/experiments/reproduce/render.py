"""What every reproduction report is built from: its :class:`Experiment` objects, per-run
metrics grouped ``cell -> arm -> seed`` by :func:`tabulate` (the claims' ``Values``), and the
Markdown pieces of ``report.md`` (:func:`~mrexplore.experiments.reproduce.base.write_report`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mrexplore.experiments.reproduce.claims import CellKey, Interpretation, Values, fmt
from mrexplore.experiments.stats import Summary, summarize_metric
from mrexplore.experiments.store import Store
from mrexplore.experiments.sweep import Sweep, sweep_from_dict

Lines = list[str]
Row = Mapping[str, Any]
Metric = Callable[[Row], float]
"""A number of one run, from its row of the ``runs`` table."""


@dataclass(frozen=True)
class Experiment:
    """One sweep of a reproduction: fixed settings, a grid and the seeds."""

    name: str
    fixed: Mapping[str, Any]
    grid: Mapping[str, Any] = field(default_factory=dict)
    seeds: Sequence[int] = (1,)
    curves_every: int | None = None

    def sweep(self, source: str) -> Sweep:
        head: dict[str, Any] = {"name": self.name, "seeds": list(self.seeds)}
        if self.curves_every:
            head["curves_every"] = self.curves_every
        data = {"sweep": head, "fixed": dict(self.fixed), "grid": dict(self.grid)}
        return sweep_from_dict(data, source=f"{source}:{self.name}")


def text_rows(text: str) -> list[list[str]]:
    """The rows of an ``a | b | c`` text table; an indented line continues its row."""
    return [row.split(" | ") for row in text.replace("\n  ", " ").strip().splitlines()]


def readings(text: str) -> tuple[Interpretation, ...]:
    """Interpretations from a ``name | sentence | reading | overrides | strategies`` text
    table: overrides ``key=value`` (JSON or text; ``scenario.key`` a scenario setting,
    ``share.key`` a sharing parameter), strategies separated by commas, ``*`` for every run."""
    out = []
    for name, sentence, reading, overrides, strategies in text_rows(text):
        pairs = [item.split("=", 1) for item in overrides.split()]
        values = {key: _json_or_text(value) for key, value in pairs}
        part = {p: {k.removeprefix(p): v for k, v in values.items() if k.startswith(p)}
                for p in ("scenario.", "share.")}  # fmt: skip
        set_ = {k: v for k, v in values.items() if "." not in k}
        chosen = tuple(s.strip() for s in strategies.split(",") if s.strip() not in ("*", ""))
        out.append(
            Interpretation(name, sentence, reading, set_, chosen, part["scenario."], part["share."])
        )
    return tuple(out)


def _json_or_text(value: str) -> Any:
    try:
        return json.loads(value)
    except json.JSONDecodeError:
        return value


# ----------------------------------------------------------------- per-run values


def number(row: Row, key: str) -> float:
    """``row[key]`` as a float; ``0.0`` when missing or NaN (a count that never happened)."""
    value = row.get(key)
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return 0.0
    return float(value)


def column(key: str) -> Metric:
    """The metric that reads one column (missing counts as 0)."""
    return lambda row: number(row, key)


def measured(key: str) -> Metric:
    """A column, nan where a run has none (a time never reached): missing, not 0."""
    return lambda row: math.nan if row.get(key) is None else float(row[key])


def bytes_of(types: Iterable[str], kind: str = "bytes") -> Metric:
    """Bytes (or ``kind="messages"``) a run sent in messages of ``types``."""
    keys = [f"{kind}_by_type_{t}" for t in types]
    return lambda row: sum(number(row, k) for k in keys)


def bytes_by_type(row: Row) -> dict[str, float]:
    """``message type -> bytes`` of one run (types it sent)."""
    prefix = "bytes_by_type_"
    return {
        k[len(prefix) :]: number(row, k) for k in row if k.startswith(prefix) and number(row, k)
    }


def time_to(key: str) -> Metric:
    """A time metric (``T99``, ...), or the run's length (a lower bound) where never reached."""
    return lambda row: float(row[key]) if row.get(key) is not None else float(row["ticks"])


def reached(key: str) -> Metric:
    return lambda row: float(row.get(key) is not None)


def unfinished(reached: Values) -> dict[tuple[CellKey, str], str]:
    """:func:`arm_table` flags: ``*`` where a run of the arm did not get there (0 in
    ``reached``)."""
    return {
        (c, a): "*"
        for c, by_arm in reached.items()
        for a, x in by_arm.items()
        if min(x.values()) < 1
    }


def rows_of(stores: Mapping[str, Store]) -> tuple[list[dict[str, Any]], dict[str, int]]:
    """Every run row of every store (``experiment`` added), without the failed runs,
    and the number of runs by status (failed included)."""
    rows: list[dict[str, Any]] = []
    statuses: dict[str, int] = {}
    for name, store in stores.items():
        for row in store.query("SELECT * FROM runs ORDER BY run_id").to_pylist():
            statuses[row["status"]] = statuses.get(row["status"], 0) + 1
            if row["status"] != "failed":
                rows.append({**row, "experiment": name})
    return rows, dict(sorted(statuses.items()))


def tabulate(
    rows: Iterable[Row],
    metrics: Mapping[str, Metric],
    cell: Callable[[Row], CellKey | None],
    arm: Callable[[Row], str],
    order: Callable[[CellKey], Any] | None = None,
) -> dict[str, dict[CellKey, dict[str, dict[int, float]]]]:
    """``metric -> cell -> arm -> seed -> value``; rows whose ``cell`` is ``None`` are
    left out; cells in ``order`` (default: first seen)."""
    out: dict[str, dict[CellKey, dict[str, dict[int, float]]]] = {m: {} for m in metrics}
    for row in rows:
        key = cell(row)
        if key is None:
            continue
        name, seed = arm(row), int(row["seed"])
        for metric, of in metrics.items():
            out[metric].setdefault(key, {}).setdefault(name, {})[seed] = float(of(row))
    if order is not None:
        out = {m: {c: v[c] for c in sorted(v, key=order)} for m, v in out.items()}
    return out


def summaries(values: Values) -> dict[CellKey, dict[str, Summary]]:
    """``cell -> arm ->`` mean, sd and 95% CI over the seeds."""
    return {
        c: {a: summarize_metric(list(s.values())) for a, s in arms.items()}
        for c, arms in values.items()
    }


def arms_in(values: Values, order: Sequence[str]) -> list[str]:
    """The arms of ``order`` that have values, in that order."""
    present = {a for arms in values.values() for a in arms}
    return [a for a in order if a in present]


# ------------------------------------------------------------------------- Markdown


def summary_cell(s: Summary | None, digits: int = 0, flag: str = "") -> str:
    """``mean (sd; CI low..high; n)``."""
    if s is None or s.n == 0:
        return "-"
    interval = f"{fmt(s.ci_low, digits)}..{fmt(s.ci_high, digits)}"
    return f"{fmt(s.mean, digits)}{flag} (sd {fmt(s.sd, digits)}; CI {interval}; n {s.n})"


def blocks(*parts: str | Sequence[str]) -> Lines:
    """Markdown blocks, a blank line after each: a string is a paragraph or a heading, a
    list the lines of one block (a table, a figure's link)."""
    out: Lines = []
    for part in parts:
        lines = [part] if isinstance(part, str) else list(part)
        out += [*lines, ""] if lines and lines[-1] else lines
    return out


def table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> Lines:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]


def arm_table(
    values: Values,
    arms: Sequence[str],
    cell_columns: Sequence[str],
    cell_label: Callable[[CellKey], Sequence[Any]] = lambda c: c,
    digits: int = 0,
    flags: Mapping[tuple[CellKey, str], str] | None = None,
) -> Lines:
    """One row per cell, one column per arm of ``arms`` that has values: mean (sd; CI; n)."""
    shown = arms_in(values, arms)
    stats = summaries(values)
    rows = [
        [*cell_label(c)]
        + [summary_cell(stats[c].get(a), digits, (flags or {}).get((c, a), "")) for a in shown]
        for c in values
    ]
    return table([*cell_columns, *(f"`{a}`" for a in shown)], rows)


def settings_table(rows: str | Iterable[Sequence[str]], notes: Sequence[str] = ()) -> Lines:
    """The settings section (``rows``: ``setting | paper | ours``, or a :func:`text_rows`
    text), then our choices where the paper is silent."""
    rows = text_rows(rows) if isinstance(rows, str) else rows
    lines = ["## Settings", "", *table(["setting", "paper", "ours"], rows), ""]
    if notes:
        lines += ["Choices where the paper is silent or our world differs:", ""]
        lines += [f"- {note}" for note in notes] + [""]
    return lines


# -------------------------------------------------------------------------- figures


Panels = Mapping[str, Mapping[str, Mapping[Any, Summary]]]
"""``panel -> arm -> x -> summary``: a figure of :func:`~mrexplore.viz.plots.plot_arm_lines`."""


def figure(out: Path, name: str, panels: Panels, *, title: str, **axes: Any) -> Lines:
    """:func:`~mrexplore.viz.plots.plot_arm_lines` into ``out/name`` and the report's link
    to it (nothing when there is nothing to draw)."""
    from mrexplore.viz.plots import plot_arm_lines

    drawn = plot_arm_lines(panels, Path(out) / name, title=title, **axes)
    return [f"![{title}]({name})", ""] if drawn else []


def panels_of(
    values: Values,
    arms: Sequence[str],
    panel: Callable[[CellKey], str] = lambda c: str(c[0]),
    x: Callable[[CellKey], Any] = lambda c: c[-1],
) -> dict[str, dict[str, dict[Any, Summary]]]:
    """:func:`figure` input: ``panel -> arm -> x -> summary``, arms in the
    order of ``arms`` (the default panel: the cell's first key, x: its last)."""
    out: dict[str, dict[str, dict[Any, Summary]]] = {}
    for c, by_arm in summaries(values).items():
        for a in arms:
            if a in by_arm:
                out.setdefault(panel(c), {}).setdefault(a, {})[x(c)] = by_arm[a]
    return out
