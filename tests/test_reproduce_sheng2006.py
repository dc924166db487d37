"""Reproduction of Sheng et al. (2006): the quick run end to end, the helpers on
hand-made tables, and the full run (slow)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pyarrow as pa
import pytest

from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import sheng2006 as repro
from mrexplore.experiments.stats import summarize_metric

FIGURES = (
    "fig11_diameter.png",
    "fig11_diameter_curve.png",
    "fig12_time.png",
    "fig13_distance.png",
    "table4_bytes.png",
    "fig17a_time.png",
    "fig17b_distance.png",
)
N_CLAIMS = 11  # Fig. 11: 1, Figs. 12-13: 5, Table 4: 2, Fig. 17: 3
VERDICT = re.compile(r"^- \*\*(reproduced|partly|not reproduced)\*\*: (.+)$")


def _check_report(out: Path) -> str:
    text = (out / "report.md").read_text()
    assert text.startswith("# Reproduction: Sheng et al. (2006)")
    assert repro.CITATION in text
    verdicts_part = text.split("## Verdicts", 1)[1]
    lines = [line for line in verdicts_part.splitlines() if line.startswith("- **")]
    assert len(lines) == N_CLAIMS
    for line in lines:
        assert VERDICT.match(line), line
    # The paper's Table 4, as typed in, beside ours.
    for without, with_, sd_without, sd_with in repro.PAPER_TABLE4.values():
        for number in (without, with_, sd_without, sd_with):
            assert repro._fmt(number) in text
    for claim in (repro.PAPER_FIG11, repro.PAPER_FIG12, repro.PAPER_FIG13, repro.PAPER_FIG17):
        assert claim in text
    for name in FIGURES:
        assert (out / name).stat().st_size > 1000, name
        assert f"]({name})" in text
    return text


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("sheng2006-quick")
    assert main(["reproduce", "sheng2006", "--quick", "--out", str(out), "--no-progress"]) == 0
    return out


def test_quick_reproduction_writes_the_report(quick_run: Path) -> None:
    text = _check_report(quick_run)
    assert "**Quick run**" in text.split("## Settings")[0]
    for name in ("fig11", "fig12_13_random", "fig12_13_bidding", "table4", "fig17"):
        assert (quick_run / name / "runs").is_dir()
    assert "failed" not in re.findall(r"\d+ runs (\w+)", text)


def test_registered() -> None:
    reproduction = get_reproduction("sheng2006")
    assert reproduction is repro.REPRODUCTION
    assert reproduction.id == "sheng2006"


def test_full_sweeps_have_the_papers_run_counts() -> None:
    sweeps = repro.sweeps(False)
    counts = {name: len(sweep) for name, sweep in sweeps.items()}
    assert counts == {
        "fig11": 2 * 8,  # two cases, eight runs
        "fig12_13_random": 8 * 6,  # 1..8 robots, six runs
        "fig12_13_bidding": 2 * 8 * 6,
        "table4": 2 * 3 * 20,  # with/without tracking, three w3, 20 runs
        "fig17": 2 * 6 * 6,  # two cases, r_c 4..24, six runs
    }
    for sweep in sweeps.values():
        for spec in sweep.runs():
            scenario = spec.scenario
            assert scenario.map == "sheng40"
            assert scenario.sensor_range == 4
            assert scenario.sensing == "arrival"
            assert scenario.coverage_threshold == 1.0
    table4 = sweeps["table4"].runs()
    assert {s.scenario.sharing for s in table4} == {"sheng-sync", "full"}
    assert {s.scenario.robots for s in table4} == {5}
    fig17 = sweeps["fig17"].runs()
    assert sorted({s.scenario.comm_range for s in fig17}) == [4, 8, 12, 16, 20, 24]
    assert {s.scenario.comm_range for s in sweeps["fig11"].runs()} == {16}


def test_quick_sweeps_are_small() -> None:
    total = sum(len(sweep) for sweep in repro.sweeps(True).values())
    assert total <= 30


# ------------------------------------------------------------------ helpers


def _runs(**columns: list[object]) -> pa.Table:
    return pa.table(columns)


def test_case_of() -> None:
    assert repro.case_of("random-frontier", None) == repro.CASE_RANDOM
    assert repro.case_of("sheng-bidding", 0.0) == repro.CASE_WITHOUT
    assert repro.case_of("sheng-bidding", 1.5) == repro.CASE_WITH
    assert repro.case_of("sheng-bidding", None) == repro.CASE_WITH
    assert repro.case_of("sheng-bidding", math.nan) == repro.CASE_WITH


def test_collect_and_paired_skip_failed_runs_and_match_seeds() -> None:
    runs = _runs(
        strategy=["random-frontier"] * 3 + ["sheng-bidding"] * 3,
        param_w3=[None, None, None, 0.0, 0.0, 0.0],
        robots=[2, 2, 2, 2, 2, 2],
        seed=[1, 2, 3, 1, 2, 3],
        status=["complete", "complete", "failed", "complete", "max_ticks", "complete"],
        T100=[100, 120, None, 40, None, 30],
    )
    collected = repro.collect(runs, "T100", "robots")
    assert collected[repro.CASE_RANDOM] == {2: {1: 100.0, 2: 120.0}}
    assert collected[repro.CASE_WITHOUT][2][1] == 40.0
    assert math.isnan(collected[repro.CASE_WITHOUT][2][2])
    stats = repro.summaries(collected)
    assert stats[repro.CASE_WITHOUT][2].n == 2
    assert stats[repro.CASE_WITHOUT][2].n_missing == 1
    difference = repro.paired(collected, repro.CASE_WITHOUT, repro.CASE_RANDOM)[2]
    # seed 1 only: seed 2 is missing on one side, seed 3 failed on the other.
    assert difference.n == 1
    assert difference.mean == -60.0
    assert repro.paired(collected, repro.CASE_WITH, repro.CASE_RANDOM) == {}


def test_concat_rows_fills_missing_columns() -> None:
    random = _runs(strategy=["random-frontier"], seed=[1])
    bidding = _runs(strategy=["sheng-bidding"], seed=[1], param_w3=[0.0])
    both = repro._concat_rows(random, bidding)
    assert both.column("param_w3").to_pylist() == [None, 0.0]
    cases = repro.collect(
        both.append_column("robots", pa.array([1, 1]))
        .append_column("status", pa.array(["complete"] * 2))
        .append_column("T100", pa.array([5, 6])),
        "T100",
        "robots",
    )
    assert set(cases) == {repro.CASE_RANDOM, repro.CASE_WITHOUT}


def test_sync_bytes_counts_only_merge_messages() -> None:
    full = {
        "sharing": "full",
        "bytes_by_type_map_full": 1000,
        "bytes_by_type_map_multicast": 500,
        "bytes_by_type_map_update": 9999,
        "bytes_by_type_bid": 77,
    }
    sync = {
        "sharing": "sheng-sync",
        "bytes_by_type_seq_table": 37,
        "bytes_by_type_map_sync": 200,
        "bytes_by_type_map_multicast": None,
        "bytes_by_type_map_delta": 9999,
    }
    assert repro.sync_bytes(full) == 1500.0
    assert repro.sync_bytes(sync) == 237.0
    assert repro.broadcast_bytes(full) == 9999.0
    assert repro.broadcast_bytes(sync) == 9999.0
    with pytest.raises(ValueError, match="polygon"):
        repro.sync_bytes({"sharing": "polygon"})


def test_table4_rows() -> None:
    def row(w3: float, sharing: str, seed: int, sync: int, ticks: int) -> dict[str, object]:
        base: dict[str, object] = {
            "strategy": "sheng-bidding",
            "param_w3": w3,
            "sharing": sharing,
            "seed": seed,
            "status": "complete",
            "ticks": ticks,
            "total_distance": 50.0,
            "partition_events": seed,
            "bytes_by_type_map_multicast": 0,
            "bytes_by_type_map_full": None,
            "bytes_by_type_map_update": None,
            "bytes_by_type_map_sync": None,
            "bytes_by_type_map_delta": None,
        }
        if sharing == "full":
            base |= {"bytes_by_type_map_full": sync, "bytes_by_type_map_update": 10}
        else:
            base |= {"bytes_by_type_map_sync": sync, "bytes_by_type_map_delta": 11}
        return base

    runs = pa.Table.from_pylist(
        [
            row(0.0, "full", 1, 1000, 100),
            row(0.0, "full", 2, 3000, 100),
            row(0.0, "sheng-sync", 1, 100, 100),
            row(0.0, "sheng-sync", 2, 300, 101),  # a different exploration
            row(2.0, "full", 1, 800, 90),
            row(2.0, "sheng-sync", 1, 100, 90),
        ]
    )
    rows = repro.table4_rows(runs)
    assert [r.w3 for r in rows] == [0.0, 2.0]
    first = rows[0]
    assert (first.without.mean, first.with_.mean, first.ratio) == (2000.0, 200.0, 10.0)
    assert (first.identical_pairs, first.pairs) == (1, 2)
    assert first.broadcast.mean == 11.0
    assert first.partitions.mean == 1.5
    assert rows[1].ratio == 8.0


# -------------------------------------------------------------------- rules


def _s(*values: float) -> repro.Summary:
    return summarize_metric(list(values))


def test_fig11_rule() -> None:
    assert repro.fig11_outcome(_s(-2.0, -3.0, -2.5)) == "reproduced"
    assert repro.fig11_outcome(_s(-2.0, 3.0, -2.5)) == "partly"
    assert repro.fig11_outcome(_s(2.0, 3.0)) == "not reproduced"
    assert repro.fig11_outcome(_s()) == "not reproduced"


def test_lower_rule() -> None:
    significant, noisy, higher = _s(-5.0, -6.0, -7.0), _s(-4.0, 3.0, -2.0), _s(4.0, 5.0)
    assert repro.lower_outcome({1: significant, 2: noisy}) == "reproduced"
    assert repro.lower_outcome({1: noisy, 2: noisy, 3: significant}) == "partly"
    assert repro.lower_outcome({1: significant, 2: higher}) == "partly"
    assert repro.lower_outcome({1: significant, 2: higher, 3: higher}) == "not reproduced"
    assert repro.lower_outcome({}) == "not reproduced"


def test_decreasing_rule() -> None:
    assert repro.decreasing_outcome({"a": {1: 9.0, 2: 5.0}, "b": {1: 8.0, 2: 7.0}}) == (
        "reproduced"
    )
    assert repro.decreasing_outcome({"a": {1: 9.0, 2: 5.0, 3: 6.0}}) == "partly"
    assert repro.decreasing_outcome({"a": {1: 9.0, 2: 5.0}, "b": {1: 8.0, 2: 9.0}}) == (
        "not reproduced"
    )


def _row4(w3: float, without: float, with_: float) -> repro.Table4Row:
    return repro.Table4Row(w3, _s(without), _s(with_), _s(1.0), _s(1.0), 1, 1)


def test_table4_rules() -> None:
    # Paper ratios 4.7, 5.6, 8.7: within a factor 2 -> reproduced.
    close = [_row4(0.0, 5000, 1000), _row4(1.0, 3000, 500), _row4(2.0, 2000, 200)]
    assert repro.table4_tracking_outcome(close) == "reproduced"
    assert repro.table4_w3_outcome(close) == "reproduced"
    far = [_row4(0.0, 50000, 1000), _row4(1.0, 3000, 500), _row4(2.0, 2000, 200)]
    assert repro.table4_tracking_outcome(far) == "partly"
    inverted = [_row4(0.0, 500, 1000), *close[1:]]
    assert repro.table4_tracking_outcome(inverted) == "not reproduced"
    ends_only = [_row4(0.0, 5000, 1000), _row4(1.0, 6000, 1200), _row4(2.0, 2000, 200)]
    assert repro.table4_w3_outcome(ends_only) == "partly"
    rising = [_row4(0.0, 1000, 100), _row4(1.0, 2000, 200), _row4(2.0, 3000, 300)]
    assert repro.table4_w3_outcome(rising) == "not reproduced"


def test_fig17_rules() -> None:
    assert repro.spearman([4, 8, 12], [3.0, 2.0, 1.0]) == -1.0
    assert repro.spearman([4, 8, 12], [2.0, 2.0, 2.0]) == 0.0
    assert repro.falls_with_range({4: 300.0, 8: 280.0, 16: 250.0, 24: 260.0})
    assert not repro.falls_with_range({4: 300.0, 16: 350.0, 24: 290.0})
    below, above = repro.gains_around({4: 400.0, 16: 280.0, 24: 272.0})
    assert (below, above) == (10.0, 1.0)
    assert all(math.isnan(g) for g in repro.gains_around({4: 1.0, 8: 2.0}))
    assert repro.total_gain({4: 400.0, 24: 250.0}) == 150.0
    assert [repro.count_outcome(k) for k in (2, 1, 0)] == [
        "reproduced",
        "partly",
        "not reproduced",
    ]


# --------------------------------------------------------------------- full


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    assert main(["reproduce", "sheng2006", "--out", str(tmp_path), "--no-progress"]) == 0
    text = _check_report(tmp_path)
    assert "**Quick run**" not in text
    assert "failed" not in re.findall(r"\d+ runs (\w+)", text)
