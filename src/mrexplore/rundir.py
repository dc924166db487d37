"""Run folders (``mrexplore run --out DIR``): writing one, what holds a run, and
replacing one whole.

:func:`save_run` writes a run's data (:meth:`mrexplore.sim.RunRecord.save`) and its
pictures (:mod:`mrexplore.viz`) into a folder.

A folder *holds a run* when any of :data:`RUN_FILES` is in it. ``mrexplore run``
refuses such a folder, and any other non-empty folder, unless ``--force``; an
empty or new folder is fine. Whatever the case, the run is first written into a
fresh staging folder and only moved into place once every file is complete
(:func:`staged_dir`), so a crash or a failed run never leaves a folder that mixes
two runs, and never a half-written run in place of an earlier one:

* a new folder: the staging folder is a hidden sibling, renamed to ``DIR``;
* an existing empty folder: the staging folder is hidden inside it, and its
  files are moved up (``DIR`` itself stays, with its owner and permissions);
* a folder to replace (``--force``): the staging folder is a hidden sibling;
  ``DIR`` is renamed aside (``.DIR.old-*``), the staging folder renamed to
  ``DIR``, then the old folder deleted. If the process dies between the two
  renames, the old run is still whole in ``.DIR.old-*``.
"""

from __future__ import annotations

import os
import shutil
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from mrexplore.errors import MrexploreInputError, RunDirError

if TYPE_CHECKING:
    from mrexplore.sim.record import RunRecord

RUN_FILES = ("result.json", "trace.npz", "final.png", "run.gif", "run.mp4", "replay.html")
"""Files whose presence makes a folder hold a run."""

RUN_FILE_KINDS = {
    "result.json": "result",
    "trace.npz": "trace",
    "final.png": "final",
    "run.gif": "gif",
    "run.mp4": "mp4",
}
"""The kind :func:`save_run` returns each file of a run under."""


def run_files(folder: str | Path) -> list[str]:
    """The :data:`RUN_FILES` present in ``folder`` (empty if it is not a folder)."""
    path = Path(folder)
    if not path.is_dir():
        return []
    return [name for name in RUN_FILES if (path / name).exists()]


def _listing(names: list[str], limit: int = 4) -> str:
    shown = ", ".join(names[:limit])
    return shown + (f" and {len(names) - limit} more" if len(names) > limit else "")


def check_out_dir(out: str | Path, *, option: str = "out_dir") -> None:
    """Raise :class:`RunDirError` unless ``out`` is, or can become, a writable folder.

    Checked before time is spent on a run; ``option`` names ``out`` in the message.
    """
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise RunDirError(f"{option} {out}: exists and is not a folder")
    parent = path if path.exists() else next((p for p in path.parents if p.exists()), Path("."))
    if not parent.is_dir():
        raise RunDirError(f"{option} {out}: {parent} is a file, not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise RunDirError(f"{option} {out}: folder {parent} is not writable")


def check_ffmpeg(mp4: bool) -> None:
    """Raise :class:`~mrexplore.errors.MrexploreInputError` if an MP4 is wanted but no
    encoder is found (:func:`mrexplore.viz.ffmpeg_path`)."""
    if not mp4:
        return
    from mrexplore.viz.animate import FFMPEG_MISSING, ffmpeg_path

    if ffmpeg_path() is None:
        raise MrexploreInputError(FFMPEG_MISSING)


def check_run_dir(out: str | Path, *, force: bool = False, option: str = "--out") -> None:
    """Raise :class:`RunDirError` unless a run may be written to ``out``.

    Without ``force``: ``out`` must be new or an empty folder. With ``force`` an
    existing folder will be replaced whole, except one that holds the current
    folder or the home folder.
    """
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise RunDirError(f"{option} {out}: exists and is not a folder")
    if not path.exists():
        return
    present = run_files(path)
    others = sorted(p.name for p in path.iterdir() if p.name not in present)
    if not force:
        if present:
            raise RunDirError(
                f"{option} {out}: already holds a run ({_listing(present)}); add --force to "
                "replace the folder whole, or choose another folder"
            )
        if others:
            raise RunDirError(
                f"{option} {out}: folder is not empty and holds no run ({_listing(others)}); "
                "add --force to replace it whole (its files are deleted), or choose a new "
                "or empty folder"
            )
        return
    if not present and not others:
        return
    target = Path(os.path.realpath(path))
    for keep, what in ((Path.cwd(), "the current folder"), (Path.home(), "the home folder")):
        if keep.resolve().is_relative_to(target):
            raise RunDirError(
                f"{option} {out}: is or holds {what}; --force will not replace it, "
                "choose another folder"
            )
    if not os.access(target.parent, os.W_OK):
        raise RunDirError(
            f"{option} {out}: --force needs to write in {target.parent}, which is not writable"
        )


def _fsync_tree(folder: Path) -> None:
    """Flush every file of ``folder`` and the folder itself to disk."""
    for entry in folder.iterdir():
        if entry.is_file():
            with open(entry, "rb") as handle:
                os.fsync(handle.fileno())
    _fsync_dir(folder)


def _fsync_dir(folder: Path) -> None:
    try:
        descriptor = os.open(folder, os.O_RDONLY)
    except OSError:  # e.g. not supported on this platform
        return
    try:
        os.fsync(descriptor)
    except OSError:
        pass
    finally:
        os.close(descriptor)


@contextmanager
def staged_dir(out: str | Path) -> Iterator[Path]:
    """Yield an empty staging folder; on a normal exit its files become ``out``,
    which is replaced whole if it exists. On an exception the staging folder is
    deleted and ``out`` is left as it was.

    The caller decides whether ``out`` may be replaced (:func:`check_run_dir`).
    """
    target = Path(os.path.realpath(out))
    tag = uuid.uuid4().hex[:12]
    inside = target.is_dir() and not any(target.iterdir())
    if inside:  # an empty folder: keep it (owner, permissions) and fill it
        stage = target / f".mrexplore-new-{tag}"
    else:
        target.parent.mkdir(parents=True, exist_ok=True)
        stage = target.parent / f".{target.name}.new-{tag}"
    stage.mkdir()
    try:
        yield stage
        _fsync_tree(stage)
        if inside:
            for entry in list(stage.iterdir()):
                os.replace(entry, target / entry.name)
            stage.rmdir()
        elif not target.exists():
            os.rename(stage, target)
        else:
            old = target.parent / f".{target.name}.old-{tag}"
            os.rename(target, old)
            try:
                os.rename(stage, target)
            except BaseException:
                os.rename(old, target)
                raise
            shutil.rmtree(old, ignore_errors=True)
        _fsync_dir(target.parent)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise


def save_run(
    record: RunRecord,
    out_dir: str | Path,
    *,
    png: bool = True,
    gif: bool = False,
    mp4: bool = False,
    belief_panels: bool = False,
    max_frames: int | None = None,
    replace: bool = False,
) -> dict[str, Path]:
    """Write ``result.json``, ``trace.npz``, ``final.png`` (and ``run.gif``, ``run.mp4``).

    The files of ``mrexplore run --out``: the data of :meth:`RunRecord.save
    <mrexplore.sim.RunRecord.save>`, then the pictures. The animations are those of
    :func:`mrexplore.viz.save_animation` (links, targets, header; one panel per
    robot's own belief with ``belief_panels``, which needs ``robot_first_known``);
    ``max_frames`` defaults to 300. An MP4 needs an ffmpeg (:func:`mrexplore.viz.ffmpeg_path`).

    ``replace`` as in :meth:`RunRecord.save <mrexplore.sim.RunRecord.save>`: data and
    pictures are written into a staging folder that then replaces ``out_dir`` whole.
    Returns the paths written, by kind (``result``, ``trace``, ``final``, ``gif``,
    ``mp4``).
    """
    if replace:
        with staged_dir(out_dir) as stage:
            staged = save_run(
                record,
                stage,
                png=png,
                gif=gif,
                mp4=mp4,
                belief_panels=belief_panels,
                max_frames=max_frames,
            )
        return {name: Path(out_dir) / path.name for name, path in staged.items()}
    out = Path(out_dir)
    written = record.save(out)
    if png or gif or mp4:
        from mrexplore import viz

        arrays = record.trace_arrays()
        grid = record.world.grid
        title = f"{record.scenario.strategy}, {record.scenario.robots} robots on {grid.name}"
        if png:
            written["final"] = viz.save_final_png(
                out / "final.png",
                arrays["truth"],
                record.first_known,
                record.positions,
                title=f"{title}: {record.status} at tick {record.ticks}",
                credit=grid.credit,
                alive=record.alive,
                explorable=record.world.explorable,
                estimated_positions=arrays.get("estimated_positions"),
            )
        frames = {"max_frames": max_frames} if max_frames is not None else {}
        for wanted, name in ((gif, "gif"), (mp4, "mp4")):
            if wanted:
                written[name] = viz.save_animation(
                    out / f"run.{name}",
                    arrays,
                    belief_panels=belief_panels,
                    title=title,
                    **frames,
                )
    return written
