"""Finding the real maps of the shared collection (``../shared/maps``).

The collection is looked up in ``$MREXPLORE_MAPS``, then ``../shared/maps`` and
``shared/maps`` from the current folder, then next to the source checkout.
"""

from __future__ import annotations

import os
from pathlib import Path

_MAP_PATTERNS = ("ros/**/*.yaml", "movingai/*.map")


def shared_maps_dir() -> Path | None:
    """The folder of the shared map collection, if one is present."""
    candidates = []
    if env := os.environ.get("MREXPLORE_MAPS"):
        candidates.append(Path(env))
    candidates += [Path("../shared/maps"), Path("shared/maps")]
    candidates.append(Path(__file__).resolve().parents[3] / ".." / "shared" / "maps")
    for candidate in candidates:
        if (candidate / "ros").is_dir() or (candidate / "movingai").is_dir():
            return candidate
    return None


def shared_maps() -> list[Path]:
    """Every loadable map file of the shared collection (sorted), or ``[]``."""
    root = shared_maps_dir()
    if root is None:
        return []
    found: list[Path] = []
    for pattern in _MAP_PATTERNS:
        found.extend(root.glob(pattern))
    return sorted(found)
