"""A self-contained HTML replay of a run: ``mrexplore replay RUN_DIR``.

:func:`write_replay` turns a run folder (``trace.npz`` and ``result.json``) into
one ``replay.html`` that any browser opens without a network: the page's script
and style are inline, and the run's arrays are embedded compactly, each
little-endian in the narrowest integer type that holds it, compressed with zlib
(``deflate``) and base64-encoded; the page inflates them with the browser's own
``DecompressionStream``. Positions and targets are sent as per-tick deltas,
failures as one tick per robot, and the team's map as ``first_known`` alone: the
page sorts the cells by that tick once and then paints only the cells that change
between two frames, so playing or seeking costs the cells that changed, not the
whole map (1000 x 1000 cells and 5,000 ticks stay fluid).

The page shows the map (ground truth faint, the team's known map, robots, paths,
targets, links coloured by sub-network, failed robots crossed out), the tick, the
coverage, the bytes sent and the number of sub-networks, and under the map the
coverage, bytes and sub-network curves with a cursor at the current tick. It has
play/pause (space), a time slider (arrow keys step), a speed menu (ticks per
second), toggles for links, targets, trails and per-robot beliefs, and a click on
a curve jumps to that tick. Stable element ids (``#tick``, ``#coverage``,
``#bytes``, ``#subnetworks``, ``#play``, ``#slider``, ``#speed``,
``#show-links``, ``#show-targets``, ``#show-trails``, ``#show-beliefs``) make it
scriptable; ``window.replay`` exposes ``seek(tick)``, ``play()``, ``pause()`` and
``benchmark(frames)`` (mean milliseconds to draw a frame). A fragment opens the page
at a moment with chosen layers: ``replay.html#tick=250&beliefs=1&links=0``
(also ``targets``, ``trails``, ``believed``, ``speed``).

A noisy run's trace (:mod:`mrexplore.viz.noise`) adds, when it has them: each
robot's believed cell (``estimated_positions``, sent as per-tick deltas like the
positions) drawn as a hollow square in its colour joined to the robot by a thin
line, with a toggle ``#show-believed``; the mean and largest localisation error
(``#localisation``); and belief panels coloured by each robot's final belief
(``robot_belief``), with the cells it holds wrongly tinted red. As in the
animation (:mod:`mrexplore.viz.animate`), a panel shows a cell from the tick the
robot first knew it, with the value it held at the end of the run.

Maps wider or taller than :data:`MAX_MAP_CELLS` cells are embedded reduced by
whole blocks (each block shows its earliest-known cell and any wall); belief
panels are embedded at most :data:`MAX_PANEL_CELLS` cells across.
"""

from __future__ import annotations

import base64
import json
import math
import os
import zipfile
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore import __version__
from mrexplore.errors import MrexploreInputError
from mrexplore.trace import REQUIRED_TRACE_ARRAYS, load_trace
from mrexplore.viz.animate import every_pair_linked
from mrexplore.viz.noise import (
    belief_codes,
    belief_first_known,
    block_belief_codes,
    estimated_positions,
    localisation_errors,
)
from mrexplore.viz.render import (
    BELIEF_WRONG_FREE_RGB,
    BELIEF_WRONG_OCCUPIED_RGB,
    KNOWN_FREE_RGB,
    KNOWN_OCCUPIED_RGB,
    ROBOT_COLOURS,
    UNKNOWN_FREE_RGB,
    UNKNOWN_OCCUPIED_RGB,
    _block_any,
    _block_min_ticks,
    _check_trace,
)

#: Longest side, in cells, of the map embedded at full resolution.
MAX_MAP_CELLS = 2048
#: Longest side, in cells, of each embedded per-robot belief panel.
MAX_PANEL_CELLS = 256

_DTYPE_CODES = {
    np.dtype(np.uint8): "u1",
    np.dtype(np.int8): "i1",
    np.dtype(np.uint16): "u2",
    np.dtype(np.int16): "i2",
    np.dtype(np.uint32): "u4",
    np.dtype(np.int32): "i4",
    np.dtype(np.float32): "f4",
    np.dtype(np.float64): "f8",
}


def _hex(colour: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*colour)


def _pack(array: npt.NDArray[Any]) -> dict[str, Any]:
    """An array as ``{dtype, shape, z}``: little-endian bytes, zlib, base64."""
    code = _DTYPE_CODES[array.dtype]
    raw = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<")).tobytes()
    return {
        "dtype": code,
        "shape": list(array.shape),
        "z": base64.b64encode(zlib.compress(raw, 9)).decode("ascii"),
    }


def _narrow_int(array: npt.NDArray[Any], signed: bool = True) -> npt.NDArray[Any]:
    """``array`` in the narrowest of int8/16/32 (or uint8/16/32) holding its values."""
    low = int(array.min(initial=0))
    high = int(array.max(initial=0))
    kinds = (np.int8, np.int16, np.int32) if signed else (np.uint8, np.uint16, np.uint32)
    for kind in kinds:
        info = np.iinfo(kind)
        if info.min <= low and high <= info.max:
            return array.astype(kind)
    raise MrexploreInputError(f"values {low}..{high} do not fit in 32 bits")


def _time_deltas(array: npt.NDArray[Any]) -> tuple[list[Any], npt.NDArray[Any]]:
    """The first row (as a list) and the per-tick differences (row 0 all zero)."""
    values = np.asarray(array, dtype=np.int64)
    deltas = np.zeros_like(values)
    deltas[1:] = np.diff(values, axis=0)
    return values[0].tolist(), _narrow_int(deltas)


def _ticks_plus_one(first_known: npt.NDArray[Any]) -> npt.NDArray[Any]:
    """First-known ticks as ``tick + 1`` (0 = never), unsigned and narrow."""
    values = np.asarray(first_known, dtype=np.int64)
    return _narrow_int(np.where(values >= 0, values + 1, 0), signed=False)


def _bits(mask: npt.NDArray[np.bool_]) -> dict[str, Any]:
    spec = _pack(np.packbits(mask.ravel()))
    spec["shape"] = list(mask.shape)
    spec["bits"] = True
    return spec


def replay_data(
    trace: Mapping[str, Any], result: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """The JSON document embedded in ``replay.html``: ``meta`` and packed ``arrays``."""
    for name in ("truth", "first_known", "positions"):
        if name not in trace:
            raise MrexploreInputError(f"the trace has no {name!r} array")
    checked = _check_trace(
        trace["truth"], trace["first_known"], trace["positions"], trace.get("alive")
    )
    result = dict(result or {})
    height, width = checked.occupied.shape
    n_ticks, n_robots = checked.positions.shape[:2]
    last_tick = n_ticks - 1
    first_known = np.asarray(trace["first_known"], dtype=np.int64)
    map_stride = max(1, math.ceil(max(height, width) / MAX_MAP_CELLS))
    arrays: dict[str, Any] = {
        "truth": _bits(_block_any(checked.occupied != 0, map_stride)),
        "first_known": _pack(_ticks_plus_one(_block_min_ticks(first_known, map_stride))),
    }
    start, deltas = _time_deltas(checked.positions)
    arrays["positions"] = _pack(deltas)
    meta: dict[str, Any] = {
        "format": 1,
        "version": __version__,
        "height": height,
        "width": width,
        "last_tick": last_tick,
        "robots": n_robots,
        "map_stride": map_stride,
        "start": start,
        "colours": [_hex(c) for c in ROBOT_COLOURS],
        "map_colours": {
            "unknown_free": _hex(UNKNOWN_FREE_RGB),
            "unknown_occupied": _hex(UNKNOWN_OCCUPIED_RGB),
            "known_free": _hex(KNOWN_FREE_RGB),
            "known_occupied": _hex(KNOWN_OCCUPIED_RGB),
            "wrong_free": _hex(BELIEF_WRONG_FREE_RGB),
            "wrong_occupied": _hex(BELIEF_WRONG_OCCUPIED_RGB),
        },
    }
    estimated = estimated_positions(trace, checked.positions, (height, width))
    if estimated is not None:
        estimated_start, estimated_deltas = _time_deltas(estimated)
        meta["estimated_start"] = estimated_start
        arrays["estimated_positions"] = _pack(estimated_deltas)
    errors = localisation_errors(trace, checked.positions, estimated)
    if errors is not None:
        # In tenths of a cell, as the page shows them: narrow integers compress well.
        tenths = np.rint(np.clip(errors, 0, None) * 10).astype(np.int64)
        arrays["localisation_error"] = _pack(_narrow_int(tenths, signed=False))
    if checked.alive is not None:
        dead = ~checked.alive
        meta["fail_tick"] = [
            int(np.argmax(dead[:, robot])) if dead[:, robot].any() else -1
            for robot in range(n_robots)
        ]
    if "goals" in trace and np.asarray(trace["goals"]).shape == (n_ticks, n_robots, 2):
        goal_start, goal_deltas = _time_deltas(np.asarray(trace["goals"]))
        meta["goal_start"] = goal_start
        arrays["goals"] = _pack(goal_deltas)
    component = trace.get("component")
    link_bits = trace.get("link_bits")
    if component is not None and link_bits is not None:
        component = np.asarray(component)
        link_bits = np.asarray(link_bits, dtype=np.uint8)
        n_pairs = n_robots * (n_robots - 1) // 2
        if component.shape == (n_ticks, n_robots) and link_bits.shape == (
            n_ticks,
            -(-n_pairs // 8),
        ):
            arrays["component"] = _pack(_narrow_int(component))
            arrays["link_bits"] = _pack(link_bits)
            meta["all_linked"] = every_pair_linked(link_bits, component)
    arrays["coverage"] = _pack(_coverage(trace, checked).astype(np.float32))
    if "bytes_per_tick" in trace and np.asarray(trace["bytes_per_tick"]).shape[0] >= n_ticks:
        sent = np.cumsum(np.asarray(trace["bytes_per_tick"], dtype=np.float64)[:n_ticks])
        arrays["bytes"] = _pack(sent)
    if "subnetworks" in trace and np.asarray(trace["subnetworks"]).shape == (n_ticks,):
        arrays["subnetworks"] = _pack(_narrow_int(np.asarray(trace["subnetworks"])))
    robot_known = belief_first_known(trace)
    if robot_known is not None and robot_known.shape == (n_robots, height, width):
        panel_stride = max(1, math.ceil(max(height, width) / MAX_PANEL_CELLS))
        meta["panel_stride"] = panel_stride
        arrays["panel_truth"] = _bits(_block_any(checked.occupied != 0, panel_stride))
        arrays["robot_known"] = _pack(_ticks_plus_one(_block_min_ticks(robot_known, panel_stride)))
        codes = belief_codes(trace, checked.occupied)
        if codes is not None and codes.shape[0] == n_robots:
            # The colour class each panel cell takes once known (noise.belief_codes).
            arrays["panel_belief"] = _pack(block_belief_codes(codes, panel_stride))
    meta.update(_describe(result, n_robots))
    return {"meta": meta, "arrays": arrays}


def _coverage(trace: Mapping[str, Any], checked: Any) -> npt.NDArray[np.float64]:
    from mrexplore.viz.animate import _coverage as coverage

    return coverage(trace, checked)


def _describe(result: Mapping[str, Any], n_robots: int) -> dict[str, Any]:
    """Title, subtitle and credit of the page from ``result.json`` (may be empty)."""
    strategy = result.get("strategy", "")
    map_name = result.get("map_name", result.get("map", ""))
    title = " ".join(
        part
        for part in (
            str(strategy),
            f"with {n_robots} robots" if strategy else f"{n_robots} robots",
            f"on {map_name}" if map_name else "",
        )
        if part
    )
    details = []
    for key, label in (
        ("status", "status"),
        ("ticks", "ticks"),
        ("comm_description", "communication"),
        ("sharing", "sharing"),
        ("sensor_range_cells", "sensor range (cells)"),
        ("seed", "seed"),
    ):
        if key in result and result[key] is not None:
            value = result[key]
            text = f"{value:g}" if isinstance(value, float) else str(value)
            details.append(f"{label}: {text}")
    return {
        "title": title,
        "subtitle": " · ".join(details),
        "credit": str(result.get("map_credit") or ""),
        "bytes_total": result.get("bytes_total"),
    }


def replay_html(trace: Mapping[str, Any], result: Mapping[str, Any] | None = None) -> str:
    """The text of a self-contained ``replay.html`` for a run."""
    from mrexplore.viz.replay_page import PAGE_TEMPLATE, SCRIPT, STYLE

    document = json.dumps(replay_data(trace, result), separators=(",", ":"))
    # Inside <script>, "</" could close the element: JSON allows "<\/" instead.
    document = document.replace("</", "<\\/")
    return (
        PAGE_TEMPLATE.replace("/*STYLE*/", STYLE)
        .replace("/*SCRIPT*/", SCRIPT)
        .replace("/*DATA*/", document)
    )


#: Arrays every trace has (DESIGN: the run contract); the rest are optional.
REQUIRED_ARRAYS = REQUIRED_TRACE_ARRAYS


def load_run(run_dir: str | os.PathLike[str]) -> tuple[dict[str, Any], dict[str, Any]]:
    """The trace arrays and ``result.json`` (``{}`` if absent) of a run folder."""
    folder = Path(run_dir)
    if not folder.is_dir():
        raise MrexploreInputError(f"{folder}: not a run folder (written by mrexplore run --out)")
    trace_path = folder / "trace.npz"
    if not trace_path.is_file():
        raise MrexploreInputError(f"{folder}: no trace.npz (written by mrexplore run --out)")
    try:
        trace = load_trace(trace_path)
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as error:
        # A truncated or foreign file: numpy raises BadZipFile, EOFError, ValueError...
        raise MrexploreInputError(
            f"{trace_path}: not a readable trace ({type(error).__name__}: {error})"
        ) from None
    missing = [name for name in REQUIRED_ARRAYS if name not in trace]
    if missing:
        raise MrexploreInputError(
            f"{trace_path}: not a trace written by mrexplore run (no {missing[0]!r} array)"
        )
    result_path = folder / "result.json"
    result: dict[str, Any] = {}
    if result_path.is_file():
        try:
            result = json.loads(result_path.read_text())
        except json.JSONDecodeError as error:
            raise MrexploreInputError(f"{result_path}: not valid JSON ({error})") from None
    return trace, result


def write_replay(
    run_dir: str | os.PathLike[str], out: str | os.PathLike[str] | None = None
) -> Path:
    """Write ``replay.html`` for the run in ``run_dir`` (default: ``RUN_DIR/replay.html``).

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    trace, result = load_run(run_dir)
    path = Path(out) if out is not None else Path(run_dir) / "replay.html"
    write_text_file(path, replay_html(trace, result), "--out")
    return path


def write_text_file(path: Path, text: str, option: str) -> None:
    """Write ``text`` to ``path``; a folder that is missing or not writable is the
    user's to fix (``MrexploreInputError`` naming ``option``), not a crash."""
    parent = path.parent
    if not parent.is_dir():
        problem = "is not a folder" if parent.exists() else "does not exist"
        raise MrexploreInputError(f"{option} {path}: the folder {parent} {problem}")
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as error:
        raise MrexploreInputError(
            f"{option} {path}: cannot write ({error.strerror or error})"
        ) from None
