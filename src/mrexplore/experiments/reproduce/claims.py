"""Claims of a paper as data: the sentence, the comparison, the rule that decides it.

A :class:`Claim` names where in the paper it stands, the paper's sentence, the metric, the
arms and a rule object that computes the verdict and writes the words that describe it, so
report and code cannot drift apart. A :class:`Rule` grades items (cells, curves) *holds*,
*weak* or *fails* from ``cell -> arm -> seed -> value`` (:data:`Values`), and
:class:`Needs` counts the grades into the outcome. An :class:`Interpretation` is another
reading of a sentence of the paper, as run overrides; :func:`robustness_section` shows
whether each verdict stays the same under every reading.
"""

from __future__ import annotations

import itertools
import math
import operator
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

from mrexplore.experiments.stats import Summary, summarize_metric

CellKey = tuple[Any, ...]
"""A cell a claim is judged in, e.g. ``(map, robots)``."""
BySeed = Mapping[int, float]
Arms = Mapping[str, BySeed]
"""One cell of :data:`Values`: ``arm -> seed -> value``."""
Values = Mapping[CellKey, Arms]
"""``cell -> arm -> seed -> value``."""
Outcome = Literal["reproduced", "partly", "not reproduced"]
Judgement = tuple[Outcome, str]
HOLDS, WEAK, FAILS = 2, 1, 0
"""The grades of an item; ``None``: shown, not judged."""
_MARKS = {HOLDS: "", WEAK: " (weak)", FAILS: " x", None: ""}
_RELATIONS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}


def fmt(value: float | None, digits: int = 0) -> str:
    """A number for a verdict line: ``digits`` decimals, thin-space thousands, ``-``
    for a missing or non-finite value.

    >>> fmt(12345.678), fmt(0.25, 2), fmt(None), fmt(float("nan"))
    ('12 346', '0.25', '-', '-')
    """
    if value is None or not math.isfinite(value):
        return "-"
    return f"{value:,.{digits}f}".replace(",", " ")


def paired(by_seed: Arms, a: str, b: str) -> Summary:
    """``A - B`` over the seeds both arms ran (mean, sd, 95% CI).

    >>> paired({"a": {1: 5.0, 2: 7.0}, "b": {1: 4.0, 2: 4.0, 3: 1.0}}, "a", "b").mean
    2.0
    """
    first, second = by_seed.get(a, {}), by_seed.get(b, {})
    return summarize_metric([first[s] - second[s] for s in sorted(set(first) & set(second))])


def _mean(by_seed: BySeed) -> float:
    return summarize_metric(list(by_seed.values())).mean


def _ratio(a: float, b: float) -> float:
    return a / b if b > 0 else math.nan


def _diff(d: Summary, digits: int) -> str:
    return f"{fmt(d.mean, digits)} [{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}], n {d.n}"


def _cell_name(cell: CellKey) -> str:
    last = f"/{cell[-1]}r" if len(cell) > 1 else str(cell[0])
    return "/".join(str(part) for part in cell[:-1]) + last


def series_text(series: Mapping[Any, float], digits: int = 0) -> str:
    """``x:mean, ...`` of one curve.

    >>> series_text({4: 310.0, 8.0: 290.5}, 1)
    '4:310.0, 8:290.5'
    """
    name = lambda x: f"{x:g}" if isinstance(x, int | float) else str(x)  # noqa: E731
    return ", ".join(f"{name(x)}:{fmt(m, digits)}" for x, m in series.items())


def lowest_arm(arms: Arms, among: Sequence[str]) -> str | None:
    """The arm of ``among`` with the lowest mean (ties: the first by name), ``None``
    when none has a finite mean.

    >>> lowest_arm({"b": {1: 2.0}, "a": {1: 2.0}, "c": {1: 1.0}, "d": {}}, ["a", "b", "d"])
    'a'
    """
    means = {a: _mean(arms[a]) for a in among if a in arms}
    finite = {a: m for a, m in means.items() if math.isfinite(m)}
    return min(finite, key=lambda a: (finite[a], a)) if finite else None


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


# ------------------------------------------------------------ grades and outcomes


def _share_words(share: float, item: str) -> str:
    words = {1.0: f"every {item}", 0.5: f"at least half of the {item}s"}
    return words.get(share, f"at least {share:.0%} of the {item}s" if share else f"one {item}")


@dataclass(frozen=True)
class Needs:
    """The shares of the judged items that must hold, and hold at least weakly: all that
    are given for ``reproduced``, one of them for ``partly``; 0 means at least one item.

    >>> Needs().outcome([HOLDS, FAILS]), Needs().outcome([HOLDS, FAILS, FAILS]), Needs().outcome([])
    ('partly', 'not reproduced', 'not reproduced')
    >>> SOME_WEAK.words("it holds", "it holds weakly", "cell")
    'reproduced if it holds in every cell, partly if it holds weakly in one cell'
    """

    holds: float | None = 1.0
    weakly: float | None = None
    partly_holds: float | None = 0.5
    partly_weakly: float | None = None

    def outcome(self, grades: Sequence[int]) -> Outcome:
        counts = (grades.count(HOLDS), len(grades) - grades.count(FAILS))

        def met(share: float | None, count: int) -> bool:
            return share is not None and count > 0 and count / len(grades) >= share

        reproduced = zip((self.holds, self.weakly), counts, strict=True)
        if all(t is None or met(t, c) for t, c in reproduced):
            return "reproduced"
        partly = zip((self.partly_holds, self.partly_weakly), counts, strict=True)
        return "partly" if any(met(t, c) for t, c in partly) else "not reproduced"

    def words(self, strong: str, weak: str, item: str) -> str:
        def said(pair: tuple[float | None, float | None], joint: str) -> str:
            parts = zip(pair, (strong, weak), strict=True)
            return joint.join(f"{w} in {_share_words(t, item)}" for t, w in parts if t is not None)

        reproduced = said((self.holds, self.weakly), " and ")
        partly = said((self.partly_holds, self.partly_weakly), " or ")
        return f"reproduced if {reproduced}, partly if {partly}"


EVERY_HALF = Needs()
"""Reproduced if every item holds, partly if at least half do."""
EVERY_WEAK = Needs(partly_holds=None, partly_weakly=1.0)
"""Reproduced if every item holds, partly if every one holds at least weakly."""
SOME_WEAK = Needs(partly_holds=None, partly_weakly=0.0)
"""Reproduced if every item holds, partly if one holds at least weakly."""


@dataclass(frozen=True)
class Check:
    """One judged item: its name, its numbers, its grade (``None``: shown, not judged), the
    comparison it belongs to (``block``) when a rule makes several."""

    name: str
    text: str
    grade: int | None
    block: str = ""
    data: Any = None

    def line(self) -> str:
        return (f"{self.name}: {self.text}" if self.name else self.text) + _MARKS[self.grade]


@dataclass(frozen=True)
class Ask:
    """What a rule judges: the values, the first arm and those it is compared with, the
    decimals of the numbers shown."""

    values: Values
    first: str
    seconds: tuple[str, ...]
    digits: int

    def fmt(self, value: float) -> str:
        return fmt(value, self.digits)


@dataclass(frozen=True, kw_only=True)
class Rule:
    """Base of the rules: :meth:`checks` grades the items, :attr:`needs` (or :attr:`usual`)
    counts them, :meth:`describe` says so from :meth:`what` and :meth:`conditions`.
    ``shown``: arms shown beside, not judged; ``brief``: the evidence names only the items
    that do not hold; ``also``: another pair of arms whose count is cited."""

    needs: Needs | None = None
    shown: tuple[str, ...] = ()
    brief: bool = False
    also: tuple[str, str] | None = None
    usual: ClassVar[Needs] = EVERY_HALF
    item: ClassVar[str] = "cell"
    grade_words: ClassVar[tuple[str, str]] = ("it holds", "")
    """What holds and what holds weakly (``""``: no weak grade), when the fields do not say."""

    def what(self, first: str, second: str, metric: str) -> str:
        raise NotImplementedError

    def conditions(self) -> tuple[str, str]:
        return self.grade_words

    def checks(self, ask: Ask) -> Iterator[Check]:
        raise NotImplementedError

    def describe(self, first: str, second: str, metric: str) -> str:
        strong, weak = self.conditions()
        words = self.what(first, second, metric)
        if self.shown:
            words += f" ({', '.join(f'`{a}`' for a in self.shown)} shown, not judged)"
        if self.also:
            words += f" (also counted on `{self.also[0]}` vs `{self.also[1]}`)"
        return f"{words}; {(self.needs or self.usual).words(strong, weak or strong, self.item)}"

    def judge(self, values: Values, first: str, seconds: Sequence[str], digits: int) -> Judgement:
        checks = list(self.checks(Ask(values, first, tuple(seconds), digits)))
        blocks: dict[str, list[Check]] = {}
        for check in checks:
            blocks.setdefault(check.block, []).append(check)
        text = " | ".join(
            f"{name}: {self._block(part)}" if len(blocks) > 1 else self._block(part)
            for name, part in blocks.items()
        )
        if self.also:
            more = list(self.checks(Ask(values, self.also[0], self.also[1:], digits)))
            text += f"; `{self.also[0]}` vs `{self.also[1]}`: {self.tally(more)}"
        grades = [c.grade for c in checks if c.grade is not None]
        return (self.needs or self.usual).outcome(grades), text or self.tally([])

    def _block(self, checks: Sequence[Check]) -> str:
        judged = [c for c in checks if c.grade is not None]
        lines = [c.line() for c in checks if not (self.brief and c.grade == HOLDS)]
        if self.brief:
            lines = [f"fails in {', '.join(lines)}"] if lines else []
        return "; ".join(([self.tally(judged), *self.totals(judged)] if judged else []) + lines)

    def tally(self, checks: Sequence[Check]) -> str:
        """``holds in 3/4 cells``, and how many hold at least weakly if the rule grades so."""
        grades = [c.grade for c in checks]
        text = f"holds in {grades.count(HOLDS)}/{len(grades)} {self.item}s"
        if not self.conditions()[1]:
            return text
        return f"{text}, at least weakly in {len(grades) - grades.count(FAILS)}/{len(grades)}"

    def totals(self, checks: Sequence[Check]) -> list[str]:
        """Numbers over all the judged items, after the count."""
        return []


# ------------------------------------------------------------------ cell by cell


@dataclass(frozen=True)
class Pair:
    """Two arms of one cell: each one's summary and, over the seeds both ran, ``a - b``."""

    a: Summary
    b: Summary
    d: Summary | None


@dataclass(frozen=True, kw_only=True)
class Cells(Rule):
    """Base of the rules that compare ``first`` with each arm of ``seconds`` (``best``: the
    one with the lowest mean) cell by cell, leaving out cells without both. ``seeds``:
    ``all`` (each arm over its seeds, the paired difference over those both ran), ``common``
    (both over the seeds both ran, at least ``min_seeds``) or ``unpaired`` (no difference).
    ``except_at``: last cell keys where the claim is the opposite. ``members``: ``first``
    names a :func:`family`; compare ``each`` member or the ``top`` level."""

    seeds: Literal["all", "common", "unpaired"] = "all"
    min_seeds: int = 1
    best: bool = False
    except_at: tuple[Any, ...] = ()
    members: Literal["", "each", "top"] = ""

    def grade(self, pair: Pair, cell: CellKey, ask: Ask) -> tuple[int, str]:
        raise NotImplementedError

    def checks(self, ask: Ask) -> Iterator[Check]:
        for second in [""] if self.best else [*ask.seconds, *self.shown]:
            for cell, arms in ask.values.items():
                other = second or lowest_arm(arms, ask.seconds) or ""
                for arm in self._members(arms, ask.first):
                    pair = self._pair(arms, arm, other)
                    if pair is None:
                        continue
                    grade, text = self.grade(pair, cell, ask)
                    grade = HOLDS + FAILS - grade if cell[-1] in self.except_at else grade
                    name = _cell_name(cell) + (f" {arm}" if self.members else "")
                    name += "" if second else f" (best other `{other}`)"
                    judged = None if second in self.shown else grade
                    yield Check(name, text, judged, f"vs `{second}`" if second else "", pair)

    def _members(self, arms: Arms, first: str) -> list[str]:
        found = family(arms, first) if self.members else [first]
        return found[-1:] if self.members == "top" else found

    def _pair(self, arms: Arms, a: str, b: str) -> Pair | None:
        if a not in arms or b not in arms:
            return None
        x, y = arms[a], arms[b]
        common = sorted(set(x) & set(y))
        if self.seeds == "common":
            if len(common) < max(self.min_seeds, 1):
                return None
            x, y = ({s: v[s] for s in common} for v in (x, y))
        d = summarize_metric([x[s] - y[s] for s in common])
        mean_a, mean_b = (summarize_metric(list(v.values())) for v in (x, y))
        return Pair(mean_a, mean_b, None if self.seeds == "unpaired" else d)

    def arm(self, first: str) -> str:
        words = {"": f"`{first}`", "each": f"each `{first} *` arm"}
        return words.get(self.members, f"the highest-level `{first} *` arm")

    def over(self) -> str:
        """How the cells are read, in words."""
        at_least = f" (at least {self.min_seeds})" if self.min_seeds > 1 else ""
        seeds = {"common": f" over the seeds both ran{at_least}", "unpaired": " (seeds not paired)"}
        opposite = ", ".join(map(str, self.except_at))
        opposite = f" (the opposite where the last cell key is {opposite})" if opposite else ""
        return f"{seeds.get(self.seeds, '')}, cell by cell{opposite}"

    def versus(self, second: str) -> str:
        return f"the lowest of `{second}` in each cell" if self.best else f"`{second}`"


@dataclass(frozen=True)
class Means(Cells):
    """The mean (``statistic="sd"``: the sd) of ``first`` ``relation`` that of ``second``;
    each cell shows the paired difference and its 95% CI (but ``unpaired``). ``summary``:
    also how many CIs lie below / above 0 and the ratios' median and range.

    >>> values = {("m", 2): {"a": {1: 1.0, 2: 3.0}, "b": {1: 2.0, 2: 4.0}},
    ...           ("m", 3): {"a": {1: 5.0}, "b": {1: 4.0}}}
    >>> Means("<=").judge(values, "a", ["b"], 0)
    ('partly', 'holds in 1/2 cells; m/2r: 2 vs 3 (paired -1 [-1, -1], n 2); m/3r: 5 vs 4 \
(paired 1 [-, -], n 1) x')
    >>> print(Means("<", best=True, except_at=(3,)).describe("b", "a / c", "T99"))
    mean T99 of `b` < that of the lowest of `a / c` in each cell, cell by cell (the opposite \
where the last cell key is 3); reproduced if it holds in every cell, partly if it holds in at \
least half of the cells
    """

    relation: str
    statistic: Literal["mean", "sd"] = "mean"
    summary: bool = False

    def what(self, first: str, second: str, metric: str) -> str:
        compared = f"{self.statistic} {metric} of {self.arm(first)} {self.relation} that of"
        return f"{compared} {self.versus(second)}{self.over()}"

    def grade(self, pair: Pair, cell: CellKey, ask: Ask) -> tuple[int, str]:
        a, b = getattr(pair.a, self.statistic), getattr(pair.b, self.statistic)
        text = f"{ask.fmt(a)} vs {ask.fmt(b)}"
        if pair.d is not None and self.statistic == "mean":
            text += f" (paired {_diff(pair.d, ask.digits)})"
        return (HOLDS if _RELATIONS[self.relation](a, b) else FAILS), text

    def totals(self, checks: Sequence[Check]) -> list[str]:
        from statistics import median

        pairs: list[Pair] = [c.data for c in checks]
        differences = [p.d for p in pairs if p.d is not None]
        out = []
        if self.summary and self.statistic == "mean" and len(differences) == len(pairs):
            below, above = (
                sum(d.ci_high < 0 for d in differences),
                sum(d.ci_low > 0 for d in differences),
            )
            out.append(f"paired 95% CI below 0 in {below}, above 0 in {above}")
        of = [_ratio(getattr(p.a, self.statistic), getattr(p.b, self.statistic)) for p in pairs]
        ratios = {c.name: r for c, r in zip(checks, of, strict=True) if math.isfinite(r)}
        if self.summary and ratios:
            low, spread = min(ratios, key=ratios.__getitem__), sorted(ratios.values())
            middle, ends = fmt(median(spread), 2), f"{fmt(spread[0], 2)}-{fmt(spread[-1], 2)}"
            out.append(f"ratio median {middle}, range {ends}, lowest at {low}")
        return out


@dataclass(frozen=True)
class Paired(Cells):
    """The paired difference ``first - second``: ``<`` its 95% CI below 0 holds, its mean
    below 0 weakly (``>``: above); ``=`` its mean within ``tolerance`` of the mean of
    ``second`` and its CI holding 0 (or unknown: one seed) holds, one of the two weakly.

    >>> values = {("m", 2): {"a": {s: 1.0 + s % 2 for s in range(6)},
    ...                      "b": {s: 5.0 for s in range(6)}}}
    >>> Paired("<").judge(values, "a", ["b"], 1)
    ('reproduced', 'holds in 1/1 cells, at least weakly in 1/1; m/2r: 1.5 vs 5.0 (paired -3.5 \
[-4.1, -2.9], n 6)')
    """

    relation: Literal["<", ">", "="] = "<"
    tolerance: float = 0.1
    usual: ClassVar[Needs] = EVERY_WEAK

    def what(self, first: str, second: str, metric: str) -> str:
        difference = f"paired difference of {metric}, {self.arm(first)} - `{second}`"
        return f"{difference}, over the seeds both ran{self.over()}"

    def conditions(self) -> tuple[str, str]:
        if self.relation == "=":
            close = f"|its mean| is within {self.tolerance:.0%} of the second arm's mean"
            return f"{close} and its 95% CI holds 0", "one of the two holds"
        side = "below" if self.relation == "<" else "above"
        return f"its 95% CI is {side} 0", f"its mean is {side} 0"

    def grade(self, pair: Pair, cell: CellKey, ask: Ask) -> tuple[int, str]:
        d = pair.d or summarize_metric([])
        text = f"{ask.fmt(pair.a.mean)} vs {ask.fmt(pair.b.mean)} (paired {_diff(d, ask.digits)})"
        if self.relation == "=":
            close, known = abs(d.mean) <= self.tolerance * pair.b.mean, math.isfinite(d.ci_low)
            zero_in = not known or d.ci_low <= 0 <= d.ci_high
            grade = HOLDS if close and zero_in else WEAK if close or (known and zero_in) else FAILS
            return grade if math.isfinite(d.mean + pair.b.mean) else FAILS, text
        sure, likely = (d.ci_high, d.mean) if self.relation == "<" else (-d.ci_low, -d.mean)
        return (HOLDS if sure < 0 else WEAK if likely < 0 else FAILS), text


@dataclass(frozen=True)
class Ratio(Cells):
    """The ratio of the means ``first / second`` ``relation`` ``bound`` holds, ``relation``
    ``weak`` weakly; with ``paper`` (cell -> the paper's ratio) it holds only if also
    within ``factor`` of the paper's, else weakly. ``digits``: of the ratios.

    >>> values = {("m", n): {"a": {1: 10.0 + n}, "b": {1: 10.0}} for n in (1, 5)}
    >>> Ratio("<=", 1.25).judge(values, "a", ["b"], 0)[1]
    'holds in 1/2 cells; m/1r: 11 vs 10 (ratio 1.10); m/5r: 15 vs 10 (ratio 1.50) x'
    """

    relation: str
    bound: float
    weak: float | None = None
    paper: Mapping[CellKey, float] | None = None
    factor: float = 2.0
    digits: int = 2

    def what(self, first: str, second: str, metric: str) -> str:
        return f"ratio of the mean {metric} of {self.arm(first)} to that of `{second}`{self.over()}"

    def conditions(self) -> tuple[str, str]:
        bound = f"it is {self.relation} {self.bound:g}"
        if self.paper is not None:
            return f"{bound} and within a factor {self.factor:g} of the paper's", bound
        return bound, f"it is {self.relation} {self.weak:g}" if self.weak is not None else ""

    def grade(self, pair: Pair, cell: CellKey, ask: Ask) -> tuple[int, str]:
        holds, r = _RELATIONS[self.relation], _ratio(pair.a.mean, pair.b.mean)
        text = f"{ask.fmt(pair.a.mean)} vs {ask.fmt(pair.b.mean)} (ratio {fmt(r, self.digits)}"
        if self.paper is None:
            weak = self.weak is not None and holds(r, self.weak)
            return (HOLDS if holds(r, self.bound) else WEAK if weak else FAILS), text + ")"
        paper = self.paper.get(cell, math.nan)
        near = 1 / self.factor <= r / paper <= self.factor
        grade = (HOLDS if near else WEAK) if holds(r, self.bound) else FAILS
        return grade, f"{text}, paper {fmt(paper, self.digits)})"


@dataclass(frozen=True)
class Level(Rule):
    """The mean of ``first`` ``relation`` ``bound`` in a cell holds, ``relation`` ``weak``
    weakly; cells without a finite mean are left out.

    >>> values = {("m", 2): {"a": {1: 0.95}, "b": {1: 0.2}}, ("m", 4): {"a": {1: 0.9}}}
    >>> Level(">=", 0.95, 0.8, shown=("b",)).judge(values, "a", [], 2)
    ('partly', '`a`: holds in 1/2 cells, at least weakly in 2/2; m/2r: 0.95; m/4r: 0.90 (weak) \
| `b`: m/2r: 0.20')
    """

    relation: str
    bound: float
    weak: float | None = None
    usual: ClassVar[Needs] = EVERY_WEAK

    def what(self, first: str, second: str, metric: str) -> str:
        return f"mean {metric} of `{first}`, cell by cell"

    def conditions(self) -> tuple[str, str]:
        weak = f"it is {self.relation} {self.weak:g}" if self.weak is not None else ""
        return f"it is {self.relation} {self.bound:g}", weak

    def checks(self, ask: Ask) -> Iterator[Check]:
        holds = _RELATIONS[self.relation]
        for arm in (ask.first, *self.shown):
            for cell, arms in ask.values.items():
                mean = _mean(arms.get(arm, {}))
                weak = self.weak is not None and holds(mean, self.weak)
                grade = HOLDS if holds(mean, self.bound) else WEAK if weak else FAILS
                if math.isfinite(mean):
                    judged = grade if arm == ask.first else None
                    yield Check(_cell_name(cell), ask.fmt(mean), judged, f"`{arm}`")


@dataclass(frozen=True)
class NotBelowAll(Rule):
    """``first`` is not superior to the other arms: superior in a cell where the paired 95%
    CI of ``first - second`` lies below 0 against every other arm.

    >>> far = {s: 5.0 + s % 2 for s in range(4)}
    >>> values = {("m", 2): {"a": {s: 1.0 + s % 2 for s in range(4)}, "b": far, "c": far},
    ...           ("m", 4): {"a": far, "b": far, "c": far}}
    >>> NotBelowAll(brief=True).judge(values, "a", ["b", "c"], 0)
    ('partly', 'holds in 1/2 cells; fails in m/2r: `b` -4 [-4, -4], n 4; `c` -4 [-4, -4], n 4 x')
    """

    def what(self, first: str, second: str, metric: str) -> str:
        test = f"the paired 95% CI of its {metric} minus that of each of `{second}` lies below 0"
        return f"`{first}` is superior in a cell if {test}; the claim holds where it is not"

    def checks(self, ask: Ask) -> Iterator[Check]:
        for cell, arms in ask.values.items():
            if {ask.first, *ask.seconds} <= set(arms):
                ds = {s: paired(arms, ask.first, s) for s in ask.seconds}
                text = "; ".join(f"`{s}` {_diff(d, ask.digits)}" for s, d in ds.items())
                superior = all(d.ci_high < 0 for d in ds.values())
                yield Check(_cell_name(cell), text, FAILS if superior else HOLDS)


# ------------------------------------------------------------------------ curves


@dataclass(frozen=True, kw_only=True)
class Along(Rule):
    """Base of the rules that follow curves: ``along`` the last cell key (a curve per group
    of the other keys), the ``cells`` in the caller's order (one curve), or the levels of
    the :func:`family` ``first`` (a curve per cell); ``within``: the cells whose key starts
    with these parts only."""

    along: Literal["key", "cells", "family"] = "key"
    within: CellKey = ()
    item: ClassVar[str] = "curve"

    def curves(self, values: Values, arm: str) -> dict[str, dict[Any, BySeed]]:
        """``curve name -> x -> seed -> value`` of one arm."""
        out: dict[str, dict[Any, BySeed]] = {}
        for cell, arms in values.items():
            if cell[: len(self.within)] != self.within:
                continue
            if self.along == "family" and family(arms, arm):
                out[_cell_name(cell)] = {level(a): arms[a] for a in family(arms, arm)}
            elif self.along != "family" and arm in arms:
                group, x = (
                    ((), _cell_name(cell)) if self.along == "cells" else (cell[:-1], cell[-1])
                )
                out.setdefault("/".join(map(str, group)), {})[x] = arms[arm]
        return out

    def means(self, ask: Ask, arm: str) -> dict[str, dict[Any, float]]:
        """``curve name -> x -> mean`` of one arm."""
        curves = self.curves(ask.values, arm).items()
        return {name: {x: _mean(s) for x, s in curve.items()} for name, curve in curves}

    def axis(self, first: str) -> str:
        axes = {"key": "the last cell key, per group of the other keys", "cells": "the cells"}
        return axes.get(self.along, f"the level of `{first} *`, cell by cell")


def _moves(direction: str, a: float, b: float) -> bool:
    return b < a if direction == "falls" else b > a


@dataclass(frozen=True)
class Trend(Along):
    """The curves of ``first`` and of each arm of ``seconds`` (``ratio``, ``gap``: of
    ``first`` against ``second``, over the seeds both ran) fall or rise. ``kind``:
    ``steps``, at every step (holds) or from the first point to the last (weakly), beside
    ``paper`` (arm -> numbers); ``rank``, Spearman's rho beyond ``rho`` and the last point
    beyond the first (``paired``: by the paired 95% CI of first - last; one of the two, or
    that difference's mean, weakly); ``diminishing``, falling from the smallest key to the
    largest (weakly) and at least as much up to the middle key as after (holds); ``ratio``,
    the ratio of the means moves from the first point to the last (and ends beyond
    ``bound``, if given; else weakly); ``gap``, the difference and the ratio shrink (the
    difference only: weakly).

    >>> values = {("m", n): {"a": {1: 9 / n}, "b": {1: b}} for n, b in ((1, 8), (2, 6), (3, 7))}
    >>> Trend("steps", needs=EVERY_WEAK).judge(values, "a", ["b"], 0)[1]
    'holds in 1/2 curves, at least weakly in 2/2; `a` m: 1:9, 2:4, 3:3, -67% first to last; \
`b` m: 1:8, 2:6, 3:7, -12% first to last (weak)'
    >>> Trend("rank").judge(values, "b", [], 0)
    ('not reproduced', 'holds in 0/1 curves; m: 1:8, 2:6, 3:7 (Spearman rho -0.50) x')
    >>> Trend("gap").judge(values, "a", ["b"], 0)[1]
    'holds in 1/1 curves, at least weakly in 1/1; m: 1: 1 (x1.12) -> 3: -4 (x0.43)'
    """

    kind: Literal["steps", "rank", "diminishing", "ratio", "gap"]
    direction: Literal["falls", "rises"] = "falls"
    rho: float = 0.6
    paired: bool = False
    bound: float | None = None
    paper: Mapping[str, Sequence[float]] = field(default_factory=dict)
    digits: int = 2
    """Decimals of the ratios."""

    def what(self, first: str, second: str, metric: str) -> str:
        if self.kind in ("ratio", "gap"):
            of = "ratio" if self.kind == "ratio" else "difference and ratio"
            means = f"the mean {metric} of `{first}` over that of `{second}` (seeds both ran)"
            return f"{of} of {means} against {self.axis(first)}"
        arms = " / ".join(f"`{a}`" for a in (first, *second.split(" / ")) if a)
        arms = f"each of {arms}" if " / " in arms else arms
        arms = f"`{first} *`" if self.along == "family" else arms
        paper = " (beside the paper's numbers)" if self.paper else ""
        return f"mean {metric} of {arms} against {self.axis(first)}{paper}"

    def conditions(self) -> tuple[str, str]:
        way, side = self.direction, "below" if self.direction == "falls" else "above"
        ends = f"it ends {side} where it starts"
        rho = f"Spearman's rho {'<= -' if way == 'falls' else '>= '}{self.rho:g}"
        bound = f" and it ends {side} {self.bound:g}" if self.bound is not None else ""
        words = {
            "steps": (f"it {way} at every step", ends),
            "rank": (f"{rho} and {ends}", ""),
            "diminishing": ("it falls with diminishing returns", "it falls"),
            "ratio": (f"it {way}{bound}", f"it {way}" if bound else ""),
            "gap": ("both shrink", "the difference shrinks"),
        }
        if self.kind == "rank" and self.paired:
            sure = f"first - last has a paired 95% CI {'above' if way == 'falls' else 'below'} 0"
            return f"{rho} and {sure}", "one of the two holds, or that mean is above 0"
        return words[self.kind]

    def checks(self, ask: Ask) -> Iterator[Check]:
        if self.kind in ("ratio", "gap"):
            yield from self._against(ask)
            return
        arms = [ask.first, *ask.seconds, *self.shown]
        test = {"steps": self._steps, "rank": self._rank, "diminishing": self._diminishing}
        for arm in arms:
            for name, curve in self.curves(ask.values, arm).items():
                if self.kind == "diminishing" and len(curve) < 2:
                    continue
                grade, text = test[self.kind](arm, curve, ask)
                label = f"`{arm}` {name}".strip() if len(arms) > 1 else name
                yield Check(label, text, None if arm in self.shown else grade)

    def _steps(self, arm: str, curve: Mapping[Any, BySeed], ask: Ask) -> tuple[int, str]:
        means = [_mean(s) for s in curve.values()]
        every = all(_moves(self.direction, a, b) for a, b in itertools.pairwise(means))
        ends = len(means) > 1 and _moves(self.direction, means[0], means[-1])
        paper = ", ".join(ask.fmt(p) for p in self.paper.get(arm, ()))
        text = series_text(dict(zip(curve, means, strict=True)), ask.digits)
        text += f" (paper {paper})" if paper else ""
        if len(means) > 1:
            change = _ratio(means[-1], means[0])
            text += f", {100 * (change - 1):+.0f}% first to last" if math.isfinite(change) else ""
        return (HOLDS if every and ends else WEAK if ends else FAILS), text

    def _rank(self, arm: str, curve: Mapping[Any, BySeed], ask: Ask) -> tuple[int, str]:
        xs, means = list(curve), [_mean(s) for s in curve.values()]
        rho = spearman([float(x) for x in xs], means)
        steep = rho <= -self.rho if self.direction == "falls" else rho >= self.rho
        series = series_text(dict(zip(xs, means, strict=True)), ask.digits)
        text = f"{series} (Spearman rho {fmt(rho, 2)}"
        if not self.paired:
            ends = _moves(self.direction, means[0], means[-1])
            return (HOLDS if steep and ends else FAILS), text + ")"
        d = paired({"a": curve[xs[0]], "b": curve[xs[-1]]}, "a", "b")
        sure, likely = (d.ci_low, d.mean) if self.direction == "falls" else (-d.ci_high, -d.mean)
        grade = HOLDS if steep and sure > 0 else WEAK if steep or likely > 0 else FAILS
        return grade, f"{text}; first - last paired {_diff(d, ask.digits)})"

    def _diminishing(self, arm: str, curve: Mapping[Any, BySeed], ask: Ask) -> tuple[int, str]:
        keys = sorted(curve)
        a, middle, z = (_mean(curve[k]) for k in (keys[0], keys[len(keys) // 2], keys[-1]))
        grade = (HOLDS if a - middle >= middle - z else WEAK) if z < a else FAILS
        return grade, series_text({k: _mean(curve[k]) for k in curve}, ask.digits)

    def _against(self, ask: Ask) -> Iterator[Check]:
        second = self.curves(ask.values, ask.seconds[0])
        for name, curve in self.curves(ask.values, ask.first).items():
            points: dict[Any, tuple[float, float]] = {}
            for x, a in curve.items():
                b = second.get(name, {}).get(x, {})
                common = sorted(set(a) & set(b))
                if common:
                    points[x] = (_mean({s: a[s] for s in common}), _mean({s: b[s] for s in common}))
            if len(points) >= 2:
                yield Check(name, *self._ratios(points, ask))

    def _ratios(self, points: Mapping[Any, tuple[float, float]], ask: Ask) -> tuple[str, int]:
        ratios = {x: _ratio(a, b) for x, (a, b) in points.items()}
        (x0, r0), (x1, r1) = next(iter(ratios.items())), list(ratios.items())[-1]
        if self.kind == "ratio":
            moves = _moves(self.direction, r0, r1)
            bound = self.bound is None or _moves(self.direction, self.bound, r1)
            grade = HOLDS if moves and bound else WEAK if moves else FAILS
            return series_text(ratios, self.digits), grade
        (a0, b0), (a1, b1) = points[x0], points[x1]
        text = f"{x0}: {ask.fmt(a0 - b0)} (x{fmt(r0, self.digits)}) -> "
        text += f"{x1}: {ask.fmt(a1 - b1)} (x{fmt(r1, self.digits)})"
        return text, ((HOLDS if r1 < r0 else WEAK) if a1 - b1 < a0 - b0 else FAILS)


@dataclass(frozen=True)
class FallsFasterBelow(Along):
    """Per curve of ``first`` (x: its key), the mean falls per unit of x from the smallest x
    to ``at`` (the gain below, above 0) faster than from ``at`` to the largest (above).

    >>> values = {("t", x): {"a": {1: m}} for x, m in ((4, 400.0), (16, 280.0), (24, 272.0))}
    >>> FallsFasterBelow(16, "cell").judge(values, "a", [], 2)
    ('reproduced', 'holds in 1/1 curves; t: 10.00 per cell below 16 vs 1.00 above')
    """

    at: float
    unit: str = "unit"
    grade_words: ClassVar = ("the gain below is positive and larger than above", "")

    def what(self, first: str, second: str, metric: str) -> str:
        at = f"{self.at:g}"
        below, above = (
            f"(m(x_min) - m({at})) / ({at} - x_min)",
            f"(m({at}) - m(x_max)) / (x_max - {at})",
        )
        gains = f"gain per {self.unit} below {at} = {below}, above = {above}"
        return f"mean {metric} of `{first}` against {self.axis(first)}, x the key: {gains}"

    def checks(self, ask: Ask) -> Iterator[Check]:
        for name, m in self.means(ask, ask.first).items():
            low, high, at = min(m), max(m), self.at
            below = above = math.nan
            if at in m and low < at < high:
                below, above = (m[low] - m[at]) / (at - low), (m[at] - m[high]) / (high - at)
            text = f"{ask.fmt(below)} per {self.unit} below {at:g} vs {ask.fmt(above)} above"
            yield Check(name, text, HOLDS if below > 0 and below > above else FAILS)


@dataclass(frozen=True)
class FallsLess(Along):
    """Per curve, the mean of ``first`` falls less from the smallest key to the largest than
    that of ``second`` (a rise counts as less).

    >>> values = {("t", x): {"a": {1: a}, "b": {1: b}} for x, a, b in ((4, 30, 34), (8, 29, 30))}
    >>> FallsLess().judge(values, "a", ["b"], 0)
    ('reproduced', 'holds in 1/1 curves; t: `a` falls by 1 vs `b` by 4')
    """

    grade_words: ClassVar = ("the fall of the first is smaller", "")

    def what(self, first: str, second: str, metric: str) -> str:
        means = f"the mean {metric} of `{first}` and of `{second}`"
        return f"fall m(x_min) - m(x_max) of {means} against {self.axis(first)}"

    def checks(self, ask: Ask) -> Iterator[Check]:
        arms = (ask.first, ask.seconds[0])
        curves = [self.means(ask, arm) for arm in arms]
        for name in dict.fromkeys(n for c in curves for n in c):
            falls = [
                c[name][min(c[name])] - c[name][max(c[name])] if c.get(name) else math.nan
                for c in curves
            ]
            text = f"`{arms[0]}` falls by {ask.fmt(falls[0])} vs `{arms[1]}` by {ask.fmt(falls[1])}"
            yield Check(name, text, HOLDS if falls[0] < falls[1] else FAILS)


@dataclass(frozen=True)
class RisesAbove(Along):
    """Per curve of ``first``, the mean at every key above ``at`` exceeds that at the largest
    key of at most ``at`` (for instance: a team does worse above seven robots).

    >>> values = {("s", 1, n): {"a": {1: t}} for n, t in ((6, 30.0), (7, 25.0), (8, 26.0))}
    >>> RisesAbove(7, within=("s",)).judge(values, "a", [], 0)
    ('reproduced', 'holds in 1/1 curves; s/1: 25 at 7, 26 at 8')
    """

    at: float
    usual: ClassVar[Needs] = SOME_WEAK

    def what(self, first: str, second: str, metric: str) -> str:
        where = f" (cells {'/'.join(map(str, self.within))}/...)" if self.within else ""
        above = f"at every key above {self.at:g} exceeds that at the largest key up to {self.at:g}"
        return f"mean {metric} of `{first}` {above}, against {self.axis(first)}{where}"

    def checks(self, ask: Ask) -> Iterator[Check]:
        for name, means in self.means(ask, ask.first).items():
            above = [k for k in means if k > self.at]
            ref = max((k for k in means if k <= self.at), default=None)
            if ref is not None and above:
                shown = ", ".join(f"{ask.fmt(means[k])} at {k}" for k in [ref, *above])
                yield Check(
                    name, shown, HOLDS if all(means[k] > means[ref] for k in above) else FAILS
                )


# ----------------------------------------------------- against the paper's numbers


@dataclass(frozen=True)
class SignsAsPaper(Rule):
    """In each cell ``(column,)`` the sign of Spearman rho(level, mean) along the
    :func:`family` ``first`` (0 if ``|rho| < threshold``) is that of the paper's column
    (``paper``: level -> column -> value).

    >>> paper = {1.0: {"A": 9.0, "B": 1.0}, 2.0: {"A": 5.0, "B": 1.0}, 3.0: {"A": 1.0, "B": 1.0}}
    >>> ours = {("A",): {"SR 1": {1: 3.0}, "SR 2": {1: 2.0}}, ("B",): {"SR 1": {1: 3.0}}}
    >>> SignsAsPaper(paper, 0.3).judge(ours, "SR", [], 0)
    ('reproduced', 'holds in 2/2 columns; A: paper -1, ours -1; B: paper +0, ours +0')
    """

    paper: Mapping[float, Mapping[str, float]]
    threshold: float
    item: ClassVar[str] = "column"

    def what(self, first: str, second: str, metric: str) -> str:
        rho = f"Spearman rho(level, mean {metric} of `{first} *`), 0 if |rho| < {self.threshold:g}"
        return f"sign of {rho}, column by column, as the paper's"

    def checks(self, ask: Ask) -> Iterator[Check]:
        levels, rows = list(self.paper), list(self.paper.values())
        for column in rows[0] if rows else {}:
            theirs = trend_sign(levels, [row[column] for row in rows], self.threshold)
            arms = ask.values.get((column,), {})
            means = {a: _mean(arms[a]) for a in family(arms, ask.first)}
            ours = trend_sign([level(a) for a in means], list(means.values()), self.threshold)
            yield Check(
                column, f"paper {theirs:+d}, ours {ours:+d}", HOLDS if theirs == ours else FAILS
            )


@dataclass(frozen=True)
class AtEnds(Rule):
    """In cell ``(column,)``, the mean of the :func:`family` ``first`` is at least ``high`` at
    its lowest level and at most ``low`` at its highest: both hold, one weakly.

    >>> AtEnds("TPT", 20, 5).judge({("TPT",): {"SR 1": {1: 30.0}, "SR 9": {1: 8.0}}}, "SR", [], 1)
    ('partly', 'holds in 0/1 cells, at least weakly in 1/1; TPT: SR 1 30.0, SR 9 8.0 (weak)')
    """

    column: str
    high: float
    low: float
    usual: ClassVar[Needs] = EVERY_WEAK
    grade_words: ClassVar = ("both hold", "at least one holds")

    def what(self, first: str, second: str, metric: str) -> str:
        ends = f">= {self.high:g} at the lowest level, <= {self.low:g} at the highest"
        return f"mean {metric} of {self.column} along `{first} *`: {ends}"

    def checks(self, ask: Ask) -> Iterator[Check]:
        arms = ask.values.get((self.column,), {})
        means = {a: _mean(arms[a]) for a in family(arms, ask.first)}
        if means:
            low, high = next(iter(means)), list(means)[-1]
            met = (means[low] >= self.high) + (means[high] <= self.low)
            text = ", ".join(f"{a} {ask.fmt(means[a])}" for a in (low, high))
            yield Check(self.column, text, [FAILS, WEAK, HOLDS][met])


@dataclass(frozen=True)
class NearPaper(Rule):
    """Per cell, the means of the :func:`family` ``first`` at the paper's levels (``paper``:
    level -> value) fall strictly (weakly) and each is within ``factor`` of the paper's.

    >>> values = {("m", 3): {"SR 1": {1: 9.0}, "SR 10": {1: 3.0}}}
    >>> NearPaper({1.0: 8.0, 10.0: 1.0}, 2).judge(values, "SR", [], 1)
    ('partly', 'holds in 0/1 cells, at least weakly in 1/1; m/3r: SR 1 9.0, SR 10 3.0 (weak)')
    """

    paper: Mapping[float, float]
    factor: float
    usual: ClassVar[Needs] = EVERY_WEAK

    def what(self, first: str, second: str, metric: str) -> str:
        return f"mean {metric} of `{first} *` at the paper's levels"

    def conditions(self) -> tuple[str, str]:
        within = f"each within a factor {self.factor:g} of the paper's"
        return f"it falls strictly, {within}", "it falls strictly"

    def checks(self, ask: Ask) -> Iterator[Check]:
        for cell, arms in ask.values.items():
            ours = {x: _mean(arms.get(f"{ask.first} {x:g}", {})) for x in sorted(self.paper)}
            steps = itertools.pairwise(ours.values())
            falls = all(map(math.isfinite, ours.values())) and all(a > b for a, b in steps)
            near = all(p / self.factor <= ours[x] <= p * self.factor for x, p in self.paper.items())
            text = ", ".join(f"{ask.first} {x:g} {ask.fmt(v)}" for x, v in ours.items())
            yield Check(_cell_name(cell), text, (HOLDS if near else WEAK) if falls else FAILS)


# ------------------------------------------------------------------------ claims


@dataclass(frozen=True)
class Verdict:
    """One claim of the paper and whether our numbers agree (``evidence``: ours beside the
    paper's)."""

    claim: str
    outcome: Outcome
    evidence: str

    def line(self) -> str:
        return f"- **{self.outcome}**: {self.claim} ({self.evidence})"


@dataclass(frozen=True)
class Claim:
    """One claim of the paper and how it is judged: ``where`` in the paper (``"§IV"``), our
    ``statement``, the paper's own ``sentence``, the ``metric`` (a key of the
    :data:`Values` tables) and its label, the arms (the rule pools ``seconds`` with
    ``second``), the rule, the decimals of its numbers."""

    id: str
    where: str
    statement: str
    sentence: str
    metric: str
    metric_label: str
    first: str
    second: str
    rule: Rule
    digits: int = 0
    seconds: tuple[str, ...] = ()

    def rule_text(self) -> str:
        """The rule in words, for the report's rule list."""
        second = " / ".join(a for a in (self.second, *self.seconds) if a)
        return self.rule.describe(self.first, second, self.metric_label)

    def judge(self, tables: Mapping[str, Values]) -> Verdict:
        """The verdict from ``metric -> values``."""
        seconds = [a for a in (self.second, *self.seconds) if a]
        outcome, text = self.rule.judge(
            tables.get(self.metric, {}), self.first, seconds, self.digits
        )
        evidence = f'{self.metric_label}: {text}; paper: "{self.sentence}"'
        return Verdict(f"{self.where}: {self.statement}", outcome, evidence)


@dataclass(frozen=True)
class Interpretation:
    """A named alternative reading of a sentence of the paper (``sentence``, with where it
    stands; ``reading``: how it reads it, against the default), as run overrides: ``set``
    overrides strategy parameters and ``scenario`` scenario settings (for instance
    ``sharing``) of the runs whose strategy is in ``strategies`` (every run when empty);
    the experiments it does not change are reused."""

    name: str
    sentence: str
    reading: str
    set: Mapping[str, Any] = field(default_factory=dict)
    strategies: tuple[str, ...] = ()
    scenario: Mapping[str, Any] = field(default_factory=dict)

    def applies_to(self, strategy: str) -> bool:
        return not self.strategies or strategy in self.strategies


def claims_section(claims: Sequence[Claim], tables: Mapping[str, Values]) -> list[str]:
    """The verdict section: each claim's rule, then one verdict line per claim."""
    lines = ["## Verdicts", "", "Rules, fixed before the runs and never tuned:", ""]
    lines += [f"- `{claim.id}`: {claim.rule_text()}, not reproduced otherwise" for claim in claims]
    lines += ["", "(`x` marks a cell or curve where the comparison fails, `(weak)` one where"]
    lines += ["only its weaker form holds.)", ""]
    return lines + [claim.judge(tables).line() for claim in claims]


def robustness_section(
    claims: Sequence[Claim],
    readings: Mapping[str, Mapping[str, Values]],
    interpretations: Sequence[Interpretation],
) -> list[str]:
    """Per claim, its verdict under every reading (``readings``: name, the default first,
    -> ``metric -> values``) and ``robust`` / ``fragile``.

    >>> claim = Claim("c", "§1", "a is faster", "a is fast", "time", "T", "a", "b", Means("<="))
    >>> default = {"time": {("m", 2): {"a": {1: 1.0}, "b": {1: 2.0}}}}
    >>> other = {"time": {("m", 2): {"a": {1: 3.0}, "b": {1: 2.0}}}}
    >>> lines = robustness_section([claim], {"default": default, "slow-a": other},
    ...     [Interpretation("slow-a", "§2 'a moves'", "a waits")])
    >>> lines[-2]
    '| `c` | reproduced | not reproduced | **fragile** (changes under slow-a) |'
    """
    names = list(readings)
    lines = ["## Robustness to the readings of the paper", ""]
    lines += [
        "Each claim judged under our default reading and under each interpretation "
        "(the same rule; only the runs the interpretation changes differ). `robust`: "
        "the same verdict under every reading; `fragile`: it changes, under the readings "
        "named.",
        "",
    ]
    if len(names) < 2:
        return [*lines, "Only the default reading was run (`--interpretations none`).", ""]
    known = {i.name: i for i in interpretations}
    read = [known[n] for n in names[1:] if n in known]
    lines += [f"- `{i.name}`: {i.reading} (reads {i.sentence})" for i in read]
    lines += ["", f"| claim | {' | '.join(names)} | summary |", "|---" * (len(names) + 2) + "|"]
    for claim in claims:
        outcomes = {name: claim.judge(tables).outcome for name, tables in readings.items()}
        changed = [name for name in names[1:] if outcomes[name] != outcomes[names[0]]]
        summary = "robust" if not changed else f"**fragile** (changes under {', '.join(changed)})"
        lines.append(f"| `{claim.id}` | {' | '.join(outcomes.values())} | {summary} |")
    return [*lines, ""]
