"""mrexplore: simulate and compare multi-robot exploration strategies.

>>> import mrexplore
>>> result = mrexplore.run(mrexplore.Scenario(map="sheng40", robots=2, seed=1))
>>> result["status"]
'complete'
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

if TYPE_CHECKING:
    from mrexplore.rundir import save_run
    from mrexplore.sim import RunRecord, Scenario

__all__ = ["Scenario", "__version__", "run", "save_run", "simulate"]


def __getattr__(name: str) -> Any:
    if name == "Scenario":
        from mrexplore.sim.scenario import Scenario

        return Scenario
    if name == "save_run":  # data and pictures of a run, as `mrexplore run --out` writes them
        from mrexplore.rundir import save_run

        return save_run
    raise AttributeError(f"module 'mrexplore' has no attribute {name!r}")


def simulate(scenario: Scenario) -> RunRecord:
    """Run ``scenario`` and return the full :class:`~mrexplore.sim.RunRecord`."""
    from mrexplore.sim.engine import simulate as _simulate

    return _simulate(scenario)


def run(scenario: Scenario, out_dir: str | None = None, *, gif: bool = False) -> dict[str, Any]:
    """Run ``scenario``; return the content of ``result.json`` (and write files to ``out_dir``)."""
    from mrexplore.rundir import save_run

    record = simulate(scenario)
    if out_dir is not None:
        save_run(record, out_dir, gif=gif)  # data and pictures
    return record.result()
