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
        text = f"{fmt(a, digits)} vs {fmt(b, digits)} (ratio {fmt(_ratio(a, b), 2)})"
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
            c: _ratio(_mean(a.get(first, {})), _mean(a.get(seconds[0], {})))
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
                ratios = {a: _ratio(m, reference) for a, m in family_means(arms, first).items()}
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


def _ratio(a: float, b: float) -> float:
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
    "GRADED",
    "AtEnds",
    "Claim",
    "ConvergesAtTop",
    "Counted",
    "FallsAlong",
    "FallsNearPaper",
    "Graded",
    "Interpretation",
    "PairedAbove",
    "PairedLower",
    "RatioBound",
    "RatioGrows",
    "RatioWithin",
    "Rule",
    "Trend",
    "TrendsAsPaper",
    "Values",
    "WithinFactor",
    "claims_section",
    "count_outcome",
    "family",
    "family_means",
    "fmt",
    "graded",
    "level",
    "paired",
    "robustness",
    "robustness_section",
    "spearman",
    "trend_sign",
]
