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
from mrexplore.experiments.suite import (
    Suite,
    SuiteError,
    load_suite,
    merge_folders,
    run_suite,
    shipped_suites,
)
from mrexplore.experiments.sweep import RunSpec, Sweep, SweepError, load_sweep, sweep_from_dict

__all__ = [
    "ENGINES",
    "EngineError",
    "RunSpec",
    "Store",
    "StoreError",
    "Suite",
    "SuiteError",
    "Sweep",
    "SweepError",
    "SweepSummary",
    "connect",
    "load_suite",
    "load_sweep",
    "make_engine",
    "merge_folders",
    "query",
    "run_suite",
    "run_sweep",
    "shipped_suites",
    "sweep_from_dict",
]
