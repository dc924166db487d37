"""Run a sweep into a results folder, on any engine, resumably."""

from __future__ import annotations

import os
import shutil
import sys
import time
import tomllib
import uuid
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

from mrexplore.errors import MrexploreInputError
from mrexplore.experiments.engines import Engine, WorkerLost, make_engine
from mrexplore.experiments.runner import RunOutcome, execute, scenario_columns
from mrexplore.experiments.store import COMPACT_AFTER, Store, StoreError
from mrexplore.experiments.sweep import (
    RunSpec,
    Sweep,
    SweepError,
    load_sweep,
    resume_differences,
    sweep_data,
    sweep_from_dict,
    sweep_to_toml,
)


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
    specs = sweep.runs()
    new_text = _sweep_text(sweep, source)
    if resume:
        _check_resume(sweep, specs, out, store, new_text)
    store.create()
    _record_sweep_file(root / "sweep.toml", new_text)
    return run_specs(specs, out, engine=engine, workers=workers, address=address, progress=progress)


def run_specs(
    specs: list[RunSpec],
    out: str | Path,
    *,
    engine: str | Engine = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: bool = True,
    desc: str = "sweep",
) -> SweepSummary:
    """Run every run of ``specs`` not yet stored in the results folder ``out`` and
    store its rows (the folder's checks are the caller's: :func:`run_sweep`, a suite)."""
    store = Store(out)
    store.create()
    store.recover()
    store.compact(minimum=COMPACT_AFTER)
    done = store.done_ids()
    todo = [spec for spec in specs if spec.run_id not in done]
    started = time.perf_counter()
    failed = finished = 0
    context = None
    if todo:  # before the bar: an engine that cannot start says so in one line
        context = (
            nullcontext(engine)
            if isinstance(engine, Engine)
            else make_engine(engine, workers, address)
        )
    bar = _progress(len(specs), len(specs) - len(todo), progress, desc)
    try:
        if context is not None:
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


def _sweep_text(sweep: Sweep, source: Path | None) -> str | None:
    """The text ``DIR/sweep.toml`` should hold for ``sweep``: its file, or for a sweep
    built in Python its TOML form (``None`` if a value has none)."""
    if source is not None:
        return source.read_text()
    try:
        return sweep_to_toml(sweep)
    except ValueError:
        return None


def _check_resume(
    sweep: Sweep, specs: list[RunSpec], out: str | Path, store: Store, new_text: str | None
) -> None:
    """Refuse to resume a folder with a sweep that does more than add seeds or grid
    values to the one the folder holds (the rows of two sweeps would mix)."""
    recorded = Path(out) / "sweep.toml"
    new_name = sweep.source if sweep.source != "<sweep>" else "the sweep"
    refuse = f"--out {out} --resume: {new_name} is not the sweep of this folder"
    ids = {spec.run_id for spec in specs}
    if recorded.is_file():
        old_text = recorded.read_text(errors="replace")
        try:
            old_data = tomllib.loads(old_text)
        except tomllib.TOMLDecodeError:
            old_data = None  # hand-edited into nonsense: only the rows can tell
        if old_data is not None and old_text != new_text:
            new_data = tomllib.loads(new_text) if new_text is not None else sweep_data(sweep)
            problems = resume_differences(old_data, new_data, str(recorded), new_name)
            try:
                old_ids = {spec.run_id for spec in sweep_from_dict(old_data, str(recorded)).runs()}
            except MrexploreInputError:  # no longer valid (a map file moved, ...)
                old_ids = None
            # The runs decide when both files expand (an explicit default is no change).
            if (old_ids is None and problems) or (old_ids is not None and not old_ids <= ids):
                detail = "; ".join(problems) or (
                    f"{len((old_ids or set()) - ids)} runs of {recorded} are not in {new_name}"
                )
                raise SweepError(
                    f"{refuse} and not one that only adds seeds or grid values: {detail}; "
                    "choose another --out folder"
                )
    strangers = store.done_ids() - ids
    if strangers:
        raise SweepError(
            f"{refuse}: {len(strangers)} of the runs stored in {out} are not runs of "
            f"{new_name} (another sweep, or another mrexplore version); choose another "
            "--out folder"
        )


def _record_sweep_file(path: Path, text: str | None) -> None:
    """Make ``DIR/sweep.toml`` describe the folder: write it if missing; if it holds
    another sweep (a resume that added seeds or grid values), keep it as
    ``sweep.toml.1`` (``.2``, ...) and write the new one. Atomic: ``sweep.toml``
    always exists once written."""
    if text is None:
        return
    if path.is_file():
        old = path.read_text(errors="replace")
        if old == text:
            return
        try:
            if tomllib.loads(old) == tomllib.loads(text):
                return  # comments or layout only
        except tomllib.TOMLDecodeError:
            pass
    temporary = path.with_name(f".{path.name}.{uuid.uuid4().hex}.tmp")
    with open(temporary, "w") as handle:
        handle.write(text)
        handle.flush()
        os.fsync(handle.fileno())
    if path.is_file():
        number = 1
        while True:
            kept = path.with_name(f"{path.name}.{number}")
            try:
                os.link(path, kept)  # never replaces an earlier kept file
                break
            except FileExistsError:
                number += 1
            except OSError:  # no hard links here: copy instead
                if kept.exists():
                    number += 1
                    continue
                shutil.copyfile(path, kept)
                break
    os.replace(temporary, path)


def _lost(spec: RunSpec, lost: WorkerLost) -> RunOutcome:
    from mrexplore import __version__

    row = {
        "run_id": spec.run_id,
        **dict(spec.tags),
        **scenario_columns(spec.scenario),
        "status": "failed",
        "error": f"WorkerLost: {lost}",
        "mrexplore_version": __version__,
    }
    return RunOutcome(spec.run_id, row)


def _progress(total: int, initial: int, enabled: bool, desc: str = "sweep"):  # type: ignore[no-untyped-def]
    """A tqdm bar on stderr: runs done (of all), failed, rate and ETA."""
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(
        total=total,
        initial=initial,
        unit="run",
        desc=desc,
        file=sys.stderr,
        dynamic_ncols=True,
        smoothing=0.1,
    )
