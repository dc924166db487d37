"""Third-party plugins for real: a package written to disk, found through its entry
points, checked by the shipped checkers, and run through the command line.

The package holds the worked example ``examples/comm_plugin/log_distance_radio.py``
(entry-point group ``mrexplore.comm``) and a small strategy (group
``mrexplore.strategies``), with the ``.dist-info`` metadata pip would write.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from mrexplore.checks import check_comm_model, check_strategy
from mrexplore.comm import COMM_MODELS, Message, Network
from mrexplore.comm.models import CommSetup
from mrexplore.errors import CommModelError, UnknownIdError
from mrexplore.sim import Scenario, simulate
from mrexplore.strategies import get_strategy
from mrexplore.strategies.registry import STRATEGIES

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "examples" / "comm_plugin" / "log_distance_radio.py"
DIST = "mrexplore-test-plugins"

STRATEGY_MODULE = '''"""A third-party strategy: each robot heads for its farthest frontier cell."""

import numpy as np

from mrexplore.strategies.base import FrontierStrategy, reachable_frontier_cells


class FarthestFrontier(FrontierStrategy):
    id = "farthest-frontier"
    summary = "test plugin: the farthest reachable frontier cell"

    def choose_goal(self, view, frontier, dist):
        rows, cols = reachable_frontier_cells(frontier, dist)
        if rows.size == 0:
            return None
        best = int(np.argmax(dist[rows, cols]))
        return int(rows[best]), int(cols[best])
'''

ENTRY_POINTS = """[mrexplore.comm]
log-distance = log_distance_radio:LogDistanceRadio

[mrexplore.strategies]
farthest-frontier = farthest_frontier:FarthestFrontier
"""


def _forget_plugins() -> None:
    STRATEGIES.forget_plugins()
    COMM_MODELS.forget_plugins()
    for module in ("log_distance_radio", "farthest_frontier"):
        sys.modules.pop(module, None)


@pytest.fixture
def plugin_package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """An installed package (as pip leaves it in site-packages) on ``sys.path``."""
    (tmp_path / "log_distance_radio.py").write_text(EXAMPLE.read_text())
    (tmp_path / "farthest_frontier.py").write_text(STRATEGY_MODULE)
    info = tmp_path / "mrexplore_test_plugins-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {DIST}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(ENTRY_POINTS)
    monkeypatch.syspath_prepend(str(tmp_path))
    _forget_plugins()  # look again: a package was installed
    try:
        yield tmp_path
    finally:
        _forget_plugins()


def test_installed_plugins_are_found_through_entry_points(plugin_package: Path) -> None:
    strategy = get_strategy("farthest-frontier")
    model = COMM_MODELS.get("log-distance")
    assert strategy.__module__ == "farthest_frontier"
    assert model.__module__ == "log_distance_radio" and issubclass(model, Network)
    listed = {entry.id: entry for entry in COMM_MODELS.entries()}
    assert listed["log-distance"].plugin == DIST
    assert listed["network"].plugin is None
    assert "exponent" in listed["log-distance"].params


def test_installed_plugins_pass_their_checkers(plugin_package: Path) -> None:
    check_strategy("farthest-frontier")
    check_comm_model("log-distance")


def test_plugins_run_through_the_command_line(plugin_package: Path) -> None:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(plugin_package), str(REPO / "src")])}
    run = [sys.executable, "-m", "mrexplore"]
    listing = subprocess.run(
        [*run, "comm-models"], env=env, capture_output=True, text=True, check=True
    )
    assert "log-distance" in listing.stdout and f"[plugin: {DIST}]" in listing.stdout
    argv = [
        *run, "run", "--map", "sheng40", "--robots", "3", "--strategy", "farthest-frontier",
        "--comm-model", "log-distance", "--comm", "exponent=3.5", "--seed", "2", "--json",
    ]  # fmt: skip
    done = subprocess.run(argv, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["status"] == "complete"
    assert result["strategy"] == "farthest-frontier"
    assert result["comm_model"] == "log-distance"
    assert result["comm_params"] == {"exponent": 3.5}
    assert result["comm_description"].startswith("log-distance n=3.5")
    bad = subprocess.run(
        [*argv[:-1], "--comm", "exponent=0.5"], env=env, capture_output=True, text=True
    )
    assert bad.returncode == 2 and "--comm exponent=0.5" in bad.stderr


def test_the_example_model_refuses_a_fixed_range(plugin_package: Path) -> None:
    with pytest.raises(Exception, match="link budget"):
        simulate(Scenario(map="sheng40", robots=2, comm_model="log-distance", comm_range=5))


def test_packet_error_rate_grows_with_distance(plugin_package: Path) -> None:
    import log_distance_radio as radio

    snrs = [
        radio.mean_snr_db(
            d, exponent=3.0, pl_d0_db=55.0, d0_m=1.0, tx_power_dbm=0.0, noise_dbm=-105.0
        )
        for d in (5.0, 15.0, 20.0, 22.0, 25.0, 30.0)
    ]
    success = [radio.packet_success(snr, 100, 1.5625) for snr in snrs]
    assert success == sorted(success, reverse=True) and success[0] > 0.999 > 1e-6 > success[-1]
    # a longer packet fails more often over the same link
    assert radio.packet_success(snrs[3], 200, 1.5625) < radio.packet_success(snrs[3], 20, 1.5625)


def test_unknown_plugin_ids_stay_input_errors(plugin_package: Path) -> None:
    with pytest.raises(UnknownIdError, match="known: log-distance, network"):
        COMM_MODELS.get("psychic")


class _EchoNetwork(Network):
    """A broken model: every message also comes back to its sender."""

    id = "test-echo"
    summary = "broken on purpose"

    @classmethod
    def from_setup(cls, setup: CommSetup, **params: object) -> _EchoNetwork:
        return cls(setup.n_robots, Network.from_setup(setup).link_model)

    def deliver(self, tick: int) -> dict[int, list[Message]]:
        inbox = super().deliver(tick)
        echoes = [message for messages in inbox.values() for message in messages]
        for message in echoes:
            inbox.setdefault(message.sender, []).append(message)
        return inbox


def test_the_checker_catches_a_model_that_breaks_the_protocol() -> None:
    COMM_MODELS.register(_EchoNetwork)
    try:
        with pytest.raises(CommModelError, match="from itself"):
            check_comm_model("test-echo")
    finally:
        COMM_MODELS.unregister("test-echo")
