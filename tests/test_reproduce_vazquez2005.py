"""The Vazquez & Malcolm reproduction: the quick run end to end, its helpers on
hand-made tables, and (marked slow) the full reproduction."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import pyarrow as pa
import pytest

from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import vazquez2005 as vz
from mrexplore.grid import generate_map

OUTCOMES = ("reproduced", "partly", "not reproduced")
VERDICT_LINE = re.compile(r"^- \*\*(reproduced|partly|not reproduced)\*\*: .+ \(.+\)$")
N_CLAIMS = len(vz.verdicts([]))


def _verdict_lines(report: str) -> list[str]:
    section = report.split("## Verdicts", 1)[1]
    return [line for line in section.splitlines() if line.startswith("- **")]


def _check_report(out: Path, quick: bool) -> str:
    report = (out / "report.md").read_text()
    assert report.startswith(f"# {vz.REPRODUCTION.title}")
    assert "Vazquez, C. Malcolm" in report
    assert ("indicative only" in report) is quick
    assert "## Verdicts" in report
    lines = _verdict_lines(report)
    assert len(lines) == N_CLAIMS
    for line in lines:
        assert VERDICT_LINE.match(line), line
    # The paper's numbers (§4) beside ours.
    for number in ("10.2 m^2", "23.5 m^2", "45 cm", "1 m, 1.5 m, 2 m", "2-10", "+-5%"):
        assert number in report, number
    pngs = sorted(out.glob("*.png"))
    assert any(p.name.startswith("fig6_") for p in pngs)
    assert any(p.name.startswith("fig12_") for p in pngs)
    assert any(p.name.startswith("map_") for p in pngs)
    for png in pngs:
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"({png.name})" in report
    return report


def test_quick_reproduction_through_the_cli(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert (
        main(["reproduce", "vazquez2005", "--quick", "--out", str(tmp_path), "--no-progress"]) == 0
    )
    assert "report.md" in capsys.readouterr().out
    report = _check_report(tmp_path, quick=True)
    assert "office 50x50" in report


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    assert main(["reproduce", "vazquez2005", "--out", str(tmp_path), "--no-progress"]) == 0
    report = _check_report(tmp_path, quick=False)
    for figure in range(6, 12):
        assert f"![Fig. {figure}]" in report
    assert "office 72x72" in report and "office 105x105" in report


# --------------------------------------------------------------------- settings


def test_registered_and_settings_follow_the_paper() -> None:
    assert get_reproduction("vazquez2005") is vz.REPRODUCTION
    assert vz.SENSOR_RANGE_CELLS == 4.5
    assert vz.COMM_RANGES_CELLS == (20, 30, 40)
    full = vz.sweeps(False)
    assert set(full) == {"small-vazquez", "small-yamauchi", "large"}
    yamauchi = full["small-yamauchi"]
    assert yamauchi.grid["robots"] == list(range(2, 11))
    assert len(yamauchi.seeds) == vz.PAPER_TRIALS
    for sweep in full.values():
        assert sweep.fixed["map_seed"] == vz.MAP_SEED
        assert sweep.fixed["coverage_threshold"] == 1.0
        assert sweep.grid["comm_range"] == [20, 30, 40]
    quick = vz.sweeps(True)
    assert len(quick["small"]) == 16


@pytest.mark.parametrize("label", ["small", "large"])
def test_office_maps_match_the_papers_areas(label: str) -> None:
    spec = vz.MAPS[label]
    width, height = (int(v) for v in spec.size.split("x"))
    grid = generate_map("office", width, height, seed=vz.MAP_SEED)
    area = int((~grid.occupied).sum()) * vz.CELL_SIZE_M**2
    assert area == pytest.approx(spec.paper_area_m2, rel=0.02)


# --------------------------------------------------------------------- hand-made tables


def _runs(rows: list[dict[str, Any]]) -> pa.Table:
    defaults: dict[str, Any] = {
        "size": "72x72",
        "comm_range": 20.0,
        "status": "complete",
        "T99": None,
        "explorable_cells": 4087,
    }
    full = []
    for i, row in enumerate(rows):
        merged = {**defaults, "run_id": f"r{i}", **row}
        if "T100" not in merged:
            merged["T100"] = merged["ticks"] if merged["status"] == "complete" else None
        if merged["T99"] is None and merged["T100"] is not None:
            merged["T99"] = merged["T100"]
        full.append(merged)
    return pa.Table.from_pylist(full)


def _records(rows: list[dict[str, Any]]) -> list[vz.RunRecord]:
    return vz.run_records(_runs(rows))


def _setting(strategy: str, robots: int, times: list[float], **extra: Any) -> list[dict[str, Any]]:
    return [
        {"strategy": strategy, "robots": robots, "seed": seed, "ticks": t, **extra}
        for seed, t in enumerate(times, start=1)
    ]


def test_run_records_keep_incomplete_runs_as_lower_bounds() -> None:
    runs = _runs(
        [
            {"strategy": vz.VAZQUEZ, "robots": 2, "seed": 1, "ticks": 500},
            {"strategy": vz.VAZQUEZ, "robots": 2, "seed": 2, "ticks": 900, "status": "max_ticks"},
            {"strategy": vz.VAZQUEZ, "robots": 2, "seed": 3, "ticks": 10, "status": "failed"},
            {"strategy": vz.VAZQUEZ, "robots": 2, "seed": 4, "ticks": 700, "size": "105x105"},
        ]
    )
    curves = pa.table(
        {
            "run_id": ["r0", "r0", "r0", "r0", "r1", "r1"],
            "subnetworks": [1, 1, 2, 1, 1, 1],
        }
    )
    records = vz.run_records(runs, curves)
    assert [r.seed for r in records] == [1, 2, 4]  # the failed run is left out
    first, capped, large = records
    assert first.complete and first.time == 500 and first.connected_share == 0.75
    assert not capped.complete and capped.time == 900 and capped.status == "max_ticks"
    assert capped.connected_share == 1.0
    assert large.map == "large" and math.isnan(large.connected_share)
    assert vz.connected_shares(None) == {}


def test_comparisons_pair_on_common_seeds() -> None:
    records = _records(
        _setting(vz.YAMAUCHI, 4, [100, 110, 120, 130]) + _setting(vz.VAZQUEZ, 4, [150, 170])
    )
    (c,) = vz.comparisons(records)
    assert c.seeds == (1, 2)
    assert c.yamauchi.mean == 105 and c.vazquez.mean == 160
    assert c.difference.mean == 55 and c.difference.n == 2
    assert c.ratio == pytest.approx(160 / 105)


def test_verdict_faster() -> None:
    slower = _records(_setting(vz.YAMAUCHI, 4, [100, 110]) + _setting(vz.VAZQUEZ, 4, [200, 210]))
    assert vz.verdict_faster(slower).outcome == "not reproduced"
    faster = _records(_setting(vz.YAMAUCHI, 4, [200, 210]) + _setting(vz.VAZQUEZ, 4, [100, 105]))
    verdict = vz.verdict_faster(faster)
    assert verdict.outcome == "reproduced"
    assert "1/1 settings" in verdict.evidence
    mixed = faster + _records(
        _setting(vz.YAMAUCHI, 8, [100, 110]) + _setting(vz.VAZQUEZ, 8, [200, 210])
    )
    assert vz.verdict_faster(mixed).outcome == "partly"
    assert vz.verdict_faster([]).outcome == "not reproduced"


def test_verdict_team_size_trend() -> None:
    diminishing = _records(
        _setting(vz.VAZQUEZ, 2, [1000])
        + _setting(vz.VAZQUEZ, 6, [400])
        + _setting(vz.VAZQUEZ, 10, [300])
    )
    assert vz.verdict_team_size_trend(diminishing).outcome == "reproduced"
    accelerating = _records(
        _setting(vz.VAZQUEZ, 2, [1000])
        + _setting(vz.VAZQUEZ, 6, [900])
        + _setting(vz.VAZQUEZ, 10, [300])
    )
    assert vz.verdict_team_size_trend(accelerating).outcome == "not reproduced"
    rising = _records(_setting(vz.YAMAUCHI, 2, [300]) + _setting(vz.YAMAUCHI, 10, [400]))
    assert vz.verdict_team_size_trend(diminishing + rising).outcome == "partly"


def test_verdict_yamauchi_worse_above_seven() -> None:
    rows = (
        _setting(vz.YAMAUCHI, 6, [300])
        + _setting(vz.YAMAUCHI, 7, [250])
        + _setting(vz.YAMAUCHI, 8, [260])
        + _setting(vz.YAMAUCHI, 10, [270])
    )
    assert vz.verdict_yamauchi_worse_above_seven(_records(rows)).outcome == "reproduced"
    better = [dict(r, ticks=200) if r["robots"] == 10 else r for r in rows]
    verdict = vz.verdict_yamauchi_worse_above_seven(_records(better))
    assert verdict.outcome == "not reproduced"
    assert "7 robots 250" in verdict.evidence
    other_range = [dict(r, comm_range=40.0) for r in better]
    assert vz.verdict_yamauchi_worse_above_seven(_records(rows + other_range)).outcome == "partly"
    # Only the small map counts.
    large = [dict(r, size="105x105") for r in rows]
    assert vz.verdict_yamauchi_worse_above_seven(_records(large)).outcome == "not reproduced"


def test_verdict_variance() -> None:
    noisy_yamauchi = _records(
        _setting(vz.YAMAUCHI, 4, [100, 300]) + _setting(vz.VAZQUEZ, 4, [200, 210])
    )
    assert vz.verdict_variance(noisy_yamauchi).outcome == "reproduced"
    noisy_vazquez = _records(
        _setting(vz.YAMAUCHI, 4, [100, 105]) + _setting(vz.VAZQUEZ, 4, [200, 400])
    )
    assert vz.verdict_variance(noisy_vazquez).outcome == "not reproduced"
    one_seed = _records(_setting(vz.YAMAUCHI, 4, [100]) + _setting(vz.VAZQUEZ, 4, [200]))
    assert vz.verdict_variance(one_seed).outcome == "not reproduced"


def _by_range(times: dict[tuple[float, int], float]) -> list[vz.RunRecord]:
    rows = []
    for (comm_range, robots), t in times.items():
        rows += _setting(vz.VAZQUEZ, robots, [t], comm_range=comm_range)
    return _records(rows)


def test_verdicts_on_ranges() -> None:
    similar = _by_range({(20, 2): 1100, (40, 2): 1000, (20, 10): 310, (40, 10): 300})
    assert vz.verdict_range_tradeoff(similar).outcome == "reproduced"
    assert vz.verdict_range_gap(similar).outcome == "reproduced"
    # The gap in ticks shrinks but the ratio grows: partly.
    growing = _by_range({(20, 2): 2000, (40, 2): 1000, (20, 10): 900, (40, 10): 300})
    assert vz.verdict_range_tradeoff(growing).outcome == "not reproduced"
    gap = vz.verdict_range_gap(growing)
    assert gap.outcome == "partly"
    assert "x2.00" in gap.evidence and "x3.00" in gap.evidence
    widening = _by_range({(20, 2): 1100, (40, 2): 1000, (20, 10): 800, (40, 10): 300})
    assert vz.verdict_range_gap(widening).outcome == "not reproduced"
    half = _by_range({(20, 2): 1100, (40, 2): 1000, (20, 10): 900, (40, 10): 300})
    assert vz.verdict_range_tradeoff(half).outcome == "partly"


def test_verdict_incremental() -> None:
    rows = (
        _setting(vz.YAMAUCHI, 2, [1000])
        + _setting(vz.VAZQUEZ, 2, [2000])
        + _setting(vz.YAMAUCHI, 10, [300])
        + _setting(vz.VAZQUEZ, 10, [330])
    )
    verdict = vz.verdict_incremental(_records(rows))
    assert verdict.outcome == "reproduced"
    assert "2.00 -> 1.10" in verdict.evidence
    worse = [
        dict(r, ticks=900) if r["robots"] == 10 and r["strategy"] == vz.VAZQUEZ else r for r in rows
    ]
    assert vz.verdict_incremental(_records(worse)).outcome == "not reproduced"


def test_verdict_network() -> None:
    runs = _runs(_setting(vz.VAZQUEZ, 4, [100, 100]) + _setting(vz.YAMAUCHI, 4, [100, 100]))

    def shares(vazquez_second: list[int]) -> pa.Table:
        return pa.table(
            {
                "run_id": ["r0"] * 10 + ["r1"] * 10 + ["r2"] * 2 + ["r3"] * 2,
                "subnetworks": [1] * 10 + vazquez_second + [2, 2] + [1, 2],
            }
        )

    verdict = vz.verdict_network(vz.run_records(runs, shares([1] * 10)))
    assert verdict.outcome == "reproduced"
    assert "1.00-1.00" in verdict.evidence and "Yamauchi 0.25-0.25" in verdict.evidence
    partly = vz.verdict_network(vz.run_records(runs, shares([1] * 8 + [2] * 2)))  # mean 0.9
    assert partly.outcome == "partly"
    split = vz.verdict_network(vz.run_records(runs, shares([1] * 2 + [2] * 8)))  # mean 0.6
    assert split.outcome == "not reproduced"
    assert vz.verdict_network(vz.run_records(runs)).outcome == "not reproduced"


def test_verdicts_on_nothing_still_give_one_line_per_claim() -> None:
    lines = [v.line() for v in vz.verdicts([])]
    assert len(lines) == N_CLAIMS
    assert all(VERDICT_LINE.match(line) for line in lines)
