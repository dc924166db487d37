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


def run(
    scenario: Scenario,
    out_dir: str | None = None,
    *,
    png: bool = True,
    gif: bool = False,
    mp4: bool = False,
    belief_panels: bool = False,
    max_frames: int | None = None,
    force: bool = False,
    option: str = "out_dir",
) -> dict[str, Any]:
    """Run ``scenario``; return the content of ``result.json`` (and write files to ``out_dir``).

    What ``mrexplore run`` does: bad input is refused before the run starts
    (:class:`~mrexplore.errors.MrexploreInputError`), in the order the run meets it:
    the scenario, the folder being writable, an MP4 encoder for ``mp4``, the map and
    start cells, then ``out_dir`` being new or empty (or replaced whole with
    ``force``). The files are those of :func:`save_run` (``final.png``, and ``run.gif``
    / ``run.mp4`` with one panel per robot's own map with ``belief_panels``), written
    aside and swapped in whole. ``option`` names ``out_dir`` in error messages (the CLI
    passes ``--out``).
    """
    from mrexplore.rundir import check_ffmpeg, check_out_dir, check_run_dir, save_run
    from mrexplore.sim.engine import Simulation

    scenario.check()  # fields, map, strategy, sharing and their parameters
    if out_dir is not None:
        check_out_dir(out_dir, option=option)
        check_ffmpeg(mp4)
    simulation = Simulation(scenario, record_beliefs=True if belief_panels else None)
    if out_dir is not None:  # after the map and start cells: their errors come first
        check_run_dir(out_dir, force=force, option=option)
    record = simulation.run()
    if out_dir is not None:
        save_run(
            record,
            out_dir,
            png=png,
            gif=gif,
            mp4=mp4,
            belief_panels=belief_panels,
            max_frames=max_frames,
            replace=True,  # written aside, then swapped in whole
        )
    return record.result()
