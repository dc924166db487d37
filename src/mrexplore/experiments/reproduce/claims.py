"""Claims of a paper as data: the sentence, the comparison, the rule that decides it.

A reproduction declares each claim it tests as a :class:`Claim`: where in the paper
it stands, the paper's sentence, the metric, the two arms compared, the cells
(for instance map x team size) it is judged in, and a rule object. The rule both
computes the verdict and writes the words that describe it, so the text of a
report and the code that decides cannot drift apart.

An :class:`Interpretation` is a documented alternative reading of an ambiguous
sentence of the paper, given as parameter overrides of the runs it changes. The
claims are judged under the default reading and under each interpretation;
:func:`robustness_section` shows, per claim, whether the verdict is ``robust``
(the same under every reading) or ``fragile`` (and under which readings it
changes).

Values are given to the rules as ``cell -> arm -> seed -> value``
(:data:`Values`); a rule never looks at anything else.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from mrexplore.experiments.reproduce.base import Outcome, Verdict
from mrexplore.experiments.stats import Summary, summarize_metric

CellKey = tuple[Any, ...]
"""A cell a claim is judged in, e.g. ``(map, robots)``."""
Values = Mapping[CellKey, Mapping[str, Mapping[int, float]]]
"""``cell -> arm -> seed -> value``."""


def fmt(value: float | None, digits: int = 0) -> str:
    """A number for a verdict line: ``digits`` decimals, thin-space thousands, ``-``
    for a missing or non-finite value.

    >>> fmt(12345.678), fmt(0.25, 2), fmt(None), fmt(float("nan"))
    ('12 346', '0.25', '-', '-')
    """
    if value is None or not math.isfinite(value):
        return "-"
    return f"{value:,.{digits}f}".replace(",", " ")


def paired(by_seed: Mapping[str, Mapping[int, float]], a: str, b: str) -> Summary:
    """``A - B`` over the seeds both arms ran (mean, sd, 95% CI).

    >>> paired({"a": {1: 5.0, 2: 7.0}, "b": {1: 4.0, 2: 4.0, 3: 1.0}}, "a", "b").mean
    2.0
    """
    first, second = by_seed.get(a, {}), by_seed.get(b, {})
    seeds = sorted(set(first) & set(second))
    return summarize_metric([first[s] - second[s] for s in seeds])


def _mean(by_seed: Mapping[int, float]) -> float:
    return summarize_metric(list(by_seed.values())).mean


def _cell_name(cell: CellKey) -> str:
    return "/".join(str(part) for part in cell[:-1]) + (
        f"/{cell[-1]}r" if len(cell) > 1 else str(cell[0])
    )


class Rule(Protocol):
    """Decides a claim from its values and says how, in words."""

    def describe(self, first: str, second: str, metric: str) -> str: ...

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]: ...


@dataclass(frozen=True)
class Counted:
    """The comparison of the means holds in every cell (reproduced), in at least half
    (partly), or in fewer (not reproduced). Each cell also shows the paired
    difference ``first - second`` with its 95% CI.

    >>> rule = Counted("<=")
    >>> values = {("m", 2): {"a": {1: 1.0, 2: 3.0}, "b": {1: 2.0, 2: 4.0}},
    ...           ("m", 3): {"a": {1: 5.0}, "b": {1: 4.0}}}
    >>> rule.judge(values, "a", ["b"], 0)[0]
    'partly'
    """

    relation: str
    """``<``, ``<=``, ``>`` or ``>=``: first against second."""

    def holds(self, a: float, b: float) -> bool:
        return bool(_RELATIONS[self.relation](a, b))

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of `{first}` {self.relation} that of `{second}`, cell by cell; "
            "reproduced if it holds in every cell, partly if in at least half, not "
            "reproduced otherwise"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        """Cells of every arm in ``seconds`` are pooled in one count."""
        count = total = 0
        texts = []
        for second in seconds:
            here = held = 0
            parts = []
            for cell, arms in values.items():
                if first not in arms or second not in arms:
                    continue
                a, b = _mean(arms[first]), _mean(arms[second])
                ok = self.holds(a, b)
                here, held = here + 1, held + ok
                d = paired(arms, first, second)
                parts.append(
                    f"{_cell_name(cell)} {fmt(a, digits)} vs {fmt(b, digits)} (paired "
                    f"{fmt(d.mean, digits)} [{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}])"
                    + ("" if ok else " x")
                )
            count, total = count + held, total + here
            texts.append(f"vs `{second}` holds in {held}/{here} cells; " + "; ".join(parts))
        return count_outcome(count, total), " | ".join(texts)


@dataclass(frozen=True)
class PairedLower:
    """``first`` is lower than ``second`` over the seeds both ran: the paired
    difference's upper CI bound is below zero in every cell (reproduced); its mean
    is below zero in every cell (partly); otherwise not reproduced.

    >>> rule = PairedLower()
    >>> values = {("m", 2): {"a": {s: 1.0 + s % 2 for s in range(6)},
    ...                      "b": {s: 5.0 for s in range(6)}}}
    >>> rule.judge(values, "a", ["b"], 1)[0]
    'reproduced'
    """

    confidence: float = 0.95

    def describe(self, first: str, second: str, metric: str) -> str:
        pct = f"{100 * self.confidence:g}%"
        return (
            f"paired difference of {metric}, `{first}` - `{second}`, over the seeds both "
            f"ran: reproduced if its {pct} CI lies below 0 in every cell, partly if its mean "
            "does, not reproduced otherwise"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        parts, sure, lower, total = [], 0, 0, 0
        for cell, arms in values.items():
            for second in seconds:
                if first not in arms or second not in arms:
                    continue
                seeds = sorted(set(arms[first]) & set(arms[second]))
                d = summarize_metric(
                    [arms[first][s] - arms[second][s] for s in seeds], confidence=self.confidence
                )
                total += 1
                sure += bool(math.isfinite(d.ci_high) and d.ci_high < 0)
                lower += bool(math.isfinite(d.mean) and d.mean < 0)
                parts.append(
                    f"{_cell_name(cell)} vs `{second}` {fmt(d.mean, digits)} "
                    f"[{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}] (n {d.n})"
                )
        outcome: Outcome = (
            "reproduced"
            if total and sure == total
            else "partly"
            if total and lower == total
            else "not reproduced"
        )
        return outcome, "; ".join(parts) or "no cell with both arms"


@dataclass(frozen=True)
class WithinFactor:
    """Our mean of ``first`` is within ``factor`` of the paper's number for each cell
    (``paper`` maps a cell to it): every cell (reproduced), at least half (partly).

    >>> rule = WithinFactor(2.0, {("m", 2): 10.0, ("m", 4): 10.0})
    >>> rule.judge({("m", 2): {"a": {1: 15.0}}, ("m", 4): {"a": {1: 30.0}}}, "a", [], 0)[0]
    'partly'
    """

    factor: float
    paper: Mapping[CellKey, float] = field(default_factory=dict)

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of `{first}` within a factor {self.factor:g} of the paper's, cell "
            "by cell; reproduced if in every cell, partly if in at least half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        count = total = 0
        parts = []
        for cell, theirs in self.paper.items():
            ours = values.get(cell, {}).get(first)
            if not ours:
                continue
            mean = _mean(ours)
            total += 1
            ok = theirs > 0 and mean > 0 and max(mean / theirs, theirs / mean) <= self.factor
            count += ok
            parts.append(
                f"{_cell_name(cell)} {fmt(mean, digits)} vs paper {fmt(theirs, digits)}"
                + ("" if ok else " x")
            )
        return count_outcome(count, total), f"within in {count}/{total} cells; " + "; ".join(parts)


@dataclass(frozen=True)
class Trend:
    """The mean of ``first`` rises (or falls) with the last part of the cell key (for
    instance the team size), within each group of the other parts: every step
    (reproduced), at least half the steps (partly).

    >>> rule = Trend("falls")
    >>> values = {("m", 2): {"a": {1: 9.0}}, ("m", 4): {"a": {1: 5.0}}, ("m", 8): {"a": {1: 6.0}}}
    >>> rule.judge(values, "a", [], 0)
    ('partly', 'falls in 1/2 steps; m: 9 -> 5 -> 6 x')
    """

    direction: str
    """``rises`` or ``falls``."""

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of `{first}` {self.direction} with each step of the last cell "
            "key; reproduced if at every step, partly if at least half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        groups: dict[CellKey, list[tuple[Any, float]]] = {}
        for cell, arms in values.items():  # in the caller's order: the steps' order
            if first in arms:
                groups.setdefault(cell[:-1], []).append((cell[-1], _mean(arms[first])))
        count = total = 0
        parts = []
        for group, series in groups.items():
            means = [m for _, m in series]
            steps = [
                b < a if self.direction == "falls" else b > a for a, b in itertools.pairwise(means)
            ]
            count += sum(steps)
            total += len(steps)
            label = "/".join(map(str, group)) or "all"
            parts.append(
                f"{label}: "
                + " -> ".join(fmt(m, digits) for m in means)
                + ("" if all(steps) else " x")
            )
        return count_outcome(count, total), (
            f"{self.direction} in {count}/{total} steps; " + "; ".join(parts)
        )


def series_of(values: Values, arm: str) -> dict[CellKey, dict[Any, float]]:
    """``group -> x -> mean`` of ``arm``: x is a cell key's last part, the group the
    parts before it; in the caller's order.

    >>> series_of({("t", 4): {"a": {1: 3.0}}, ("t", 8): {"a": {1: 1.0, 2: 2.0}}}, "a")
    {('t',): {4: 3.0, 8: 1.5}}
    """
    out: dict[CellKey, dict[Any, float]] = {}
    for cell, arms in values.items():
        if arm in arms:
            out.setdefault(cell[:-1], {})[cell[-1]] = _mean(arms[arm])
    return out


def series_text(series: Mapping[Any, float], digits: int = 0) -> str:
    """``x:mean, ...`` of one series.

    >>> series_text({4: 310.0, 8.0: 290.5}, 1)
    '4:310.0, 8:290.5'
    """
    return ", ".join(f"{_x(x)}:{fmt(m, digits)}" for x, m in series.items())


def _x(value: Any) -> str:
    return f"{value:g}" if isinstance(value, int | float) else str(value)


def _group_name(group: CellKey) -> str:
    return "/".join(map(str, group)) or "all"


@dataclass(frozen=True)
class PairedMostlyLower:
    """The paired difference ``first - second`` (over the seeds both ran) has its
    mean below 0 in every cell and its 95% CI below 0 in at least half of them
    (reproduced); its mean below 0 in at least half (partly); else not reproduced.

    >>> values = {(2,): {"a": {1: 1.0, 2: 2.0, 3: 1.5}, "b": {1: 5.0, 2: 6.0, 3: 5.0}},
    ...           (5,): {"a": {1: 1.0, 2: 9.0}, "b": {1: 2.0, 2: 3.0}}}
    >>> outcome, text = PairedMostlyLower().judge(values, "a", ["b"], 0)
    >>> outcome, text.split(", 5:")[0]
    ('partly', '`a` - `b` 2:-4 [-5, -3]')
    >>> text.split("; ")[1]
    'mean below 0 in 1/2 cells, 95% CI below 0 in 1/2'
    """

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"paired difference of {metric}, `{first}` - `{second}`, cell by cell: reproduced "
            "if its mean is below 0 in every cell and its 95% CI in at least half of them, "
            "partly if its mean is below 0 in at least half, not reproduced otherwise"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        lower = sure = total = 0
        texts = []
        for second in seconds:
            parts = []
            for cell, arms in values.items():
                if first in arms and second in arms:
                    d = paired(arms, first, second)
                    lower, sure, total = lower + (d.mean < 0), sure + (d.ci_high < 0), total + 1
                    interval = f"[{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}]"
                    parts.append(f"{_cell_name(cell)}:{fmt(d.mean, digits)} {interval}")
            texts.append(f"`{first}` - `{second}` " + ", ".join(parts))
        outcome: Outcome = (
            "reproduced"
            if total and lower == total and 2 * sure >= total
            else "partly"
            if total and 2 * lower >= total
            else "not reproduced"
        )
        return outcome, (
            "; ".join(texts) + f"; mean below 0 in {lower}/{total} cells, 95% CI below 0 in "
            f"{sure}/{total}"
        )


@dataclass(frozen=True)
class Monotone:
    """The mean of every compared arm (``first`` and each of ``seconds``) falls (or
    rises) at every step of the cells' last key, within each group of the other
    parts (reproduced); every such series ends below (above) where it starts
    (partly); otherwise not reproduced.

    >>> values = {(n,): {"a": {1: 9.0 / n}, "b": {1: m}} for n, m in ((1, 8.0), (2, 6.0), (3, 7.0))}
    >>> Monotone("falls").judge(values, "a", ["b"], 0)
    ('partly', '`a` 1:9, 2:4, 3:3; `b` 1:8, 2:6, 3:7 x')
    """

    direction: str
    """``falls`` or ``rises``."""

    def _step(self, a: float, b: float) -> bool:
        return b < a if self.direction == "falls" else b > a

    def describe(self, first: str, second: str, metric: str) -> str:
        arms = " / ".join(f"`{a}`" for a in (first, *second.split(" / ")) if a)
        return (
            f"mean {metric} of each of {arms} {self.direction} at every step of the last cell "
            f"key: reproduced if every one does, partly if every one {self.direction} from the "
            "first step to the last, not reproduced otherwise"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        every = ends = True
        parts = []
        count = 0
        for arm in (first, *seconds):
            for group, series in series_of(values, arm).items():
                means = list(series.values())
                steps = all(self._step(a, b) for a, b in itertools.pairwise(means))
                every &= steps
                ends &= len(means) > 1 and self._step(means[0], means[-1])
                count += 1
                label = f"`{arm}`" + (f" {_group_name(group)}" if group else "")
                parts.append(f"{label} {series_text(series, digits)}" + ("" if steps else " x"))
        outcome: Outcome = (
            "not reproduced" if not count or not ends else "reproduced" if every else "partly"
        )
        return outcome, "; ".join(parts)


@dataclass(frozen=True)
class RatioWithinFactor:
    """``first`` is below ``second`` in every cell (partly) and the ratio of their
    means, second / first, is within ``factor`` of the paper's in every cell
    (reproduced); otherwise not reproduced. ``paper`` maps a cell to its ratio.

    >>> rule = RatioWithinFactor(2.0, {("x",): 4.0, ("y",): 4.0})
    >>> values = {(c,): {"a": {1: 10.0}, "b": {1: b}} for c, b in (("x", 50.0), ("y", 90.0))}
    >>> rule.judge(values, "a", ["b"], 0)[0]
    'partly'
    >>> rule.judge(values, "a", ["b"], 0)[1].split("; ")[1]
    'y: `b` 90 vs `a` 10, ratio 9.0 (paper 4.0) x'
    """

    factor: float
    paper: Mapping[CellKey, float]
    ratio_digits: int = 1

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of `{first}` below that of `{second}` in every cell, and the ratio "
            f"`{second}` / `{first}` within a factor {self.factor:g} of the paper's in every "
            "cell: reproduced if both hold, partly if only the first, not reproduced otherwise"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        lower = within = bool(values)
        parts = []
        for cell, arms in values.items():
            a, b = _mean(arms.get(first, {})), _mean(arms.get(seconds[0], {}))
            ratio = b / a if a > 0 else math.inf
            theirs = self.paper.get(cell, math.nan)
            near = 1 / self.factor <= ratio / theirs <= self.factor
            lower, within = lower and a < b, within and near
            parts.append(
                f"{_cell_name(cell)}: `{seconds[0]}` {fmt(b, digits)} vs `{first}` "
                f"{fmt(a, digits)}, ratio "
                f"{fmt(ratio, self.ratio_digits)} (paper {fmt(theirs, self.ratio_digits)})"
                + ("" if near and a < b else " x")
            )
        outcome: Outcome = (
            "reproduced" if lower and within else "partly" if lower else "not reproduced"
        )
        return outcome, "; ".join(parts)


def _spearman(x: Sequence[float], y: Sequence[float]) -> float:
    """Spearman's rank correlation (average ranks for ties); 0 if either is constant.

    >>> _spearman([4, 8, 12], [30.0, 20.0, 10.0]), _spearman([1, 2], [3.0, 3.0])
    (-1.0, 0.0)
    """
    import numpy as np
    from scipy.stats import rankdata

    rx, ry = rankdata(np.asarray(x, dtype=float)), rankdata(np.asarray(y, dtype=float))
    if rx.std() == 0 or ry.std() == 0:
        return 0.0
    return float(np.corrcoef(rx, ry)[0, 1])


@dataclass(frozen=True)
class RankTrend:
    """Within each group of the cell key but its last part, the mean of ``first``
    ends below where it starts and Spearman's rank correlation between the last
    part and the mean is at most ``-rho`` (``falls``; ``rises``: above, at least
    ``rho``): in every group (reproduced), in at least half (partly).

    >>> means = {"t": (3.0, 1.0, 2.0), "d": (3.0, 2.0, 1.0)}
    >>> values = {(g, x): {"a": {1: m}} for g, ms in means.items() for x, m in zip((4, 8, 12), ms)}
    >>> RankTrend("falls").judge(values, "a", [], 0)
    ('partly', 't: 4:3, 8:1, 12:2 (Spearman rho -0.50) x; d: 4:3, 8:2, 12:1 (Spearman rho -1.00)')
    """

    direction: str
    """``falls`` or ``rises``."""
    rho: float = 0.6

    def describe(self, first: str, second: str, metric: str) -> str:
        falls = self.direction == "falls"
        sign, bound = ("below", f"<= -{self.rho:g}") if falls else ("above", f">= {self.rho:g}")
        return (
            f"mean {metric} of `{first}` against the last cell key, in each group of the other "
            f"parts: it ends {sign} where it starts and Spearman's rho is {bound}; reproduced "
            "if in every group, partly if in at least half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        count = 0
        parts = []
        groups = series_of(values, first)
        for group, series in groups.items():
            xs, means = list(series), list(series.values())
            rho = _spearman(xs, means) if len(xs) > 1 else math.nan
            ok = (
                means[-1] < means[0] and rho <= -self.rho
                if self.direction == "falls"
                else means[-1] > means[0] and rho >= self.rho
            )
            count += ok
            parts.append(
                f"{_group_name(group)}: {series_text(series, digits)} (Spearman rho "
                f"{fmt(rho, 2)})" + ("" if ok else " x")
            )
        return count_outcome(count, len(groups)), "; ".join(parts)


@dataclass(frozen=True)
class WithMeans:
    """``rule``, its evidence preceded by each compared arm's mean per cell."""

    rule: Rule
    mean_digits: int = 0

    def describe(self, first: str, second: str, metric: str) -> str:
        return self.rule.describe(first, second, metric)

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        outcome, text = self.rule.judge(values, first, seconds, digits)
        means = "; ".join(
            f"{_cell_name(cell)} "
            + ", ".join(
                f"`{a}` {fmt(_mean(arms[a]), self.mean_digits)}"
                for a in (first, *seconds)
                if a in arms
            )
            for cell, arms in values.items()
        )
        return outcome, f"means {means}; {text}"


@dataclass(frozen=True)
class FallsFasterBelow:
    """Within each group of the cell key but its last part (x), the mean of ``first``
    falls per unit of x from the smallest x to ``pivot`` (the gain below, above 0)
    faster than from ``pivot`` to the largest x (the gain above): in every group
    (reproduced), in at least half (partly).

    >>> values = {("t", x): {"a": {1: m}} for x, m in ((4, 400.0), (16, 280.0), (24, 272.0))}
    >>> FallsFasterBelow(16, "cell").judge(values, "a", [], 2)
    ('reproduced', 't: 10.00 per cell below 16 vs 1.00 above')
    """

    pivot: float
    unit: str = "unit"

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of `{first}` against the last cell key x, in each group of the "
            f"other parts: gain per {self.unit} below {self.pivot:g} = (m(x_min) - "
            f"m({self.pivot:g})) / ({self.pivot:g} - x_min), above = (m({self.pivot:g}) - "
            f"m(x_max)) / (x_max - {self.pivot:g}); reproduced if the gain below is positive "
            "and larger than above in every group, partly if in at least half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        groups = series_of(values, first)
        count = 0
        parts = []
        for group, m in groups.items():
            low, high, pivot = min(m), max(m), self.pivot
            below = above = math.nan
            if pivot in m and low < pivot < high:
                below = (m[low] - m[pivot]) / (pivot - low)
                above = (m[pivot] - m[high]) / (high - pivot)
            ok = below > 0 and below > above
            count += ok
            parts.append(
                f"{_group_name(group)}: {fmt(below, digits)} per {self.unit} below {pivot:g} "
                f"vs {fmt(above, digits)} above" + ("" if ok else " x")
            )
        return count_outcome(count, len(groups)), "; ".join(parts)


@dataclass(frozen=True)
class FallsLess:
    """Within each group of the cell key but its last part (x), the mean of ``first``
    falls less from the smallest x to the largest than that of ``second`` (a rise
    counts as less): in every group (reproduced), in at least half (partly).

    >>> rows = ((4, 30.0, 34.0), (8, 29.0, 30.0))
    >>> values = {("t", x): {"a": {1: a}, "b": {1: b}} for x, a, b in rows}
    >>> FallsLess().judge(values, "a", ["b"], 0)
    ('reproduced', 't: `a` falls by 1 vs `b` by 4')
    """

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"fall of the mean {metric} from the smallest to the largest last cell key, "
            f"m(x_min) - m(x_max), in each group of the other parts: reproduced if that of "
            f"`{first}` is smaller than that of `{second}` in every group (a rise counts as "
            "smaller), partly if in at least half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        arms = (first, seconds[0])
        series = [series_of(values, arm) for arm in arms]
        groups = list(dict.fromkeys(g for s in series for g in s))
        count = 0
        parts = []
        for group in groups:
            a, b = (_fall(s.get(group, {})) for s in series)
            ok = a < b
            count += ok
            parts.append(
                f"{_group_name(group)}: `{arms[0]}` falls by {fmt(a, digits)} vs `{arms[1]}` "
                f"by {fmt(b, digits)}" + ("" if ok else " x")
            )
        return count_outcome(count, len(groups)), "; ".join(parts)


def _fall(series: Mapping[Any, float]) -> float:
    return series[min(series)] - series[max(series)] if series else math.nan


@dataclass(frozen=True)
class FallAlong:
    """The mean of every compared arm (``first`` and each of ``seconds``) falls at every
    step of the cells, in the caller's order (reproduced); every one ends below where
    it starts, or one falls at every step (partly); otherwise not reproduced. Unlike
    :class:`Monotone`, it prints each arm's means beside the ``paper``'s (arm -> its
    numbers, cell by cell), their change from the first cell to the last, and the
    ``shown`` arms (not judged, 1 decimal).

    >>> values = {(w,): {"a": {1: a}, "b": {1: b}} for w, a, b in ((0, 9.0, 9.0), (2, 6, 9.5))}
    >>> FallAlong({"a": (5.0, 1.0)}).judge(values, "a", ["b"], 0)
    ('partly', '`a` 9, 6 (paper 5, 1); `b` 9, 10; first to last: -33% `a`, +6% `b`')
    """

    paper: Mapping[str, Sequence[float]] = field(default_factory=dict)
    shown: tuple[str, ...] = ()

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of `{first}` and of `{second}` along the cells: reproduced if both "
            "fall at every step, partly if both end below where they start or one falls at "
            "every step, not reproduced otherwise"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        arms, n = (first, *seconds), len(values)
        means = {
            arm: [_mean(by_arm.get(arm, {})) for by_arm in values.values()]
            for arm in (*arms, *self.shown)
        }
        falls = [all(b < a for a, b in itertools.pairwise(means[arm])) for arm in arms]
        ends = n >= 2 and all(means[arm][-1] < means[arm][0] for arm in arms)
        outcome: Outcome = "not reproduced"
        if n >= 2 and (ends or any(falls)):
            outcome = "reproduced" if all(falls) else "partly"

        def column(arm: str, digits: int) -> str:
            paper = ", ".join(fmt(p, digits) for p in self.paper.get(arm, ()))
            text = f"`{arm}` " + ", ".join(fmt(m, digits) for m in means[arm])
            return text + (f" (paper {paper})" if paper else "")

        parts = [column(arm, digits) for arm in arms]
        if n >= 2:
            change = (f"{100 * (means[a][-1] / means[a][0] - 1):+.0f}% `{a}`" for a in arms)
            parts.append("first to last: " + ", ".join(change))
        return outcome, "; ".join(parts + [column(arm, 1) for arm in self.shown])


_RELATIONS: dict[str, Callable[[float, float], bool]] = {
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
}


def count_outcome(holds: int, total: int) -> Outcome:
    """Every cell, at least half of them, fewer (or none to judge).

    >>> count_outcome(4, 4), count_outcome(2, 4), count_outcome(1, 4), count_outcome(0, 0)
    ('reproduced', 'partly', 'not reproduced', 'not reproduced')
    """
    if total <= 0:
        return "not reproduced"
    if holds >= total:
        return "reproduced"
    return "partly" if 2 * holds >= total else "not reproduced"


@dataclass(frozen=True)
class Claim:
    """One claim of the paper and how it is judged."""

    id: str
    where: str
    """Where in the paper: ``"Abstract"``, ``"§IV"``, ``"Fig. 10"``."""
    statement: str
    """The claim in our words, as the verdict line names it."""
    sentence: str
    """The paper's own sentence (or the part of it the claim rests on)."""
    metric: str
    """The key of :data:`Values` tables the claim reads (``time``, ``bytes``, ...)."""
    metric_label: str
    first: str
    second: str
    rule: Rule
    digits: int = 0
    seconds: tuple[str, ...] = ()
    """Further arms to compare ``first`` with (a rule pools their cells)."""

    def rule_text(self) -> str:
        """The rule in words, for the report's rule list."""
        second = " / ".join(a for a in (self.second, *self.seconds) if a)
        return self.rule.describe(self.first, second, self.metric_label)

    def judge(self, tables: Mapping[str, Values]) -> Verdict:
        """The verdict from ``metric -> values``."""
        seconds = [a for a in (self.second, *self.seconds) if a]
        values = tables.get(self.metric, {})
        outcome, text = self.rule.judge(values, self.first, seconds, self.digits)
        return Verdict(
            f"{self.where}: {self.statement}",
            outcome,
            f'{self.metric_label}: {text}; paper: "{self.sentence}"',
        )


@dataclass(frozen=True)
class Interpretation:
    """A named alternative reading of a sentence of the paper, as run overrides.

    ``set`` overrides strategy parameters of the runs whose strategy is in
    ``strategies`` (every run when empty); the experiments it does not change are
    reused from the default reading.
    """

    name: str
    sentence: str
    """The paper's sentence that is read differently (with where it stands)."""
    reading: str
    """How this interpretation reads it, against the default reading."""
    set: Mapping[str, Any] = field(default_factory=dict)
    strategies: tuple[str, ...] = ()

    def applies_to(self, strategy: str) -> bool:
        return not self.strategies or strategy in self.strategies


def claims_section(claims: Sequence[Claim], tables: Mapping[str, Values]) -> list[str]:
    """The verdict section: each claim's rule, then one verdict line per claim."""
    lines = ["## Verdicts", "", "Rules, fixed before the runs and never tuned:", ""]
    lines += [f"- `{claim.id}`: {claim.rule_text()}" for claim in claims]
    lines += ["", "(`x` marks a cell where the comparison fails.)", ""]
    lines += [claim.judge(tables).line() for claim in claims]
    return lines


def robustness(
    claims: Sequence[Claim], readings: Mapping[str, Mapping[str, Values]]
) -> dict[str, dict[str, Outcome]]:
    """``claim id -> reading -> outcome``; ``readings`` maps a reading's name (the
    first is the default) to its ``metric -> values`` tables."""
    return {
        claim.id: {name: claim.judge(tables).outcome for name, tables in readings.items()}
        for claim in claims
    }


def robustness_section(
    claims: Sequence[Claim],
    readings: Mapping[str, Mapping[str, Values]],
    interpretations: Sequence[Interpretation],
) -> list[str]:
    """Per claim, its verdict under every reading and ``robust`` / ``fragile``.

    >>> claim = Claim("c", "§1", "a is faster", "a is fast", "time", "T", "a", "b",
    ...               Counted("<="))
    >>> default = {"time": {("m", 2): {"a": {1: 1.0}, "b": {1: 2.0}}}}
    >>> other = {"time": {("m", 2): {"a": {1: 3.0}, "b": {1: 2.0}}}}
    >>> lines = robustness_section([claim], {"default": default, "slow-a": other},
    ...     [Interpretation("slow-a", "§2 'a moves'", "a waits")])
    >>> lines[-2]
    '| `c` | reproduced | not reproduced | **fragile** (changes under slow-a) |'
    """
    names = list(readings)
    lines = [
        "## Robustness to the readings of the paper",
        "",
        "Each claim judged under our default reading and under each interpretation "
        "(the same rule; only the runs the interpretation changes differ). `robust`: "
        "the same verdict under every reading; `fragile`: it changes, under the readings "
        "named.",
        "",
    ]
    if len(names) < 2:
        return [*lines, "Only the default reading was run (`--interpretations none`).", ""]
    known = {i.name: i for i in interpretations}
    lines += [
        f"- `{name}`: {known[name].reading} (reads {known[name].sentence})"
        for name in names[1:]
        if name in known
    ]
    lines += [
        "",
        "| claim | " + " | ".join(names) + " | summary |",
        "|---" * (len(names) + 2) + "|",
    ]
    for claim_id, outcomes in robustness(claims, readings).items():
        default = outcomes[names[0]]
        changed = [name for name in names[1:] if outcomes[name] != default]
        summary = "robust" if not changed else f"**fragile** (changes under {', '.join(changed)})"
        cells = " | ".join(outcomes[name] for name in names)
        lines.append(f"| `{claim_id}` | {cells} | {summary} |")
    return [*lines, ""]


__all__ = [
    "Claim",
    "Counted",
    "FallAlong",
    "FallsFasterBelow",
    "FallsLess",
    "Interpretation",
    "Monotone",
    "PairedLower",
    "PairedMostlyLower",
    "RankTrend",
    "RatioWithinFactor",
    "Rule",
    "Trend",
    "Values",
    "WithMeans",
    "WithinFactor",
    "claims_section",
    "count_outcome",
    "fmt",
    "paired",
    "robustness",
    "robustness_section",
    "series_of",
    "series_text",
]
