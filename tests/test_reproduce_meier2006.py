"""The meier2006 reproduction: the quick run through the CLI (one interpretation), its
metrics and tables on hand-made rows, and the full run (slow); its rules are tested in
``test_claims``."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from mrexplore.cli import main
from mrexplore.comm.bytes import HEADER_BYTES, SCAN_BEAM_BYTES
from mrexplore.experiments.reproduce import claims as c
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import meier2006 as m
from mrexplore.experiments.reproduce.base import interpret, write_report

OUTCOMES = ("reproduced", "partly", "not reproduced")
FIGURES = (
    "fig6_exploration_time.png",
    "fig7_traffic.png",
    "table1_package_shares.png",
    "table2_approximation_error.png",
)
READING = "every-target-discounts"  # re-runs only the meier-polygon sweeps


def _check_report(out: Path, *, quick: bool) -> str:
    text = (out / "report.md").read_text()
    assert text.startswith(f"# Reproduction: {m.TITLE}")
    assert m.CITATION in text
    assert ("**Quick run**" in text) is quick
    lines = [x for x in text.split("## Verdicts", 1)[1].splitlines() if x.startswith("- **")]
    assert len(lines) == len(m.CLAIMS) == 10
    for line in lines:
        outcome = re.match(r"- \*\*(.+?)\*\*: ", line)
        assert outcome is not None and outcome.group(1) in OUTCOMES, line
    # The paper's numbers are in the report: Table 1, Table 2, the §5.2 text.
    for number in ("31.12", "78.95", "21.05", "8.92", "0.86", "0.19", "200,000", "7,500"):
        assert number in text, number
    for name in FIGURES:
        assert (out / name).stat().st_size > 1000, name
        assert f"]({name})" in text
    return text


# ------------------------------------------------------------------- quick run


def test_quick_reproduction_through_cli(tmp_path: Path) -> None:
    argv = ["reproduce", "meier2006", "--quick", "--out", str(tmp_path), "--no-progress"]
    assert main([*argv, "--interpretations", READING]) == 0
    text = _check_report(tmp_path, quick=True)
    for name in m.REPRODUCTION.sweeps(True):
        assert (tmp_path / name / "runs").is_dir()
    robustness = text.split("## Robustness to the readings of the paper", 1)[1]
    assert f"| claim | default | {READING} | summary |" in robustness
    for claim in m.CLAIMS:
        assert re.search(
            rf"^\| `{claim.id}` \| .* \| (robust|\*\*fragile\*\*.*) \|$", robustness, re.M
        )
    readings = tmp_path / "readings" / READING
    assert (readings / "quick_polygon").is_dir() and (
        readings / "quick_baselines-meier-polygon"
    ).is_dir()
    assert not (readings / "quick_baselines-burgard").exists()


def test_registered() -> None:
    reproduction = get_reproduction("meier2006")
    assert reproduction is m.REPRODUCTION
    assert reproduction.id == "meier2006"
    assert {i.name for i in reproduction.interpretations} == {
        "epsilon-half-cell",
        "replan-when-explored",
        "coordinator-assigns-requesting",
        "discount-within-range",
        "every-target-discounts",
        "raw-path-cost",
    }


def test_sweeps_full_and_quick() -> None:
    full = m.REPRODUCTION.sweeps(False)
    assert list(full) == [
        f"{key}_{kind}"
        for key in ("unstructured3", "corridor5", "two_robots")
        for kind in ("polygon", "baselines-burgard", "baselines-meier-polygon")
    ]
    polygon = full["unstructured3_polygon"].runs()
    assert {spec.scenario.sharing_params["split_rate"] for spec in polygon} == set(m.PAPER_TABLE1)
    assert all(s.scenario.robots == 3 and s.scenario.map == "unstructured" for s in polygon)
    assert all(spec.scenario.map_seed == m.MAP_SEED for spec in polygon)
    assert {s.scenario.robots for s in full["corridor5_polygon"].runs()} == {5}
    assert {s.scenario.robots for s in full["two_robots_baselines-burgard"].runs()} == {2}
    for strategy in ("burgard", "meier-polygon"):
        runs = full[f"corridor5_baselines-{strategy}"].runs()
        assert {(s.scenario.strategy, s.scenario.sharing) for s in runs} == {(strategy, "full")}
    quick = m.REPRODUCTION.sweeps(True)
    assert set(quick) == {
        "quick_polygon",
        "quick_baselines-burgard",
        "quick_baselines-meier-polygon",
    }
    maps = {(s.scenario.map, s.scenario.robots) for s in quick["quick_polygon"].runs()}
    assert maps == {("unstructured", 3), ("corridor", 3)}
    assert sum(len(s) for s in quick.values()) < sum(len(s) for s in full.values()) / 5


def test_quick_sweeps_are_the_runs_of_before() -> None:
    """The split-rate sweep is unchanged; the baselines are the old sweep split by strategy."""
    polygon = m.REPRODUCTION.sweeps(True)["quick_polygon"]
    assert polygon.fixed["strategy"] == "meier-polygon" and polygon.fixed["max_ticks"] == 1000
    assert polygon.grid == {
        "map": ["unstructured", "corridor"],
        "share": {"split_rate": [0.1, 1.0, 10.0]},
    }
    assert polygon.seeds == [1]


def test_the_tolerance_reading_changes_the_polygon_runs_only_and_keeps_their_rates() -> None:
    """§5.1 splits until "the approximation error is equal to zero" (``epsilon`` 0); the
    reading ``epsilon-half-cell`` sets the sharing parameter of the polygon sweeps only."""
    reading = next(i for i in m.INTERPRETATIONS if i.name == "epsilon-half-cell")
    assert reading.share == {"epsilon": 0.5} and not reading.set
    for name, sweep in m.REPRODUCTION.sweeps(True).items():
        changed = interpret(sweep, reading)
        assert (changed is not None) == name.endswith("_polygon"), name
        if changed is not None:
            shares = [spec.scenario.sharing_params for spec in changed.runs()]
            assert {s["epsilon"] for s in shares} == {0.5}
            assert {s["split_rate"] for s in shares} == {0.1, 1.0, 10.0}
    default = m.REPRODUCTION.sweeps(True)["quick_polygon"].runs()[0].scenario
    assert "epsilon" not in default.sharing_params  # the mechanism's default, 0


# ------------------------------------------------------------ paper's numbers


def test_paper_table1_rows_sum_to_100_and_trend_as_the_text_says() -> None:
    for rate, row in m.PAPER_TABLE1.items():
        assert set(row) == set(m.PACKAGE_TYPES)
        assert sum(row.values()) == pytest.approx(100.0, abs=0.1), rate
    rates = list(m.PAPER_TABLE1)
    signs = {
        t: c.trend_sign(rates, [m.PAPER_TABLE1[r][t] for r in rates], 0.3) for t in m.PACKAGE_TYPES
    }
    assert signs == {"TPT": -1, "ES": 1, "B": -1, "VP": 1, "EP": -1}


# -------------------------------------------------------------- metrics, tables


def _run(strategy: str, sharing: str, seed: int, ticks: int, **more: object) -> dict[str, object]:
    reached = more.pop("reached", True)
    return {"map": "unstructured", "robots": 2, "strategy": strategy, "sharing": sharing,
            "seed": seed, "ticks": ticks, "T99": ticks if reached else None,
            "status": "complete" if reached else "max_ticks", **more}  # fmt: skip


def _rows() -> list[dict[str, object]]:
    """Hand-made run rows: two split rates and the two baselines, two seeds each, 2 robots."""
    polygon = ("meier-polygon", "polygon")
    rows = [
        _run(*polygon, 1, 99, share_split_rate=0.1, bytes_total=1000, bytes_by_type_TPT=200,
             bytes_by_type_ES=300, polygon_approximation_error_mean="[0.1, 0.3]"),
        _run(*polygon, 2, 109, share_split_rate=0.1, bytes_total=1200, bytes_by_type_TPT=200,
             bytes_by_type_ES=400, polygon_approximation_error_mean="[0.2, null]"),
        _run(*polygon, 1, 89, share_split_rate=10.0, bytes_total=5000, bytes_by_type_TPT=100,
             bytes_by_type_ES=4000),
        _run(*polygon, 2, 3000, share_split_rate=10.0, bytes_total=6000, bytes_by_type_TPT=100,
             bytes_by_type_ES=5000, reached=False),
    ]  # fmt: skip
    for seed, ticks in ((1, 79), (2, 89)):
        rows.append(
            _run("burgard", "full", seed, ticks, bytes_total=3000, bytes_by_type_status=150,
                 bytes_by_type_assign=130)
        )  # fmt: skip
        rows.append(
            _run("meier-polygon", "full", seed, ticks + 5, bytes_total=2100, bytes_by_type_TPT=100)
        )
    return rows


def test_metrics_of_a_run_row() -> None:
    rows = _rows()
    shares = m.package_shares(rows[0])
    assert shares["TPT"] == pytest.approx(20.0) and shares["ES"] == pytest.approx(30.0)
    assert shares["B"] == shares["VP"] == shares["EP"] == 0.0
    assert shares["other"] == pytest.approx(50.0)
    assert all(math.isnan(v) for v in m.package_shares({"bytes_total": 0}).values())
    assert m.METRICS["map_bytes"](rows[0]) == 800  # polygon: all but TPT
    assert m.METRICS["map_bytes"](rows[4]) == 3000 - 150 - 130  # burgard: all but status/assign
    assert m.METRICS["map_bytes"](rows[5]) == 2000  # meier-polygon + full: all but TPT
    assert m.team_error(rows[0]["polygon_approximation_error_mean"]) == pytest.approx(20.0)
    assert m.team_error("[0.2, null]") == pytest.approx(20.0)
    assert math.isnan(m.team_error("[null]")) and math.isnan(m.team_error(None))
    per_scan = HEADER_BYTES + 360 * SCAN_BEAM_BYTES
    assert m.centralised_raw_bytes(rows[4]) == 150 + 130 + 2 * 80 * per_scan
    per_scan_181 = HEADER_BYTES + 181 * SCAN_BEAM_BYTES
    assert m.centralised_raw_bytes(rows[4], 181) == 150 + 130 + 2 * 80 * per_scan_181
    assert m.METRICS["rate"](rows[0]) == pytest.approx(1000 / (100 * 2))
    assert math.isnan(m.METRICS["time"](rows[3]))  # never reached 99%: no exploration time
    assert [m.arm_of(r) for r in rows[:6:2]] == ["SR 0.1", "SR 10", "centralised"]
    assert m.arm_of(rows[5]) == "no-approximation"


def test_run_values_and_claim_tables() -> None:
    values = m.run_values(_rows(), quick=False)
    cell = ("unstructured", 2)
    assert set(values["bytes"][cell]) == {
        "SR 0.1",
        "SR 10",
        "centralised",
        "no-approximation",
        "raw",
        "raw-181",
    }
    assert values["bytes"][cell]["raw"][1] == 150 + 130 + 2 * 80 * 727
    assert set(values["error"][cell]) == {"SR 0.1"} | {"SR 10"}  # polygon runs only
    assert values["error"][cell]["SR 0.1"] == {1: pytest.approx(20.0), 2: pytest.approx(20.0)}
    assert values["reached"][cell]["SR 10"] == {1: 1.0, 2: 0.0}
    tables = m.claim_tables(values, quick=False)
    assert tables["traffic"] == {cell: values["bytes"][cell]}  # the Fig. 7 setting: 2 robots
    assert tables["time"] == {} and tables["error"] == {("unstructured", 3): {}}
    assert set(tables["shares"]) == {(t,) for t in (*m.PACKAGE_TYPES, "other")}


def test_report_without_runs(tmp_path: Path) -> None:
    text = write_report(m.REPRODUCTION, {"default": {}}, tmp_path, quick=True).read_text()
    assert "## Verdicts" in text and "holds in 0/0 cells" in text
    for name in FIGURES:  # a figure with no panel is not drawn, nor linked
        assert (tmp_path / name).exists() is (f"]({name})" in text), name


def test_every_claim_says_how_it_is_judged() -> None:
    ids = [claim.id for claim in m.CLAIMS]
    assert ids == [
        "decreasing",
        "converge",
        "slower",
        "advantage",
        "similar",
        "tpt",
        "trends",
        "error",
        "fragment",
        "cheaper",
    ]
    for claim in m.CLAIMS:
        assert (
            claim.rule_text()
            and claim.sentence
            and claim.metric
            in (
                "time",
                "shares",
                "error",
                "traffic",
                "map_bytes",
            )
        )


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
    assert main(["reproduce", "meier2006", "--out", str(tmp_path), "--no-progress"]) == 0
    text = _check_report(tmp_path, quick=False)
    assert "SR 25" in text
