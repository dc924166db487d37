"""Shared fixtures: where the shared map collection is, small scenarios."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_MAPS = REPO / ".." / "shared" / "maps"


@pytest.fixture
def shared_maps() -> Path:
    if not (SHARED_MAPS / "ros").is_dir():
        pytest.skip("the shared map collection ../shared/maps is absent")
    return SHARED_MAPS
