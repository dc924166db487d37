"""Shared fixtures.

Real maps come from the package's catalogue (:mod:`mrexplore.grid.catalogue`), so
no test depends on a folder outside the repository. A user's ``$MREXPLORE_MAPS``
must not change what a test loads either: it is cleared for every test (tests of
user map folders set it themselves).
"""

from __future__ import annotations

from pathlib import Path

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
