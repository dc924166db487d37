"""Reproduction of Wu, Puig and Garcia §V: the quick run end to end, the helpers on
hand-made tables, and the full run (slow)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import wu2011 as repro
from mrexplore.experiments.stats import summarize_metric

QUICK_FIGURES = ("fig6_wtv_together.png", "fig7_wtv_separate.png", "fig8_epv_separate.png")
FULL_FIGURES = (*QUICK_FIGURES, "wtv_all_combinations.png", "epv_all_combinations.png")
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
    # The paper's statements and numbers, as typed in.
    for claim in (
        repro.PAPER_FIG6_FEWER_ROBOTS_HIGHER,
        repro.PAPER_FIG7_SEPARATE_LOWER,
        repro.PAPER_SIX_COMBINATIONS,
        repro.PAPER_ZLOT_NOT_SUPERIOR,
    ):
        assert claim in text
    for numbers in (
        repro.PAPER_FIG6_KME_LOWEST,
        repro.PAPER_FIG6_KME_FINAL_NOT_LOWEST,
        repro.PAPER_FIG8_KME_LOWEST,
    ):
        assert str(numbers) in text
    assert f"{repro.PAPER_CONFIGURATIONS} configurations" in text
    assert f"{repro.PAPER_RUNS_PER_CONFIGURATION} set-ups" in text
    for name in figures:
        assert (out / name).stat().st_size > 1000, name
        assert f"]({name})" in text
    return text


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wu2011-quick")
    assert main(["reproduce", "wu2011", "--quick", "--out", str(out), "--no-progress"]) == 0
    return out


def test_quick_reproduction_writes_the_report(quick_run: Path) -> None:
    text = _check_report(quick_run, QUICK_FIGURES)
    assert "**Quick run**" in text.split("## Settings")[0]
    assert (quick_run / "unstructured" / "runs").is_dir()
    assert "failed" not in text.split("## Settings")[0]
    # Every seed placed the team differently, and the strategies of a seed alike.
    section = text.split("## Start set-ups", 1)[1].split("## Fig. 6", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| unstructured")]
    assert len(rows) == 2 * len(repro.QUICK_TEAM_SIZES)
    for row in rows:
        distinct, seeds, equal = (int(x) for x in row.strip("| ").split(" | ")[3:])
        assert distinct == seeds == equal == len(repro.QUICK_SEEDS)


def test_registered() -> None:
    reproduction = get_reproduction("wu2011")
    assert reproduction is repro.REPRODUCTION
    assert reproduction.id == "wu2011"


def test_full_sweeps_have_the_papers_design() -> None:
    sweeps = repro.sweeps(False)
    assert list(sweeps) == list(repro.MAPS)
    for name, sweep in sweeps.items():
        # 2 schemes x 4 strategies x 4 team sizes x 15 set-ups, one map per type.
        assert len(sweep) == 2 * 4 * 4 * 15
        scenarios = [spec.scenario for spec in sweep.runs()]
        assert {s.map for s in scenarios} == {name}
        assert {s.map_seed for s in scenarios} == {repro.MAP_SEED}
        assert {s.start for s in scenarios} == {"together", "separate"}
        assert {s.coverage_threshold for s in scenarios} == {1.0}
    assert sum(len(s) for s in sweeps.values()) == 1440


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


def test_step_values_and_time_mean_carry_the_final_value() -> None:
    ticks = np.array([0.0, 10.0, 20.0, 23.0])
    values = np.array([4.0, 8.0, 6.0, 2.0])
    grid = repro.horizon_grid(40, 10)
    assert grid.tolist() == [0.0, 10.0, 20.0, 30.0, 40.0]
    assert repro.step_values(ticks, values, grid).tolist() == [4.0, 8.0, 6.0, 2.0, 2.0]
    assert repro.time_mean(ticks, values, 40, 10) == pytest.approx(22.0 / 5)
    # Before the first sample there is no value.
    assert math.isnan(repro.step_values(np.array([5.0]), np.array([1.0]), np.array([0.0]))[0])


def _runs_and_curves() -> tuple[pa.Table, pa.Table]:
    """Two seeds x two strategies, one panel; KME's WTV falls faster."""
    runs = pa.table(
        {
            "run_id": ["k1", "k2", "y1", "y2", "bad"],
            "map": ["unstructured"] * 5,
            "start": ["together"] * 5,
            "robots": [4] * 5,
            "strategy": ["kme", "kme", "nearest-frontier", "nearest-frontier", "burgard"],
            "seed": [1, 2, 1, 2, 1],
            "status": ["complete"] * 4 + ["failed"],
            "starts": ["[[1, 1]]", "[[2, 2]]", "[[1, 1]]", "[[2, 2]]", None],
            "T100": [30, 40, 20, 60, None],
            "wtv_8_final": [10.0, 20.0, 30.0, 50.0, None],
            "epv_8_final": [0.0, 0.0, 0.0, 0.0, None],
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
    return runs, curves


def test_run_values_use_one_horizon_per_map_and_team_size() -> None:
    runs, curves = _runs_and_curves()
    values = {v.run_id: v for v in repro.run_values(runs, curves, every=10)}
    assert set(values) == {"k1", "k2", "y1", "y2"}  # the failed run is left out
    # Horizon 60 (y2's end): k1 = (50+30+20+10+10+10+10)/7, y1 = (50+40+30*5)/7.
    assert values["k1"].wtv_time == pytest.approx(140.0 / 7)
    assert values["y1"].wtv_time == pytest.approx(240.0 / 7)
    assert values["y2"].wtv_time == pytest.approx(397.0 / 7)
    assert values["k2"].t100 == 40.0 and values["k2"].wtv_final == 20.0
    stats = repro.panel_means(values.values(), "wtv_time")
    panel = ("unstructured", "together", 4)
    assert repro.lowest(stats[panel]) == "kme"
    assert stats[panel]["kme"].n == 2
    assert repro.start_check(list(values.values())) == [("unstructured", "together", 4, 2, 2, 2)]


def test_outcome_rules() -> None:
    assert repro.count_outcome(3, 3) == "reproduced"
    assert repro.count_outcome(9, 18) == "partly"
    assert repro.count_outcome(8, 18) == "not reproduced"
    assert repro.decreasing_outcome({"a": {2: 5.0, 4: 3.0, 6: 2.0}}) == "reproduced"
    assert repro.decreasing_outcome({"a": {2: 5.0, 4: 6.0, 6: 2.0}}) == "partly"
    assert repro.decreasing_outcome({"a": {2: 5.0, 4: 6.0, 6: 7.0}}) == "not reproduced"


def test_zlot_superior_needs_significance_against_both() -> None:
    zlot = {1: 1.0, 2: 1.2, 3: 0.9, 4: 1.1}
    far = {1: 5.0, 2: 5.1, 3: 4.9, 4: 5.2}
    assert repro.zlot_superior({"zlot-market": zlot, "nearest-frontier": far, "burgard": far})
    assert not repro.zlot_superior(
        {"zlot-market": zlot, "nearest-frontier": far, "burgard": {1: 1.0, 2: 1.3, 3: 0.8, 4: 1.0}}
    )


def test_paired_and_lowest() -> None:
    by_seed = {"kme": {1: 1.0, 2: 2.0, 3: 3.0}, "burgard": {1: 2.0, 2: 4.0}}
    difference = repro.paired(by_seed, "kme", "burgard")
    assert difference.n == 2 and difference.mean == -1.5
    assert repro.lowest({"kme": summarize_metric([]), "burgard": summarize_metric([2.0])}) == (
        "burgard"
    )
    assert repro.lowest({}) is None


def test_mean_curve_band_is_the_t_interval() -> None:
    series = [(np.array([0.0]), np.array([v])) for v in (1.0, 2.0, 3.0)]
    curve = repro.mean_curve(series, np.array([0.0, 5.0]))
    expected = summarize_metric([1.0, 2.0, 3.0])
    assert curve.mean.tolist() == [2.0, 2.0]
    assert curve.low[0] == pytest.approx(expected.ci_low)
    assert curve.high[1] == pytest.approx(expected.ci_high)


# ------------------------------------------------------------------ full run


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    assert main(["reproduce", "wu2011", "--out", str(tmp_path), "--no-progress"]) == 0
    text = _check_report(tmp_path, FULL_FIGURES)
    assert "**Quick run**" not in text
    for name in repro.MAPS:
        assert (tmp_path / name / "runs").is_dir()
