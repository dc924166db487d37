"""Reproduction of the decentralised market paper: the quick run end to end (on
the two catalogue maps and the office), the helpers on hand-made tables, and the
full run (slow)."""

from __future__ import annotations

import re
from pathlib import Path

import pyarrow as pa
import pytest

from conftest import quick_reproduction
from mrexplore.cli import main
from mrexplore.experiments.reproduce import get_reproduction
from mrexplore.experiments.reproduce import market2018 as repro
from mrexplore.experiments.reproduce.claims import paired
from mrexplore.experiments.reproduce.render import bytes_by_type, summaries
from mrexplore.experiments.store import Store

FIGURES = ("time.png", "coordination_bytes.png", "bytes_by_type.png")
N_CLAIMS = 6  # time vs centralised (grid, RRT), dispersion, event data, event time, minimal
VERDICT = re.compile(r"^- \*\*(reproduced|partly|not reproduced)\*\*: (.+)$")


def _check_report(out: Path) -> str:
    text = (out / "report.md").read_text()
    assert text.startswith(f"# Reproduction: {repro.TITLE}")
    assert repro.CITATION in text
    lines = [
        line for line in text.split("## Verdicts", 1)[1].splitlines() if line.startswith("- **")
    ]
    assert len(lines) == N_CLAIMS
    for line in lines:
        assert VERDICT.match(line), line
    for claim in (
        repro.PAPER_QUICK,
        repro.PAPER_DISPERSED,
        repro.PAPER_EVENT_LESS_DATA,
        repro.PAPER_EVENT_FASTER,
        repro.PAPER_MINIMAL,
    ):
        assert claim in text
    assert f"{repro.PAPER_ENVIRONMENTS} environments" in text
    assert "1 to 3 robots" in text
    for name in FIGURES:
        assert (out / name).stat().st_size > 1000, name
        assert f"]({name})" in text
    return text


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return quick_reproduction(tmp_path_factory, "market2018", "coordinator-assigns-requesting")


def test_quick_reproduction_writes_the_report(quick_run: Path) -> None:
    text = _check_report(quick_run)
    assert "**Quick run**" in text.split("## Settings")[0]
    for key in ("intel", "house", "office"):
        for arm in ("centralised", "decentralised", "rrt", "timer"):
            assert (quick_run / f"{key}-{arm}" / "runs").is_dir()
    stores = [Store(path) for path in sorted(quick_run.iterdir()) if (path / "runs").is_dir()]
    maps = {
        m for store in stores for m in store.query("SELECT map FROM runs").column(0).to_pylist()
    }
    assert maps == {"intel", "aws-small-house", "office"}
    robustness = text.split("## Robustness to the readings of the paper", 1)[1]
    assert "| claim | default | coordinator-assigns-requesting | summary |" in robustness
    for claim in repro.CLAIMS:
        assert re.search(
            rf"^\| `{claim.id}` \| .* \| (robust|\*\*fragile\*\*.*) \|$", robustness, re.M
        )
    reading = quick_run / "readings" / "coordinator-assigns-requesting"
    assert (reading / "intel-centralised").is_dir()
    assert not (reading / "intel-rrt").exists()
    arms = text.split("## Arms", 1)[1].split("## Exploration time", 1)[0]
    for arm in repro.ARMS:
        assert f"`{arm}`" in arms


def test_registered() -> None:
    reproduction = get_reproduction("market2018")
    assert reproduction is repro.REPRODUCTION
    assert reproduction.id == "market2018"


def test_full_sweeps_cover_the_arms_maps_and_team_sizes() -> None:
    sweeps = repro.REPRODUCTION.sweeps(False)
    maps = ("intel", "house", "office")
    arms = ("centralised", "decentralised", "rrt", "timer")
    assert list(sweeps) == [f"{m}-{a}" for m in maps for a in arms]
    n = len(repro.SEEDS) * len(repro.TEAM_SIZES)
    for name, sweep in sweeps.items():
        expected = 2 * n if name.endswith(("-decentralised", "-timer")) else n
        assert len(sweep) == expected, name
    scenario = sweeps["intel-timer"].runs()[0].scenario
    assert scenario.map == "intel"
    assert scenario.cell_size == repro.CELL_SIZE_M and scenario.sensor_range == "3m"
    assert scenario.params["event_based"] is False
    assert scenario.idle_ticks > max(repro.TIMER_PERIODS)


# ------------------------------------------------------------------ helpers


def test_arm_of_every_arm() -> None:
    rows = [
        ({"strategy": "burgard"}, "centralised"),
        ({"strategy": "market-occupancy"}, "decentralised"),
        ({"strategy": "market-occupancy", "param_lambda_f": 0.0}, "decentralised"),
        ({"strategy": "market-occupancy", "param_lambda_f": 1e-9}, "no-occupancy"),
        ({"strategy": "market-occupancy", "param_frontier_detector": "rrt"}, "rrt"),
        (
            {"strategy": "market-occupancy", "param_event_based": False, "param_replan_every": 10},
            "timer-10",
        ),
        (
            {"strategy": "market-occupancy", "param_event_based": True, "param_replan_every": 10},
            "decentralised",
        ),
    ]
    for row, arm in rows:
        assert repro.arm_of(row) == arm, row


def _runs() -> pa.Table:
    return pa.table(
        {
            "strategy": ["burgard", "burgard", "market-occupancy", "market-occupancy", "burgard"],
            "param_event_based": [None, None, True, True, None],
            "robots": [2, 2, 2, 2, 2],
            "seed": [1, 2, 1, 2, 3],
            "status": ["complete", "complete", "complete", "max_ticks", "failed"],
            "T99": [100, 120, 90, None, None],
            "ticks": [110, 130, 95, 400, None],
            "bytes_total": [1000, 1100, 2000, 2600, None],
            "bytes_by_type_map_update": [900, 980, 1500, 1800, None],
            "bytes_by_type_status": [60, 70, None, None, None],
            "bytes_by_type_assign": [40, 50, None, None, None],
            "bytes_by_type_weight_request": [None, None, 200, 300, None],
            "bytes_by_type_weights": [None, None, 300, 500, None],
            "messages_by_type_weight_request": [None, None, 4, 6, None],
            "messages_by_type_weights": [None, None, 8, 12, None],
            "group_diameter_mean": [10.0, 12.0, 20.0, 22.0, None],
        }
    )


def test_run_values_and_summaries() -> None:
    rows = [{**r, "experiment": "intel-x"} for r in _runs().to_pylist() if r["status"] != "failed"]
    values = repro.run_values(rows)
    cell = ("intel", 2)
    assert values["coordination_bytes"][cell]["centralised"][1] == 100.0
    assert values["negotiation_bytes"][cell]["centralised"][1] == 0.0
    assert values["time"][cell]["decentralised"][2] == 400.0  # censored at its end
    assert values["reached"][cell]["decentralised"] == {1: 1.0, 2: 0.0}
    assert values["negotiation_bytes"][cell]["decentralised"][2] == 800.0
    assert values["coordination_bytes"][cell]["decentralised"][2] == 800.0
    assert values["negotiation_messages"][cell]["decentralised"][2] == 18.0
    assert bytes_by_type(rows[3]) == {
        "map_update": 1800.0,
        "weight_request": 300.0,
        "weights": 500.0,
    }
    times = summaries(values["time"])[cell]
    assert times["centralised"].mean == 110.0
    assert times["decentralised"].mean == 245.0 and times["decentralised"].n == 2
    difference = paired(values["time"][cell], "decentralised", "centralised")
    assert difference.mean == pytest.approx(((90 - 100) + (400 - 120)) / 2)


def test_the_claims_read_the_teams_in_the_reports_order() -> None:
    ids = [claim.id for claim in repro.CLAIMS]
    assert ids == ["quick", "quick_rrt", "dispersed", "event_data", "event_time", "minimal"]
    event = next(c for c in repro.CLAIMS if c.id == "event_data")
    assert (event.second, *event.seconds) == tuple(repro.timer_arm(p) for p in repro.TIMER_PERIODS)


def test_map_settings_convert_metres() -> None:
    settings = repro.map_settings(False)
    assert list(settings) == ["intel", "house", "office"] == list(repro.MAP_LABELS)
    assert settings["intel"]["sensor_range"] == "3m"
    assert settings["office"]["sensor_range"] == pytest.approx(15.0)
    assert list(repro.map_settings(True)) == ["intel", "house", "office"]
    assert repro.map_settings(True)["office"]["size"] == "80x56"


# ------------------------------------------------------------------ full run


@pytest.mark.slow
def test_full_reproduction(tmp_path: Path) -> None:
    assert main(["reproduce", "market2018", "--out", str(tmp_path), "--no-progress"]) == 0
    text = _check_report(tmp_path)
    assert "**Quick run**" not in text
    for name in repro.REPRODUCTION.sweeps(False):
        assert (tmp_path / name / "runs").is_dir()
