"""Benchmark suites: shipped files that never change, their instances and regimes,
``mrexplore suite run`` (resumable, plugins and engines), ``suite merge``, and the
mid-run failure ``--fail ROBOT@P%`` that the harsh regime uses."""

from __future__ import annotations

import hashlib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.cli import main
from mrexplore.errors import MrexploreInputError
from mrexplore.experiments import Store
from mrexplore.experiments.runner import TIMING_COLUMNS
from mrexplore.experiments.suite import (
    load_suite,
    merge_folders,
    run_suite,
    shipped_suites,
    suite_from_bytes,
)
from mrexplore.sim import Scenario
from mrexplore.sim.engine import Simulation
from mrexplore.sim.scenario import ScenarioError, parse_coverage_failure

#: The content hashes of the released suites. A released suite never changes: if this
#: test fails, the edit belongs in a new file with a new version.
RELEASED = {
    "standard-v1": "bd60fffdb06eef85",
    "standard-v1-quick": "033533b91f4b2ab4",
}

SMALL = b"""
[suite]
name = "tiny"
version = 1
seeds = [1, 2]
robots = [2]

[fixed]
sensor_range = 5

[maps.sheng40]

[regimes.unlimited]

[regimes.lossy]
comm_range = 12
loss = 0.1
fail = ["any@50%"]
sharing_instead_of_full = "sheng-sync"
"""


@pytest.fixture
def tiny(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.toml"
    path.write_bytes(SMALL)
    return path


def _rows(folder: Path) -> list[dict[str, object]]:
    table = Store(folder).query("SELECT * FROM runs ORDER BY run_id")
    return [{k: v for k, v in row.items() if k not in TIMING_COLUMNS} for row in table.to_pylist()]


def _same(a: dict[str, object], b: dict[str, object]) -> bool:
    """Equal rows: nan equals nan, a missing column equals null."""

    def norm(v: object) -> object:
        return "nan" if isinstance(v, float) and v != v else v

    return all(norm(a.get(k)) == norm(b.get(k)) for k in set(a) | set(b))


# ------------------------------------------------------------------ suite files


def test_released_suites_never_change() -> None:
    assert set(shipped_suites()) == set(RELEASED)
    for name, expected in RELEASED.items():
        data = resources.files("mrexplore.suites").joinpath(f"{name}.toml").read_bytes()
        assert hashlib.sha256(data).hexdigest()[:16] == expected, name
        suite = load_suite(name)
        assert suite.content_hash == expected and suite.name == name


def test_standard_v1_is_what_the_issue_asks_for() -> None:
    suite = load_suite("standard-v1")
    assert suite.seeds == tuple(range(1, 11))
    assert suite.robots == (2, 4, 8, 16)
    assert [r.name for r in suite.regimes] == ["unlimited", "multi-hop", "harsh"]
    assert {"intel", "depot", "aws-small-house", "office", "cityblock"} <= set(suite.maps)
    harsh = {r.name: r for r in suite.regimes}["harsh"]
    assert harsh.settings["comm_los"] is True and harsh.settings["loss"] == 0.1
    assert harsh.settings["fail"] == ["any@50%"] and harsh.settings["bandwidth"] < float("inf")
    assert suite.n_instances == 3 * len(suite.maps) * 4 * 10


def test_runs_cover_every_instance_and_keep_a_method_s_own_sharing() -> None:
    suite = load_suite("standard-v1-quick")
    specs = suite.runs(["nearest-frontier", "meier-polygon", "vazquez-network"])
    assert len(specs) == suite.n_instances * 3 == len({s.run_id for s in specs})
    seeds = [s.scenario.seed for s in specs]
    assert seeds == sorted(seeds)  # seeds outermost: a half-run suite has every condition
    for spec in specs:
        tags = dict(spec.tags)
        assert tags["suite"] == "standard-v1-quick" and tags["suite_hash"] == suite.content_hash
        sharing = spec.scenario.sharing
        if tags["regime"] == "unlimited":
            assert sharing is None
        elif spec.scenario.strategy == "nearest-frontier":
            assert sharing == "sheng-sync"  # its own sharing is "full"
        else:
            assert sharing is None  # polygons and broadcast are part of those methods
        if tags["regime"] == "harsh":
            assert spec.scenario.fail_at_coverage == [(-1, 0.5)]


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (b'[suite]\nname = "x"\nversion = 0\nseeds = [1]\nrobots = [2]\n', "version"),
        (SMALL.replace(b"[maps.sheng40]", b"[maps.sheng40]\nstrategy = 'burgard'"), "open"),
        (SMALL.replace(b"sensor_range = 5", b"sensor_rang = 5"), "unknown key 'sensor_rang'"),
        (SMALL.replace(b"robots = [2]", b"robots = [2, 2]"), "repeated"),
        (SMALL + b"\n[extra]\n", "unknown table [extra]"),
        (SMALL.replace(b"loss = 0.1", b"loss = 2.0"), "regime lossy"),
        (SMALL.replace(b'"any@50%"', b'"any@150%"'), "share"),
    ],
)
def test_a_bad_suite_file_is_one_clear_error(edit: bytes, message: str) -> None:
    with pytest.raises(MrexploreInputError) as error:
        suite_from_bytes(edit, "bad.toml")
    assert message in str(error.value) and "bad.toml" in str(error.value)


# ------------------------------------------------------------- running a suite


def test_suite_run_tags_rows_continues_and_adds_strategies(tiny: Path, tmp_path: Path) -> None:
    out = tmp_path / "store"
    first = run_suite(tiny, "nearest-frontier", out, workers=1, progress=False)
    assert (first.total, first.done, first.failed) == (4, 4, 0)
    again = run_suite(tiny, "nearest-frontier", out, workers=1, progress=False)
    assert (again.done, again.skipped) == (0, 4)
    more = run_suite(tiny, "nearest-frontier,burgard", out, workers=1, progress=False)
    assert (more.done, more.skipped) == (4, 4)
    rows = _rows(out)
    assert len(rows) == 8
    suite = load_suite(tiny)
    for row in rows:
        assert row["suite"] == "tiny" and row["suite_version"] == 1
        assert row["suite_hash"] == suite.content_hash
        assert row["regime"] in ("unlimited", "lossy")
        if row["regime"] == "lossy":
            assert row["robots_failed"] == 1 and row["fail_at_coverage"] == "any@50%"
            assert row["sharing"] == "sheng-sync"
    assert (out / "suite.toml").read_bytes() == SMALL


def test_suite_run_refuses_another_suite_s_folder(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "store"
    run_suite(tiny, "nearest-frontier", out, workers=1, progress=False)
    before = sorted(p.name for p in (out / "runs").iterdir())
    other = tmp_path / "other.toml"
    other.write_bytes(SMALL.replace(b'name = "tiny"', b'name = "tiny2"'))
    status = main(["suite", "run", str(other), "--strategies", "burgard", "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and "tiny" in err and "--out" in err
    assert sorted(p.name for p in (out / "runs").iterdir()) == before
    assert (out / "suite.toml").read_bytes() == SMALL
    assert main(["suite", "run", "standard-v9", "--strategies", "all", "--out", "x"]) == 2
    assert "no such suite" in capsys.readouterr().err
    assert main(["suite", "run", str(tiny), "--strategies", "nope", "--out", "x"]) == 2
    assert "--strategies nope" in capsys.readouterr().err


def test_cli_dry_run_and_list(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["suite", "list"]) == 0
    out = capsys.readouterr().out
    assert "standard-v1 " in out and "standard-v1-quick" in out and "bd60fffdb06eef85" in out
    assert (
        main(["suite", "run", "standard-v1", "--strategies", "all", "--out", "x", "--dry-run"]) == 0
    )
    assert "840 instances x 10 strategies = 8400 runs" in capsys.readouterr().out


@pytest.mark.parametrize("engine", ["dask"])
def test_a_suite_gives_the_same_rows_on_another_engine(
    tiny: Path, tmp_path: Path, engine: str
) -> None:
    pytest.importorskip("distributed")
    run_suite(tiny, "burgard", tmp_path / "local", workers=2, progress=False)
    run_suite(tiny, "burgard", tmp_path / engine, engine=engine, workers=2, progress=False)
    assert _rows(tmp_path / "local") == _rows(tmp_path / engine)


# ------------------------------------------------------------------- merging


def test_merge_joins_one_suite_and_refuses_two(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run_suite(tiny, "nearest-frontier,burgard", tmp_path / "a", workers=1, progress=False)
    run_suite(tiny, "burgard,random-frontier", tmp_path / "b", workers=1, progress=False)
    merged = merge_folders([tmp_path / "a", tmp_path / "b"], tmp_path / "m")
    assert merged.runs == 12 and merged.duplicates == 4
    assert merged.strategies == ("burgard", "nearest-frontier", "random-frontier")
    rows = _rows(tmp_path / "m")
    assert len(rows) == 12 and len({r["run_id"] for r in rows}) == 12
    by_id = {r["run_id"]: r for r in _rows(tmp_path / "a") + _rows(tmp_path / "b")}
    assert all(_same(by_id[r["run_id"]], r) for r in rows)
    curves = Store(tmp_path / "m").query("SELECT DISTINCT run_id FROM curves").num_rows
    assert curves == 12

    other = tmp_path / "other.toml"
    other.write_bytes(SMALL.replace(b"version = 1", b"version = 2"))
    run_suite(other, "nearest-frontier", tmp_path / "c", workers=1, progress=False)
    status = main(["suite", "merge", str(tmp_path / "a"), str(tmp_path / "c"), "--out", "n"])
    err = capsys.readouterr().err
    assert status == 2 and "version 2" in err and "version 1" in err
    status = main(
        ["suite", "merge", str(tmp_path / "a"), str(tmp_path / "b"), "--out", str(tmp_path / "m")]
    )
    assert status == 2 and "not empty" in capsys.readouterr().err


# -------------------------------------------------------- failing mid-run


def _coverage_failure_run(seed: int, robots: int, share: float) -> tuple[int, float, int]:
    """Run until the failure; returns (failed robot, coverage when it failed, tick)."""
    scenario = Scenario(
        map="sheng40", robots=robots, seed=seed, sensor_range=4, fail_at_coverage=[(-1, share)]
    )
    sim = Simulation(scenario)
    sim.start()
    coverage = 0.0
    while sim.status is None:
        before = sim.known_explorable / sim.n_explorable
        sim.step()
        dead = [r.id for r in sim.roster.robots if not r.alive]
        if dead:
            return dead[0], before, sim.tick
        coverage = before
    raise AssertionError(f"no robot failed (coverage reached {coverage})")


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 10_000), robots=st.integers(2, 5), share=st.floats(0.2, 0.8))
def test_a_robot_fails_at_the_first_tick_after_the_share_is_known(
    seed: int, robots: int, share: float
) -> None:
    robot, coverage_before, tick = _coverage_failure_run(seed, robots, share)
    assert 0 <= robot < robots
    assert coverage_before >= share  # the share was known at the end of the last tick
    again = _coverage_failure_run(seed, robots, share)
    assert again == (robot, coverage_before, tick)  # the same robot for every strategy's run


def test_any_robot_is_drawn_from_the_seed() -> None:
    chosen = {_coverage_failure_run(seed, 4, 0.3)[0] for seed in range(12)}
    assert len(chosen) > 1


def test_coverage_failures_are_parsed_and_checked(capsys: pytest.CaptureFixture[str]) -> None:
    assert parse_coverage_failure("any@50%") == (-1, 0.5)
    assert parse_coverage_failure("1@25%") == (1, 0.25)
    with pytest.raises(ScenarioError):
        parse_coverage_failure("x@5%")
    with pytest.raises(ScenarioError, match="already fails"):
        Scenario(map="sheng40", robots=2, fail=[(1, 5)], fail_at_coverage=[(1, 0.5)]).check()
    assert main(["run", "--map", "sheng40", "--robots", "2", "--fail", "5@50%"]) == 2
    assert "no robot 5" in capsys.readouterr().err


def test_without_coverage_failures_nothing_changes() -> None:
    plain = Simulation(Scenario(map="sheng40", robots=3, seed=4, sensor_range=4)).run()
    far = Simulation(
        Scenario(map="sheng40", robots=3, seed=4, sensor_range=4, fail_at_coverage=[(-1, 0.999)])
    ).run()
    a, b = plain.trace_arrays(), far.trace_arrays()
    assert np.array_equal(a["positions"], b["positions"])


def test_suite_report_through_the_cli(
    tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "store"
    run_suite(tiny, "nearest-frontier,burgard,simmons", out, workers=2, progress=False)
    assert main(["suite", "report", str(out)]) == 0
    assert "leaderboard.md" in capsys.readouterr().out
    markdown = (out / "leaderboard.md").read_text()
    for name in ("nearest-frontier", "burgard", "simmons", "unlimited", "lossy", "Friedman"):
        assert name in markdown
    assert (out / "leaderboard.html").is_file() and (out / "leaderboard.png").is_file()
    assert main(["suite", "report", str(tmp_path)]) == 2
    assert "not a suite's results folder" in capsys.readouterr().err
