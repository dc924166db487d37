"""Reproduction of Sheng et al. (2006): the quick run end to end (one reading of the
paper besides the default), the run values and the rule objects on hand-made tables,
and the full run (slow)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import sheng2006 as repro
from mrexplore.experiments.reproduce.base import interpret
from mrexplore.experiments.reproduce.claims import (
    FallAlong,
    FallsFasterBelow,
    FallsLess,
    Monotone,
    PairedLower,
    PairedMostlyLower,
    RankTrend,
    RatioWithinFactor,
    WithMeans,
    fmt,
)
from mrexplore.experiments.store import Store

FIGURES = (
    "fig11_diameter.png",
    "fig12_time.png",
    "fig13_distance.png",
    "table4_bytes.png",
    "fig17a_time.png",
    "fig17b_distance.png",
)
N_CLAIMS = 11  # Fig. 11: 1, Figs. 12-13: 5, Table 4: 2, Fig. 17: 3
VERDICT = re.compile(r"^- \*\*(reproduced|partly|not reproduced)\*\*: (.+)$")
READING = "both-replan-when-explored"


def _check_report(out: Path) -> str:
    text = (out / "report.md").read_text()
    assert text.startswith("# Reproduction: Sheng et al. (2006)")
    assert repro.CITATION in text
    head = text.split("## Settings")[0]
    assert "Runs: complete" in head and "failed" not in head
    verdicts = text.split("## Verdicts", 1)[1].split("## Robustness", 1)[0]
    lines = [line for line in verdicts.splitlines() if line.startswith("- **")]
    assert len(lines) == N_CLAIMS
    for line, claim in zip(lines, repro.CLAIMS, strict=True):
        assert VERDICT.match(line), line
        assert f"{claim.where}: {claim.statement}" in line
        assert f'paper: "{claim.sentence}")' in line
    # The paper's Table 4, as typed in, beside ours.
    for numbers in repro.PAPER_TABLE4.values():
        for number in numbers:
            assert fmt(number) in text
    for name in FIGURES:
        assert (out / name).stat().st_size > 1000, name
        assert f"]({name})" in text
    return text


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("sheng2006-quick")
    argv = ["reproduce", "sheng2006", "--quick", "--out", str(out), "--no-progress"]
    # one interpretation keeps the suite short (it re-runs the 28 quick runs)
    assert main([*argv, "--interpretations", READING]) == 0
    return out


def test_quick_reproduction_writes_the_report(quick_run: Path) -> None:
    text = _check_report(quick_run)
    assert "**Quick run**" in text.split("## Settings")[0]
    for name in repro.sweeps(True):
        assert (quick_run / name / "runs").is_dir()
        assert (quick_run / "readings" / READING / name / "runs").is_dir()
    robustness = text.split("## Robustness to the readings of the paper", 1)[1]
    assert f"| claim | default | {READING} | summary |" in robustness
    for claim in repro.CLAIMS:
        assert re.search(
            rf"^\| `{claim.id}` \| .* \| (robust|\*\*fragile\*\*.*) \|$", robustness, re.M
        )
    # The reading changed the runs it names, both arms alike.
    store = Store(quick_run / "readings" / READING / "fig12_13_random")
    column = store.query("SELECT param_replan_on_target_explored FROM runs").column(0)
    assert set(column.to_pylist()) == {True}


def test_registered() -> None:
    reproduction = get_reproduction("sheng2006")
    assert reproduction is repro.REPRODUCTION
    assert [c.id for c in reproduction.claims] == list(repro.STATEMENTS)


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
    assert sum(len(sweep) for sweep in repro.sweeps(True).values()) == 28


def test_every_interpretation_changes_whole_sweeps_and_its_strategies_only() -> None:
    for reading in repro.INTERPRETATIONS:
        for name, sweep in repro.sweeps(True).items():
            changed = interpret(sweep, reading)  # raises on a sweep it changes in part
            strategy = sweep.fixed["strategy"]
            assert (changed is not None) == (strategy in reading.strategies), (reading, name)
            if changed is not None:
                for spec in changed.runs():
                    assert reading.set.items() <= spec.scenario.params.items()
        assert '"' in reading.sentence and reading.sentence.startswith("§")


# ------------------------------------------------------------------ run values


def _row(experiment: str, seed: int, **columns: object) -> dict[str, object]:
    return {"experiment": experiment, "seed": seed, "status": "complete", **columns}


def _tables(rows: list[dict[str, object]]) -> dict[str, repro.Values]:
    import pyarrow as pa

    class Fake:
        def __init__(self, table: list[dict[str, object]]) -> None:
            names = list(dict.fromkeys(k for row in table for k in row))
            self.table = pa.Table.from_pylist([{k: row.get(k) for k in names} for row in table])

        def query(self, sql: str) -> pa.Table:
            return self.table

    by_experiment: dict[str, list[dict[str, object]]] = {}
    for row in rows:
        by_experiment.setdefault(str(row.pop("experiment")), []).append(row)
    stores = {name: Fake(rs) for name, rs in by_experiment.items()}
    return repro.tables(stores, quick=True)  # type: ignore[arg-type]  # duck-typed stores


def test_tables_by_case_with_missing_times_and_failed_runs() -> None:
    fig = "fig12_13_bidding"
    rows = [
        _row(
            "fig12_13_random", 1, strategy="random-frontier", robots=2, T100=100, total_distance=9.0
        ),
        _row(fig, 1, strategy="sheng-bidding", param_w3=0.0, robots=2, T100=40, total_distance=5.0),
        _row(
            fig, 2, strategy="sheng-bidding", param_w3=0.0, robots=2, T100=None, total_distance=6.0
        ),
        {**_row(fig, 3, strategy="sheng-bidding", param_w3=0.0, robots=2), "status": "failed"},
        _row(fig, 1, strategy="sheng-bidding", param_w3=1.5, robots=1, T100=50, total_distance=7.0),
    ]
    values = _tables(rows)
    assert values["time"][(2,)][repro.CASE_RANDOM] == {1: 100.0}
    assert values["time"][(2,)][repro.CASE_WITHOUT][1] == 40.0
    assert math.isnan(values["time"][(2,)][repro.CASE_WITHOUT][2])  # never completed: missing
    assert 3 not in values["distance"][(2,)][repro.CASE_WITHOUT]  # failed: left out
    assert (1,) in values["time"] and (1,) not in values["time_teams"]


def test_table4_values_count_only_merge_messages() -> None:
    common = {"strategy": "sheng-bidding", "param_w3": 0.0, "ticks": 90, "total_distance": 50.0}
    full = {"sharing": "full", "bytes_by_type_map_full": 1000, "bytes_by_type_map_multicast": 500}
    sync = {"sharing": "sheng-sync", "bytes_by_type_seq_table": 37, "bytes_by_type_map_sync": 200}
    rows = [
        _row("table4", 1, **common, **full, bytes_by_type_map_update=9999, partition_events=3),
        _row("table4", 1, **common, **sync, bytes_by_type_map_delta=11, partition_events=4),
    ]
    table = _tables(rows)["table4"][("w3=0",)]
    assert table[repro.WITHOUT] == {1: 1500.0} and table[repro.WITH] == {1: 237.0}
    assert table[repro.PARTITIONS] == {1: 4.0} and table[repro.BROADCAST] == {1: 11.0}
    assert repro.sync_bytes({"sharing": "full", "bytes_by_type_map_full": 7}) == 7.0
    with pytest.raises(KeyError, match="polygon"):
        repro.sync_bytes({"sharing": "polygon"})


def test_case_of() -> None:
    assert repro.case_of({"strategy": "random-frontier"}) == repro.CASE_RANDOM
    assert repro.case_of({"strategy": "sheng-bidding", "param_w3": 0.0}) == repro.CASE_WITHOUT
    assert repro.case_of({"strategy": "sheng-bidding", "param_w3": math.nan}) == repro.CASE_WITH


# ------------------------------------------------------------------ rule objects


def _series(**by_arm: dict[object, float]) -> dict[tuple[object, ...], dict[str, dict[int, float]]]:
    """``arm={x: mean}`` -> values with one seed per cell ``(x,)``."""
    out: dict[tuple[object, ...], dict[str, dict[int, float]]] = {}
    for arm, means in by_arm.items():
        for x, mean in means.items():
            out.setdefault(x if isinstance(x, tuple) else (x,), {})[arm] = {1: mean}
    return out


def test_paired_mostly_lower_needs_every_mean_and_half_the_intervals() -> None:
    sure = {(2,): {"a": {1: 1.0, 2: 2.0, 3: 1.5}, "b": {1: 5.0, 2: 6.0, 3: 5.0}}}
    noisy = {(5,): {"a": {1: 1.0, 2: 5.0}, "b": {1: 2.0, 2: 5.5}}}
    rule = PairedMostlyLower()
    outcome, text = rule.judge({**sure, **noisy}, "a", ["b"], 0)
    assert outcome == "reproduced"  # lower in 2/2, CI below 0 in 1/2
    assert (
        text
        == "`a` - `b` 2:-4 [-5, -3], 5:-1 [-4, 2]; mean below 0 in 2/2 cells, 95% CI below 0 in 1/2"
    )
    assert rule.judge(noisy, "a", ["b"], 0)[0] == "partly"  # no interval below 0
    assert rule.judge({(2,): {"a": {1: 3.0}, "b": {1: 2.0}}}, "a", ["b"], 0)[0] == "not reproduced"
    assert rule.judge({}, "a", ["b"], 0)[0] == "not reproduced"
    assert "at least half" in rule.describe("a", "b", "T100")


def test_monotone_every_step_or_only_the_ends() -> None:
    values = _series(a={1: 9.0, 2: 5.0, 3: 4.0}, b={1: 8.0, 2: 6.0, 3: 7.0})
    assert Monotone("falls").judge(values, "a", ["b"], 0) == (
        "partly",
        "`a` 1:9, 2:5, 3:4; `b` 1:8, 2:6, 3:7 x",
    )
    assert Monotone("falls").judge(values, "a", [], 0)[0] == "reproduced"
    assert Monotone("rises").judge(values, "a", [], 0)[0] == "not reproduced"
    assert "`a` / `b` / `c`" in Monotone("falls").describe("a", "b / c", "T100")


def test_ratio_within_factor_of_the_papers() -> None:
    rule = RatioWithinFactor(2, {("w3=0",): 4.7, ("w3=2",): 8.7})
    values = _series(w={"w3=0": 1000.0, "w3=2": 1000.0}, o={"w3=0": 5000.0, "w3=2": 20000.0})
    outcome, text = rule.judge(values, "w", ["o"], 0)
    assert outcome == "partly"  # 20 is more than twice 8.7
    assert text.endswith("w3=2: `o` 20 000 vs `w` 1 000, ratio 20.0 (paper 8.7) x")
    close = _series(w={"w3=0": 1000.0}, o={"w3=0": 5000.0})
    assert rule.judge(close, "w", ["o"], 0)[0] == "reproduced"
    inverted = _series(w={"w3=0": 6000.0}, o={"w3=0": 5000.0})
    assert rule.judge(inverted, "w", ["o"], 0)[0] == "not reproduced"


def test_rank_trend_needs_the_end_and_spearman() -> None:
    values = _series(a={("t", 4): 300.0, ("t", 16): 250.0, ("t", 24): 260.0})
    outcome, text = RankTrend("falls", 0.6).judge(values, "a", [], 0)
    assert (outcome, text) == ("not reproduced", "t: 4:300, 16:250, 24:260 (Spearman rho -0.50) x")
    falling = _series(a={("t", 4): 3.0, ("t", 8): 2.0, ("d", 4): 3.0, ("d", 8): 2.0})
    assert RankTrend("falls").judge(falling, "a", [], 0)[0] == "reproduced"
    assert "<= -0.6" in RankTrend("falls").describe("a", "", "time")


def test_falls_faster_below_the_pivot() -> None:
    values = _series(a={("t", 4): 400.0, ("t", 16): 280.0, ("t", 24): 272.0})
    rule = FallsFasterBelow(16, "cell")
    assert rule.judge(values, "a", [], 2) == (
        "reproduced",
        "t: 10.00 per cell below 16 vs 1.00 above",
    )
    no_pivot = _series(a={("t", 4): 400.0, ("t", 24): 272.0})
    assert rule.judge(no_pivot, "a", [], 2) == (
        "not reproduced",
        "t: - per cell below 16 vs - above x",
    )
    assert "(16 - x_min)" in rule.describe("a", "", "time")


def test_falls_less_counts_a_rise_as_less() -> None:
    values = _series(a={("t", 4): 300.0, ("t", 24): 320.0}, b={("t", 4): 340.0, ("t", 24): 300.0})
    assert FallsLess().judge(values, "a", ["b"], 0) == (
        "reproduced",
        "t: `a` falls by -20 vs `b` by 40",
    )
    assert FallsLess().judge(values, "b", ["a"], 0)[0] == "not reproduced"


def test_fall_along_prints_the_papers_columns_and_the_shown_ones() -> None:
    values = _series(
        w={"w3=0": 13628.0, "w3=1": 12104.0, "w3=2": 12104.0},
        o={"w3=0": 184883.0, "w3=1": 215799.0, "w3=2": 215799.0},
        p={"w3=0": 9.0, "w3=1": 13.0, "w3=2": 13.0},
    )
    rule = FallAlong({"w": (4893.0, 2126.0, 812.0)}, ("p",))
    outcome, text = rule.judge(values, "w", ["o"], 0)
    assert outcome == "not reproduced"
    assert text == (
        "`w` 13 628, 12 104, 12 104 (paper 4 893, 2 126, 812); `o` 184 883, 215 799, 215 799; "
        "first to last: -11% `w`, +17% `o`; `p` 9.0, 13.0, 13.0"
    )
    ends = _series(w={0: 9.0, 1: 9.5, 2: 8.0}, o={0: 9.0, 1: 10.0, 2: 8.5})
    assert rule.judge(ends, "w", ["o"], 0)[0] == "partly"  # both end lower
    assert rule.judge(_series(w={0: 9.0, 1: 8.0}, o={0: 9.0, 1: 9.5}), "w", ["o"], 0)[0] == "partly"


def test_with_means_adds_the_means_to_the_rules_evidence() -> None:
    values = {(4,): {"a": {1: 27.0, 2: 25.0}, "b": {1: 28.0, 2: 29.0}}}
    outcome, text = WithMeans(PairedLower(), 1).judge(values, "a", ["b"], 2)
    assert outcome == "partly"
    assert text.startswith("means 4 `a` 26.0, `b` 28.5; 4 vs `b` -2.50 [")
    assert WithMeans(PairedLower()).describe("a", "b", "d") == PairedLower().describe("a", "b", "d")


# --------------------------------------------------------------------- full


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    argv = ["reproduce", "sheng2006", "--out", str(tmp_path), "--no-progress"]
    assert main([*argv, "--interpretations", "none"]) == 0
    text = _check_report(tmp_path)
    assert "**Quick run**" not in text
