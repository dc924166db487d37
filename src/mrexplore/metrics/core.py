"""Metrics computed from a run's trace arrays and ground truth (DESIGN §7).

Everything here is a pure function of the arrays stored in ``trace.npz``, so
anyone can recompute a run's metrics from its trace alone.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.metrics.map_quality import map_quality_metrics
from mrexplore.metrics.regions import final_epv, final_wtv

NOISY_METRICS = (
    "T90_correct",
    "T99_correct",
    "T100_correct",
    "localisation_error_mean",
    "localisation_error_max",
    "localisation_error_final",
)
"""Keys of ``result.json`` that only a noisy run has (:func:`summarize` computes them
from the arrays a noisy run's trace adds); the results store gives every run these
columns, null without noise."""


def coverage_curve(
    first_known: npt.NDArray[np.int32], explorable: npt.NDArray[np.bool_], n_ticks: int
) -> npt.NDArray[np.float64]:
    """Share of explorable cells known to the team at each tick ``0 .. n_ticks - 1``."""
    total = int(np.count_nonzero(explorable))
    if total == 0:
        return np.ones(n_ticks, dtype=np.float64)
    ticks = first_known[explorable]
    ticks = ticks[ticks >= 0]
    counts = np.bincount(ticks, minlength=n_ticks)[:n_ticks]
    return np.cumsum(counts) / total


def time_to_fraction(curve: npt.NDArray[np.float64], fraction: float) -> int | None:
    """First tick at which the coverage curve reaches ``fraction`` (``None`` if never)."""
    hits = np.nonzero(curve >= fraction - 1e-12)[0]
    return int(hits[0]) if hits.size else None


def group_diameter(positions: npt.NDArray[np.int32]) -> npt.NDArray[np.float64]:
    """Largest Euclidean distance between two robots at each tick (Sheng Fig. 11).

    One robot at a time against the robots after it, so the temporaries are
    ``T x N x 2`` rather than ``T x N x N x 2`` (64 robots over 3 000 ticks: 3 MB
    instead of 200 MB); the largest squared distance is taken before the square root
    (which is monotonic, so the result is the same to the bit).
    """
    ticks, n_robots = positions.shape[0], positions.shape[1]
    if n_robots < 2:
        return np.zeros(ticks, dtype=np.float64)
    points = positions.astype(np.float64)
    widest = np.zeros(ticks, dtype=np.float64)
    for i in range(n_robots - 1):
        diff = points[:, i + 1 :, :] - points[:, i : i + 1, :]
        np.maximum(widest, (diff**2).sum(axis=-1).max(axis=1), out=widest)
    return np.sqrt(widest)


def localisation_metrics(
    localisation_error: npt.NDArray[np.float64], alive: npt.NDArray[np.bool_]
) -> dict[str, float]:
    """How far the robots' position estimates were from where they were (cells).

    ``localisation_error`` and ``alive`` are ``T+1 x N`` (the trace's arrays).
    ``localisation_error_mean`` and ``localisation_error_max`` are over every tick
    and every robot alive at it; ``localisation_error_final`` is the mean over the
    robots alive at the last tick (over every robot when none is). All are 0.0
    without a live robot.

    >>> error = np.array([[0.0, 0.0], [1.0, 3.0], [2.0, 9.0]])
    >>> alive = np.array([[True, True], [True, True], [True, False]])
    >>> localisation_metrics(error, alive)  # robot 1 failed at tick 2
    {'localisation_error_mean': 1.2, 'localisation_error_max': 3.0, 'localisation_error_final': 2.0}
    """
    error = np.asarray(localisation_error, dtype=np.float64)
    live = np.asarray(alive, dtype=bool)
    seen = error[live]
    last = error[-1][live[-1]] if live[-1].any() else error[-1]
    return {
        "localisation_error_mean": float(seen.mean()) if seen.size else 0.0,
        "localisation_error_max": float(seen.max()) if seen.size else 0.0,
        "localisation_error_final": float(last.mean()) if last.size else 0.0,
    }


def summarize(trace: dict[str, Any]) -> dict[str, Any]:
    """The metrics of ``result.json`` from the trace arrays.

    Needs ``positions``, ``first_known``, ``explorable``, ``distance``,
    ``sense_count`` and ``alive``. The arrays of a noisy run add map quality:
    ``correct_coverage`` gives ``T90_correct``, ``T99_correct`` and ``T100_correct``
    (as ``T90``... of ``coverage``), ``localisation_error`` the
    :func:`localisation_metrics`, and ``robot_belief`` (with ``truth``) the
    :func:`~mrexplore.metrics.map_quality.map_quality_metrics`.
    """
    positions = trace["positions"]
    n_ticks = positions.shape[0]
    explorable = trace["explorable"]
    curve = coverage_curve(trace["first_known"], explorable, n_ticks)
    distance = trace["distance"][-1]
    sense_count = trace["sense_count"]
    sensed_explorable = sense_count[explorable & (sense_count > 0)]
    sensed_by_robot = trace.get("sensed_by_robot")
    alive_end = trace["alive"][-1]
    diameter = group_diameter(positions)
    metrics: dict[str, Any] = {
        "explorable_cells": int(np.count_nonzero(explorable)),
        "explored_fraction": float(curve[-1]),
        "T90": time_to_fraction(curve, 0.90),
        "T99": time_to_fraction(curve, 0.99),
        "T100": time_to_fraction(curve, 1.0),
        "total_distance": float(distance.sum()),
        "distance_per_robot": [float(d) for d in distance],
        "overlap": float(sensed_explorable.mean()) if sensed_explorable.size else 0.0,
        "robots_failed": int(np.count_nonzero(~alive_end)),
        "group_diameter_mean": float(diameter.mean()),
        "wtv_8_final": final_wtv(trace, 8),  # Wu, Puig & Garcia eq. (10), ticks²
        "epv_8_final": final_epv(trace, 8),  # Wu, Puig & Garcia §V.B, percent²
    }
    robot_complete = trace.get("robot_complete")
    if robot_complete is not None:  # the first tick each robot held the whole map itself
        ticks = [int(t) if t >= 0 else None for t in np.asarray(robot_complete)]
        metrics["T100_by_robot"] = ticks
        metrics["T100_first_robot"] = min((t for t in ticks if t is not None), default=None)
    if sensed_by_robot is not None:
        cells = np.asarray(sensed_by_robot, dtype=np.float64)
        mean = cells.mean()
        metrics["sensed_cells_per_robot"] = [int(c) for c in cells]
        metrics["coverage_spread"] = float(cells.std() / mean) if mean > 0 else 0.0
    robot_belief = trace.get("robot_belief")
    if robot_belief is not None:  # noisy runs: the robots' final maps
        metrics.update(map_quality_metrics(robot_belief, trace["truth"], explorable))
    correct_coverage = trace.get("correct_coverage")
    if correct_coverage is not None:  # noisy runs: coverage counted on correct cells only
        correct_curve = np.asarray(correct_coverage, dtype=np.float64)
        metrics["T90_correct"] = time_to_fraction(correct_curve, 0.90)
        metrics["T99_correct"] = time_to_fraction(correct_curve, 0.99)
        metrics["T100_correct"] = time_to_fraction(correct_curve, 1.0)
    localisation_error = trace.get("localisation_error")
    if localisation_error is not None:
        metrics.update(localisation_metrics(localisation_error, trace["alive"]))
    return metrics


def json_safe(value: Any) -> Any:
    """Replace non-finite floats by strings so the result is strict JSON."""
    if isinstance(value, float) and not math.isfinite(value):
        return "inf" if value > 0 else ("-inf" if value < 0 else "nan")
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_safe(v) for v in value]
    return value
