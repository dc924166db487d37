"""Reproduction of Sheng et al. (2006): the quick run end to end (one reading of the
paper besides the default), the run values on hand-made tables, and the full run
(slow); its rules are tested in ``test_claims``."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from conftest import quick_reproduction
from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import sheng2006 as repro
from mrexplore.experiments.reproduce.base import interpret
from mrexplore.experiments.reproduce.claims import fmt
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
    return quick_reproduction(tmp_path_factory, "sheng2006", READING)


def test_quick_reproduction_writes_the_report(quick_run: Path) -> None:
    text = _check_report(quick_run)
    assert "**Quick run**" in text.split("## Settings")[0]
    for name in repro.REPRODUCTION.sweeps(True):
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
    assert [c.id for c in reproduction.claims] == [words[0] for words in repro.CLAIM_WORDS]


def test_full_sweeps_have_the_papers_run_counts() -> None:
    sweeps = repro.REPRODUCTION.sweeps(False)
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
    # "by varying the starting time of each robot": the same cells, start ticks 0..16
    assert len({str(s.scenario.start) for s in table4}) == 1
    assert {s.scenario.start_delay for s in table4} == {16}
    assert {s.scenario.start_delay for s in sweeps["fig11"].runs()} == {0}
    fig17 = sweeps["fig17"].runs()
    assert sorted({s.scenario.comm_range for s in fig17}) == [4, 8, 12, 16, 20, 24]
    assert {s.scenario.comm_range for s in sweeps["fig11"].runs()} == {16}
    assert sum(len(sweep) for sweep in repro.REPRODUCTION.sweeps(True).values()) == 28


def test_every_interpretation_changes_whole_sweeps_and_its_strategies_only() -> None:
    for reading in repro.INTERPRETATIONS:
        for name, sweep in repro.REPRODUCTION.sweeps(True).items():
            changed = interpret(sweep, reading)  # raises on a sweep it changes in part
            strategy = sweep.fixed["strategy"]
            # Table 4's start readings change Table 4 only (the others start so already).
            table4_only = reading.name in ("same-start-times", "varied-places")
            hit = reading.applies_to(strategy) and (name == "table4" or not table4_only)
            assert (changed is not None) == hit, (reading, name)
            if changed is not None:
                for spec in changed.runs():
                    assert reading.set.items() <= spec.scenario.params.items()
                    assert all(getattr(spec.scenario, k) == v for k, v in reading.scenario.items())
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
    assert repro.case_of({"strategy": "sheng-bidding"}) == repro.CASE_WITH  # w3 not set


def test_same_run_counts_cells_at_five_or_one_byte() -> None:
    row = {"sync_bytes_with_tracking": 57, "sync_cells_with_tracking": 10}
    assert (repro.same_run("with")(row), repro.same_run("with", 1)(row)) == (57.0, 17.0)


# --------------------------------------------------------------------- full


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    argv = ["reproduce", "sheng2006", "--out", str(tmp_path), "--no-progress"]
    assert main([*argv, "--interpretations", "none"]) == 0
    text = _check_report(tmp_path)
    assert "**Quick run**" not in text
