"""The committed standard-v1 leaderboard is what its committed store gives.

``docs/leaderboards/standard-v1/store`` holds the runs of the full suite with the ten
built-in strategies (the ``runs`` table; curves are left out to keep the repository
small). Reporting it again must give the committed ``leaderboard.md`` to the byte, and
``docs/benchmark.md`` must quote its tables as they are.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from mrexplore.cli import main
from mrexplore.experiments import Store, load_suite
from mrexplore.experiments.suite import folder_suite
from mrexplore.strategies.registry import STRATEGIES

REPO = Path(__file__).resolve().parents[1]
PUBLISHED = REPO / "docs" / "leaderboards" / "standard-v1"
STORE = PUBLISHED / "store"
BUILT_IN = (
    "burgard",
    "kme",
    "market-occupancy",
    "meier-polygon",
    "nearest-frontier",
    "random-frontier",
    "sheng-bidding",
    "simmons",
    "vazquez-network",
    "zlot-market",
)


def test_the_store_holds_every_run_of_the_released_suite() -> None:
    suite = folder_suite(STORE)
    assert suite is not None and suite.content_hash == load_suite("standard-v1").content_hash
    runs = Store(STORE).query("SELECT run_id, strategy, suite_hash FROM runs")
    assert runs.num_rows == suite.n_instances * len(BUILT_IN) == 8400
    assert sorted(set(runs.column("strategy").to_pylist())) == list(BUILT_IN)
    assert set(runs.column("suite_hash").to_pylist()) == {suite.content_hash}
    assert {spec.run_id for spec in suite.runs(list(BUILT_IN))} == set(
        runs.column("run_id").to_pylist()
    )
    assert set(BUILT_IN) <= set(STRATEGIES.ids())


def test_reporting_the_store_again_gives_the_committed_leaderboard(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["suite", "report", str(STORE), "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    assert (tmp_path / "leaderboard.md").read_text() == (PUBLISHED / "leaderboard.md").read_text()
    assert (REPO / "docs" / "img" / "leaderboard-standard-v1.png").is_file()


def test_the_benchmark_page_quotes_the_leaderboard_tables() -> None:
    committed = (PUBLISHED / "leaderboard.md").read_text().splitlines()
    rows = [line for line in committed if line.startswith("| ") and line[2:3].isdigit()]
    assert len(rows) == 3 * len(BUILT_IN)
    page = (REPO / "docs" / "benchmark.md").read_text()
    assert all(row in page for row in rows)
