"""Shared fixtures.

Real maps come from the package's catalogue (:mod:`mrexplore.grid.catalogue`), so
no test depends on a folder outside the repository. A user's ``$MREXPLORE_MAPS``
must not change what a test loads either: it is cleared for every test (tests of
user map folders set it themselves).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mrexplore.grid.catalogue import MAPS_ENV


@pytest.fixture(autouse=True)
def _no_user_map_folders(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(MAPS_ENV, raising=False)


def quick_reproduction(factory: pytest.TempPathFactory, paper: str, reading: str) -> Path:
    """``mrexplore reproduce PAPER --quick`` through the CLI with one reading only (one
    keeps the suite short: it re-runs only the experiments that reading changes)."""
    from mrexplore.cli import main

    out = factory.mktemp(f"{paper}-quick")
    argv = ["reproduce", paper, "--quick", "--out", str(out), "--no-progress"]
    assert main([*argv, "--interpretations", reading]) == 0
    return out


def robot_view(belief: np.ndarray, position: tuple[int, int], **fields: Any) -> Any:
    """A :class:`~mrexplore.strategies.base.RobotView` of robot 0 alone at tick 1, with no
    goal and an empty inbox; ``fields`` override any of its fields."""
    from mrexplore.strategies.base import RobotView

    defaults: dict[str, Any] = {
        "robot_id": 0, "n_robots": 1, "tick": 1, "goal": None, "path_remaining": 0,
        "arrived": False, "blocked": False, "inbox": (), "subnetwork": frozenset({0}),
        "sensor_range": 4.0, "speed": 1.0, "rng": np.random.default_rng(0), "new_cells": 0,
    }  # fmt: skip
    return RobotView(belief=belief, position=position, **{**defaults, **fields})
