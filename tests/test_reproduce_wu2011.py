"""Reproduction of Wu, Puig and Garcia §V: the quick run end to end (one reading of the
paper besides the default), the helpers on hand-made tables, and the full run (slow);
its rules are tested in ``test_claims``."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

from conftest import quick_reproduction
from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import wu2011 as repro
from mrexplore.experiments.reproduce.base import interpret
from mrexplore.experiments.store import Store

READING = "coordinator-assigns-requesting"
QUICK_FIGURES = tuple(
    f"fig{n}_{kind}_{scheme}_{robots}r.png"
    for n, kind, scheme in ((6, "wtv", "together"), (7, "wtv", "separate"), (8, "epv", "separate"))
    for robots in repro.QUICK_TEAM_SIZES
)
FULL_FIGURES = (
    *(name.replace("_4r", "_8r") for name in QUICK_FIGURES),
    "wtv_all_combinations.png",
    "epv_all_combinations.png",
)
FIG7_4 = ("unstructured", "separate", 4)
N_CLAIMS = 8  # Fig. 6: 3, Fig. 7: 2, Fig. 8: 1, §V.C: 2
VERDICT = re.compile(r"^- \*\*(reproduced|partly|not reproduced)\*\*: (.+)$")


def _check_report(out: Path, figures: tuple[str, ...]) -> str:
    text = (out / "report.md").read_text()
    assert text.startswith("# Reproduction: Wu, Puig and Garcia")
    assert repro.CITATION in text
    lines = [
        line for line in text.split("## Verdicts", 1)[1].splitlines() if line.startswith("- **")
    ]
    assert len(lines) == N_CLAIMS
    for line in lines:
        assert VERDICT.match(line), line
    for claim in repro.CLAIMS:  # the paper's sentences, in their sections and verdicts
        assert text.count(f'"{claim.sentence}"') >= 2, claim.id
        assert f"- `{claim.id}`: " in text
    assert f"{repro.PAPER_CONFIGURATIONS} configurations" in text
    assert f"{repro.PAPER_RUNS_PER_CONFIGURATION} set-ups" in text
    for name in figures:
        assert (out / name).stat().st_size > 1000, name
        assert f"]({name})" in text
    return text


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return quick_reproduction(tmp_path_factory, "wu2011", READING)


def test_quick_reproduction_writes_the_report(quick_run: Path) -> None:
    text = _check_report(quick_run, QUICK_FIGURES)
    assert "**Quick run**" in text.split("## Settings")[0]
    assert "failed" not in text.split("## Settings")[0]
    for strategy in repro.STRATEGIES:
        assert (quick_run / f"unstructured-{strategy}" / "runs").is_dir()
    robustness = text.split("## Robustness to the readings of the paper", 1)[1]
    assert f"| claim | default | {READING} | summary |" in robustness
    for claim in repro.CLAIMS:
        assert re.search(
            rf"^\| `{claim.id}` \| .* \| (robust|\*\*fragile\*\*.*) \|$", robustness, re.M
        )
    assert (quick_run / "readings" / READING / "unstructured-burgard" / "runs").is_dir()
    assert not (quick_run / "readings" / READING / "unstructured-kme").exists()


def test_quick_runs_are_paired_by_seed(quick_run: Path) -> None:
    """Every seed places the team elsewhere, and the four strategies of a seed alike."""
    starts: dict[tuple[str, int, int], set[str]] = {}
    for strategy in repro.STRATEGIES:
        runs = Store(quick_run / f"unstructured-{strategy}").tables()[0].to_pylist()
        for r in runs:
            starts.setdefault((r["start"], r["robots"], r["seed"]), set()).add(r["starts"])
    assert len(starts) == 2 * len(repro.QUICK_TEAM_SIZES) * len(repro.QUICK_SEEDS)
    assert all(len(s) == 1 for s in starts.values())  # the strategies of a seed alike
    for scheme in repro.STARTS:
        for robots in repro.QUICK_TEAM_SIZES:
            by_seed = [starts[scheme, robots, seed] for seed in repro.QUICK_SEEDS]
            assert len({frozenset(s) for s in by_seed}) == len(repro.QUICK_SEEDS)


def test_registered() -> None:
    reproduction = get_reproduction("wu2011")
    assert reproduction is repro.REPRODUCTION
    assert reproduction.id == "wu2011"
    assert reproduction.interpretation_names() == ["all-replan-when-explored", READING]


def test_full_sweeps_have_the_papers_design() -> None:
    sweeps = repro.REPRODUCTION.sweeps(False)
    assert list(sweeps) == [f"{m}-{s}" for m in repro.MAPS for s in repro.STRATEGIES]
    for name, sweep in sweeps.items():
        # 2 schemes x 4 team sizes x 15 set-ups, one map per type, one strategy.
        assert len(sweep) == 2 * 4 * 15
        scenarios = [spec.scenario for spec in sweep.runs()]
        assert {f"{s.map}-{s.strategy}" for s in scenarios} == {name}
        assert {s.map_seed for s in scenarios} == {repro.MAP_SEED}
        assert {s.start for s in scenarios} == {"together", "separate"}
        assert {s.coverage_threshold for s in scenarios} == {1.0}
    assert sum(len(s) for s in sweeps.values()) == 1440


def test_readings_change_whole_sweeps_of_the_strategies_with_the_trigger() -> None:
    for interpretation in repro.INTERPRETATIONS:
        for name, sweep in repro.REPRODUCTION.sweeps(True).items():
            changed = interpret(sweep, interpretation)  # never a partly applying sweep
            strategy = name.removeprefix("unstructured-")
            assert (changed is not None) == (strategy in interpretation.strategies), name
            if changed is not None:
                params = changed.runs()[0].scenario.params
                assert {k: params[k] for k in interpretation.set} == interpretation.set


def test_every_arm_with_a_re_plan_trigger_re_plans_on_arrival_by_default() -> None:
    """§IV.D step 11 for KME, and the same rule for the baselines that have a trigger."""
    for name, sweep in repro.REPRODUCTION.sweeps(True).items():
        params = sweep.runs()[0].scenario.params
        if name.removeprefix("unstructured-") in repro.REPLANNING:
            assert params["replan_on_target_explored"] is False, name


def test_separate_starts_differ_between_seeds_and_not_between_strategies() -> None:
    from mrexplore.sim import Scenario
    from mrexplore.sim.engine import Simulation

    def starts(seed: int, strategy: str) -> tuple[tuple[int, int], ...]:
        scenario = Scenario(
            map="unstructured",
            size=(48, 48),
            map_seed=repro.MAP_SEED,
            robots=4,
            strategy=strategy,
            start="separate",
            seed=seed,
        )
        return tuple(tuple(int(v) for v in r.position) for r in Simulation(scenario).robots)

    by_seed = {seed: starts(seed, "kme") for seed in (1, 2, 3)}
    assert len(set(by_seed.values())) == 3
    assert starts(2, "burgard") == by_seed[2]


# ------------------------------------------------------------------ helpers


def test_time_mean_carries_the_final_value() -> None:
    ticks = np.array([0.0, 10.0, 20.0, 23.0])
    values = np.array([4.0, 8.0, 6.0, 2.0])
    assert repro.time_mean(ticks, values, 40, 10) == pytest.approx((4 + 8 + 6 + 2 + 2) / 5)
    assert repro.time_mean(ticks, values, 25, 10) == pytest.approx((4 + 8 + 6 + 2) / 4)
    # Before the first sample there is no value: tick 0 is left out.
    assert repro.time_mean(np.array([5.0]), np.array([3.0]), 10, 10) == 3.0
    assert math.isnan(repro.time_mean(np.array([5.0]), np.array([1.0]), 0, 10))


def _rows_and_curves() -> tuple[list[dict[str, object]], pa.Table]:
    """Two seeds x two strategies, one panel; KME's WTV falls faster."""
    runs = pa.table(
        {
            "run_id": ["k1", "k2", "y1", "y2"],
            "map": ["unstructured"] * 4,
            "start": ["together"] * 4,
            "robots": [4] * 4,
            "strategy": ["kme", "kme", "nearest-frontier", "nearest-frontier"],
            "seed": [1, 2, 1, 2],
            "T100": [30, 40, 20, None],
            "wtv_8_final": [10.0, 20.0, 30.0, 50.0],
        }
    )
    curves = pa.table(
        {
            "run_id": ["k1"] * 4 + ["k2"] * 5 + ["y1"] * 3 + ["y2"] * 7,
            "tick": [0, 10, 20, 30, 0, 10, 20, 30, 40, 0, 10, 20, *range(0, 70, 10)],
            "wtv_8": [
                *(50.0, 30.0, 20.0, 10.0),
                *(50.0, 40.0, 30.0, 25.0, 20.0),
                *(50.0, 40.0, 30.0),
                *(50.0, 60.0, 70.0, 60.0, 55.0, 52.0, 50.0),
            ],
            "epv_8": [0.0] * 19,
        }
    )
    return runs.to_pylist(), curves


def test_curve_means_use_one_horizon_per_map_and_team_size() -> None:
    rows, curves = _rows_and_curves()
    values = {r["run_id"]: r for r in repro.with_curve_means(rows, curves)}
    # Horizon 60 (y2's end): k1 = (50+30+20+10+10+10+10)/7, y1 = (50+40+30*5)/7.
    assert {r["horizon"] for r in values.values()} == {60}
    assert values["k1"]["wtv_time"] == pytest.approx(140.0 / 7)
    assert values["y1"]["wtv_time"] == pytest.approx(240.0 / 7)
    assert values["y2"]["wtv_time"] == pytest.approx(397.0 / 7)
    assert math.isnan(repro.with_curve_means(rows[:1], None)[0]["wtv_time"])  # no curve
    table = repro.run_values(list(values.values()))
    cell = ("unstructured", "together", 4)
    assert table["wtv_final"][cell]["kme"] == {1: 10.0, 2: 20.0}
    assert math.isnan(table["t100"][cell]["nearest-frontier"][2])  # missing, not 0


def test_the_claims_read_their_panels() -> None:
    rows, curves = _rows_and_curves()
    separate = [{**r, "start": "separate", "run_id": f"s{r['run_id']}"} for r in rows]
    two = [{**r, "robots": 2, "run_id": f"t{r['run_id']}"} for r in rows]
    stores = {"x": _FakeStore(pa.Table.from_pylist([*rows, *separate, *two]), curves)}
    tables = repro.tables(stores, quick=True)  # type: ignore[arg-type]  # a Store stand-in
    assert set(tables) == {c.metric for c in repro.CLAIMS}
    assert list(tables["wtv_time/fig6/teams"]) == [("unstructured", "together", 4)]
    assert list(tables["epv_time/fig8"]) == [("unstructured", "separate", 4)]
    assert list(tables["wtv_time/fig6"]) == [("unstructured", "together", n) for n in (2, 4)]
    schemes = tables["wtv_time/schemes"]
    assert list(schemes)[:2] == [("unstructured", "kme", 2), ("unstructured", "kme", 4)]
    assert set(schemes["unstructured", "kme", 4]) == {"together", "separate"}
    both = tables["wtv_epv_time"]
    assert both["WTV", "unstructured", "separate", 4] is tables["wtv_time/fig7/teams"][FIG7_4]
    assert both["EPV", "unstructured", "separate", 4] is tables["epv_time/fig8"][FIG7_4]


class _FakeStore:
    """The two tables of a results store."""

    def __init__(self, runs: pa.Table, curves: pa.Table) -> None:
        self._tables = (runs.append_column("status", pa.array(["complete"] * len(runs))), curves)

    def tables(self) -> tuple[pa.Table, pa.Table]:
        return self._tables

    def query(self, sql: str) -> pa.Table:
        return self._tables[0].sort_by("run_id")


def test_the_claims_in_the_papers_order() -> None:
    ids = [claim.id for claim in repro.CLAIMS]
    assert ids == [
        "fewer_robots",
        "fig6_lowest",
        "fig6_final",
        "separate_lower",
        "fig7_lowest",
        "fig8_lowest",
        "six_combinations",
        "zlot",
    ]
    zlot = repro.CLAIMS[-1]
    assert (zlot.first, zlot.second, *zlot.seconds) == (
        "zlot-market",
        "nearest-frontier",
        "burgard",
    )


# ------------------------------------------------------------------ full run


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    assert main(["reproduce", "wu2011", "--out", str(tmp_path), "--no-progress"]) == 0
    text = _check_report(tmp_path, FULL_FIGURES)
    assert "**Quick run**" not in text
    for name in repro.REPRODUCTION.sweeps(False):
        assert (tmp_path / name / "runs").is_dir()
