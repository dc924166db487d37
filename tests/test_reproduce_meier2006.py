"""The meier2006 reproduction: quick run through the CLI, its helpers and rules, full run (slow)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import meier2006 as m
from mrexplore.experiments.stats import summarize_metric

OUTCOMES = ("reproduced", "partly", "not reproduced")
N_CLAIMS = 10
FIGURES = (
    "fig6_exploration_time.png",
    "table1_package_shares.png",
    "table2_approximation_error.png",
    "fig7_traffic.png",
)


def _verdict_lines(text: str) -> list[str]:
    section = text.split("## Verdicts", 1)[1]
    return [line for line in section.splitlines() if line.startswith("- **")]


def _check_report(out: Path, *, quick: bool) -> str:
    text = (out / "report.md").read_text()
    assert text.startswith(f"# Reproduction `{m.ID}`")
    assert m.CITATION in text
    assert ("Quick run" in text) is quick
    assert "## Verdicts" in text
    lines = _verdict_lines(text)
    assert len(lines) == N_CLAIMS
    for line in lines:
        outcome = re.match(r"- \*\*(.+?)\*\*: ", line)
        assert outcome is not None and outcome.group(1) in OUTCOMES, line
    # The paper's numbers are in the report: Table 1, Table 2, the §5.2 text.
    for number in ("31.12", "78.95", "21.05", "8.92", "0.86", "0.19", "200,000", "7,500"):
        assert number in text, number
    for name in FIGURES:
        assert (out / name).stat().st_size > 0, name
        assert f"]({name})" in text
    return text


# ------------------------------------------------------------------- quick run


def test_quick_reproduction_through_cli(tmp_path: Path) -> None:
    from mrexplore.cli import main

    assert main(["reproduce", "meier2006", "--quick", "--out", str(tmp_path), "--no-progress"]) == 0
    _check_report(tmp_path, quick=True)
    for name in m.sweeps(True):
        assert (tmp_path / name / "runs").is_dir()


def test_registered() -> None:
    reproduction = get_reproduction("meier2006")
    assert reproduction is m.REPRODUCTION
    assert reproduction.id == "meier2006"


def test_sweeps_full_and_quick() -> None:
    full = m.sweeps(False)
    assert set(full) == {
        f"{key}_{kind}"
        for key in ("unstructured3", "corridor5", "two_robots")
        for kind in ("polygon", "baselines")
    }
    polygon = full["unstructured3_polygon"].runs()
    rates = {spec.scenario.sharing_params["split_rate"] for spec in polygon}
    assert rates == set(m.PAPER_TABLE1)
    assert all(
        spec.scenario.robots == 3 and spec.scenario.map == "unstructured" for spec in polygon
    )
    assert all(spec.scenario.map_seed == m.MAP_SEED for spec in polygon)
    assert {s.scenario.robots for s in full["corridor5_polygon"].runs()} == {5}
    assert {s.scenario.robots for s in full["two_robots_baselines"].runs()} == {2}
    baselines = full["corridor5_baselines"].runs()
    assert {(s.scenario.strategy, s.scenario.sharing) for s in baselines} == {
        m.CENTRALISED,
        m.DECENTRALISED_FULL,
    }
    quick = m.sweeps(True)
    assert set(quick) == {"quick_polygon", "quick_baselines"}
    maps = {(s.scenario.map, s.scenario.robots) for s in quick["quick_polygon"].runs()}
    assert maps == {("unstructured", 3), ("corridor", 3)}
    assert sum(len(s) for s in quick.values()) < sum(len(s) for s in full.values()) / 5


# ------------------------------------------------------------ paper's numbers


def test_paper_table1_rows_sum_to_100() -> None:
    for rate, row in m.PAPER_TABLE1.items():
        assert set(row) == set(m.PACKAGE_TYPES)
        assert sum(row.values()) == pytest.approx(100.0, abs=0.1), rate


def test_paper_table1_trends() -> None:
    rates = list(m.PAPER_TABLE1)
    signs = {
        name: m.trend_sign(rates, [m.PAPER_TABLE1[r][name] for r in rates])
        for name in m.PACKAGE_TYPES
    }
    assert signs == {"TPT": -1, "ES": 1, "B": -1, "VP": 1, "EP": -1}


# -------------------------------------------------------------------- helpers


def _runs_table() -> pa.Table:
    """Hand-made runs table: two split rates and two baselines, two seeds each."""
    return pa.table(
        {
            "run_id": ["a", "b", "c", "d", "e", "f", "g", "h", "i"],
            "strategy": ["meier-polygon"] * 4 + ["burgard"] * 2 + ["meier-polygon"] * 3,
            "sharing": ["polygon"] * 4 + ["full"] * 2 + ["full"] * 2 + ["polygon"],
            "share_split_rate": [0.1, 0.1, 10.0, 10.0, None, None, None, None, 1.0],
            "seed": [1, 2, 1, 2, 1, 2, 1, 2, 1],
            "robots": [2] * 9,
            "status": ["complete", "complete", "complete", "max_ticks"]
            + ["complete"] * 4
            + ["failed"],
            "ticks": [99, 109, 89, 3000, 79, 89, 84, 94, 10],
            "T99": [99, 109, 89, None, 79, 89, 84, 94, None],
            "bytes_total": [1000, 1200, 5000, 6000, 3000, 3100, 2100, 2200, None],
            "bytes_by_type_TPT": [200, 200, 100, 100, None, None, 100, 100, None],
            "bytes_by_type_ES": [300, 400, 4000, 5000, None, None, None, None, None],
            "bytes_by_type_status": [None, None, None, None, 150, 150, None, None, None],
            "bytes_by_type_assign": [None, None, None, None, 130, 130, None, None, None],
            "polygon_approximation_error_mean": ["[0.1, 0.3]", "[0.2, null]", "[0.0, 0.02]"]
            + [None] * 6,
        }
    )


def test_split_rows_groups_and_counts_failures() -> None:
    rows = _runs_table().to_pylist()
    polygon, baselines, failed = m.split_rows(
        [r for r in rows if r["sharing"] == "polygon"], [r for r in rows if r["sharing"] == "full"]
    )
    assert failed == 1
    assert list(polygon) == [0.1, 10.0]
    assert [r["run_id"] for r in polygon[0.1]] == ["a", "b"]
    assert set(baselines) == {m.CENTRALISED, m.DECENTRALISED_FULL}
    times = m.by_seed(polygon[10.0], m.exploration_time)
    assert times[1] == 89 and math.isnan(times[2])


def test_package_shares_from_runs_table() -> None:
    row = _runs_table().to_pylist()[0]
    shares = m.package_shares(row)
    assert shares["TPT"] == pytest.approx(20.0)
    assert shares["ES"] == pytest.approx(30.0)
    assert shares["B"] == shares["VP"] == shares["EP"] == 0.0
    assert shares["other"] == pytest.approx(50.0)
    assert all(math.isnan(v) for v in m.package_shares({"bytes_total": 0}).values())


def test_map_package_bytes_drops_coordination() -> None:
    rows = _runs_table().to_pylist()
    assert m.map_package_bytes(rows[0]) == 800  # polygon: all but TPT
    assert m.map_package_bytes(rows[4]) == 3000 - 150 - 130  # burgard: all but status/assign
    assert m.map_package_bytes(rows[6]) == 2000  # meier-polygon + full: all but TPT


def test_team_error() -> None:
    rows = _runs_table().to_pylist()
    assert m.team_error(rows[0]["polygon_approximation_error_mean"]) == pytest.approx(0.2)
    assert m.team_error(rows[1]["polygon_approximation_error_mean"]) == pytest.approx(0.2)
    assert math.isnan(m.team_error("[null]"))
    assert math.isnan(m.team_error(None))


def test_raw_scan_bytes_and_centralised_estimate() -> None:
    per_scan = 7 + 360 * 2
    assert m.raw_scan_bytes(1, 0) == per_scan
    assert m.raw_scan_bytes(3, 99) == 3 * 100 * per_scan
    assert m.raw_scan_bytes(2, 9, beams=181) == 2 * 10 * (7 + 181 * 2)
    row = _runs_table().to_pylist()[4]  # burgard, 2 robots, 79 ticks
    assert m.centralised_raw_bytes(row) == 150 + 130 + 2 * 80 * per_scan


def test_paired_uses_common_finite_seeds() -> None:
    s = m.paired({1: 10.0, 2: 14.0, 3: math.nan, 4: 1.0}, {1: 8.0, 2: 10.0, 3: 1.0})
    assert s.n == 2 and s.mean == pytest.approx(3.0)
    assert m.paired({}, {1: 1.0}).n == 0


def test_spearman_and_trend_sign() -> None:
    assert m.spearman([1, 2, 3, 4], [1, 3, 2, 4]) == pytest.approx(0.8)
    assert math.isnan(m.spearman([1, 2, 3], [5, 5, 5]))
    assert math.isnan(m.spearman([1], [2]))
    assert m.trend_sign([1, 2, 3, 4], [1, 2, 4, 3]) == 1
    assert m.trend_sign([1, 2, 3, 4, 5], [4, 1, 3, 5, 2]) == 0  # rho = 0


def test_mean_curve_holds_last_value() -> None:
    ticks, mean = m.mean_curve({"a": [(0, 1.0), (10, 3.0)], "b": [(0, 1.0), (5, 2.0), (20, 6.0)]})
    assert ticks.tolist() == [0, 5, 10, 20]
    assert mean.tolist() == [1.0, 1.5, 2.5, 4.5]
    empty_ticks, empty_mean = m.mean_curve({})
    assert empty_ticks.size == 0 and empty_mean.size == 0


# ---------------------------------------------------------------------- rules


def _summary(values: list[float]):  # type: ignore[no-untyped-def]
    return summarize_metric(values)


def test_combine() -> None:
    assert m.combine(["holds", "holds"]) == "reproduced"
    assert m.combine(["holds", "weak"]) == "partly"
    assert m.combine(["weak", "weak"]) == "partly"
    assert m.combine(["fails", "fails"]) == "not reproduced"


def test_decreasing_status() -> None:
    rates = [0.1, 1.0, 10.0]
    clear = _summary([40.0, 50.0, 45.0])
    assert m.decreasing_status(rates, [300, 250, 200], clear) == "holds"
    assert m.decreasing_status(rates, [300, 250, 200], _summary([40.0, -50.0, 5.0])) == "weak"
    assert m.decreasing_status(rates, [200, 250, 300], _summary([5.0])) == "weak"
    assert m.decreasing_status(rates, [200, 250, 300], _summary([-40.0, -50.0])) == "fails"


def test_converge_status() -> None:
    assert m.converge_status(_summary([5.0, -5.0, 3.0]), 100.0) == "holds"
    assert m.converge_status(_summary([40.0, -30.0, 50.0]), 100.0) == "weak"  # CI has 0
    assert m.converge_status(_summary([8.0, 9.0, 8.5]), 100.0) == "weak"  # close, significant
    assert m.converge_status(_summary([50.0, 60.0, 55.0]), 100.0) == "fails"
    assert m.converge_status(_summary([]), 100.0) == "fails"


def test_slower_status() -> None:
    assert m.slower_status(_summary([10.0, 12.0, 11.0])) == "holds"
    assert m.slower_status(_summary([10.0, -8.0, 11.0])) == "weak"
    assert m.slower_status(_summary([-10.0, -12.0])) == "fails"


def test_advantage_outcome() -> None:
    assert m.advantage_outcome(1.05, 1.2) == "reproduced"
    assert m.advantage_outcome(0.8, 0.9) == "partly"
    assert m.advantage_outcome(1.2, 1.1) == "not reproduced"
    assert m.advantage_outcome(math.nan, 1.1) == "not reproduced"


def test_similar_status() -> None:
    assert m.similar_status(110.0, 100.0) == "holds"
    assert m.similar_status(90.0, 100.0) == "holds"
    assert m.similar_status(125.0, 100.0) == "weak"
    assert m.similar_status(140.0, 100.0) == "fails"


def test_tpt_outcome() -> None:
    assert m.tpt_outcome(31.0, 0.8) == "reproduced"
    assert m.tpt_outcome(31.0, 7.0) == "partly"
    assert m.tpt_outcome(10.0, 7.0) == "not reproduced"


def test_trends_outcome() -> None:
    paper = {"TPT": -1, "ES": 1, "B": -1, "VP": 1, "EP": -1}
    assert m.trends_outcome(paper, dict(paper)) == "reproduced"
    assert m.trends_outcome(paper, {**paper, "B": 0, "VP": -1}) == "partly"
    assert m.trends_outcome(paper, {"TPT": 1, "ES": -1, "B": 1, "VP": 1, "EP": -1}) == (
        "not reproduced"
    )


def test_error_outcome() -> None:
    paper = m.PAPER_TABLE2
    assert m.error_outcome({0.1: 9.0, 1.0: 1.0, 10.0: 0.2}, paper) == "reproduced"
    assert m.error_outcome({0.1: 40.0, 1.0: 10.0, 10.0: 0.5}, paper) == "partly"
    assert m.error_outcome({0.1: 9.0, 1.0: 10.0, 10.0: 0.2}, paper) == "not reproduced"
    assert m.error_outcome({0.1: 9.0, 1.0: 1.0}, paper) == "not reproduced"


def test_fragment_outcome() -> None:
    assert m.fragment_outcome([0.05, 0.2, 0.5]) == "reproduced"
    assert m.fragment_outcome([0.05, 0.7]) == "partly"
    assert m.fragment_outcome([1.2, 0.3]) == "partly"
    assert m.fragment_outcome([1.2, 2.0]) == "not reproduced"
    assert m.fragment_outcome([]) == "not reproduced"


def test_cheaper_outcome() -> None:
    assert m.cheaper_outcome([0.5, 0.9]) == "reproduced"
    assert m.cheaper_outcome([0.5, 1.9]) == "partly"
    assert m.cheaper_outcome([1.5, 1.9]) == "not reproduced"


# -------------------------------------------- the measurement added for Table 2


def test_polygon_sharing_reports_mean_error_over_run() -> None:
    from mrexplore.sim.engine import simulate
    from mrexplore.sim.scenario import Scenario

    scenario = Scenario(
        map="unstructured",
        size=(30, 30),
        map_seed=1,
        robots=2,
        strategy="meier-polygon",
        sensor_range=6.0,
        seed=1,
        sharing="polygon",
        sharing_params={"split_rate": 0.1},
        max_ticks=60,
    )
    result = simulate(scenario).result()
    means = result["polygon_approximation_error_mean"]
    assert len(means) == 2
    assert all(v is not None and 0.0 <= v <= 1.0 for v in means)
    assert json.loads(json.dumps(means)) == means
    assert np.isfinite(m.team_error(json.dumps(means)))


# ------------------------------------------------------------------- full run


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    from mrexplore.cli import main

    assert main(["reproduce", "meier2006", "--out", str(tmp_path), "--no-progress"]) == 0
    text = _check_report(tmp_path, quick=False)
    assert "SR 25" in text


def test_rows_of_a_setting() -> None:
    quick = m.settings(True)
    row = {"map": "corridor", "robots": 3}
    assert m._of(row, quick["corridor5"]) and not m._of(row, quick["unstructured3"])
    assert quick["corridor5"].store == quick["unstructured3"].store == "quick"
    assert m.settings(False)["corridor5"].store == "corridor5"


def test_figures_draw_without_data(tmp_path: Path) -> None:
    setting = m.settings(True)["unstructured3"]
    empty = m.SettingData(setting, {}, {}, failed=0, incomplete=0, curves={})
    assert m._fig6([empty, empty], tmp_path / "f6.png").stat().st_size > 0
    assert m._fig7(empty, tmp_path / "f7.png").stat().st_size > 0
    assert m._table2_figure({}, tmp_path / "t2.png").stat().st_size > 0
