"""The results store: crash safety (SIGKILL and resume), compaction, queries, engines."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from mrexplore.cli import main
from mrexplore.experiments import Store, StoreError, run_sweep, sweep_from_dict
from mrexplore.experiments.runner import TIMING_COLUMNS

# 200 short runs: 2 strategies x 2 team sizes x 50 seeds on a 16 x 16 room.
SWEEP_200 = """
[sweep]
seeds = [{seeds}]
curves_every = 5

[fixed]
map = "blank"
size = "16x16"
sensor_range = 3

[grid]
strategy = ["nearest-frontier", "random-frontier"]
robots = [1, 2]
"""


def _sweep_file(tmp_path: Path, seeds: int = 50) -> Path:
    path = tmp_path / "sweep200.toml"
    path.write_text(SWEEP_200.format(seeds=", ".join(str(s) for s in range(1, seeds + 1))))
    return path


def _count(folder: Path) -> int:
    return len(list(folder.glob("run-*.parquet"))) if folder.is_dir() else 0


def test_sigkill_at_a_random_point_then_resume_gives_every_run_once(tmp_path: Path) -> None:
    sweep = _sweep_file(tmp_path)
    out = tmp_path / "results"
    kill_after = random.Random(os.getpid()).randint(10, 150)
    command = [sys.executable, "-m", "mrexplore", "sweep", str(sweep), "--out", str(out)]
    process = subprocess.Popen(
        [*command, "--workers", "2", "--no-progress"],
        start_new_session=True,  # its own process group: the workers die with it
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 300
    while _count(out / "runs") < kill_after and process.poll() is None:
        assert time.monotonic() < deadline, "the sweep made no progress"
        time.sleep(0.01)
    os.killpg(process.pid, signal.SIGKILL)
    process.wait()
    assert process.returncode == -signal.SIGKILL  # killed, not finished
    before = Store(out).done_ids()
    assert kill_after <= len(before) < 200

    # What was written before the kill is readable as it is.
    assert Store(out).query("SELECT count(*) AS n FROM runs").column("n")[0].as_py() == len(before)
    resumed = subprocess.run(
        [*command, "--resume", "--no-progress"], capture_output=True, text=True, check=False
    )
    assert resumed.returncode == 0, resumed.stderr
    assert f"{200 - len(before)} runs done (0 failed), {len(before)} already in" in resumed.stdout
    counts = (
        Store(out)
        .query(
            "SELECT count(*) AS n, count(DISTINCT run_id) AS ids, "
            "count(*) FILTER (WHERE status = 'complete') AS ok FROM runs"
        )
        .to_pylist()[0]
    )
    assert counts == {"n": 200, "ids": 200, "ok": 200}
    curve_runs = Store(out).query("SELECT count(DISTINCT run_id) AS n FROM curves")
    assert curve_runs.column("n")[0].as_py() == 200
    assert not list(out.rglob(".*.tmp"))


def test_an_interrupted_compaction_never_counts_a_run_twice(tmp_path: Path) -> None:
    sweep = sweep_from_dict(
        {"sweep": {"seeds": [1, 2, 3]}, "fixed": {"map": "blank", "size": "16x16", "robots": 1}}
    )
    store = Store(tmp_path)
    store.create()
    from mrexplore.experiments.runner import execute

    outcomes = [execute(spec) for spec in sweep.runs()]
    for outcome in outcomes:
        store.append(outcome)
    # Killed after the batch was written but before the single files were deleted:
    singles = sorted((tmp_path / "runs").glob("run-*.parquet"))
    store._merge(singles, "runs", "batch-crashed")
    (tmp_path / "runs" / ".run-x.123.tmp").write_bytes(b"torn")
    assert len(singles) == 3 and store.done_ids() == {o.run_id for o in outcomes}
    assert store.query("SELECT count(*) AS n FROM runs").column("n")[0].as_py() == 3
    store.recover()
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == ["batch-crashed.parquet"]
    assert store.query("SELECT count(*) AS n FROM runs").column("n")[0].as_py() == 3
    assert store.compact() == 0  # the curves were still single files: nothing else to merge
    assert store.query("SELECT count(DISTINCT run_id) AS n FROM curves").column("n")[0].as_py() == 3


def test_compaction_merges_single_files_and_keeps_every_row(tmp_path: Path) -> None:
    sweep = sweep_from_dict(
        {
            "sweep": {"seeds": [1, 2]},
            "fixed": {"map": "blank", "size": "16x16"},
            "grid": {"robots": [1, 2], "start": ["together", "0,0"]},
        }
    )
    run_sweep(sweep, tmp_path, workers=1, progress=False)  # compacts at the end
    assert [p.name[:6] for p in (tmp_path / "runs").iterdir()] == ["batch-"]
    rows = Store(tmp_path).query("SELECT status, count(*) AS n FROM runs GROUP BY 1 ORDER BY 1")
    # Failed rows (a wall start cell) and complete rows share one batch despite their
    # different columns.
    assert rows.to_pylist() == [{"status": "complete", "n": 4}, {"status": "failed", "n": 4}]


def test_query_errors_are_input_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(StoreError, match="not a results folder"):
        Store(tmp_path / "none").query("SELECT 1")
    assert main(["query", str(tmp_path / "none"), "SELECT 1"]) == 2
    assert "not a results folder" in capsys.readouterr().err
    run_sweep(
        sweep_from_dict({"sweep": {"seeds": [1]}, "fixed": {"map": "blank", "size": "16x16"}}),
        tmp_path / "r",
        workers=1,
        progress=False,
    )
    assert main(["query", str(tmp_path / "r"), "SELECT nope FROM runs"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mrexplore: error: query on") and err.count("\n") == 1
    assert main(["query", str(tmp_path / "r"), "SELECT robots, seed FROM runs", "--csv"]) == 0
    assert capsys.readouterr().out.splitlines() == ["robots,seed", "4,1"]


def _rows(folder: Path) -> list[dict[str, object]]:
    table = Store(folder).query("SELECT * FROM runs ORDER BY run_id")
    return [{k: v for k, v in row.items() if k not in TIMING_COLUMNS} for row in table.to_pylist()]


def _curves(folder: Path) -> list[dict[str, object]]:
    return Store(folder).query("SELECT * FROM curves ORDER BY run_id, tick").to_pylist()


@pytest.mark.parametrize("engine", ["ray", "dask"])
def test_every_engine_gives_the_same_rows(tmp_path: Path, engine: str) -> None:
    pytest.importorskip(engine if engine == "ray" else "distributed")
    sweep = sweep_from_dict(
        {
            "sweep": {"seeds": [1, 2], "curves_every": 20},
            "fixed": {"map": "sheng40", "comm_range": 12},
            "grid": {"strategy": ["burgard", "sheng-bidding"], "robots": [2, 3]},
        }
    )
    run_sweep(sweep, tmp_path / "local", engine="local", workers=2, progress=False)
    run_sweep(sweep, tmp_path / engine, engine=engine, workers=2, progress=False)
    local, other = _rows(tmp_path / "local"), _rows(tmp_path / engine)
    assert len(local) == 8
    assert local == other
    assert _curves(tmp_path / "local") == _curves(tmp_path / engine)
