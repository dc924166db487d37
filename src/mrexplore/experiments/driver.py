"""Run a sweep into a results folder, on any engine, resumably."""

from __future__ import annotations

import shutil
import sys
import time
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

from mrexplore.experiments.engines import Engine, WorkerLost, make_engine
from mrexplore.experiments.runner import RunOutcome, execute, scenario_columns
from mrexplore.experiments.store import COMPACT_AFTER, Store, StoreError
from mrexplore.experiments.sweep import RunSpec, Sweep, load_sweep


@dataclass(frozen=True)
class SweepSummary:
    """What a call of :func:`run_sweep` did."""

    total: int
    skipped: int
    done: int
    failed: int
    wall_time_s: float


def run_sweep(
    sweep: Sweep | str | Path,
    out: str | Path,
    *,
    engine: str | Engine = "local",
    workers: int | None = None,
    address: str | None = None,
    resume: bool = False,
    progress: bool = True,
) -> SweepSummary:
    """Run every run of ``sweep`` not yet in ``out`` and store its rows.

    Without ``resume`` the folder must not hold results already (nothing written
    is ever overwritten). With ``resume`` only the runs missing from the store
    run: after a crash, or after adding seeds or grid values to the sweep file.
    """
    if not isinstance(sweep, Sweep):
        sweep = load_sweep(sweep)
    source = Path(sweep.source) if Path(sweep.source).is_file() else None
    store = Store(out)
    root = Path(out)
    if root.exists() and not root.is_dir():
        raise StoreError(f"--out {out}: exists and is not a folder")
    if store.exists() and not resume:
        if store.done_ids():
            raise StoreError(
                f"--out {out}: already holds sweep results; use --resume to complete them "
                "or choose another folder"
            )
    elif not store.exists() and root.exists() and any(root.iterdir()) and not resume:
        raise StoreError(f"--out {out}: folder is not empty and is not a results folder")
    store.create()
    store.recover()
    store.compact(minimum=COMPACT_AFTER)
    if source is not None and not (root / "sweep.toml").exists():
        shutil.copyfile(source, root / "sweep.toml")

    specs = sweep.runs()
    done = store.done_ids()
    todo = [spec for spec in specs if spec.run_id not in done]
    started = time.perf_counter()
    failed = finished = 0
    bar = _progress(len(specs), len(specs) - len(todo), progress)
    try:
        if todo:
            context = (
                nullcontext(engine)
                if isinstance(engine, Engine)
                else make_engine(engine, workers, address)
            )
            with context as runner:
                for spec, result in runner.imap_unordered(execute, todo):
                    outcome = result if isinstance(result, RunOutcome) else _lost(spec, result)
                    store.append(outcome)
                    finished += 1
                    failed += outcome.failed
                    if bar is not None:
                        bar.set_postfix(failed=failed, refresh=False)
                        bar.update(1)
                    if finished % COMPACT_AFTER == 0:
                        store.compact(minimum=COMPACT_AFTER)
    finally:
        if bar is not None:
            bar.close()
    store.compact()
    return SweepSummary(
        total=len(specs),
        skipped=len(specs) - len(todo),
        done=finished,
        failed=failed,
        wall_time_s=time.perf_counter() - started,
    )


def _lost(spec: RunSpec, lost: WorkerLost) -> RunOutcome:
    from mrexplore import __version__

    row = {
        "run_id": spec.run_id,
        **scenario_columns(spec.scenario),
        "status": "failed",
        "error": f"WorkerLost: {lost}",
        "mrexplore_version": __version__,
    }
    return RunOutcome(spec.run_id, row)


def _progress(total: int, initial: int, enabled: bool):  # type: ignore[no-untyped-def]
    """A tqdm bar on stderr: runs done (of all), failed, rate and ETA."""
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(
        total=total,
        initial=initial,
        unit="run",
        desc="sweep",
        file=sys.stderr,
        dynamic_ncols=True,
        smoothing=0.1,
    )
