"""What every paper reproduction is made of.

A :class:`Reproduction` names its experiments as sweeps (built from plain dicts
with :func:`~mrexplore.experiments.sweep.sweep_from_dict`, at the paper's settings
or at a reduced ``quick`` size) and a report function that reads their results
stores and writes ``report.md``: the paper's numbers (typed in from the paper,
with the figure or table they come from) beside ours, the plots, and one verdict
line per claim. :func:`reproduce` runs the sweeps into ``OUT/<experiment>/``
(resumably: running it again completes what is missing) and writes the report.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from mrexplore.experiments.driver import run_sweep
from mrexplore.experiments.engines import make_engine
from mrexplore.experiments.store import Store
from mrexplore.experiments.sweep import Sweep

Outcome = Literal["reproduced", "partly", "not reproduced"]


@dataclass(frozen=True)
class Verdict:
    """One claim of the paper and whether our numbers agree."""

    claim: str
    outcome: Outcome
    evidence: str
    """The numbers and figures that say so: ours beside the paper's."""

    def line(self) -> str:
        return f"- **{self.outcome}**: {self.claim} ({self.evidence})"


@dataclass(frozen=True)
class Reproduction:
    """A paper's experiments and how to report them."""

    id: str
    title: str
    citation: str
    sweeps: Callable[[bool], Mapping[str, Sweep]]
    """``quick -> {experiment name: sweep}``."""
    report: Callable[[Mapping[str, Store], Path, bool], Path]
    """``(stores by experiment, out dir, quick) -> path of report.md``."""


def reproduce(
    reproduction: Reproduction,
    out: str | Path,
    *,
    quick: bool = False,
    engine: str = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: bool = True,
) -> Path:
    """Run every experiment of ``reproduction`` into ``out`` and write its report."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    stores: dict[str, Store] = {}
    sweeps = reproduction.sweeps(quick)
    with make_engine(engine, workers, address) as runner:  # one pool for every sweep
        for name, sweep in sweeps.items():
            folder = out / name
            run_sweep(sweep, folder, engine=runner, resume=True, progress=progress)
            stores[name] = Store(folder)
    return reproduction.report(stores, out, quick)


def rules_header(rules: Mapping[str, str]) -> list[str]:
    """The start of a report's verdict section: its heading and the rules that decide
    each verdict, one line per rule."""
    header = ["## Verdicts", "", "Rules, fixed before the runs and never tuned:", ""]
    return header + [f"- `{name}`: {rule}" for name, rule in rules.items()]


def verdict_section(verdicts: list[Verdict]) -> str:
    """The report's verdict lines, one per claim."""
    return "\n".join(v.line() for v in verdicts)
