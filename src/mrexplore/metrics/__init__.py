"""Metrics computed from a run record and ground truth."""

from mrexplore.metrics.core import (
    coverage_curve,
    group_diameter,
    json_safe,
    summarize,
    time_to_fraction,
)

__all__ = ["coverage_curve", "group_diameter", "json_safe", "summarize", "time_to_fraction"]
