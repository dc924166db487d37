"""Experiments: sweeps over scenarios, engines that run them, the results store.

>>> from mrexplore.experiments import sweep_from_dict
>>> sweep = sweep_from_dict({"sweep": {"seeds": [1, 2]}, "fixed": {"map": "sheng40"},
...                          "grid": {"robots": [2, 4], "strategy": ["burgard"]}})
>>> len(sweep)
4
"""

from __future__ import annotations

from mrexplore.experiments.driver import SweepSummary, run_sweep
from mrexplore.experiments.engines import ENGINES, EngineError, make_engine
from mrexplore.experiments.store import Store, StoreError, connect, query
from mrexplore.experiments.sweep import RunSpec, Sweep, SweepError, load_sweep, sweep_from_dict

__all__ = [
    "ENGINES",
    "EngineError",
    "RunSpec",
    "Store",
    "StoreError",
    "Sweep",
    "SweepError",
    "SweepSummary",
    "connect",
    "load_sweep",
    "make_engine",
    "query",
    "run_sweep",
    "sweep_from_dict",
]
