"""Claims of a paper as data: the sentence, the comparison, the rule that decides it.

A :class:`Claim` pairs the paper's sentence with a :class:`Rule` that grades items (cells,
curves) of :data:`Values` *holds*, *weak* or *fails* and writes the words of its verdict, so
report and code cannot drift apart; :class:`Needs` counts the grades into the outcome. An
:class:`Interpretation` is another reading of the paper (see :func:`robustness_section`).
"""

from __future__ import annotations

import itertools
import math
import operator
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from statistics import median
from typing import Any, ClassVar, Literal

from mrexplore.experiments.stats import Summary, summarize_metric

CellKey = tuple[Any, ...]
"""A cell a claim is judged in, e.g. ``(map, robots)``."""
BySeed = Mapping[int, float]
Arms = Mapping[str, BySeed]
Values = Mapping[CellKey, Arms]
"""``cell -> arm -> seed -> value``."""
Outcome = Literal["reproduced", "partly", "not reproduced"]
Judgement = tuple[Outcome, str]
Pair = tuple[Summary, Summary, Summary | None]
"""Two arms of one cell: each one's summary and, over the seeds both ran, ``a - b``."""
HOLDS, WEAK, FAILS = 2, 1, 0
"""The grades of an item; ``None``: shown, not judged."""
_MARKS = {HOLDS: "", WEAK: " (weak)", FAILS: " x", None: ""}
_RELATIONS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}


def fmt(value: float | None, digits: int = 0) -> str:
    """A number for a verdict line: spaced thousands, ``-`` if missing or not finite."""
    if value is None or not math.isfinite(value):
        return "-"
    return f"{value:,.{digits}f}".replace(",", " ")


def paired(by_seed: Arms, a: str, b: str) -> Summary:
    """``A - B`` over the seeds both arms ran (mean, sd, 95% CI)."""
    first, second = by_seed.get(a, {}), by_seed.get(b, {})
    return summarize_metric([first[s] - second[s] for s in sorted(set(first) & set(second))])


def _mean(by_seed: BySeed) -> float:
    return summarize_metric(list(by_seed.values())).mean


def _ratio(a: float, b: float) -> float:
    return a / b if b > 0 else math.nan


def _diff(d: Summary, digits: int) -> str:
    return f"{fmt(d.mean, digits)} [{fmt(d.ci_low, digits)}, {fmt(d.ci_high, digits)}], n {d.n}"


def cell_name(cell: CellKey) -> str:
    last = f"/{cell[-1]}r" if len(cell) > 1 else str(cell[0])
    return "/".join(str(part) for part in cell[:-1]) + last


def series_text(series: Mapping[Any, float], digits: int = 0) -> str:
    """``x:mean, ...`` of one curve."""
    name = lambda x: f"{x:g}" if isinstance(x, int | float) else str(x)  # noqa: E731
    return ", ".join(f"{name(x)}:{fmt(m, digits)}" for x, m in series.items())


def lowest_arm(arms: Arms, among: Sequence[str]) -> str | None:
    """The arm of ``among`` with the lowest finite mean (ties: the first by name), or ``None``."""
    finite = {a: m for a in among if a in arms and math.isfinite(m := _mean(arms[a]))}
    return min(finite, key=lambda a: (finite[a], a)) if finite else None


def family(arms: Mapping[str, Any], prefix: str) -> list[str]:
    """The arms named ``<prefix> <number>`` (``SR 0.1``, ``SR 10``), by that :func:`level`."""
    return sorted((a for a in arms if a.startswith(f"{prefix} ")), key=level)


def level(arm: str) -> float:
    """The number of an arm of a :func:`family`: ``level("SR 0.1") == 0.1``."""
    return float(arm.rsplit(" ", 1)[-1])


def spearman(x: Sequence[float], y: Sequence[float]) -> float:
    """Spearman's rho over the finite pairs; nan for fewer than two or a constant side."""
    import numpy as np
    from scipy.stats import rankdata

    pairs = [(a, b) for a, b in zip(x, y, strict=True) if math.isfinite(a) and math.isfinite(b)]
    if len(pairs) < 2:
        return math.nan
    rx, ry = rankdata([a for a, _ in pairs]), rankdata([b for _, b in pairs])
    return float(np.corrcoef(rx, ry)[0, 1]) if np.ptp(rx) and np.ptp(ry) else math.nan


def trend_sign(x: Sequence[float], y: Sequence[float], threshold: float) -> int:
    """+1 / -1 when ``y`` rises / falls with ``x`` (Spearman ``|rho| >= threshold``), else 0."""
    rho = spearman(x, y)
    return 0 if not abs(rho) >= threshold else (1 if rho > 0 else -1)


# ------------------------------------------------------------ grades and outcomes


@dataclass(frozen=True)
class Needs:
    """The shares of the judged items that must hold, and hold at least weakly: all that
    are given for ``reproduced``, one of them for ``partly``; 0 means at least one item."""

    holds: float | None = 1.0
    weakly: float | None = None
    partly_holds: float | None = 0.5
    partly_weakly: float | None = None

    def outcome(self, grades: Sequence[int]) -> Outcome:
        counts = (grades.count(HOLDS), len(grades) - grades.count(FAILS))
        shares = [c / len(grades) if c else -1.0 for c in counts]  # -1: no item, below any share
        if all(t is None or s >= t for t, s in zip((self.holds, self.weakly), shares, strict=True)):
            return "reproduced"
        partly = zip((self.partly_holds, self.partly_weakly), shares, strict=True)
        return "partly" if any(t is not None and s >= t for t, s in partly) else "not reproduced"

    def words(self, strong: str, weak: str, item: str) -> str:
        shares = {1.0: f"every {item}", 0.5: f"at least half of the {item}s", 0.0: f"one {item}"}

        def said(pair: tuple[float | None, float | None], joint: str) -> str:
            parts = [(t, w) for t, w in zip(pair, (strong, weak), strict=True) if t is not None]
            return joint.join(
                f"{w} in {shares.get(t, f'at least {t:.0%} of the {item}s')}" for t, w in parts
            )

        reproduced = said((self.holds, self.weakly), " and ")
        partly = said((self.partly_holds, self.partly_weakly), " or ")
        return f"reproduced if {reproduced}, partly if {partly}"


EVERY_HALF = Needs()  # reproduced if every item holds, partly if at least half do
EVERY_WEAK = Needs(partly_holds=None, partly_weakly=1.0)  # partly: every one at least weakly
SOME_WEAK = Needs(partly_holds=None, partly_weakly=0.0)  # partly: one at least weakly


@dataclass(frozen=True)
class Check:
    """One judged item: its name, its numbers, its grade, the comparison (``block``) it is of."""

    name: str
    text: str
    grade: int | None
    block: str = ""
    data: Any = None

    def line(self) -> str:
        return (f"{self.name}: {self.text}" if self.name else self.text) + _MARKS[self.grade]


@dataclass(frozen=True)
class Ask:
    """What a rule judges: the values, the first arm, those it is compared with, the decimals."""

    values: Values
    first: str
    seconds: tuple[str, ...]
    digits: int

    def fmt(self, value: float) -> str:
        return fmt(value, self.digits)


@dataclass(frozen=True, kw_only=True)
class Rule:
    """Base of the rules: :meth:`checks` grades the items, :attr:`needs` (or :attr:`usual`)
    counts them, :meth:`describe` says so. ``shown``: arms shown, not judged; ``brief``: name
    only the items that do not hold; ``also``: another pair of arms whose count is cited."""

    needs: Needs | None = None
    shown: tuple[str, ...] = ()
    brief: bool = False
    also: tuple[str, str] | None = None
    usual: ClassVar[Needs] = EVERY_HALF
    item: ClassVar[str] = "cell"
    grade_words: ClassVar[tuple[str, str]] = ("it holds", "")
    """What holds and what holds weakly (``""``: no weak grade), when the fields do not say."""
    phrase: ClassVar[str] = ""
    """What :meth:`what` says is compared: a format string of ``self`` and its arguments."""

    def what(self, first: str, second: str, metric: str) -> str:
        return self.phrase.format(self=self, first=first, second=second, metric=metric)

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
        blocks = [(k, list(g)) for k, g in itertools.groupby(checks, lambda c: c.block)]
        named = len(blocks) > 1
        text = " | ".join((f"{k}: " if named else "") + self._block(part) for k, part in blocks)
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
        weakly = f", at least weakly in {len(grades) - grades.count(FAILS)}/{len(grades)}"
        return text + (weakly if self.conditions()[1] else "")

    def totals(self, checks: Sequence[Check]) -> list[str]:
        """Numbers over all the judged items, after the count."""
        return []


# ------------------------------------------------------------------ cell by cell


@dataclass(frozen=True, kw_only=True)
class Cells(Rule):
    """Base of the rules comparing ``first`` with each of ``seconds`` (``best``: the lowest) cell
    by cell. ``seeds``: ``all`` (the difference over the seeds both ran), ``common`` (all over
    those, at least ``min_seeds``) or ``unpaired``; ``except_at``: last cell keys where the claim
    is the opposite; ``members``: compare ``each`` or the ``top`` arm of the family ``first``."""

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
                members = family(arms, ask.first) if self.members else [ask.first]
                for arm in members[-1:] if self.members == "top" else members:
                    pair = self._pair(arms, arm, other)
                    if pair is None:
                        continue
                    grade, text = self.grade(pair, cell, ask)
                    grade = HOLDS + FAILS - grade if cell[-1] in self.except_at else grade
                    name = cell_name(cell) + (f" {arm}" if self.members else "")
                    name += "" if second else f" (best other `{other}`)"
                    judged = None if second in self.shown else grade
                    yield Check(name, text, judged, f"vs `{second}`" if second else "", pair)

    def _pair(self, arms: Arms, a: str, b: str) -> Pair | None:
        if a not in arms or b not in arms:
            return None
        x, y = arms[a], arms[b]
        if self.seeds == "common":
            common = sorted(set(x) & set(y))
            if len(common) < max(self.min_seeds, 1):
                return None
            x, y = ({s: v[s] for s in common} for v in (x, y))
        d = None if self.seeds == "unpaired" else paired({"a": x, "b": y}, "a", "b")
        return summarize_metric(list(x.values())), summarize_metric(list(y.values())), d

    def what(self, first: str, second: str, metric: str) -> str:
        arm = f"the highest-level `{first} *` arm" if self.members == "top" else f"`{first}`"
        arm = f"each `{first} *` arm" if self.members == "each" else arm
        versus = f"the lowest of `{second}` in each cell" if self.best else f"`{second}`"
        at_least = f" (at least {self.min_seeds})" if self.min_seeds > 1 else ""
        seeds = {"common": f" over the seeds both ran{at_least}", "unpaired": " (seeds not paired)"}
        opposite = ", ".join(map(str, self.except_at))
        opposite = f" (the opposite where the last cell key is {opposite})" if opposite else ""
        words = self.phrase.format(self=self, metric=metric, arm=arm, second=second, versus=versus)
        return f"{words}{seeds.get(self.seeds, '')}, cell by cell{opposite}"


@dataclass(frozen=True)
class Means(Cells):
    """The mean (or ``statistic="sd"``) of ``first`` ``relation`` that of ``second``; ``summary``:
    also how many paired 95% CIs lie below / above 0 and the ratios' median and range."""

    relation: str
    statistic: Literal["mean", "sd"] = "mean"
    summary: bool = False
    phrase: ClassVar = "{self.statistic} {metric} of {arm} {self.relation} that of {versus}"

    def grade(self, pair: Pair, cell: CellKey, ask: Ask) -> tuple[int, str]:
        a, b = (getattr(s, self.statistic) for s in pair[:2])
        text = f"{ask.fmt(a)} vs {ask.fmt(b)}"
        if pair[2] is not None and self.statistic == "mean":
            text += f" (paired {_diff(pair[2], ask.digits)})"
        return (HOLDS if _RELATIONS[self.relation](a, b) else FAILS), text

    def totals(self, checks: Sequence[Check]) -> list[str]:
        pairs: list[Pair] = [c.data for c in checks]
        ds = [d for _, _, d in pairs if d is not None]
        out = []
        if self.summary and self.statistic == "mean" and len(ds) == len(pairs):
            below, above = sum(d.ci_high < 0 for d in ds), sum(d.ci_low > 0 for d in ds)
            out.append(f"paired 95% CI below 0 in {below}, above 0 in {above}")
        of = [_ratio(getattr(a, self.statistic), getattr(b, self.statistic)) for a, b, _ in pairs]
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
    ``second`` and its CI holding 0 (or unknown: one seed) holds, one of the two weakly."""

    relation: Literal["<", ">", "="] = "<"
    tolerance: float = 0.1
    usual: ClassVar[Needs] = EVERY_WEAK
    phrase: ClassVar = "paired difference of {metric}, {arm} - `{second}`, over the seeds both ran"

    def conditions(self) -> tuple[str, str]:
        if self.relation == "=":
            close = f"|its mean| is within {self.tolerance:.0%} of the second arm's mean"
            return f"{close} and its 95% CI holds 0", "one of the two holds"
        side = "below" if self.relation == "<" else "above"
        return f"its 95% CI is {side} 0", f"its mean is {side} 0"

    def grade(self, pair: Pair, cell: CellKey, ask: Ask) -> tuple[int, str]:
        a, b, d = pair[0], pair[1], pair[2] or summarize_metric([])
        text = f"{ask.fmt(a.mean)} vs {ask.fmt(b.mean)} (paired {_diff(d, ask.digits)})"
        if self.relation == "=":
            close, known = abs(d.mean) <= self.tolerance * b.mean, math.isfinite(d.ci_low)
            zero_in = not known or d.ci_low <= 0 <= d.ci_high
            grade = HOLDS if close and zero_in else WEAK if close or (known and zero_in) else FAILS
            return grade if math.isfinite(d.mean + b.mean) else FAILS, text
        sure, likely = (d.ci_high, d.mean) if self.relation == "<" else (-d.ci_low, -d.mean)
        return (HOLDS if sure < 0 else WEAK if likely < 0 else FAILS), text


@dataclass(frozen=True)
class Ratio(Cells):
    """The ratio of the means ``first / second`` ``relation`` ``bound`` (holds) or ``weak``
    (weakly); with ``paper`` (cell -> ratio) it holds only if also within ``factor`` of it."""

    relation: str
    bound: float
    weak: float | None = None
    paper: Mapping[CellKey, float] | None = None
    factor: float = 2.0
    digits: int = 2
    phrase: ClassVar = "ratio of the mean {metric} of {arm} to that of `{second}`"

    def conditions(self) -> tuple[str, str]:
        bound = f"it is {self.relation} {self.bound:g}"
        if self.paper is not None:
            return f"{bound} and within a factor {self.factor:g} of the paper's", bound
        return bound, f"it is {self.relation} {self.weak:g}" if self.weak is not None else ""

    def grade(self, pair: Pair, cell: CellKey, ask: Ask) -> tuple[int, str]:
        a, b = pair[0].mean, pair[1].mean
        holds, r = _RELATIONS[self.relation], _ratio(a, b)
        text = f"{ask.fmt(a)} vs {ask.fmt(b)} (ratio {fmt(r, self.digits)}"
        if self.paper is None:
            weak = self.weak is not None and holds(r, self.weak)
            return (HOLDS if holds(r, self.bound) else WEAK if weak else FAILS), text + ")"
        paper = self.paper.get(cell, math.nan)
        near = 1 / self.factor <= r / paper <= self.factor
        grade = (HOLDS if near else WEAK) if holds(r, self.bound) else FAILS
        return grade, f"{text}, paper {fmt(paper, self.digits)})"


@dataclass(frozen=True)
class Level(Rule):
    """The mean of ``first`` ``relation`` ``bound`` (holds) or ``weak`` (weakly), in each cell."""

    relation: str
    bound: float
    weak: float | None = None
    usual: ClassVar[Needs] = EVERY_WEAK
    phrase: ClassVar = "mean {metric} of `{first}`, cell by cell"

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
                    yield Check(cell_name(cell), ask.fmt(mean), judged, f"`{arm}`")


@dataclass(frozen=True)
class NotBelowAll(Rule):
    """In a cell, the paired 95% CI of ``first - second`` is not below 0 for every other arm."""

    def what(self, first: str, second: str, metric: str) -> str:
        test = f"the paired 95% CI of its {metric} minus that of each of `{second}` lies below 0"
        return f"`{first}` is superior in a cell if {test}; the claim holds where it is not"

    def checks(self, ask: Ask) -> Iterator[Check]:
        for cell, arms in ask.values.items():
            if {ask.first, *ask.seconds} <= set(arms):
                ds = {s: paired(arms, ask.first, s) for s in ask.seconds}
                text = "; ".join(f"`{s}` {_diff(d, ask.digits)}" for s, d in ds.items())
                superior = all(d.ci_high < 0 for d in ds.values())
                yield Check(cell_name(cell), text, FAILS if superior else HOLDS)


# ------------------------------------------------------------------------ curves


@dataclass(frozen=True, kw_only=True)
class Along(Rule):
    """Base of the rules that follow curves ``along`` the last cell key (one per group of the other
    keys), the ``cells`` (one), or the levels of the :func:`family` ``first`` (one per cell),
    in the cells whose key starts with ``within``."""

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
                out[cell_name(cell)] = {level(a): arms[a] for a in family(arms, arm)}
            elif self.along != "family" and arm in arms:
                key = ((), cell_name(cell)) if self.along == "cells" else (cell[:-1], cell[-1])
                out.setdefault("/".join(map(str, key[0])), {})[key[1]] = arms[arm]
        return out

    def means(self, ask: Ask, arm: str) -> dict[str, dict[Any, float]]:
        """``curve name -> x -> mean`` of one arm."""
        curves = self.curves(ask.values, arm).items()
        return {name: {x: _mean(s) for x, s in curve.items()} for name, curve in curves}

    def axis(self, first: str) -> str:
        axes = {"key": "the last cell key, per group of the other keys", "cells": "the cells"}
        return axes.get(self.along, f"the level of `{first} *`, cell by cell")


@dataclass(frozen=True)
class Trend(Along):
    """The curves of ``first`` and of each of ``seconds`` (``ratio``, ``gap``: of ``first``
    against ``second``, over the seeds both ran) fall or rise, in the way of ``kind`` that
    :meth:`conditions` words: at each step, by rank, with diminishing returns, in ratio, in gap
    (``paper``: arm -> the paper's numbers, shown beside ``steps``)."""

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
        rho = f"Spearman's rho {'<= -' if way == 'falls' else '>= '}{self.rho:g}"
        if self.kind == "rank" and self.paired:
            sure = f"first - last has a paired 95% CI {'above' if way == 'falls' else 'below'} 0"
            return f"{rho} and {sure}", "one of the two holds, or that mean is above 0"
        ends = f"it ends {side} where it starts"
        bound = f" and it ends {side} {self.bound:g}" if self.bound is not None else ""
        return {
            "steps": (f"it {way} at every step", ends),
            "rank": (f"{rho} and {ends}", ""),
            "diminishing": ("it falls with diminishing returns", "it falls"),
            "ratio": (f"it {way}{bound}", f"it {way}" if bound else ""),
            "gap": ("both shrink", "the difference shrinks"),
        }[self.kind]

    def _moves(self, a: float, b: float) -> bool:
        return b < a if self.direction == "falls" else b > a

    def checks(self, ask: Ask) -> Iterator[Check]:
        if self.kind in ("ratio", "gap"):
            yield from self._against(ask)
            return
        arms = [ask.first, *ask.seconds, *self.shown]
        for arm in arms:
            for name, curve in self.curves(ask.values, arm).items():
                if self.kind == "diminishing" and len(curve) < 2:
                    continue
                grade, text = self._curve(arm, curve, ask)
                label = f"`{arm}` {name}".strip() if len(arms) > 1 else name
                yield Check(label, text, None if arm in self.shown else grade)

    def _curve(self, arm: str, curve: Mapping[Any, BySeed], ask: Ask) -> tuple[int, str]:
        means = {x: _mean(s) for x, s in curve.items()}
        m, text = list(means.values()), series_text(means, ask.digits)
        if self.kind == "diminishing":
            keys = sorted(means)
            a, middle, z = (means[k] for k in (keys[0], keys[len(keys) // 2], keys[-1]))
            return (HOLDS if a - middle >= middle - z else WEAK) if z < a else FAILS, text
        ends = len(m) > 1 and self._moves(m[0], m[-1])
        if self.kind == "rank":
            rho, falls = spearman([float(x) for x in means], m), self.direction == "falls"
            steep = rho <= -self.rho if falls else rho >= self.rho
            text += f" (Spearman rho {fmt(rho, 2)}"
            if not self.paired:
                return (HOLDS if steep and ends else FAILS), text + ")"
            xs = list(curve)
            d = paired({"a": curve[xs[0]], "b": curve[xs[-1]]}, "a", "b")
            sure, likely = (d.ci_low, d.mean) if falls else (-d.ci_high, -d.mean)
            grade = HOLDS if steep and sure > 0 else WEAK if steep or likely > 0 else FAILS
            return grade, f"{text}; first - last paired {_diff(d, ask.digits)})"
        every = all(self._moves(a, b) for a, b in itertools.pairwise(m))
        paper = ", ".join(ask.fmt(p) for p in self.paper.get(arm, ()))
        text += f" (paper {paper})" if paper else ""
        if len(m) > 1 and math.isfinite(change := _ratio(m[-1], m[0])):
            text += f", {100 * (change - 1):+.0f}% first to last"
        return (HOLDS if every and ends else WEAK if ends else FAILS), text

    def _against(self, ask: Ask) -> Iterator[Check]:
        second = self.curves(ask.values, ask.seconds[0])
        for name, curve in self.curves(ask.values, ask.first).items():
            points: dict[Any, tuple[float, float]] = {}
            for x, a in curve.items():
                b = second.get(name, {}).get(x, {})
                if common := sorted(set(a) & set(b)):
                    points[x] = (_mean({s: a[s] for s in common}), _mean({s: b[s] for s in common}))
            if len(points) < 2:
                continue
            ratios = {x: _ratio(a, b) for x, (a, b) in points.items()}
            (x0, r0), *_, (x1, r1) = ratios.items()
            if self.kind == "ratio":
                moves = self._moves(r0, r1)
                bound = self.bound is None or self._moves(self.bound, r1)
                grade = HOLDS if moves and bound else WEAK if moves else FAILS
                yield Check(name, series_text(ratios, self.digits), grade)
                continue
            (a0, b0), (a1, b1) = points[x0], points[x1]
            text = f"{x0}: {ask.fmt(a0 - b0)} (x{fmt(r0, self.digits)}) -> "
            text += f"{x1}: {ask.fmt(a1 - b1)} (x{fmt(r1, self.digits)})"
            yield Check(name, text, (HOLDS if r1 < r0 else WEAK) if a1 - b1 < a0 - b0 else FAILS)


@dataclass(frozen=True)
class FallsFasterBelow(Along):
    """Per curve of ``first``, the mean falls faster per unit of x below ``at`` than above it."""

    at: float
    unit: str = "unit"
    grade_words: ClassVar = ("the gain below is positive and larger than above", "")

    def what(self, first: str, second: str, metric: str) -> str:
        at = f"{self.at:g}"
        gains = f"gain per {self.unit} below {at} = (m(x_min) - m({at})) / ({at} - x_min), "
        gains += f"above = (m({at}) - m(x_max)) / (x_max - {at})"
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
    """Per curve, ``first``'s mean falls less from the first key to the last than ``second``'s."""

    grade_words: ClassVar = ("the fall of the first is smaller", "")

    def what(self, first: str, second: str, metric: str) -> str:
        means = f"the mean {metric} of `{first}` and of `{second}`"
        return f"fall m(x_min) - m(x_max) of {means} against {self.axis(first)}"

    def checks(self, ask: Ask) -> Iterator[Check]:
        arms = (ask.first, ask.seconds[0])
        curves = [self.means(ask, arm) for arm in arms]
        for name in dict.fromkeys(n for c in curves for n in c):
            ms = [c.get(name) for c in curves]
            falls = [m[min(m)] - m[max(m)] if m else math.nan for m in ms]
            text = f"`{arms[0]}` falls by {ask.fmt(falls[0])} vs `{arms[1]}` by {ask.fmt(falls[1])}"
            yield Check(name, text, HOLDS if falls[0] < falls[1] else FAILS)


@dataclass(frozen=True)
class RisesAbove(Along):
    """Per curve of ``first``, each mean above key ``at`` exceeds that at the last key up to it."""

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
                grade = HOLDS if all(means[k] > means[ref] for k in above) else FAILS
                yield Check(name, shown, grade)


# ----------------------------------------------------- against the paper's numbers


@dataclass(frozen=True)
class SignsAsPaper(Rule):
    """In each cell ``(column,)`` the sign of Spearman rho(level, mean) along the family ``first``
    is that of the paper's column (``paper``: level -> column -> value)."""

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
            text = f"paper {theirs:+d}, ours {ours:+d}"
            yield Check(column, text, HOLDS if theirs == ours else FAILS)


@dataclass(frozen=True)
class AtEnds(Rule):
    """In cell ``(column,)``, the mean of the :func:`family` ``first`` is at least ``high`` at
    its lowest level and at most ``low`` at its highest: both hold, one weakly."""

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
    level -> value) fall strictly (weakly) and each is within ``factor`` of the paper's."""

    paper: Mapping[float, float]
    factor: float
    usual: ClassVar[Needs] = EVERY_WEAK
    phrase: ClassVar = "mean {metric} of `{first} *` at the paper's levels"

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
            yield Check(cell_name(cell), text, (HOLDS if near else WEAK) if falls else FAILS)


# ------------------------------------------------------------------------ claims


@dataclass(frozen=True)
class Verdict:
    """One claim of the paper and whether our numbers agree (``evidence``: ours, the paper's)."""

    claim: str
    outcome: Outcome
    evidence: str

    def line(self) -> str:
        return f"- **{self.outcome}**: {self.claim} ({self.evidence})"


@dataclass(frozen=True)
class Claim:
    """One claim of the paper and how it is judged: ``where`` in the paper (``"§IV"``), our
    ``statement``, the paper's ``sentence``, the ``metric`` (a key of the tables) and its label,
    the arms (``seconds`` pooled with ``second``), the rule, the decimals of its numbers."""

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
        second = " / ".join(a for a in (self.second, *self.seconds) if a)
        return self.rule.describe(self.first, second, self.metric_label)

    def judge(self, tables: Mapping[str, Values]) -> Verdict:
        """The verdict from ``metric -> values``."""
        seconds = [a for a in (self.second, *self.seconds) if a]
        values = tables.get(self.metric, {})
        outcome, text = self.rule.judge(values, self.first, seconds, self.digits)
        evidence = f'{self.metric_label}: {text}; paper: "{self.sentence}"'
        return Verdict(f"{self.where}: {self.statement}", outcome, evidence)


@dataclass(frozen=True)
class Interpretation:
    """A named alternative ``reading`` of a ``sentence`` of the paper, as overrides of strategy
    parameters (``set``), scenario settings (``scenario``) and sharing parameters (``share``)
    of the runs of ``strategies`` (every run when empty); the experiments it does not change
    are reused."""

    name: str
    sentence: str
    reading: str
    set: Mapping[str, Any] = field(default_factory=dict)
    strategies: tuple[str, ...] = ()
    scenario: Mapping[str, Any] = field(default_factory=dict)
    share: Mapping[str, Any] = field(default_factory=dict)

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
    -> ``metric -> values``) and ``robust`` / ``fragile``."""
    names = list(readings)
    lines = ["## Robustness to the readings of the paper", ""]
    lines += [
        "Each claim judged under our default reading and under each interpretation (the same "
        "rule; only the runs the interpretation changes differ). `robust`: the same verdict "
        "under every reading; `fragile`: it changes, under the readings named.",
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
