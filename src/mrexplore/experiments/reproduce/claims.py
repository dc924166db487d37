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


_EVERY_CELL = (
    "reproduced if it holds in every cell, partly if in at least half, not reproduced otherwise"
)


def lowest_arm(arms: Mapping[str, Mapping[int, float]], among: Sequence[str]) -> str | None:
    """The arm of ``among`` with the lowest mean (ties: the first by name), ``None``
    when none has a finite mean.

    >>> lowest_arm({"b": {1: 2.0}, "a": {1: 2.0}, "c": {1: 1.0}, "d": {}}, ["a", "b", "d"])
    'a'
    """
    means = {a: _mean(arms[a]) for a in among if a in arms}
    finite = {a: m for a, m in means.items() if math.isfinite(m)}
    return min(finite, key=lambda a: (finite[a], a)) if finite else None


@dataclass(frozen=True)
class Lowest:
    """``first`` has the lowest mean of the arms compared, cell by cell; in the cells
    whose last key is in ``unless`` the claim is that it is *not* the lowest. Every
    cell (reproduced), at least half (partly). Each cell shows ``first`` against the
    best other arm and their paired difference; ``brief``: only the cells that fail.

    >>> values = {("m", 2): {"a": {1: 1.0, 2: 2.0}, "b": {1: 2.0, 2: 4.0}},
    ...           ("m", 4): {"a": {1: 3.0}, "b": {1: 2.0}}}
    >>> outcome, text = Lowest().judge(values, "a", ["b"], 0)
    >>> outcome, text.split("; ")[:2]
    ('partly', ['holds in 1/2 cells', 'm/2r: `a` 2 vs best other `b` 3, paired -2 [-8, 5]'])
    >>> text.split("; ")[2]
    'm/4r: `a` 3 vs best other `b` 2, paired 1 [-, -] x'
    >>> Lowest(unless=(4,), brief=True).judge(values, "a", ["b"], 0)
    ('reproduced', 'holds in 2/2 cells over 1 groups of the other keys')
    """

    unless: tuple[Any, ...] = ()
    brief: bool = False

    def describe(self, first: str, second: str, metric: str) -> str:
        unless = ", ".join(map(str, self.unless))
        where = f" (not the lowest where the last cell key is {unless})" if unless else ""
        lowest = f"mean {metric} of `{first}` the lowest of it and `{second}`, cell by cell"
        return f"{lowest}{where}; {_EVERY_CELL}; no significance test"

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        count, parts, misses = 0, [], []
        for cell, arms in values.items():
            name, best = _cell_name(cell), lowest_arm(arms, [first, *seconds])
            ok = first in arms and best is not None and (best == first) != (cell[-1] in self.unless)
            count += ok
            misses += [] if ok else [f"{name} (`{best or '-'}` lowest)"]
            mark, runner = ("" if ok else " x"), lowest_arm(arms, seconds)
            ours = f"{name}: `{first}` {fmt(_mean(arms.get(first, {})), digits)}"
            if first not in arms or runner is None:
                parts.append(ours + mark)
                continue
            d = paired(arms, first, runner)
            parts.append(
                f"{ours} vs best other `{runner}` {fmt(_mean(arms[runner]), digits)}, paired "
                f"{fmt(d.mean, digits)} [{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}]{mark}"
            )
        head = f"holds in {count}/{len(values)} cells"
        if not self.brief:
            return count_outcome(count, len(values)), "; ".join([head, *parts])
        head += f" over {len({cell[:-1] for cell in values})} groups of the other keys"
        fails = f"; fails in {', '.join(misses)}" if misses else ""
        return count_outcome(count, len(values)), head + fails


@dataclass(frozen=True)
class TrendForAll:
    """The mean of every compared arm rises (or falls) with the last part of the cell
    key, within each group of the other parts: at every step for every arm
    (reproduced); from the first to the last step for every arm (partly).

    >>> values = {("m", 2): {"a": {1: 9.0}, "b": {1: 8.0}},
    ...           ("m", 4): {"a": {1: 5.0}, "b": {1: 6.0}},
    ...           ("m", 6): {"a": {1: 6.0}, "b": {1: 4.0}}}
    >>> TrendForAll("falls").judge(values, "a", ["b"], 0)
    ('partly', 'm `a`: 9 -> 5 -> 6 x; m `b`: 8 -> 6 -> 4')
    """

    direction: str
    """``rises`` or ``falls``."""

    def moves(self, a: float, b: float) -> bool:
        return b < a if self.direction == "falls" else b > a

    def describe(self, first: str, second: str, metric: str) -> str:
        each = f"mean {metric} of each of `{first}` / `{second}` {self.direction}"
        rule = "reproduced if at every step for every arm, partly if from the first to the last"
        return f"{each} with each step of the last cell key: {rule}"

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        series: dict[tuple[CellKey, str], list[float]] = {}
        for cell, arms in values.items():  # in the caller's order: the steps' order
            for arm in (first, *seconds):
                if arm in arms:
                    series.setdefault((cell[:-1], arm), []).append(_mean(arms[arm]))
        every = overall = bool(series)
        parts = []
        for (group, arm), means in series.items():
            steps = all(self.moves(a, b) for a, b in itertools.pairwise(means))
            every &= steps
            overall &= len(means) > 1 and self.moves(means[0], means[-1])
            label = "/".join(map(str, group)) or "all"
            trace = " -> ".join(fmt(m, digits) for m in means)
            parts.append(f"{label} `{arm}`: {trace}" + ("" if steps else " x"))
        outcome: Outcome = (
            "reproduced" if every and overall else "partly" if overall else "not reproduced"
        )
        return outcome, "; ".join(parts) or "no cell"


@dataclass(frozen=True)
class NotBelowAll:
    """``first`` is not superior to the other arms: it is superior in a cell where the
    paired 95% CI of ``first - second`` lies below 0 (n >= 2) against every other arm.
    Not superior in every cell (reproduced), in at least half (partly).

    >>> far = {s: 5.0 + s % 2 for s in range(4)}
    >>> values = {("m", 2): {"a": {s: 1.0 + s % 2 for s in range(4)}, "b": far, "c": far},
    ...           ("m", 4): {"a": far, "b": far, "c": far}}
    >>> NotBelowAll().judge(values, "a", ["b", "c"], 0)
    ('partly', 'not significantly below all others in 1/2 cells; superior in m/2r')
    """

    def describe(self, first: str, second: str, metric: str) -> str:
        test = f"the paired (same seeds) 95% CI of its {metric} minus that of each of `{second}`"
        superior = f"`{first}` is superior in a cell (with every arm) if {test} lies below 0"
        return f"{superior}; the claim holds where it is not: {_EVERY_CELL}"

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        superior = []
        cells = [(c, arms) for c, arms in values.items() if {first, *seconds} <= set(arms)]
        for cell, arms in cells:
            differences = [paired(arms, first, second) for second in seconds]
            if all(d.n >= 2 and d.ci_high < 0 for d in differences):
                superior.append(_cell_name(cell))
        count = len(cells) - len(superior)
        text = f"not significantly below all others in {count}/{len(cells)} cells"
        return count_outcome(count, len(cells)), text + (
            f"; superior in {', '.join(superior)}" if superior else ""
        )


@dataclass(frozen=True)
class Unpaired(Counted):
    """:class:`Counted` for arms whose seeds are not paired (the same seed is not the
    same set-up in both): means only, and the cells where it fails.

    >>> values = {("m", 2): {"a": {1: 1.0}, "b": {1: 2.0}},
    ...           ("m", 4): {"a": {1: 3.0}, "b": {1: 2.0}}}
    >>> Unpaired("<").judge(values, "a", ["b"], 0)
    ('partly', '`a` < `b` in 1/2 cells; fails in m/4r 3 vs 2')
    """

    def describe(self, first: str, second: str, metric: str) -> str:
        words = f"mean {metric} of `{first}` {self.relation} that of `{second}`"
        return f"{words}, cell by cell, the seeds not paired; {_EVERY_CELL}"

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        means = [
            (cell, _mean(arms[first]), _mean(arms[second]))
            for second in seconds
            for cell, arms in values.items()
            if first in arms and second in arms
        ]
        fails = [
            f"{_cell_name(c)} {fmt(a, digits)} vs {fmt(b, digits)}"
            for c, a, b in means
            if not self.holds(a, b)
        ]
        count, against = len(means) - len(fails), " / ".join(f"`{s}`" for s in seconds)
        text = f"`{first}` {self.relation} {against} in {count}/{len(means)} cells"
        return count_outcome(count, len(means)), text + (
            f"; fails in {'; '.join(fails)}" if fails else ""
        )


def common_seeds(
    values: Values, first: str, second: str, min_seeds: int = 1
) -> list[tuple[CellKey, Summary, Summary, Summary]]:
    """Per cell where both arms ran ``min_seeds`` or more common seeds, in the order of
    ``values``: the summaries of ``first``, of ``second`` and of ``first - second`` over
    those seeds.

    >>> [(c, a.mean, b.mean, d.mean) for c, a, b, d in common_seeds(
    ...     {("m", 2): {"a": {1: 3.0, 2: 5.0}, "b": {2: 1.0}}}, "a", "b")]
    [(('m', 2), 5.0, 1.0, 4.0)]
    """
    out = []
    for cell, arms in values.items():
        a, b = arms.get(first, {}), arms.get(second, {})
        seeds = sorted(set(a) & set(b))
        if len(seeds) >= min_seeds:
            x, y = [a[s] for s in seeds], [b[s] for s in seeds]
            diff = [p - q for p, q in zip(x, y, strict=True)]
            out.append((cell, summarize_metric(x), summarize_metric(y), summarize_metric(diff)))
    return out


def _curves(values: Values, arm: str) -> dict[CellKey, dict[Any, float]]:
    """``cell[:-1] -> cell[-1] -> mean`` of ``arm``, in the order of ``values``."""
    out: dict[CellKey, dict[Any, float]] = {}
    for cell, arms in values.items():
        if arm in arms:
            out.setdefault(cell[:-1], {})[cell[-1]] = _mean(arms[arm])
    return out


def _group_name(group: CellKey) -> str:
    return "/".join(map(str, group)) or "all"


@dataclass(frozen=True)
class Share:
    """The ``statistic`` (``mean`` or ``sd``) of ``first`` ``relation`` that of ``second``
    over the seeds both ran (at least ``min_seeds``), in a share of the cells: at least
    ``reproduced`` (reproduced), at least ``partly`` (partly). The evidence adds the
    ratio first / second, for means the paired differences (and how many 95% CIs
    exclude 0), and the same count on the arms ``also`` (another measure of the runs).

    >>> values = {("m", n): {"a": {1: 2.0, 2: 4.0}, "b": {1: 4.0, 2: 4.0 + n}} for n in (2, 4)}
    >>> outcome, text = Share("<", 0.9, 0.5).judge(values, "a", ["b"], 0)
    >>> print(outcome, *text.split("; "), sep="\\n")
    reproduced
    holds in 2/2 cells (paired 95% CI below 0 in 1, above 0 in 0)
    ratio `a` / `b` median 0.55, range 0.50-0.60, lowest at m/4r
    m/2r 3 vs 5 (paired -2 [-2, -2])
    m/4r 3 vs 6 (paired -3 [-16, 10])
    """

    relation: str
    reproduced: float
    partly: float
    statistic: str = "mean"
    min_seeds: int = 1
    also: tuple[str, str] | None = None

    def describe(self, first: str, second: str, metric: str) -> str:
        also = f" (also counted on `{self.also[0]}` vs `{self.also[1]}`)" if self.also else ""
        return (
            f"the {self.statistic} of {metric} of `{first}` {self.relation} that of `{second}` "
            f"over the seeds both ran, cell by cell{also}; reproduced if it holds in at least "
            f"{self.reproduced:.0%} of the cells, partly if in at least {self.partly:.0%}"
        )

    def compared(self, values: Values, first: str, second: str) -> list[tuple[Any, ...]]:
        """Per cell: its key, the two statistics, the paired difference, and whether the
        relation holds."""
        holds = _RELATIONS[self.relation]
        out = []
        for cell, a, b, d in common_seeds(values, first, second, self.min_seeds):
            x, y = getattr(a, self.statistic), getattr(b, self.statistic)
            out.append((cell, x, y, d, bool(holds(x, y))))
        return out

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        from statistics import median

        found = self.compared(values, first, seconds[0])
        if not found:
            return "not reproduced", "no cell with both arms"
        held = sum(ok for *_, ok in found)
        parts = [f"holds in {held}/{len(found)} cells"]
        if self.statistic == "mean":
            below = sum(d.ci_high < 0 for *_, d, _ in found)
            above = sum(d.ci_low > 0 for *_, d, _ in found)
            parts[0] += f" (paired 95% CI below 0 in {below}, above 0 in {above})"
        ratios = {c: a / b for c, a, b, *_ in found if b and math.isfinite(a / b)}
        if ratios:
            low = min(ratios, key=ratios.__getitem__)
            parts.append(
                f"ratio `{first}` / `{seconds[0]}` median {fmt(median(ratios.values()), 2)}, "
                f"range {fmt(min(ratios.values()), 2)}-{fmt(max(ratios.values()), 2)}, lowest "
                f"at {_cell_name(low)}"
            )
        for cell, a, b, d, ok in found:
            interval = f"[{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}]"
            diff = f" (paired {fmt(d.mean, digits)} {interval})" if self.statistic == "mean" else ""
            parts.append(
                f"{_cell_name(cell)} {fmt(a, digits)} vs {fmt(b, digits)}{diff}"
                + ("" if ok else " x")
            )
        if self.also:
            more = self.compared(values, *self.also)
            parts.append(
                f"`{self.also[0]}` vs `{self.also[1]}`: holds in "
                f"{sum(ok for *_, ok in more)}/{len(more)} cells"
            )
        share = held / len(found)
        outcome: Outcome = (
            "reproduced"
            if share >= self.reproduced
            else "partly"
            if share >= self.partly
            else "not reproduced"
        )
        return outcome, "; ".join(parts)


@dataclass(frozen=True)
class Diminishing:
    """Each curve (the mean of one arm against the last cell key, per group of the other
    keys) is lower at its largest key than at its smallest and drops at least as much
    up to its middle key as after it (diminishing returns): every curve of every arm
    compared (reproduced), at least half (partly).

    >>> values = {("m", n): {"a": {1: 100.0 / n}, "b": {1: 120.0 - 10.0 * n}} for n in (1, 2, 4)}
    >>> outcome, text = Diminishing().judge(values, "a", ["b"], 0)
    >>> print(outcome, *text.split("; "), sep="\\n")
    partly
    falls in 2/2 curves, with diminishing returns in 1/2
    `a` m: 100 -> 50 -> 25
    `b` m: 110 -> 100 -> 80 x
    """

    def describe(self, first: str, second: str, metric: str) -> str:
        curves = f"each curve of `{first}` and of `{second}` (mean {metric} against the last key)"
        return (
            f"{curves} falls from its smallest to its largest key, dropping at least as much up "
            "to its middle key as after (diminishing returns); reproduced if all do, partly if half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        parts: list[str] = []
        falling = passed = 0
        for arm in (first, *seconds):
            for group, means in _curves(values, arm).items():
                keys = sorted(means)
                if len(keys) < 2:
                    continue
                ends = (keys[0], keys[len(keys) // 2], keys[-1])  # with 2 keys: middle = last
                a, mid, z = (means[k] for k in ends)
                ok = z < a and a - mid >= mid - z
                falling, passed = falling + (z < a), passed + ok
                curve = " -> ".join(fmt(means[k], digits) for k in dict.fromkeys(ends))
                parts.append(f"`{arm}` {_group_name(group)}: {curve}" + ("" if ok else " x"))
        total = len(parts)
        return count_outcome(passed, total), (
            f"falls in {falling}/{total} curves, with diminishing returns in {passed}/{total}; "
            + "; ".join(parts)
        )


def _ends(
    values: Values, first: str, second: str
) -> dict[CellKey, tuple[tuple[Any, float, float], tuple[Any, float, float]]]:
    """Per group of the cells' other keys with 2+ cells both arms ran: ``(last key, mean
    of first, mean of second)`` (over the seeds both ran) at its smallest and largest
    last key."""
    groups: dict[CellKey, list[tuple[Any, float, float]]] = {}
    for cell, a, b, _ in common_seeds(values, first, second):
        groups.setdefault(cell[:-1], []).append((cell[-1], a.mean, b.mean))
    return {g: (min(ends), max(ends)) for g, ends in groups.items() if len(ends) >= 2}


def _ratio(a: float, b: float) -> float:
    return a / b if b else math.nan


@dataclass(frozen=True)
class RatioAtMost:
    """The ratio of the means ``first`` / ``second`` (over the seeds both ran) is at most
    ``limit``: in every cell (reproduced), in at least half (partly).

    >>> values = {("m", n): {"a": {1: 10.0 + n}, "b": {1: 10.0}} for n in (1, 5)}
    >>> RatioAtMost(1.25).judge(values, "a", ["b"], 0)
    ('partly', 'at most 1.25 in 1/2 cells: m/1r 1.10; m/5r 1.50 x')
    """

    limit: float

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"the mean {metric} of `{first}` over that of `{second}` (seeds both ran) at most "
            f"{self.limit:g}, cell by cell; reproduced if in every cell, partly if in at least "
            "half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        ratios = {
            c: _ratio(a.mean, b.mean) for c, a, b, _ in common_seeds(values, first, seconds[0])
        }
        held = sum(r <= self.limit for r in ratios.values())
        parts = [
            f"{_cell_name(c)} {fmt(r, 2)}" + ("" if r <= self.limit else " x")
            for c, r in ratios.items()
        ]
        return count_outcome(held, len(ratios)), (
            f"at most {self.limit:g} in {held}/{len(ratios)} cells: " + "; ".join(parts)
        )


@dataclass(frozen=True)
class RatioFalls:
    """The ratio of the means ``first`` / ``second`` (over the seeds both ran) is lower at
    the largest last cell key than at the smallest, per group of the other keys: every
    group (reproduced), at least half (partly).

    >>> values = {("m", n): {"a": {1: 30.0 / n + 10}, "b": {1: 10.0}} for n in (1, 3)}
    >>> RatioFalls().judge(values, "a", ["b"], 0)
    ('reproduced', 'falls in 1/1 groups: m: 4.00 -> 2.00')
    """

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"the ratio `{first}` / `{second}` of the mean {metric} (seeds both ran) falls from "
            "the smallest to the largest last key, per group; reproduced if in all, partly if half"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        held, parts = 0, []
        for group, ((_, a0, b0), (_, a1, b1)) in _ends(values, first, seconds[0]).items():
            smallest, largest = _ratio(a0, b0), _ratio(a1, b1)
            held += largest < smallest
            parts.append(
                f"{_group_name(group)}: {fmt(smallest, 2)} -> {fmt(largest, 2)}"
                + ("" if largest < smallest else " x")
            )
        return count_outcome(held, len(parts)), (
            f"falls in {held}/{len(parts)} groups: " + "; ".join(parts)
        )


@dataclass(frozen=True)
class GapNarrows:
    """The gap ``first - second`` of the means (over the seeds both ran) is smaller at the
    largest last cell key than at the smallest, per group of the other keys, and so is
    the ratio ``first / second``: both in every group (reproduced); the gap in some
    group (partly). A gap between falling curves shrinks almost by itself: the ratio says
    whether the two curves really converge.

    >>> values = {("m", 1): {"a": {1: 2000.0}, "b": {1: 1000.0}},
    ...           ("m", 3): {"a": {1: 900.0}, "b": {1: 300.0}}}
    >>> outcome, text = GapNarrows().judge(values, "a", ["b"], 0)
    >>> print(outcome, *text.split(": ", 1), sep="\\n")
    partly
    the gap shrinks in 1/1 groups, the ratio too in 0/1
    m: 1: 1 000 (x2.00) -> 3: 600 (x3.00)
    """

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"the gap in the mean {metric} between `{first}` and `{second}` (seeds both ran) at "
            "the largest last cell key against the smallest, as a difference and as a ratio, "
            "group by group; reproduced if both shrink in every group, partly if the difference "
            "shrinks in some"
        )

    def gaps(
        self, values: Values, first: str, second: str
    ) -> dict[CellKey, tuple[tuple[Any, float, float], tuple[Any, float, float]]]:
        """Per group: ``(last key, gap, ratio)`` at its smallest and largest last key."""
        out = {}
        for group, ((k0, a0, b0), (k1, a1, b1)) in _ends(values, first, second).items():
            out[group] = ((k0, a0 - b0, _ratio(a0, b0)), (k1, a1 - b1, _ratio(a1, b1)))
        return out

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        found = self.gaps(values, first, seconds[0])
        gap = sum(g1 < g0 for (_, g0, _), (_, g1, _) in found.values())
        both = sum(g1 < g0 and q1 < q0 for (_, g0, q0), (_, g1, q1) in found.values())
        parts = [
            f"{_group_name(group)}: {k0}: {fmt(g0, digits)} (x{fmt(q0, 2)}) -> {k1}: "
            f"{fmt(g1, digits)} (x{fmt(q1, 2)})"
            for group, ((k0, g0, q0), (k1, g1, q1)) in found.items()
        ]
        outcome: Outcome = (
            "reproduced" if found and both == len(found) else "partly" if gap else "not reproduced"
        )
        return outcome, (
            f"the gap shrinks in {gap}/{len(found)} groups, the ratio too in {both}/{len(found)}: "
            + "; ".join(parts)
        )


@dataclass(frozen=True)
class RisesAbove:
    """In each group of the other cell keys that starts with ``within``, the mean of
    ``first`` at every last key above ``threshold`` exceeds that at the largest last key
    of at most ``threshold`` (for instance: a team does worse above seven robots): every
    group (reproduced), some (partly).

    >>> values = {("s", 1, n): {"a": {1: t}} for n, t in ((6, 30.0), (7, 25.0), (8, 26.0))}
    >>> RisesAbove(7, ("s",)).judge(values, "a", [], 0)
    ('reproduced', 'holds in 1/1 groups: s/1: 25 at 7, 26 at 8')
    """

    threshold: float
    within: CellKey = ()

    def describe(self, first: str, second: str, metric: str) -> str:
        where = f" (cells {_group_name(self.within)}/...)" if self.within else ""
        return (
            f"the mean {metric} of `{first}` at every last cell key above {self.threshold:g} "
            f"exceeds that at the largest key of at most {self.threshold:g}, group by group"
            f"{where}; reproduced if in every group, partly if in some"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        held, parts = 0, []
        for group, means in _curves(values, first).items():
            above = [k for k in means if k > self.threshold]
            ref = max((k for k in means if k <= self.threshold), default=None)
            if group[: len(self.within)] != self.within or ref is None or not above:
                continue
            ok = all(means[k] > means[ref] for k in above)
            held += ok
            shown = ", ".join(f"{fmt(means[k], digits)} at {k}" for k in [ref, *above])
            parts.append(f"{_group_name(group)}: {shown}" + ("" if ok else " x"))
        outcome: Outcome = (
            "reproduced" if parts and held == len(parts) else "partly" if held else "not reproduced"
        )
        return outcome, f"holds in {held}/{len(parts)} groups: " + "; ".join(parts)


@dataclass(frozen=True)
class AtLeast:
    """The mean of ``first`` is at least ``reproduced`` in every cell (reproduced), at
    least ``partly`` in every cell (partly); the other arms' ranges are cited beside.

    >>> values = {("m", 2): {"a": {1: 0.95}, "b": {1: 0.2}}, ("m", 4): {"a": {1: 0.9}}}
    >>> AtLeast(0.95, 0.8).judge(values, "a", ["b"], 2)
    ('partly', 'mean per cell: `a` 0.90-0.95; `b` 0.20-0.20')
    """

    reproduced: float
    partly: float

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"the mean {metric} of `{first}` cell by cell: reproduced if at least "
            f"{self.reproduced:g} in every cell, partly if at least {self.partly:g} in every "
            f"cell (`{second}` cited beside)"
        )

    def judge(
        self, values: Values, first: str, seconds: Sequence[str], digits: int
    ) -> tuple[Outcome, str]:
        means = {
            arm: [
                m
                for arms in values.values()
                if arm in arms and math.isfinite(m := _mean(arms[arm]))
            ]
            for arm in (first, *seconds)
        }
        if not means[first]:
            return "not reproduced", f"no value of `{first}`"
        low = min(means[first])
        outcome: Outcome = (
            "reproduced"
            if low >= self.reproduced
            else "partly"
            if low >= self.partly
            else "not reproduced"
        )
        ranges = [
            f"`{a}` {fmt(min(m), digits)}-{fmt(max(m), digits)}" for a, m in means.items() if m
        ]
        return outcome, "mean per cell: " + "; ".join(ranges)


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


# ------------------------------------------- families of arms, graded cells (meier2006)

Arms = Mapping[str, Mapping[int, float]]
"""One cell of :data:`Values`: ``arm -> seed -> value``."""
Judgement = tuple[Outcome, str]
Grade = tuple[str, str] | None
"""``holds`` / ``weak`` / ``fails`` and its evidence, or ``None`` to leave a cell out."""
GRADED = "; reproduced if it holds in every cell, not reproduced if it fails in all, else partly"


def family(arms: Mapping[str, Any], prefix: str) -> list[str]:
    """The arms named ``<prefix> <number>`` (a parameter swept over arms: ``SR 0.1``,
    ``SR 10``, ...), in the order of that number, their :func:`level`.

    >>> family({"SR 10": {}, "full": {}, "SR 0.1": {}}, "SR")
    ['SR 0.1', 'SR 10']
    """
    return sorted((a for a in arms if a.startswith(f"{prefix} ")), key=level)


def level(arm: str) -> float:
    """The number of an arm of a :func:`family`: ``level("SR 0.1") == 0.1``."""
    return float(arm.rsplit(" ", 1)[-1])


def family_means(arms: Arms, prefix: str) -> dict[str, float]:
    """The mean of every arm of the :func:`family` ``prefix``, in its order."""
    return {a: _mean(arms[a]) for a in family(arms, prefix)}


def spearman(x: Sequence[float], y: Sequence[float]) -> float:
    """Spearman's rho over the finite pairs (average ranks for ties); nan for fewer than two
    pairs or a constant side.

    >>> spearman([1, 2, 3], [30, 20, 10]), spearman([1, 2], [5, 5])
    (-1.0, nan)
    """
    import numpy as np
    from scipy.stats import rankdata

    pairs = [(a, b) for a, b in zip(x, y, strict=True) if math.isfinite(a) and math.isfinite(b)]
    if len(pairs) < 2:
        return math.nan
    rx, ry = rankdata([a for a, _ in pairs]), rankdata([b for _, b in pairs])
    return float(np.corrcoef(rx, ry)[0, 1]) if np.ptp(rx) and np.ptp(ry) else math.nan


def trend_sign(x: Sequence[float], y: Sequence[float], threshold: float) -> int:
    """+1 / -1 when ``y`` rises / falls with ``x`` (Spearman ``|rho| >= threshold``), else 0.

    >>> trend_sign([1, 2, 3, 4], [4, 3, 2, 1], 0.3), trend_sign([1, 2, 3], [1, 1, 1], 0.3)
    (-1, 0)
    """
    rho = spearman(x, y)
    return 0 if not abs(rho) >= threshold else (1 if rho > 0 else -1)


def graded(grades: Sequence[str]) -> Outcome:
    """``holds`` / ``weak`` / ``fails`` per cell: reproduced if every cell holds, not
    reproduced if every one fails (or none was graded), partly otherwise.

    >>> graded(["holds", "holds"]), graded(["holds", "fails"]), graded([])
    ('reproduced', 'partly', 'not reproduced')
    """
    if grades and all(g == "holds" for g in grades):
        return "reproduced"
    return "not reproduced" if all(g == "fails" for g in grades) else "partly"


class Graded:
    """Base of the rules that grade each cell (:meth:`grade`, against the first arm of
    ``seconds``) and combine the grades with :func:`graded`. A comparison with nan is
    false: a missing number never holds."""

    def grade(self, arms: Arms, first: str, second: str, digits: int) -> Grade:
        raise NotImplementedError

    def judge(self, values: Values, first: str, seconds: Sequence[str], digits: int) -> Judgement:
        second = seconds[0] if seconds else ""
        grades = [(c, self.grade(arms, first, second, digits)) for c, arms in values.items()]
        done = [(c, g) for c, g in grades if g is not None]
        text = "; ".join(f"{_cell_name(c)} {evidence}: {grade}" for c, (grade, evidence) in done)
        return graded([grade for _, (grade, _) in done]), text or "no cell to judge"


@dataclass(frozen=True)
class PairedAbove(Graded):
    """``first`` is above ``second`` seed by seed: the paired difference's 95% CI lies
    above 0 (holds), only its mean (weak), neither (fails).

    >>> values = {("m", 3): {"a": {1: 12.0, 2: 11.0}, "b": {1: 10.0, 2: 10.0}}}
    >>> PairedAbove().judge(values, "a", ["b"], 0)
    ('partly', 'm/3r 2 [-5, 8] (n 2): weak')
    """

    def grade(self, arms: Arms, first: str, second: str, digits: int) -> Grade:
        d = paired(arms, first, second)
        return "holds" if d.ci_low > 0 else "weak" if d.mean > 0 else "fails", _diff(d, digits)

    def describe(self, first: str, second: str, metric: str) -> str:
        return f"paired {metric}, `{first}` - `{second}`: 95% CI above 0 holds, mean weak{GRADED}"


@dataclass(frozen=True)
class RatioWithin(Graded):
    """The mean of ``first`` is at most ``1 + close`` (holds) or ``1 + loose`` (weak) times
    that of ``second``; cells without ``first`` are left out.

    >>> RatioWithin(0.15, 0.3).judge({("m", 3): {"a": {1: 12.0}, "b": {1: 10.0}}}, "a", ["b"], 0)
    ('partly', 'm/3r 12 vs 10 (ratio 1.20): weak')
    """

    close: float
    loose: float

    def grade(self, arms: Arms, first: str, second: str, digits: int) -> Grade:
        if first not in arms:
            return None
        a, b = _mean(arms[first]), _mean(arms.get(second, {}))
        text = f"{fmt(a, digits)} vs {fmt(b, digits)} (ratio {fmt(_positive_ratio(a, b), 2)})"
        return "holds" if a <= (1 + self.close) * b else "weak" if a <= (
            1 + self.loose
        ) * b else "fails", text

    def describe(self, first: str, second: str, metric: str) -> str:
        bounds = (
            f"<= {1 + self.close:.2f} x that of `{second}` holds, <= {1 + self.loose:.2f} x weak"
        )
        return f"mean {metric} of `{first}` {bounds}{GRADED}"


@dataclass(frozen=True)
class FallsAlong(Graded):
    """The mean falls along the :func:`family` ``first``: Spearman rho(level, mean) at most
    ``rho`` and the paired lowest- minus highest-level difference above 0 with its 95% CI
    (holds); one of the two, or only that difference's mean above 0 (weak).

    >>> arms = {"SR 0.1": {1: 30.0, 2: 33.0}, "SR 1": {1: 25.0, 2: 24.0}, "SR 10": {1: 20.0}}
    >>> FallsAlong(-0.5).judge({("m", 3): arms}, "SR", [], 0)
    ('partly', 'm/3r rho -1.00, SR 0.1 - SR 10 10 [-, -] (n 1): weak')
    """

    rho: float

    def grade(self, arms: Arms, first: str, second: str, digits: int) -> Grade:
        means = family_means(arms, first)
        if not means:
            return None
        low, high = next(iter(means)), list(means)[-1]
        rho = spearman([level(a) for a in means], list(means.values()))
        d = paired(arms, low, high)
        falls, sure = rho <= self.rho, d.ci_low > 0
        grade = "holds" if falls and sure else "weak" if falls or sure or d.mean > 0 else "fails"
        return grade, f"rho {fmt(rho, 2)}, {low} - {high} {_diff(d, digits)}"

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"Spearman rho(level, mean {metric} of `{first} *`) <= {self.rho:g} and the paired "
            "lowest- minus highest-level difference above 0 with its 95% CI: holds; one of them, "
            f"or only that difference's mean above 0: weak{GRADED}"
        )


@dataclass(frozen=True)
class ConvergesAtTop(Graded):
    """At the highest level of the :func:`family` ``first`` the mean is that of ``second``:
    the paired difference within ``tolerance`` of the mean of ``second`` and its 95% CI
    holding 0 (holds: "no significant difference"); one of the two (weak).

    >>> arms = {"SR 1": {1: 30.0}, "SR 10": {1: 21.0, 2: 19.0}, "full": {1: 20.0, 2: 20.0}}
    >>> ConvergesAtTop(0.1).judge({("m", 3): arms}, "SR", ["full"], 0)
    ('reproduced', 'm/3r SR 10 - `full` 0 [-13, 13] (n 2) vs 20: holds')
    """

    tolerance: float

    def grade(self, arms: Arms, first: str, second: str, digits: int) -> Grade:
        top = family(arms, first)[-1:]
        if not top:
            return None
        d, reference = paired(arms, top[0], second), _mean(arms.get(second, {}))
        close, known = abs(d.mean) <= self.tolerance * reference, math.isfinite(d.ci_low)
        zero_in = not known or d.ci_low <= 0 <= d.ci_high
        grade = (
            "holds" if close and zero_in else "weak" if close or (known and zero_in) else "fails"
        )
        text = f"{top[0]} - `{second}` {_diff(d, digits)} vs {fmt(reference, digits)}"
        return grade if math.isfinite(d.mean + reference) else "fails", text

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"|paired {metric}, highest-level `{first} *` - `{second}`| <= {self.tolerance:.0%} "
            f"of the mean of `{second}` and its 95% CI holding 0: holds; one of them: weak{GRADED}"
        )


@dataclass(frozen=True)
class RatioGrows:
    """The ratio of the means of ``first`` and ``second`` is larger in the last cell (for
    instance the larger team) than in the first and above 1 (reproduced), only larger
    (partly), or not (not reproduced).

    >>> values = {("a", 3): {"x": {1: 9.0}, "y": {1: 10.0}},
    ...           ("b", 5): {"x": {1: 12.0}, "y": {1: 10.0}}}
    >>> RatioGrows().judge(values, "x", ["y"], 3)
    ('reproduced', 'a/3r 0.900, b/5r 1.200')
    """

    def judge(self, values: Values, first: str, seconds: Sequence[str], digits: int) -> Judgement:
        ratios = {
            c: _positive_ratio(_mean(a.get(first, {})), _mean(a.get(seconds[0], {})))
            for c, a in values.items()
        }
        ends = list(ratios.values()) or [math.nan]
        small, large = ends[0], ends[-1]
        outcome: Outcome = (
            "reproduced"
            if large > max(small, 1)
            else "partly"
            if large > small
            else "not reproduced"
        )
        return outcome, ", ".join(f"{_cell_name(c)} {fmt(r, digits)}" for c, r in ratios.items())

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"ratio of the mean {metric} of `{first}` to that of `{second}`: reproduced if larger "
            "in the last cell than in the first and above 1, partly if only larger"
        )


@dataclass(frozen=True)
class RatioBound:
    """The mean of every arm of the :func:`family` ``first`` over the mean of ``second``, in
    every cell, is at most ``bound`` (below it if ``strict``): reproduced; some is, or every
    one is below ``loose``: partly. Further arms in ``seconds`` are shown, not judged.

    >>> values = {("m", 2): {"SR 1": {1: 2.0}, "SR 9": {1: 6.0}, "raw": {1: 10.0}}}
    >>> RatioBound(0.5, loose=1.0).judge(values, "SR", ["raw"], 2)
    ('partly', 'm/2r vs `raw`: SR 1 0.20, SR 9 0.60')
    """

    bound: float
    strict: bool = False
    loose: float | None = None

    def judge(self, values: Values, first: str, seconds: Sequence[str], digits: int) -> Judgement:
        judged: list[float] = []
        parts = []
        for cell, arms in values.items():
            for i, second in enumerate(seconds):
                reference = _mean(arms.get(second, {}))
                ratios = {
                    a: _positive_ratio(m, reference) for a, m in family_means(arms, first).items()
                }
                judged += list(ratios.values()) if i == 0 else []
                listed = ", ".join(f"{a} {fmt(r, digits)}" for a, r in ratios.items())
                parts.append(f"{_cell_name(cell)} vs `{second}`: {listed}")
        finite = [r for r in judged if math.isfinite(r)]
        passes = [r < self.bound if self.strict else r <= self.bound for r in finite]
        loose = self.loose is not None and finite and all(r < self.loose for r in finite)
        outcome: Outcome = "partly" if any(passes) or loose else "not reproduced"
        if finite and len(finite) == len(judged) and all(passes):
            outcome = "reproduced"
        return outcome, "; ".join(parts)

    def describe(self, first: str, second: str, metric: str) -> str:
        judged, below = second.split(" / ")[0], f"{'<' if self.strict else '<='} {self.bound:g}"
        also = f" or all are < {self.loose:g}" if self.loose is not None else ""
        shown = ", ".join(f"`{arm}`" for arm in second.split(" / ")[1:])
        shown = f" ({shown} shown, not judged)" if shown else ""
        return (
            f"mean {metric} of each `{first} *` arm / that of `{judged}`, in every cell: "
            f"reproduced if all are {below}, partly if some are{also}{shown}"
        )


@dataclass(frozen=True)
class TrendsAsPaper:
    """In each cell ``(column,)`` the sign of Spearman rho(level, mean) along the
    :func:`family` ``first`` (0 if ``|rho| < threshold``) is that of the paper's column
    (``paper``: level -> column -> value): in every column (reproduced), in at least
    ``enough`` (partly).

    >>> paper = {1.0: {"A": 9.0, "B": 1.0}, 2.0: {"A": 5.0, "B": 1.0}, 3.0: {"A": 1.0, "B": 1.0}}
    >>> ours = {("A",): {"SR 1": {1: 3.0}, "SR 2": {1: 2.0}}, ("B",): {"SR 1": {1: 3.0}}}
    >>> TrendsAsPaper(paper, 0.3, 1).judge(ours, "SR", [], 0)
    ('reproduced', 'trend signs paper/ours: A -1/-1, B +0/+0')
    """

    paper: Mapping[float, Mapping[str, float]]
    threshold: float
    enough: int

    def judge(self, values: Values, first: str, seconds: Sequence[str], digits: int) -> Judgement:
        signs: dict[str, tuple[int, int]] = {}
        for column in next(iter(self.paper.values()), {}):
            theirs = [row[column] for row in self.paper.values()]
            ours = family_means(values.get((column,), {}), first)
            signs[column] = (
                trend_sign(list(self.paper), theirs, self.threshold),
                trend_sign([level(a) for a in ours], list(ours.values()), self.threshold),
            )
        agree = sum(a == b for a, b in signs.values())
        outcome: Outcome = "partly" if agree >= self.enough else "not reproduced"
        listed = ", ".join(f"{c} {a:+d}/{b:+d}" for c, (a, b) in signs.items())
        return "reproduced" if agree == len(signs) else outcome, f"trend signs paper/ours: {listed}"

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"sign of Spearman rho(level, mean {metric} of `{first} *`), 0 if |rho| < "
            f"{self.threshold:g}, column by column, as the paper's: reproduced if in all, partly "
            f"if in >= {self.enough}"
        )


@dataclass(frozen=True)
class AtEnds:
    """In cell ``(column,)``, the mean of the :func:`family` ``first`` is at least ``high``
    at its lowest level and at most ``low`` at its highest (reproduced), one of the two
    (partly), neither (not reproduced).

    >>> AtEnds("TPT", 20, 5).judge({("TPT",): {"SR 1": {1: 30.0}, "SR 9": {1: 8.0}}}, "SR", [], 1)
    ('partly', 'TPT: SR 1 30.0, SR 9 8.0')
    """

    column: str
    high: float
    low: float

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of {self.column} along `{first} *`: >= {self.high:g} at the lowest "
            f"level and <= {self.low:g} at the highest: reproduced; one of the two: partly"
        )

    def judge(self, values: Values, first: str, seconds: Sequence[str], digits: int) -> Judgement:
        means = family_means(values.get((self.column,), {}), first) or {"-": math.nan}
        ends = [next(iter(means)), list(means)[-1]]
        met = (means[ends[0]] >= self.high) + (means[ends[1]] <= self.low)
        outcome: Outcome = "reproduced" if met == 2 else "partly" if met else "not reproduced"
        return outcome, f"{self.column}: " + ", ".join(f"{a} {fmt(means[a], digits)}" for a in ends)


@dataclass(frozen=True)
class FallsNearPaper:
    """The means of the :func:`family` ``first`` at the paper's levels (``paper``: level ->
    value; the first cell) fall strictly and each is within ``factor`` of the paper's
    (reproduced); they only fall (partly); else not reproduced.

    >>> values = {("m", 3): {"SR 1": {1: 9.0}, "SR 10": {1: 3.0}}}
    >>> FallsNearPaper({1.0: 8.0, 10.0: 1.0}, 2).judge(values, "SR", [], 1)
    ('partly', 'SR 1 9.0, SR 10 3.0')
    """

    paper: Mapping[float, float]
    factor: float

    def judge(self, values: Values, first: str, seconds: Sequence[str], digits: int) -> Judgement:
        arms = next(iter(values.values()), {})
        ours = {x: _mean(arms.get(f"{first} {x:g}", {})) for x in sorted(self.paper)}
        steps = itertools.pairwise(ours.values())
        falls = all(map(math.isfinite, ours.values())) and all(a > b for a, b in steps)
        within = all(p / self.factor <= ours[x] <= p * self.factor for x, p in self.paper.items())
        outcome: Outcome = "partly" if falls else "not reproduced"
        text = ", ".join(f"{first} {x:g} {fmt(v, digits)}" for x, v in ours.items())
        return "reproduced" if falls and within else outcome, text

    def describe(self, first: str, second: str, metric: str) -> str:
        return (
            f"mean {metric} of `{first} *` at the paper's levels: reproduced if it falls strictly "
            f"and each is within a factor {self.factor:g} of the paper's, partly if it only falls"
        )


def _diff(d: Summary, digits: int) -> str:
    return f"{fmt(d.mean, digits)} [{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}] (n {d.n})"


def _positive_ratio(a: float, b: float) -> float:
    return a / b if b > 0 else math.nan


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

    ``set`` overrides strategy parameters and ``scenario`` scenario settings (for
    instance ``sharing``) of the runs whose strategy is in ``strategies`` (every run
    when empty); the experiments it does not change are reused from the default
    reading.
    """

    name: str
    sentence: str
    """The paper's sentence that is read differently (with where it stands)."""
    reading: str
    """How this interpretation reads it, against the default reading."""
    set: Mapping[str, Any] = field(default_factory=dict)
    strategies: tuple[str, ...] = ()
    scenario: Mapping[str, Any] = field(default_factory=dict)

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
    "GRADED",
    "AtEnds",
    "AtLeast",
    "Claim",
    "ConvergesAtTop",
    "Counted",
    "Diminishing",
    "FallAlong",
    "FallsAlong",
    "FallsFasterBelow",
    "FallsLess",
    "FallsNearPaper",
    "GapNarrows",
    "Graded",
    "Interpretation",
    "Lowest",
    "Monotone",
    "NotBelowAll",
    "PairedAbove",
    "PairedLower",
    "PairedMostlyLower",
    "RankTrend",
    "RatioAtMost",
    "RatioBound",
    "RatioFalls",
    "RatioGrows",
    "RatioWithin",
    "RatioWithinFactor",
    "RisesAbove",
    "Rule",
    "Share",
    "Trend",
    "TrendForAll",
    "TrendsAsPaper",
    "Unpaired",
    "Values",
    "WithMeans",
    "WithinFactor",
    "claims_section",
    "common_seeds",
    "count_outcome",
    "family",
    "family_means",
    "fmt",
    "graded",
    "level",
    "lowest_arm",
    "paired",
    "robustness",
    "robustness_section",
    "series_of",
    "series_text",
    "spearman",
    "trend_sign",
]
