"""Report figures added for the visual side: group diameter over time."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyarrow as pa
from PIL import Image

from mrexplore.viz.plots import label_for, plot_group_diameter, strategy_colour


def test_group_diameter_over_time_draws_one_band_per_strategy(tmp_path: Path) -> None:
    runs = pa.table({"run_id": ["a", "b", "c"], "strategy": ["burgard", "burgard", "kme"]})
    curves = pa.table(
        {
            "run_id": ["a"] * 3 + ["b"] * 3 + ["c"] * 2,
            "tick": [0, 10, 20, 0, 10, 20, 0, 10],
            "group_diameter": [1.0, 8.0, 12.0, 1.5, 9.0, 14.0, 1.0, 30.0],
        }
    )
    path = plot_group_diameter(curves, runs, tmp_path / "diameter.png")
    with Image.open(path) as image:
        rgb = np.asarray(image.convert("RGB"))
    pixels = {tuple(int(v) for v in pixel) for pixel in np.unique(rgb.reshape(-1, 3), axis=0)}
    for strategy in ("burgard", "kme"):
        colour = strategy_colour(strategy)
        assert tuple(int(colour[i : i + 2], 16) for i in (1, 3, 5)) in pixels
    assert label_for("group_diameter") == "group diameter (cells)"
