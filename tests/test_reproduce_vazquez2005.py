"""The Vazquez & Malcolm reproduction: the quick run end to end (with one reading of the
paper), its claims on hand-made runs (the rules themselves: ``test_claims``), and (marked
slow) the full reproduction."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from conftest import quick_reproduction
from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import vazquez2005 as vz
from mrexplore.experiments.reproduce.claims import Level, Ratio, RisesAbove
from mrexplore.experiments.store import Store
from mrexplore.experiments.sweep import sweep_from_dict
from mrexplore.grid import generate_map

VERDICT_LINE = re.compile(r"^- \*\*(reproduced|partly|not reproduced)\*\*: .+ \(.+\)$")
READING = "positions-every-tick"


def _verdict_lines(report: str) -> list[str]:
    section = report.split("## Verdicts", 1)[1].split("## Robustness", 1)[0]
    return [line for line in section.splitlines() if line.startswith("- **")]


def _check_report(out: Path, quick: bool) -> str:
    report = (out / "report.md").read_text()
    assert report.startswith(f"# Reproduction: {vz.TITLE}")
    assert vz.CITATION in report
    assert ("indicative only" in report) is quick
    lines = _verdict_lines(report)
    assert len(lines) == len(vz.CLAIMS) == 9
    for line in lines:
        assert VERDICT_LINE.match(line), line
    # The paper's numbers (§4) beside ours, and its sentences.
    for number in ("10.2 m^2", "23.5 m^2", "45 cm", "1 m, 1.5 m, 2 m", "2-10", "+-5%"):
        assert number in report, number
    for claim in vz.CLAIMS:
        assert f'paper: "{claim.sentence}"' in report
    pngs = sorted(out.glob("*.png"))
    names = {p.name for p in pngs}
    assert {"time_small.png", "fig12.png", "connected.png"} <= names
    assert any(name.startswith("map_") for name in names)
    for png in pngs:
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"({png.name})" in report
    return report


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return quick_reproduction(tmp_path_factory, "vazquez2005", READING)


def test_quick_reproduction_through_the_cli(quick_run: Path) -> None:
    report = _check_report(quick_run, quick=True)
    assert "office 50x50" in report
    robustness = report.split("## Robustness to the readings of the paper", 1)[1]
    assert f"| claim | default | {READING} | summary |" in robustness
    for claim in vz.CLAIMS:
        assert re.search(
            rf"^\| `{claim.id}` \| .* \| (robust|\*\*fragile\*\*.*) \|$", robustness, re.M
        )
    assert (quick_run / "readings" / READING / "small-vazquez" / "runs").is_dir()
    assert not (quick_run / "readings" / READING / "small-yamauchi").exists()


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    assert main(["reproduce", "vazquez2005", "--out", str(tmp_path), "--no-progress"]) == 0
    report = _check_report(tmp_path, quick=False)
    assert "time_large.png" in report
    assert "office 72x72" in report and "office 105x105" in report


# --------------------------------------------------------------------- settings


def test_registered_and_settings_follow_the_paper() -> None:
    assert get_reproduction("vazquez2005") is vz.REPRODUCTION
    assert vz.SENSOR_RANGE_CELLS == 4.5
    assert vz.COMM_RANGES_CELLS == (20, 30, 40)
    full = vz.REPRODUCTION.sweeps(False)
    assert list(full) == ["small-vazquez", "small-yamauchi", "large-vazquez", "large-yamauchi"]
    for sweep in full.values():  # the paper's grid: 2-10 robots, 10 trials, 3 ranges
        assert sweep.grid["robots"] == list(range(2, 11))
        assert len(sweep.seeds) == vz.PAPER_TRIALS
        assert sweep.fixed["map_seed"] == vz.MAP_SEED
        assert sweep.fixed["coverage_threshold"] == 1.0
        assert sweep.grid["comm_range"] == [20, 30, 40]
    assert [len(s) for s in vz.REPRODUCTION.sweeps(True).values()] == [8, 8]
    assert [row[0] for row in vz.SETTINGS_ROWS][:3] == ["simulator", "robot diameter", "sensor"]
    assert all(len(row) == 3 and all(row) for row in vz.SETTINGS_ROWS)


def test_the_split_sweeps_run_the_runs_of_the_former_combined_sweep() -> None:
    """The quick sweep had both methods; split per method, its runs are the same."""
    fixed = {**vz.FIXED, "size": "50x50", "max_ticks": 6000}
    grid = {"strategy": [vz.VAZQUEZ, vz.YAMAUCHI], "robots": [4, 8], "comm_range": [20, 40]}
    before = sweep_from_dict(
        {"sweep": {"name": "small", "seeds": [1, 2]}, "fixed": fixed, "grid": grid}
    )
    after = [spec for sweep in vz.REPRODUCTION.sweeps(True).values() for spec in sweep.runs()]
    assert sorted(s.run_id for s in after) == sorted(s.run_id for s in before.runs())


@pytest.mark.parametrize("label", ["small", "large"])
def test_office_maps_match_the_papers_areas(label: str) -> None:
    spec = vz.MAPS[label]
    width, height = (int(v) for v in spec.size.split("x"))
    grid = generate_map("office", width, height, seed=vz.MAP_SEED)
    area = int((~grid.occupied).sum()) * vz.CELL_SIZE_M**2
    assert area == pytest.approx(spec.paper_area_m2, rel=0.02)


def test_interpretations_change_one_setting_each() -> None:
    names = [i.name for i in vz.INTERPRETATIONS]
    assert names[:3] == ["both-replan-when-explored", READING, "maps-on-reconnection"]
    replan, positions, maps, *rules, localisation = vz.INTERPRETATIONS
    assert replan.set == {"replan_on_target_explored": True}
    assert set(replan.strategies) == {vz.VAZQUEZ, vz.YAMAUCHI}  # both arms alike
    assert positions.set == {"position_period": 1} and positions.strategies == (vz.VAZQUEZ,)
    assert maps.scenario == {"sharing": "full"} and not maps.strategies and not maps.set
    # §4 "known with an error margin of +-5%": odometry drift for both methods
    assert localisation.scenario == {"odometry_noise": vz.PAPER_POSITION_ERROR}
    assert not localisation.strategies and not localisation.set
    # every other reading of vazquez-network's rules: one parameter, a valid value
    from mrexplore.strategies.vazquez_network import VazquezNetwork

    assert len(rules) == 9
    for reading in rules:
        ((key, value),) = reading.set.items()
        assert reading.strategies == (vz.VAZQUEZ,)
        assert value != VazquezNetwork.params[key].default, reading.name
        VazquezNetwork(0, 2, **{key: value})  # accepted


def test_both_methods_share_the_paper_s_sharing_and_re_plan_rule() -> None:
    for sweep in vz.REPRODUCTION.sweeps(quick=True).values():
        runs = sweep.runs()
        assert {r.scenario.sharing for r in runs} == {"broadcast"}
        assert {r.scenario.complete_when for r in runs} == {"robot"}
        assert {r.scenario.params["replan_on_target_explored"] for r in runs} == {False}


# --------------------------------------------------------------------- reading the runs


def test_run_rows_add_the_share_of_the_time_in_one_sub_network(tmp_path: Path) -> None:
    store = Store(tmp_path / "small-vazquez")
    store.create()
    runs = [
        {"run_id": "r0", "status": "complete"},
        {"run_id": "r1", "status": "max_ticks"},
        {"run_id": "r2", "status": "failed"},
    ]
    pq.write_table(pa.Table.from_pylist(runs), store.root / "runs" / "run-0.parquet")
    curves = {"run_id": ["r0"] * 4 + ["r1"] * 2, "subnetworks": [1, 1, 2, None, 1, 1]}
    pq.write_table(pa.table(curves), store.root / "curves" / "run-0.parquet")
    rows, statuses = vz.run_rows({"small-vazquez": store})
    assert statuses == {"complete": 1, "failed": 1, "max_ticks": 1}
    assert [(r["run_id"], r["connected_share"]) for r in rows] == [("r0", 0.5), ("r1", 1.0)]
    empty = Store(tmp_path / "empty")
    empty.create()
    pq.write_table(pa.Table.from_pylist(runs[:1]), empty.root / "runs" / "run-0.parquet")
    assert math.isnan(vz.run_rows({"empty": empty})[0][0]["connected_share"])  # no curves


def _run(strategy: str, robots: int, seed: int, ticks: float, **extra: Any) -> dict[str, Any]:
    complete = extra.pop("complete", True)
    row = {"size": "72x72", "comm_range": 20.0, "strategy": strategy, "robots": robots}
    row.update(seed=seed, ticks=ticks, T100=ticks if complete else None, T99=ticks - 1)
    return {**row, "connected_share": 1.0, **extra}


def _runs(strategy: str, robots: int, times: list[float], **extra: Any) -> list[dict[str, Any]]:
    return [_run(strategy, robots, s, t, **extra) for s, t in enumerate(times, start=1)]


def test_run_values_keep_incomplete_runs_as_lower_bounds() -> None:
    rows = [*_runs(vz.VAZQUEZ, 2, [500, 700]), _run(vz.VAZQUEZ, 2, 3, 900, complete=False)]
    rows += [_run(vz.VAZQUEZ, 2, 1, 300, size="105x105", comm_range=40.0)]
    values = vz.run_values(rows)
    small, large = values["time"]  # maps in the paper's order
    assert (small, large) == (("small", 1.0, 2), ("large", 2.0, 2))
    assert str(small[1]) == "1 m" and str(large[1]) == "2 m"
    assert values["time"][small][vz.VAZQUEZ] == {1: 500.0, 2: 700.0, 3: 900.0}
    assert values["complete"][small][vz.VAZQUEZ] == {1: 1.0, 2: 1.0, 3: 0.0}
    assert values["time"][small][f"{vz.VAZQUEZ} T99"] == {1: 499.0, 2: 699.0, 3: 899.0}
    assert values["ranges"][("large", 2)] == {f"{vz.VAZQUEZ}, 2 m": {1: 300.0}}


# --------------------------------------------------------------------- the claims


def _verdict(claim_id: str, rows: list[dict[str, Any]]) -> tuple[str, str]:
    claim = next(c for c in vz.CLAIMS if c.id == claim_id)
    verdict = claim.judge(vz.run_values(rows))
    return verdict.outcome, verdict.evidence


def test_the_claims_keep_their_rules_and_thresholds() -> None:
    rules = {c.id: c.rule for c in vz.CLAIMS}
    assert list(rules) == [
        "trend",
        "faster",
        "above_7",
        "variance",
        "range_tradeoff",
        "range_gap",
        "incremental",
        "network",
        "faster_one_map",
    ]
    assert rules["faster"] == vz.FASTER and vz.FASTER.also == vz.T99_ARMS
    assert (vz.FASTER.needs.holds, vz.FASTER.needs.partly_holds) == (0.9, 1 / 3)
    assert vz.VARIANCE.statistic == "sd" and vz.VARIANCE.min_seeds == 2
    assert (vz.VARIANCE.needs.holds, vz.VARIANCE.needs.partly_holds) == (0.75, 0.5)
    assert rules["above_7"] == RisesAbove(7, within=("small",))
    assert rules["range_tradeoff"] == Ratio("<=", 1.25, seeds="common")
    assert rules["network"] == Level(">=", 0.95, 0.8, shown=(vz.YAMAUCHI,))
    assert rules["faster_one_map"] == vz.ONE_MAP and not vz.ONE_MAP.also


def test_faster() -> None:
    slower = _runs(vz.YAMAUCHI, 4, [100, 110]) + _runs(vz.VAZQUEZ, 4, [200, 210])
    assert _verdict("faster", slower)[0] == "not reproduced"
    faster = _runs(vz.YAMAUCHI, 4, [200, 210]) + _runs(vz.VAZQUEZ, 4, [100, 105])
    outcome, evidence = _verdict("faster", faster)
    assert outcome == "reproduced" and "holds in 1/1 cells" in evidence
    assert "`vazquez-network T99` vs `nearest-frontier T99`: holds in 1/1" in evidence
    mixed = faster + _runs(vz.YAMAUCHI, 8, [100, 110]) + _runs(vz.VAZQUEZ, 8, [200, 210])
    assert _verdict("faster", mixed)[0] == "partly"  # 1/2 >= 1/3
    assert _verdict("faster", [])[0] == "not reproduced"


def test_team_size_trend() -> None:
    diminishing = _runs(vz.VAZQUEZ, 2, [1000]) + _runs(vz.VAZQUEZ, 6, [400])
    diminishing += _runs(vz.VAZQUEZ, 10, [300])
    assert _verdict("trend", diminishing)[0] == "reproduced"
    accelerating = _runs(vz.VAZQUEZ, 2, [1000]) + _runs(vz.VAZQUEZ, 6, [900])
    accelerating += _runs(vz.VAZQUEZ, 10, [300])
    assert _verdict("trend", accelerating)[0] == "not reproduced"
    rising = _runs(vz.YAMAUCHI, 2, [300]) + _runs(vz.YAMAUCHI, 10, [400])
    assert _verdict("trend", diminishing + rising)[0] == "partly"


def test_yamauchi_worse_above_seven() -> None:
    rows = [_run(vz.YAMAUCHI, n, 1, t) for n, t in ((6, 300), (7, 250), (8, 260), (10, 270))]
    assert _verdict("above_7", rows)[0] == "reproduced"
    better = [dict(r, ticks=200, T100=200) if r["robots"] == 10 else r for r in rows]
    outcome, evidence = _verdict("above_7", better)
    assert outcome == "not reproduced" and "250 at 7" in evidence
    other_range = [dict(r, comm_range=40.0) for r in better]
    assert _verdict("above_7", rows + other_range)[0] == "partly"
    large = [dict(r, size="105x105") for r in rows]  # only the small map counts
    assert _verdict("above_7", large)[0] == "not reproduced"


def test_variance() -> None:
    noisy_yamauchi = _runs(vz.YAMAUCHI, 4, [100, 300]) + _runs(vz.VAZQUEZ, 4, [200, 210])
    assert _verdict("variance", noisy_yamauchi)[0] == "reproduced"
    noisy_vazquez = _runs(vz.YAMAUCHI, 4, [100, 105]) + _runs(vz.VAZQUEZ, 4, [200, 400])
    assert _verdict("variance", noisy_vazquez)[0] == "not reproduced"
    one_seed = _runs(vz.YAMAUCHI, 4, [100]) + _runs(vz.VAZQUEZ, 4, [200])
    assert _verdict("variance", one_seed)[0] == "not reproduced"


def _by_range(times: dict[tuple[float, int], float]) -> list[dict[str, Any]]:
    return [_run(vz.VAZQUEZ, n, 1, t, comm_range=r) for (r, n), t in times.items()]


def test_ranges() -> None:
    similar = _by_range({(20, 2): 1100, (40, 2): 1000, (20, 10): 310, (40, 10): 300})
    assert _verdict("range_tradeoff", similar)[0] == "reproduced"
    assert _verdict("range_gap", similar)[0] == "reproduced"
    # The gap in ticks shrinks but the ratio grows: partly.
    growing = _by_range({(20, 2): 2000, (40, 2): 1000, (20, 10): 900, (40, 10): 300})
    assert _verdict("range_tradeoff", growing)[0] == "not reproduced"
    outcome, evidence = _verdict("range_gap", growing)
    assert outcome == "partly" and "x2.00" in evidence and "x3.00" in evidence
    widening = _by_range({(20, 2): 1100, (40, 2): 1000, (20, 10): 800, (40, 10): 300})
    assert _verdict("range_gap", widening)[0] == "not reproduced"
    half = _by_range({(20, 2): 1100, (40, 2): 1000, (20, 10): 900, (40, 10): 300})
    assert _verdict("range_tradeoff", half)[0] == "partly"


def test_incremental() -> None:
    rows = _runs(vz.YAMAUCHI, 2, [1000]) + _runs(vz.VAZQUEZ, 2, [2000])
    rows += _runs(vz.YAMAUCHI, 10, [300]) + _runs(vz.VAZQUEZ, 10, [330])
    outcome, evidence = _verdict("incremental", rows)
    assert outcome == "reproduced" and "2:2.00, 10:1.10" in evidence
    worse = [
        dict(r, T100=900) if r["robots"] == 10 and r["strategy"] == vz.VAZQUEZ else r for r in rows
    ]
    assert _verdict("incremental", worse)[0] == "not reproduced"


def test_network() -> None:
    def rows(vazquez: float, yamauchi: float = 0.25) -> list[dict[str, Any]]:
        return _runs(vz.VAZQUEZ, 4, [100], connected_share=vazquez) + _runs(
            vz.YAMAUCHI, 4, [100], connected_share=yamauchi
        )

    outcome, evidence = _verdict("network", rows(1.0))
    assert outcome == "reproduced"
    assert "`vazquez-network`: holds in 1/1 cells" in evidence
    assert "| `nearest-frontier`: small/1 m/4r: 0.25" in evidence
    assert _verdict("network", rows(0.9))[0] == "partly"
    assert _verdict("network", rows(0.6))[0] == "not reproduced"
    assert _verdict("network", rows(math.nan))[0] == "not reproduced"  # no curves


def test_every_claim_gives_a_verdict_line_on_no_runs() -> None:
    for claim in vz.CLAIMS:
        line = claim.judge(vz.run_values([])).line()
        assert VERDICT_LINE.match(line), line
        assert line.startswith("- **not reproduced**")
