"""The worked example of docs/benchmark.md: ``examples/plugin_strategy`` installed for
real with pip, found through its entry point, checked, run, and benchmarked.

* the class from ``examples/plugin_strategy/utility_frontier.py`` passes
  :func:`~mrexplore.checks.check_strategy`;
* ``pip install --target`` of the package, then ``mrexplore strategies`` lists
  ``utility-frontier`` and ``mrexplore run`` completes with it;
* the acceptance test of the benchmark page: ``mrexplore suite run standard-v1-quick``
  with the plugin and two built-ins, then ``mrexplore suite report``, whose
  leaderboards have a ``utility-frontier`` row wherever ``nearest-frontier`` has one.
"""

from __future__ import annotations

import html
import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from mrexplore.checks import check_strategy
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies.registry import STRATEGIES

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "examples" / "plugin_strategy"
DIST = "mrexplore-utility-frontier"
STRATEGY = "utility-frontier"


def _load_example() -> ModuleType:
    """``utility_frontier.py`` imported from the example folder (not installed)."""
    spec = importlib.util.spec_from_file_location(
        "_example_utility_frontier", PACKAGE / "utility_frontier.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def example_class() -> Iterator[type]:
    """The example's class, registered under its id for the duration of a test."""
    cls = _load_example().UtilityFrontier
    STRATEGIES.register(cls)
    try:
        yield cls
    finally:
        STRATEGIES.unregister(cls.id)


def test_the_example_passes_check_strategy(example_class: type) -> None:
    assert example_class.id == STRATEGY
    check_strategy(STRATEGY)


def test_the_example_declares_lambda_with_its_unit(example_class: type) -> None:
    decay = example_class.params["distance_decay"]
    assert (decay.default, decay.unit, decay.symbol) == (0.2, "1/cell", "lambda")
    robot = example_class(0, 2, distance_decay="0.05")  # as `--set distance_decay=0.05`
    assert robot.distance_decay == 0.05


def test_a_failed_robot_in_a_door_does_not_freeze_the_team(example_class: type) -> None:
    """standard-v1-quick, harsh regime, room-64-64-8, 4 robots, seed 1: robot 3 fails in
    front of a one-cell door that the others' best frontier lies behind. Without the
    blocked-targets rule they were sent through it until the run stalled."""
    scenario = Scenario(
        map="room-64-64-8",
        robots=4,
        strategy=STRATEGY,
        seed=1,
        sensor_range=16,
        comm_range=20,
        comm_los=True,
        loss=0.1,
        bandwidth=1250,
        fail_at_coverage=[(-1, 0.5)],  # --fail any@50%
        sharing="sheng-sync",
    )
    record = simulate(scenario)
    assert record.result()["robots_failed"] == 1
    assert record.status == "complete"
    assert simulate(replace(scenario, params={"block_limit": 0})).status == "stalled"


def test_utility_trades_gain_against_distance() -> None:
    best = _load_example().best_candidate
    gains, distances = np.array([10, 40, 0]), np.array([2.0, 10.0, 1.0])
    # 10 e^{-0.4} > 40 e^{-2} at lambda 0.2; 40 e^{-1} > 10 e^{-0.2} at lambda 0.1
    assert best(gains, distances, 0.2) == 0
    assert best(gains, distances, 0.1) == 1
    assert best(gains, distances, 0.0) == 1  # lambda = 0: the largest gain
    # paths so long that exp(-lambda L) underflows still rank by the utility
    assert best(np.array([5, 50]), np.array([4000.0, 4010.0]), 0.2) == 1


# ---------------------------------------------------------------- installed for real


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The package installed by pip into a fresh folder (as into site-packages).

    pip builds from a copy: an in-tree build would leave ``build/`` and
    ``*.egg-info`` in the example folder.
    """
    root = tmp_path_factory.mktemp("plugin")
    source, target = root / "source", root / "site"
    shutil.copytree(PACKAGE, source, ignore=shutil.ignore_patterns("build", "*.egg-info"))
    pip = [sys.executable, "-m", "pip"]
    if subprocess.run([*pip, "--version"], capture_output=True).returncode != 0:
        pytest.skip(f"pip is not installed for {sys.executable}")
    argv = [*pip, "install", "--quiet", "--disable-pip-version-check", "--no-deps"]
    argv += ["--no-build-isolation", "--no-index", "--target", str(target), str(source)]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=120)
    # The dev extra pins setuptools >= 77, which builds wheels without the `wheel`
    # package: a failure here is a real one, never a skip.
    assert done.returncode == 0, done.stderr
    assert (target / "utility_frontier.py").is_file()
    return target


def _cli(installed: Path, *args: str, timeout: float) -> subprocess.CompletedProcess[str]:
    """``python -m mrexplore ARGS`` with the installed package on the path."""
    path = os.pathsep.join([str(installed), str(REPO / "src")])
    env = {**os.environ, "PYTHONPATH": path}
    done = subprocess.run(
        [sys.executable, "-m", "mrexplore", *args],
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert done.returncode == 0, f"mrexplore {' '.join(args)}:\n{done.stderr}"
    return done


def test_the_installed_package_is_listed_and_runs(installed: Path, tmp_path: Path) -> None:
    listing = _cli(installed, "strategies", timeout=60).stdout
    line = next((x for x in listing.splitlines() if x.split()[:1] == [STRATEGY]), "")
    assert line, f"{STRATEGY} not listed:\n{listing}"
    out = tmp_path / "run"
    argv = ["run", "--map", "sheng40", "--robots", "2", "--strategy", STRATEGY]
    _cli(installed, *argv, "--seed", "1", "--out", str(out), timeout=120)
    result = json.loads((out / "result.json").read_text())
    assert result["strategy"] == STRATEGY
    assert result["status"] == "complete"


def _markdown_tables(text: str) -> list[list[list[str]]]:
    """Every Markdown table of ``text``: its rows (header first, the rule left out) as
    lists of cell texts without code ticks or emphasis."""
    tables: list[list[list[str]]] = []
    rows: list[list[str]] = []
    for line in [*text.splitlines(), ""]:
        if line.lstrip().startswith("|"):
            cells = [c.strip().strip("`*_ ") for c in line.strip().strip("|").split("|")]
            if not all(re.fullmatch(r":?-+:?", c) for c in cells):
                rows.append(cells)
        elif rows:
            tables.append(rows)
            rows = []
    return tables


def _html_rows(text: str) -> list[list[str]]:
    """The cell texts (tags stripped) of every ``<tr>`` of an HTML page."""
    rows = []
    for row in re.findall(r"<tr\b.*?</tr>", text, flags=re.S | re.I):
        cells = re.findall(r"<t[dh]\b[^>]*>(.*?)</t[dh]>", row, flags=re.S | re.I)
        rows.append([html.unescape(re.sub(r"<[^>]+>", "", c)).strip() for c in cells])
    return rows


def test_the_quick_suite_ranks_the_plugin(installed: Path, tmp_path: Path) -> None:
    """docs/benchmark.md, end to end: run the quick suite with the plugin and two
    built-ins, report, and find the plugin in every leaderboard table that ranks
    strategies."""
    bench = tmp_path / "bench"
    strategies = f"{STRATEGY},nearest-frontier,burgard"
    run = ["suite", "run", "standard-v1-quick", "--strategies", strategies]
    _cli(installed, *run, "--out", str(bench), "--workers", "2", "--no-progress", timeout=1800)
    _cli(installed, "suite", "report", str(bench), timeout=300)

    tables = _markdown_tables((bench / "leaderboard.md").read_text())
    ranking = [t for t in tables if any("nearest-frontier" in row for row in t[1:])]
    assert ranking, "leaderboard.md has no table with a nearest-frontier row"
    for table in ranking:
        assert any(STRATEGY in row for row in table[1:]), f"no {STRATEGY} row in {table}"

    rows = _html_rows((bench / "leaderboard.html").read_text())
    assert any(STRATEGY in row for row in rows), f"leaderboard.html has no {STRATEGY} row"
