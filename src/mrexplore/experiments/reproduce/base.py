"""What every paper reproduction is made of: a :class:`Reproduction` names its experiments (at
the paper's settings or a reduced ``quick`` size) and the sections of its report;
:func:`reproduce` runs the sweeps into ``OUT/<experiment>/`` (resumably) and
:func:`write_report` writes ``report.md``: head, sections, verdicts and their robustness.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from mrexplore.experiments.driver import run_sweep
from mrexplore.experiments.engines import make_engine
from mrexplore.experiments.reproduce.claims import claims_section, robustness_section
from mrexplore.experiments.reproduce.render import rows_of
from mrexplore.experiments.store import Store
from mrexplore.experiments.sweep import Sweep

if TYPE_CHECKING:
    from mrexplore.experiments.reproduce.claims import Claim, Interpretation, Values
    from mrexplore.experiments.reproduce.render import Experiment, Lines


@dataclass(frozen=True)
class Reproduction:
    """A paper's experiments and how to report them."""

    id: str
    title: str
    """The report's title (the paper's, with its authors where they help)."""
    citation: str
    experiments: Callable[[bool], Iterable[Experiment]]
    """``quick -> the experiments``, in the report's order."""
    report: Callable[[Mapping[str, Store], Path, bool], Lines]
    """``(stores by experiment, out dir, quick) -> the report's sections`` (figures in ``out``)."""
    tables: Callable[[Mapping[str, Store], bool], Mapping[str, Values]]
    """``(stores by experiment, quick) -> metric -> values`` the claims read."""
    claims: Sequence[Claim] = ()
    """The claims judged by :mod:`~mrexplore.experiments.reproduce.claims` rules."""
    interpretations: Sequence[Interpretation] = ()
    """Alternative readings of the paper the claims are also judged under."""
    quick_note: str = ""
    """What a ``quick`` run reduces, for the warning at the report's head."""

    def sweeps(self, quick: bool) -> dict[str, Sweep]:
        """``experiment name -> sweep``, in order."""
        return {e.name: e.sweep(self.id) for e in self.experiments(quick)}

    def interpretation_names(self) -> list[str]:
        return [i.name for i in self.interpretations]


def select_interpretations(reproduction: Reproduction, chosen: str) -> list[Interpretation]:
    """``all``, ``none`` or comma-separated names of ``reproduction``'s interpretations
    (:class:`~mrexplore.errors.MrexploreInputError` for an unknown name)."""
    from mrexplore.errors import MrexploreInputError

    if chosen == "all":
        return list(reproduction.interpretations)
    if chosen == "none":
        return []
    known = {i.name: i for i in reproduction.interpretations}
    names = [n.strip() for n in chosen.split(",") if n.strip()]
    unknown = [n for n in names if n not in known]
    if unknown or not names:
        listing = ", ".join(known) or "none declared"
        raise MrexploreInputError(
            f"--interpretations {chosen}: {reproduction.id} has no interpretation "
            f"{', '.join(unknown) or '(empty)'}; use all, none or some of: {listing}"
        )
    return [known[n] for n in names]


def interpret(sweep: Sweep, interpretation: Interpretation) -> Sweep | None:
    """``sweep`` under ``interpretation`` (its overrides fixed, replacing grid axes of the
    same name; sharing overrides only where the sweep sets sharing parameters), or ``None``
    when it changes none of its runs (none of its strategies, or every run the same); an
    error when it applies to some of the sweep's strategies only."""
    fixed_strategy = sweep.fixed.get("strategy")
    strategies = [fixed_strategy] if fixed_strategy else list(sweep.grid.get("strategy", []))
    hit = [s for s in strategies if interpretation.applies_to(str(s))]
    if not hit:
        return None
    if len(hit) != len(strategies):
        raise ValueError(
            f"interpretation {interpretation.name} applies to some strategies of sweep "
            f"{sweep.name} only; split the sweep by strategy"
        )
    grid: dict[str, Any] = {k: v for k, v in sweep.grid.items() if k not in interpretation.scenario}
    fixed = {**sweep.fixed, **interpretation.scenario}
    # Sharing overrides reach only sweeps whose mechanism takes parameters already.
    share = interpretation.share if "share" in sweep.fixed or "share" in grid else {}
    for key, overrides in (("set", interpretation.set), ("share", share)):
        if key in grid:
            grid[key] = {k: v for k, v in grid[key].items() if k not in overrides}
            if not grid[key]:
                del grid[key]
        if overrides:
            fixed[key] = {**sweep.fixed.get(key, {}), **overrides}
    changed = replace(sweep, fixed=fixed, grid=grid, name=f"{sweep.name}@{interpretation.name}")
    same = [r.run_id for r in changed.runs()] == [r.run_id for r in sweep.runs()]
    return None if same else changed


def reproduce(
    reproduction: Reproduction,
    out: str | Path,
    *,
    quick: bool = False,
    engine: str = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: bool = True,
    interpretations: str = "all",
) -> Path:
    """Run every experiment of ``reproduction`` into ``out`` and write its report; each
    selected interpretation re-runs the experiments it changes into
    ``out/readings/<name>/<experiment>``, and the report ends with the robustness section."""
    out = Path(out)
    chosen = select_interpretations(reproduction, interpretations)
    out.mkdir(parents=True, exist_ok=True)
    readings: dict[str, dict[str, Store]] = {}
    sweeps = reproduction.sweeps(quick)
    with make_engine(engine, workers, address) as runner:  # one pool for every sweep

        def run(sweep: Sweep, folder: Path) -> Store:
            run_sweep(sweep, folder, engine=runner, resume=True, progress=progress)
            return Store(folder)

        stores = {name: run(sweep, out / name) for name, sweep in sweeps.items()}
        for interpretation in chosen:
            reading = readings.setdefault(interpretation.name, dict(stores))
            for name, sweep in sweeps.items():
                if (changed := interpret(sweep, interpretation)) is not None:
                    reading[name] = run(changed, out / "readings" / interpretation.name / name)
    return write_report(reproduction, {"default": stores, **readings}, out, quick)


def write_report(
    reproduction: Reproduction, readings: Mapping[str, Mapping[str, Store]], out: Path, quick: bool
) -> Path:
    """``out/report.md``: the head (title, quick-run warning, citation, runs by status), the
    sections and the claims' verdicts from the stores of the ``default`` reading, then the claims
    under every reading (``readings``: name -> stores by experiment, the default first)."""
    r, stores = reproduction, readings["default"]
    lines = [f"# Reproduction: {r.title}", ""]
    if quick and r.quick_note:
        lines += [
            f"> **Quick run** (`--quick`): {r.quick_note}. Its verdicts are indicative only; run "
            "without `--quick` for the full settings.",
            "",
        ]
    counts = ", ".join(f"{k} {v}" for k, v in rows_of(stores)[1].items()) or "none"
    written = f"Written {time.strftime('%Y-%m-%d %H:%M')}. Runs: {counts}."
    lines += [f"Citation: {r.citation}", "", written, "", *r.report(stores, out, quick)]
    tables = {name: r.tables(s, quick) for name, s in readings.items()}
    lines += [*claims_section(r.claims, tables["default"]), ""]
    lines += robustness_section(r.claims, tables, r.interpretations)
    path = out / "report.md"
    path.write_text("\n".join(lines))
    return path
