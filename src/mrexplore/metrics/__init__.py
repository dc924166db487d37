"""Metrics computed from a run record and ground truth."""

from mrexplore.metrics.core import (
    NOISY_METRICS,
    coverage_curve,
    group_diameter,
    json_safe,
    localisation_metrics,
    summarize,
    time_to_fraction,
)
from mrexplore.metrics.map_quality import (
    MapQuality,
    TeamCounter,
    map_quality,
    map_quality_metrics,
    team_counts,
    team_map,
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
    "NOISY_METRICS",
    "REGION_COUNTS",
    "MapQuality",
    "TeamCounter",
    "coverage_curve",
    "epv",
    "final_epv",
    "final_wtv",
    "group_diameter",
    "json_safe",
    "localisation_metrics",
    "map_quality",
    "map_quality_metrics",
    "region_curves",
    "region_tiling",
    "split_regions",
    "summarize",
    "team_counts",
    "team_map",
    "time_to_fraction",
    "waiting_times",
    "wtv",
]
