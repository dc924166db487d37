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
    "Interpretation",
    "Lowest",
    "NotBelowAll",
    "PairedLower",
    "Rule",
    "Trend",
    "TrendForAll",
    "Unpaired",
    "Values",
    "WithinFactor",
    "claims_section",
    "count_outcome",
    "fmt",
    "lowest_arm",
    "paired",
    "robustness",
    "robustness_section",
]
