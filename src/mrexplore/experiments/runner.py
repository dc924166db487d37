"""One run of a sweep, as rows of the results store.

:func:`execute` is what every engine ships to its workers: it runs one
:class:`~mrexplore.experiments.sweep.RunSpec` and returns its row of the ``runs``
table and its rows of the ``curves`` table, plain Python values only (cheap to
pickle). A run that raises becomes a row with ``status = "failed"`` and the error,
so one bad run never stops a sweep.
"""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mrexplore import __version__
from mrexplore.experiments.sweep import RunSpec
from mrexplore.sim.scenario import Scenario

REGION_COUNTS = (2, 4, 8, 16, 32, 64)

TIMING_COLUMNS = ("wall_time_s", "decide_ms_per_plan")
"""Columns that measure the machine, not the run: they differ between engines and
repetitions; every other column is a function of the scenario."""


@dataclass
class RunOutcome:
    """A finished (or failed) run: its ``runs`` row and its ``curves`` columns."""

    run_id: str
    row: dict[str, Any]
    curves: dict[str, list[Any]] = field(default_factory=dict)

    @property
    def failed(self) -> bool:
        return bool(self.row.get("status") == "failed")


def scenario_columns(scenario: Scenario) -> dict[str, Any]:
    """The scenario as flat columns named like ``run``'s long options.

    ``params`` become ``param_<name>`` columns, ``sharing_params`` ``share_<name>``,
    ``comm_params`` ``comm_<name>`` (as ``--comm name=value``), ``sensor_params``
    ``sensor_<name>`` and ``odometry_params`` ``odometry_<name>`` (``--sensor``,
    ``--odometry``); ``size`` is ``"WxH"``, ``start`` and ``fail`` are text.
    """
    data = scenario.to_dict()
    params = data.pop("params")
    share = data.pop("sharing_params")
    comm = data.pop("comm_params")
    sensor = data.pop("sensor_params")
    odometry = data.pop("odometry_params")
    out: dict[str, Any] = {}
    for key, value in data.items():
        if key == "start" and not isinstance(value, str):
            value = ";".join(f"{r},{c}" for r, c in value)
        elif key in ("fail", "fail_at_coverage"):
            value = ",".join(value) if value else None
        out[key] = value
    out.update({f"param_{k}": _scalar(v) for k, v in params.items()})
    out.update({f"share_{k}": _scalar(v) for k, v in share.items()})
    out.update({f"comm_{k}": _scalar(v) for k, v in comm.items()})
    out.update({f"sensor_{k}": _scalar(v) for k, v in sensor.items()})
    out.update({f"odometry_{k}": _scalar(v) for k, v in odometry.items()})
    return out


def execute(spec: RunSpec) -> RunOutcome:
    """Run one scenario; never raises for a failing run (it is recorded as failed)."""
    from mrexplore.metrics import NOISY_METRICS
    from mrexplore.sim.engine import Simulation

    started = time.perf_counter()
    base = {"run_id": spec.run_id, **dict(spec.tags), **scenario_columns(spec.scenario)}
    try:
        # Per-robot beliefs are for viewers; a sweep stores no traces.
        record = Simulation(spec.scenario, record_beliefs=False).run()
        result = record.result()
        trace = record.trace_arrays()
        curves = run_curves(trace, record.bytes_per_tick, spec.curves_every)
    except Exception as error:  # one failing run must not stop the sweep
        row = {
            **base,
            "status": "failed",
            "error": f"{type(error).__name__}: {error}",
            "traceback": traceback.format_exc(limit=8),
            "wall_time_s": time.perf_counter() - started,
            "mrexplore_version": __version__,
        }
        return RunOutcome(spec.run_id, row)
    row = {**base, **metric_columns(result, base), "error": None}
    for name in NOISY_METRICS:  # one schema for every sweep: null without noise
        row.setdefault(name, None)
    row["wall_time_s"] = time.perf_counter() - started
    row["mrexplore_version"] = __version__
    curves["run_id"] = [spec.run_id] * len(curves["tick"])
    return RunOutcome(spec.run_id, row, curves)


_NOT_METRICS = (
    "params",
    "sharing_params",
    "comm_params",
    "sensor_params",
    "odometry_params",
    "mrexplore_version",
)


def metric_columns(result: dict[str, Any], scenario: dict[str, Any]) -> dict[str, Any]:
    """Scalar columns of ``result.json`` that are not scenario settings.

    Dicts are flattened one level (``bytes_by_type`` -> ``bytes_by_type_map``);
    lists become JSON text; ``"inf"``/``"nan"`` strings (strict JSON) become floats;
    the limits the run used when the scenario left them automatic are
    ``max_ticks_in_force`` and ``sharing_in_force``.
    """
    import json

    out: dict[str, Any] = {}
    for key, value in result.items():
        if key in ("max_ticks", "sharing"):  # resolved values, when the scenario left them
            out[f"{key}_in_force"] = value
            continue
        if key in scenario or key in _NOT_METRICS:
            continue
        if isinstance(value, dict):
            for sub, sub_value in sorted(value.items()):
                out[f"{key}_{sub}"] = _scalar(sub_value)
        elif isinstance(value, list):
            out[key] = json.dumps(value)
        else:
            out[key] = _scalar(value)
    return out


def run_curves(
    trace: dict[str, np.ndarray], bytes_per_tick: np.ndarray, every: int
) -> dict[str, list[Any]]:
    """Curves over time sampled every ``every`` ticks and at the last tick: coverage,
    cumulative bytes, sub-networks, group diameter, WTV and EPV for 2..64 regions."""
    from mrexplore.metrics.regions import region_curves

    n_ticks = int(trace["positions"].shape[0])
    regions = region_curves(trace, region_counts=REGION_COUNTS, every=every)
    ticks = np.asarray(regions["tick"], dtype=np.int64)
    if ticks.size == 0 or ticks[-1] != n_ticks - 1:  # the helper's sampling, checked
        raise AssertionError("region_curves must sample the last tick")
    out: dict[str, list[Any]] = {
        "tick": ticks.tolist(),
        "coverage": np.asarray(trace["coverage"])[ticks].tolist(),
        "bytes_total": np.cumsum(bytes_per_tick)[ticks].astype(np.float64).tolist(),
        "subnetworks": np.asarray(trace["subnetworks"])[ticks].tolist(),
        "group_diameter": np.asarray(trace["group_diameter"])[ticks].tolist(),
    }
    for name, values in regions.items():
        if name != "tick":
            out[name] = np.asarray(values, dtype=np.float64).tolist()
    return out


def _scalar(value: Any) -> Any:
    if isinstance(value, str) and value in ("inf", "-inf", "nan"):
        return float(value)
    if isinstance(value, np.generic):
        return value.item()
    return value
