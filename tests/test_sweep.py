"""Sweep files: parsing, validation messages, expansion, run ids; sweeps through the CLI."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.cli import main
from mrexplore.experiments import Store, SweepError, load_sweep, run_sweep, sweep_from_dict
from mrexplore.experiments.sweep import scenario_id
from mrexplore.sim import Scenario

SMALL = """
[sweep]
seeds = [1, 2]
curves_every = 25

[fixed]
map = "sheng40"
sensor_range = 6

[grid]
strategy = ["nearest-frontier", "burgard"]
robots = [2, 3]
comm_range = [inf, 12]
"""


def _write(tmp_path: Path, text: str, name: str = "sweep.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_expansion_is_the_product_of_the_grid_and_the_seeds(tmp_path: Path) -> None:
    sweep = load_sweep(_write(tmp_path, SMALL))
    runs = sweep.runs()
    assert len(sweep) == len(runs) == 2 * 2 * 2 * 2
    assert len({run.run_id for run in runs}) == len(runs)
    # Seeds outermost: the first half of the runs are all seed 1.
    assert [run.scenario.seed for run in runs[:8]] == [1] * 8
    first = runs[0].scenario
    assert (first.map, first.sensor_range, first.strategy, first.robots) == (
        "sheng40",
        6.0,
        "nearest-frontier",
        2,
    )
    assert math.isinf(first.comm_range) and runs[1].scenario.comm_range == 12.0
    assert runs[0].curves_every == 25


def test_strategy_and_sharing_parameters_fixed_and_gridded() -> None:
    sweep = sweep_from_dict(
        {
            "sweep": {"seeds": [3]},
            "fixed": {
                "map": "sheng40",
                "strategy": "sheng-bidding",
                "sharing": "polygon",
                "set": {"alpha": 0.25},
            },
            "grid": {"set": {"w3": [0.0, 1.5]}, "share": {"epsilon": [0.5]}},
        }
    )
    params = [run.scenario.params for run in sweep.runs()]
    assert params == [{"alpha": 0.25, "w3": 0.0}, {"alpha": 0.25, "w3": 1.5}]
    assert sweep.runs()[0].scenario.sharing_params == {"epsilon": 0.5}


def test_run_ids_are_stable_and_follow_the_scenario() -> None:
    a = scenario_id(Scenario(map="sheng40", robots=2, seed=1))
    assert a == scenario_id(Scenario(map="sheng40", robots=2, seed=1))
    assert a != scenario_id(Scenario(map="sheng40", robots=2, seed=2))
    assert a != scenario_id(Scenario(map="sheng40", robots=2, seed=1, params={"x": 1}))
    assert len(a) == 16


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"fixed": {"map": "sheng40"}}, "seeds: expected a non-empty list"),
        ({"sweep": {"seeds": [1, 1]}}, "a seed is repeated"),
        ({"sweep": {"seeds": [1], "speed": 2}}, "[sweep] unknown key 'speed'"),
        ({"sweep": {"seeds": [1]}, "fixd": {}}, "unknown table [fixd]"),
        ({"sweep": {"seeds": [1]}, "fixed": {"comm-range": 5}}, "did you mean 'comm_range'"),
        ({"sweep": {"seeds": [1]}, "grid": {"robots": 3}}, "[grid] robots: expected a non-empty"),
        ({"sweep": {"seeds": [1]}, "grid": {"robots": []}}, "[grid] robots: expected a non-empty"),
        ({"sweep": {"seeds": [1]}, "fixed": {"seed": 3}}, "list the seeds in [sweep] seeds"),
        (
            {"sweep": {"seeds": [1]}, "fixed": {"robots": 2}, "grid": {"robots": [2, 3]}},
            "'robots' is both in [fixed] and in [grid]",
        ),
        ({"sweep": {"seeds": [1]}, "grid": {"robots": [2, -1]}}, "robots=-1, seed=1): --robots"),
        ({"sweep": {"seeds": [1]}, "grid": {"strategy": ["greedy"]}}, "unknown strategy 'greedy'"),
        (
            {
                "sweep": {"seeds": [1]},
                "fixed": {"strategy": "burgard"},
                "grid": {"set": {"w": [1]}},
            },
            "--set w: strategy 'burgard' has no such parameter",
        ),
        ({"sweep": {"seeds": [1]}, "fixed": {"map": "missing.pgm"}}, "missing.pgm: no such file"),
        ({"sweep": {"seeds": [1]}, "grid": {"robots": [2, 2]}}, "are the same scenario"),
        ({"sweep": {"seeds": [1], "curves_every": 0}}, "curves_every: expected an integer >= 1"),
    ],
)
def test_bad_sweeps_name_the_key_and_the_problem(data: dict[str, Any], message: str) -> None:
    with pytest.raises(SweepError) as caught:
        sweep_from_dict(data, "s.toml")
    assert message in str(caught.value)
    assert str(caught.value).startswith("s.toml: ")


@settings(max_examples=25, deadline=None)
@given(
    robots=st.lists(st.integers(1, 6), min_size=1, max_size=3, unique=True),
    seeds=st.lists(st.integers(0, 99), min_size=1, max_size=3, unique=True),
    ranges=st.lists(st.sampled_from([4.0, 8.0, 16.0, math.inf]), min_size=1, unique=True),
)
def test_every_combination_appears_once(
    robots: list[int], seeds: list[int], ranges: list[float]
) -> None:
    sweep = sweep_from_dict(
        {"sweep": {"seeds": seeds}, "grid": {"robots": robots, "comm_range": ranges}}
    )
    combos = [(r.scenario.robots, r.scenario.comm_range, r.scenario.seed) for r in sweep.runs()]
    assert sorted(combos) == sorted(
        (robot, comm, seed) for robot in robots for comm in ranges for seed in seeds
    )


def test_sweep_through_the_cli_then_query(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    sweep_file = _write(tmp_path, SMALL)
    out = tmp_path / "results"
    assert (
        main(["sweep", str(sweep_file), "--out", str(out), "--workers", "2", "--no-progress"]) == 0
    )
    assert "16 runs done (0 failed)" in capsys.readouterr().out
    assert (out / "sweep.toml").read_text() == SMALL
    runs = Store(out).query("SELECT * FROM runs")
    assert runs.num_rows == 16
    assert set(runs.column("status").to_pylist()) == {"complete"}
    assert set(runs.column("strategy").to_pylist()) == {"nearest-frontier", "burgard"}
    # Columns named like the scenario keys and result.json's metrics.
    for column in ("map", "robots", "comm_range", "seed", "ticks", "T99", "total_distance"):
        assert column in runs.column_names
    assert main(["query", str(out), "SELECT strategy, count(*) AS n FROM runs GROUP BY 1"]) == 0
    printed = capsys.readouterr().out
    assert "burgard" in printed and "(2 rows)" in printed
    # Curves: sampled every 25 ticks plus the last tick, for every run.
    curves = Store(out).query(
        "SELECT run_id, max(tick) AS last, count(*) AS n, max(coverage) AS cov FROM curves "
        "GROUP BY run_id"
    )
    ticks = dict(
        zip(runs.column("run_id").to_pylist(), runs.column("ticks").to_pylist(), strict=True)
    )
    for row in curves.to_pylist():
        assert row["last"] == ticks[row["run_id"]]
        assert row["n"] == len(range(0, ticks[row["run_id"]], 25)) + 1
        assert row["cov"] >= 0.99


def test_results_match_single_runs(tmp_path: Path) -> None:
    sweep = sweep_from_dict(
        {"sweep": {"seeds": [4]}, "fixed": {"map": "sheng40", "robots": 3, "strategy": "burgard"}}
    )
    run_sweep(sweep, tmp_path, workers=1, progress=False)
    row = Store(tmp_path).query("SELECT * FROM runs").to_pylist()[0]
    single = __import__("mrexplore").run(
        Scenario(map="sheng40", robots=3, strategy="burgard", seed=4)
    )
    for key in ("ticks", "T99", "total_distance", "bytes_total", "status", "overlap"):
        assert row[key] == single[key], key


def test_a_run_that_raises_is_recorded_as_failed_and_the_sweep_goes_on(tmp_path: Path) -> None:
    # Start cell (0, 0) is a wall of sheng40: the run itself fails, not the validation.
    sweep = sweep_from_dict(
        {
            "sweep": {"seeds": [1, 2]},
            "fixed": {"map": "sheng40", "robots": 1},
            "grid": {"start": ["together", "0,0"]},
        }
    )
    summary = run_sweep(sweep, tmp_path, workers=2, progress=False)
    assert (summary.done, summary.failed) == (4, 2)
    rows = Store(tmp_path).query("SELECT start, status, error FROM runs ORDER BY start").to_pylist()
    assert [r["status"] for r in rows] == ["failed", "failed", "complete", "complete"]
    assert all("start" in r["error"] for r in rows[:2])
    assert rows[2]["error"] is None


def test_bad_sweep_file_is_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = _write(tmp_path, "[sweep]\nseeds = [1]\n[grid]\nrobot = [2]\n")
    assert main(["sweep", str(bad), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "unknown key 'robot'" in err and str(bad) in err
    assert not (tmp_path / "o").exists()
    broken = _write(tmp_path, "[sweep\n", "broken.toml")
    assert main(["sweep", str(broken), "--out", str(tmp_path / "o")]) == 2
    assert "not valid TOML" in capsys.readouterr().err
    assert main(["sweep", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")]) == 2
    assert "no such sweep file" in capsys.readouterr().err
    good = _write(tmp_path, SMALL, "good.toml")
    assert main(["sweep", str(good), "--out", str(tmp_path / "o"), "--engine", "spark"]) == 2
    assert "--engine spark" in capsys.readouterr().err


def test_existing_results_are_never_overwritten(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    sweep = _write(tmp_path, "[sweep]\nseeds = [1]\n[fixed]\nmap = 'sheng40'\nrobots = 2\n")
    out = tmp_path / "r"
    assert main(["sweep", str(sweep), "--out", str(out), "--no-progress"]) == 0
    before = sorted(p.name for p in (out / "runs").iterdir())
    assert main(["sweep", str(sweep), "--out", str(out), "--no-progress"]) == 2
    assert "--resume" in capsys.readouterr().err
    assert sorted(p.name for p in (out / "runs").iterdir()) == before
    # --resume with nothing missing runs nothing.
    assert main(["sweep", str(sweep), "--out", str(out), "--resume", "--no-progress"]) == 0
    assert "0 runs done (0 failed), 1 already in" in capsys.readouterr().out
    other = tmp_path / "notes"
    other.mkdir()
    (other / "mine.txt").write_text("keep")
    assert main(["sweep", str(sweep), "--out", str(other), "--no-progress"]) == 2
    assert (other / "mine.txt").read_text() == "keep"


def test_resume_runs_added_seeds_only(tmp_path: Path) -> None:
    base = {"fixed": {"map": "sheng40", "robots": 2}}
    first = sweep_from_dict({"sweep": {"seeds": [1, 2]}, **base})
    run_sweep(first, tmp_path, workers=1, progress=False)
    summary = run_sweep(
        sweep_from_dict({"sweep": {"seeds": [1, 2, 3]}, **base}),
        tmp_path,
        workers=1,
        resume=True,
        progress=False,
    )
    assert (summary.skipped, summary.done) == (2, 1)
    seeds = Store(tmp_path).query("SELECT seed FROM runs ORDER BY seed").column("seed")
    assert seeds.to_pylist() == [1, 2, 3]


def test_example_sweep_files_are_valid() -> None:
    examples = sorted((Path(__file__).resolve().parents[1] / "examples" / "sweeps").glob("*.toml"))
    assert examples
    for path in examples:
        assert len(load_sweep(path)) > 0, path


# --------------------------------------------- resuming with another sweep (issue 13)
RESUME_A = """[sweep]
seeds = [1, 2]
[fixed]
map = "sheng40"
sensor_range = 4
robots = 2
"""


def _sweep_cli(file: Path, out: Path, *extra: str) -> int:
    return main(["sweep", str(file), "--out", str(out), "--workers", "1", "--no-progress", *extra])


@pytest.mark.parametrize(
    ("change", "needle"),
    [
        (("sensor_range = 4", "sensor_range = 6"), "[fixed] sensor_range: 4 in {old}, 6 in {new}"),
        (("seeds = [1, 2]", "seeds = [2, 3]"), "[sweep] seeds: 1 in {old}, not in {new}"),
        (("robots = 2", "robots = 3"), "[fixed] robots: 2 in {old}, 3 in {new}"),
        (("robots = 2\n", "robots = 2\nspeed = 2\n"), "[fixed] speed: not in {old}, 2 in {new}"),
    ],
)
def test_resume_with_another_sweep_is_refused_naming_the_keys(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], change: tuple[str, str], needle: str
) -> None:
    first = _write(tmp_path, RESUME_A, "a.toml")
    other = _write(tmp_path, RESUME_A.replace(*change), "b.toml")
    out = tmp_path / "D"
    assert _sweep_cli(first, out) == 0
    before = sorted(p.name for p in out.rglob("*"))
    capsys.readouterr()
    assert _sweep_cli(other, out, "--resume") == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert needle.format(old=out / "sweep.toml", new=other) in err
    assert f"--out {out} --resume" in err and "choose another --out folder" in err
    # Nothing written: same files, the same sweep.toml, only the first sweep's rows.
    assert sorted(p.name for p in out.rglob("*")) == before
    assert (out / "sweep.toml").read_text() == RESUME_A
    assert Store(out).query("SELECT count(*) AS n FROM runs").column("n")[0].as_py() == 2


def test_resume_that_adds_seeds_and_values_records_the_new_sweep_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    first = _write(tmp_path, RESUME_A, "a.toml")
    out = tmp_path / "D"
    assert _sweep_cli(first, out) == 0
    # One more seed, and robots from [fixed] 2 to [grid] [2, 3]: only adds runs.
    larger_text = (
        RESUME_A.replace("seeds = [1, 2]", "seeds = [1, 2, 3]").replace("robots = 2\n", "")
        + "[grid]\nrobots = [2, 3]\n"
    )
    larger = _write(tmp_path, larger_text, "c.toml")
    capsys.readouterr()
    assert _sweep_cli(larger, out, "--resume") == 0
    assert "4 runs done (0 failed), 2 already in" in capsys.readouterr().out
    assert (out / "sweep.toml").read_text() == larger_text  # describes what the folder holds
    assert (out / "sweep.toml.1").read_text() == RESUME_A  # the earlier file, kept
    rows = Store(out).query("SELECT robots, seed FROM runs ORDER BY ALL").to_pylist()
    assert [(r["robots"], r["seed"]) for r in rows] == [
        (2, 1),
        (2, 2),
        (2, 3),
        (3, 1),
        (3, 2),
        (3, 3),
    ]
    # The same sweep again (comments aside): nothing to run, no new copy kept.
    _write(tmp_path, "# again\n" + larger_text, "c.toml")
    assert _sweep_cli(larger, out, "--resume") == 0
    assert sorted(p.name for p in out.glob("sweep.toml*")) == ["sweep.toml", "sweep.toml.1"]
    # The first, smaller sweep no longer describes the folder.
    assert _sweep_cli(first, out, "--resume") == 2
    assert "[sweep] seeds: 3 in" in capsys.readouterr().err


def test_resume_refuses_rows_of_another_sweep_without_a_sweep_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    first = _write(tmp_path, RESUME_A, "a.toml")
    out = tmp_path / "D"
    assert _sweep_cli(first, out) == 0
    (out / "sweep.toml").unlink()  # e.g. a folder written by an older mrexplore
    other = _write(tmp_path, RESUME_A.replace("sensor_range = 4", "sensor_range = 6"), "b.toml")
    capsys.readouterr()
    assert _sweep_cli(other, out, "--resume") == 2
    assert "2 of the runs stored in" in capsys.readouterr().err
    assert not (out / "sweep.toml").exists()


def test_sweeps_built_in_python_record_an_equivalent_sweep_file(tmp_path: Path) -> None:
    from mrexplore.experiments.sweep import sweep_to_toml

    sweep = sweep_from_dict(
        {
            "sweep": {"seeds": [1, 2], "name": "mine", "curves_every": 5},
            "fixed": {"map": "sheng40", "comm_range": math.inf, "fail": ["1@30"]},
            "grid": {
                "strategy": ["sheng-bidding"],
                "robots": [2, 3],
                "set": {"w3": [0.0, 1.5]},
                "share": {},
            },
        }
    )
    text = sweep_to_toml(sweep)
    again = load_sweep(_write(tmp_path, text, "again.toml"))
    assert [s.run_id for s in again.runs()] == [s.run_id for s in sweep.runs()]
    assert (again.name, again.curves_every) == ("mine", 5)
    small = sweep_from_dict({"sweep": {"seeds": [1]}, "fixed": {"map": "sheng40", "robots": 2}})
    run_sweep(small, tmp_path / "D", workers=1, progress=False)
    recorded = load_sweep(tmp_path / "D" / "sweep.toml")
    assert [s.run_id for s in recorded.runs()] == [s.run_id for s in small.runs()]
