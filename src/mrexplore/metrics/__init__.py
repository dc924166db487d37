"""Metrics computed from a run record and ground truth."""

from mrexplore.metrics.core import (
    coverage_curve,
    group_diameter,
    json_safe,
    summarize,
    time_to_fraction,
)
from mrexplore.metrics.regions import (
    REGION_COUNTS,
    epv,
    final_epv,
    final_wtv,
    region_curves,
    region_tiling,
    split_regions,
    waiting_times,
    wtv,
)

__all__ = [
    "REGION_COUNTS",
    "coverage_curve",
    "epv",
    "final_epv",
    "final_wtv",
    "group_diameter",
    "json_safe",
    "region_curves",
    "region_tiling",
    "split_regions",
    "summarize",
    "time_to_fraction",
    "waiting_times",
    "wtv",
]
