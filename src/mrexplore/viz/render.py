"""Frames, GIFs and summary figures drawn from a run record.

A run record ("trace") is a handful of numpy arrays:

* ``truth``: ``H x W`` uint8 (or bool), 1 = occupied, 0 = free.
* ``first_known``: ``H x W`` int, the first tick at which any robot knew the cell,
  -1 if never.
* ``positions``: ``(T+1) x N x 2`` int, ``(row, col)`` of every robot at every tick
  (tick 0 = start). Row 0 is the top of the picture.
* ``alive`` (optional): ``(T+1) x N`` bool; a robot with ``alive[t, n]`` False has
  failed by tick ``t``.

Colours (the same in frames, GIFs and the summary figure):

============================  =====================================
cell                          colour
============================  =====================================
not yet known, free           light grey (the true map, dimmed)
not yet known, occupied       dark grey
known free                    white
known occupied                black
path so far of robot ``n``    ``ROBOT_COLOURS[n % 12]`` (lightened when
                              cells are 5 px or more)
robot ``n``                   ``ROBOT_COLOURS[n % 12]``, dark outline
failed robot                  as above, crossed out
believed cell of robot ``n``  noisy runs: a hollow square in
                              ``ROBOT_COLOURS[n % 12]`` and a thin line
                              to the robot (the summary figure and
                              :mod:`~mrexplore.viz.animate`)
============================  =====================================

:func:`render_frame` and :func:`save_gif` are pure numpy + Pillow. Frames are built
as indices into one fixed palette, so a GIF frame needs no colour quantization at
all: the index image goes straight into Pillow. :func:`save_final_png` and
:func:`coverage_plot_png` use matplotlib (``Figure`` + ``FigureCanvasAgg``, never
pyplot), imported inside those functions.
"""

from __future__ import annotations

import math
import os
import textwrap
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError

RGB = tuple[int, int, int]
UInt8Array = npt.NDArray[np.uint8]
IntArray = npt.NDArray[np.intp]
BoolArray = npt.NDArray[np.bool_]

#: Qualitative robot palette (tab10 without its grey, plus teal, magenta and navy):
#: 12 colours that stay distinct from each other and from the grey/black/white map.
#: Robot ``n`` gets ``ROBOT_COLOURS[n % len(ROBOT_COLOURS)]``.
ROBOT_COLOURS: tuple[RGB, ...] = (
    (31, 119, 180),  # blue
    (255, 127, 14),  # orange
    (44, 160, 44),  # green
    (214, 39, 40),  # red
    (148, 103, 189),  # purple
    (140, 86, 75),  # brown
    (227, 119, 194),  # pink
    (23, 190, 207),  # cyan
    (188, 189, 34),  # olive
    (70, 153, 144),  # teal
    (240, 50, 230),  # magenta
    (0, 0, 117),  # navy
)

UNKNOWN_FREE_RGB: RGB = (208, 208, 208)
UNKNOWN_OCCUPIED_RGB: RGB = (112, 112, 112)
KNOWN_FREE_RGB: RGB = (255, 255, 255)
KNOWN_OCCUPIED_RGB: RGB = (0, 0, 0)
#: Belief panels of noisy runs: a cell the robot holds free that is a wall in truth.
BELIEF_WRONG_FREE_RGB: RGB = (255, 160, 160)
#: Belief panels of noisy runs: a cell the robot holds as a wall that is free in truth.
BELIEF_WRONG_OCCUPIED_RGB: RGB = (128, 0, 0)
_OUTLINE_RGB: RGB = (20, 20, 20)
#: Summary figure only: free cells not reachable from the start (not to explore).
_UNREACHABLE_RGB: RGB = (242, 234, 218)
#: Fraction of white mixed into a robot's colour for its path when cells are at least
#: as big as a robot's square, so the robot (full colour, dark outline) stands out
#: from the trail behind it. Smaller cells give thin trails, drawn in full colour.
_TRAIL_WHITE = 0.35

# Palette layout: the four map classes are 2 * known + occupied, so a frame's
# background is one integer expression; robot bodies and trails follow.
_I_UNKNOWN_FREE = 0
_I_UNKNOWN_OCCUPIED = 1
_I_KNOWN_FREE = 2
_I_KNOWN_OCCUPIED = 3
_I_OUTLINE = 4
_I_BODY0 = 5
_I_TRAIL0 = _I_BODY0 + len(ROBOT_COLOURS)
_I_WRONG_FREE = _I_TRAIL0 + len(ROBOT_COLOURS)
_I_WRONG_OCCUPIED = _I_WRONG_FREE + 1
#: Palette index of each belief code (:mod:`mrexplore.viz.noise`): the four map
#: classes keep theirs, the two wrong beliefs get their own.
_BELIEF_CODE_INDEX = np.array(
    [
        _I_UNKNOWN_FREE,
        _I_UNKNOWN_OCCUPIED,
        _I_KNOWN_FREE,
        _I_KNOWN_OCCUPIED,
        _I_WRONG_FREE,
        _I_WRONG_OCCUPIED,
    ],
    dtype=np.uint8,
)


def _build_palette() -> UInt8Array:
    colours: list[RGB] = [
        UNKNOWN_FREE_RGB,
        UNKNOWN_OCCUPIED_RGB,
        KNOWN_FREE_RGB,
        KNOWN_OCCUPIED_RGB,
        _OUTLINE_RGB,
    ]
    colours.extend(ROBOT_COLOURS)
    for red, green, blue in ROBOT_COLOURS:
        colours.append(
            (
                round(red + (255 - red) * _TRAIL_WHITE),
                round(green + (255 - green) * _TRAIL_WHITE),
                round(blue + (255 - blue) * _TRAIL_WHITE),
            )
        )
    colours.extend((BELIEF_WRONG_FREE_RGB, BELIEF_WRONG_OCCUPIED_RGB))
    return np.array(colours, dtype=np.uint8)


_PALETTE: UInt8Array = _build_palette()

#: Aimed-for longer side of an automatically scaled frame, in pixels.
_TARGET_PX = 500
#: Maps whose longer side exceeds this many cells are reduced, not enlarged.
_MAX_UNREDUCED_CELLS = 600
#: Smallest side of a robot's square (without its 1 px outline), in pixels.
_MIN_ROBOT_PX = 5


def robot_colour(robot: int) -> RGB:
    """The RGB colour (0-255) of robot ``robot``; the palette cycles every 12 robots.

    >>> robot_colour(0) == robot_colour(12)
    True
    """
    return ROBOT_COLOURS[robot % len(ROBOT_COLOURS)]


# --------------------------------------------------------------------------- input


@dataclass(frozen=True)
class _Trace:
    """Validated trace arrays, prepared for fast repeated rendering."""

    occupied: UInt8Array  # H x W, 0/1
    known_from: npt.NDArray[np.int64]  # H x W, first tick known; never known -> int64 max
    positions: IntArray  # (T+1) x N x 2
    alive: BoolArray | None  # (T+1) x N

    @property
    def last_tick(self) -> int:
        return int(self.positions.shape[0]) - 1

    @property
    def n_robots(self) -> int:
        return int(self.positions.shape[1])


def _check_trace(
    truth: npt.ArrayLike,
    first_known: npt.ArrayLike,
    positions: npt.ArrayLike,
    alive: npt.ArrayLike | None,
) -> _Trace:
    truth_arr = np.asarray(truth)
    if truth_arr.ndim != 2 or truth_arr.size == 0:
        raise MrexploreInputError(
            f"truth must be a non-empty H x W array, got shape {truth_arr.shape}"
        )
    height, width = truth_arr.shape
    known_arr = np.asarray(first_known)
    if known_arr.shape != truth_arr.shape:
        raise MrexploreInputError(
            f"first_known has shape {known_arr.shape}, truth has {truth_arr.shape}; they must match"
        )
    if not np.issubdtype(known_arr.dtype, np.integer):
        raise MrexploreInputError(f"first_known must hold integer ticks, got {known_arr.dtype}")
    pos_arr = np.asarray(positions)
    if pos_arr.ndim != 3 or pos_arr.shape[2] != 2 or pos_arr.shape[0] == 0:
        raise MrexploreInputError(
            f"positions must be a (T+1) x N x 2 array of (row, col), got shape {pos_arr.shape}"
        )
    if not np.issubdtype(pos_arr.dtype, np.integer):
        raise MrexploreInputError(f"positions must be integers, got {pos_arr.dtype}")
    if pos_arr.size:
        rows, cols = pos_arr[..., 0], pos_arr[..., 1]
        if rows.min() < 0 or rows.max() >= height or cols.min() < 0 or cols.max() >= width:
            raise MrexploreInputError(
                f"positions leave the {height} x {width} map "
                f"(rows {rows.min()}..{rows.max()}, cols {cols.min()}..{cols.max()})"
            )
    alive_arr: BoolArray | None = None
    if alive is not None:
        alive_arr = np.asarray(alive, dtype=bool)
        if alive_arr.shape != pos_arr.shape[:2]:
            raise MrexploreInputError(
                f"alive has shape {alive_arr.shape}, expected (T+1) x N = {pos_arr.shape[:2]}"
            )
    known_from = known_arr.astype(np.int64)
    known_from[known_from < 0] = np.iinfo(np.int64).max
    return _Trace(
        occupied=(truth_arr != 0).astype(np.uint8),
        known_from=known_from,
        positions=pos_arr.astype(np.intp),
        alive=alive_arr,
    )


def _check_tick(trace: _Trace, tick: int) -> int:
    if not 0 <= tick <= trace.last_tick:
        raise MrexploreInputError(f"tick {tick} is outside the trace (0..{trace.last_tick})")
    return int(tick)


# ------------------------------------------------------------------------- frames


def _auto_geometry(height: int, width: int) -> tuple[int, int]:
    """``(scale, stride)`` putting the longer side near ``_TARGET_PX`` pixels."""
    longer = max(height, width)
    if longer <= _MAX_UNREDUCED_CELLS:
        return max(1, round(_TARGET_PX / longer)), 1
    return 1, max(2, round(longer / _TARGET_PX))


def _block_max(image: UInt8Array, stride: int) -> UInt8Array:
    """Reduce by ``stride`` keeping each block's highest class.

    With classes ordered 2 * known + occupied, a block shows known over unknown and a
    wall over free space, so thin walls survive where plain striding would drop them.
    """
    height, width = image.shape
    out_h, out_w = -(-height // stride), -(-width // stride)
    padded = np.zeros((out_h * stride, out_w * stride), dtype=image.dtype)
    padded[:height, :width] = image
    # stride**2 strided maxima: ~10x faster than reshape(...).max(axis=(1, 3)).
    reduced = padded[::stride, ::stride].copy()
    for row_offset in range(stride):
        for col_offset in range(stride):
            if row_offset or col_offset:
                block = padded[row_offset::stride, col_offset::stride]
                np.maximum(reduced, block, out=reduced)
    return reduced


def _block_min_ticks(first_known: npt.NDArray[Any], stride: int) -> npt.NDArray[np.int64]:
    """Reduce by ``stride``: each block's earliest known tick, -1 if none known."""
    if stride == 1:
        return np.asarray(first_known, dtype=np.int64)
    values = np.asarray(first_known, dtype=np.int64)
    never = np.iinfo(np.int64).max
    values = np.where(values >= 0, values, never)
    height, width = values.shape[-2:]
    out_h, out_w = -(-height // stride), -(-width // stride)
    padded = np.full((*values.shape[:-2], out_h * stride, out_w * stride), never, np.int64)
    padded[..., :height, :width] = values
    blocks = padded.reshape(*values.shape[:-2], out_h, stride, out_w, stride)
    reduced = blocks.min(axis=(-3, -1))
    result: npt.NDArray[np.int64] = np.where(reduced == never, -1, reduced)
    return result


def _block_any(mask: npt.NDArray[np.bool_], stride: int) -> npt.NDArray[np.bool_]:
    if stride == 1:
        return mask
    height, width = mask.shape
    out_h, out_w = -(-height // stride), -(-width // stride)
    padded = np.zeros((out_h * stride, out_w * stride), dtype=bool)
    padded[:height, :width] = mask
    result = np.asarray(padded.reshape(out_h, stride, out_w, stride).any(axis=(1, 3)))
    return result


def _frame_indices(
    trace: _Trace, tick: int, trail: int | None, scale: int, stride: int
) -> UInt8Array:
    """The frame at ``tick`` as indices into ``_PALETTE`` (inputs trusted)."""
    image = _map_and_trails(trace, tick, trail, scale, stride)
    _draw_robots(image, trace, tick, scale, stride)
    return image


def _map_and_trails(
    trace: _Trace,
    tick: int,
    trail: int | None,
    scale: int,
    stride: int,
    light_trails: bool | None = None,
) -> UInt8Array:
    """The team's map at ``tick`` with the paths so far, scaled (palette indices).

    Paths are drawn in the lightened robot colours when ``light_trails`` (default:
    when cells are at least as big as a robot's square), else in full colour.
    """
    background = trace.occupied + 2 * (trace.known_from <= tick).view(np.uint8)
    image = _block_max(background, stride) if stride > 1 else background
    n_robots = trace.n_robots
    palette_offset = np.arange(n_robots) % len(ROBOT_COLOURS)

    # Paths: every visited cell, in time order so the latest visitor's colour wins.
    first = 0 if trail is None else max(0, tick - trail)
    visited = trace.positions[first : tick + 1] // stride
    if light_trails is None:
        light_trails = scale >= _MIN_ROBOT_PX
    trail_base = _I_TRAIL0 if light_trails else _I_BODY0
    trail_index = np.broadcast_to(trail_base + palette_offset, visited.shape[:2])
    image[visited[..., 0].ravel(), visited[..., 1].ravel()] = trail_index.ravel()

    if scale > 1:
        image = np.repeat(np.repeat(image, scale, axis=0), scale, axis=1)
    return image


def _robot_side(scale: int) -> int:
    """Side in pixels of a robot's square (without its outline)."""
    return max(scale, _MIN_ROBOT_PX)


def _draw_robots(
    image: UInt8Array,
    trace: _Trace,
    tick: int,
    scale: int,
    stride: int,
    robots: IntArray | None = None,
) -> None:
    """Draw the robots (all, or ``robots``) at ``tick`` on a scaled frame, in place.

    Robots are drawn after scaling, so no reduction can make them vanish.
    """
    n_robots = trace.n_robots
    palette_offset = np.arange(n_robots) % len(ROBOT_COLOURS)
    side = _robot_side(scale)
    cells = trace.positions[tick] // stride
    tops = cells[:, 0] * scale + (scale - side) // 2
    lefts = cells[:, 1] * scale + (scale - side) // 2
    chosen = np.arange(n_robots) if robots is None else robots
    # All outlines first, then all bodies: touching robots both stay visible.
    for robot in chosen:
        top, left = int(tops[robot]), int(lefts[robot])
        image[max(top - 1, 0) : top + side + 1, max(left - 1, 0) : left + side + 1] = _I_OUTLINE
    for robot in chosen:
        top, left = int(tops[robot]), int(lefts[robot])
        image[max(top, 0) : top + side, max(left, 0) : left + side] = (
            _I_BODY0 + palette_offset[robot]
        )
    if trace.alive is not None:
        for dead in np.flatnonzero(~trace.alive[tick]):
            if robots is None or dead in chosen:
                _cross_out(image, int(tops[dead]), int(lefts[dead]), side)


def _cross_out(image: UInt8Array, top: int, left: int, side: int) -> None:
    """Draw an X in the outline colour over the square at ``(top, left)``."""
    steps = np.arange(side)
    for shift in range(max(1, side // 6)):
        rows = top + steps
        for cols in (left + steps + shift, left + side - 1 - steps + shift):
            inside = (rows >= 0) & (rows < image.shape[0]) & (cols >= 0) & (cols < image.shape[1])
            image[rows[inside], cols[inside]] = _I_OUTLINE


def _geometry(shape: tuple[int, int], scale: int | None) -> tuple[int, int]:
    if scale is None:
        return _auto_geometry(*shape)
    if scale < 1:
        raise MrexploreInputError(f"scale must be a positive integer, got {scale}")
    return int(scale), 1


def render_frame(
    truth: npt.ArrayLike,
    first_known: npt.ArrayLike,
    positions: npt.ArrayLike,
    tick: int,
    *,
    scale: int | None = None,
    trail: int | None = None,
    alive: npt.ArrayLike | None = None,
) -> UInt8Array:
    """Draw the team's knowledge, paths and robots at ``tick`` as an RGB image.

    Args:
        truth: ``H x W``, nonzero = occupied.
        first_known: ``H x W`` int, first tick each cell was known, -1 if never.
        positions: ``(T+1) x N x 2`` int, ``(row, col)`` per tick and robot.
        tick: which tick to draw, ``0 <= tick <= T``.
        scale: pixels per cell. ``None`` chooses one so the longer side is about
            500 px: an integer enlargement for maps up to 600 cells across; larger
            maps are reduced by an integer stride instead (each block shows its
            "strongest" cell, so walls survive), and paths and robots are drawn
            on the reduced picture, so none is lost.
        trail: draw only the last ``trail`` ticks of each path (all when ``None``).
        alive: optional ``(T+1) x N`` bool; robots failed at ``tick`` are crossed out.

    Returns:
        ``uint8`` array ``(H * scale) x (W * scale) x 3`` (with a reduction stride
        ``k``: ``ceil(H / k) x ceil(W / k) x 3``).

    >>> import numpy as np
    >>> truth = np.zeros((10, 20), dtype=np.uint8)
    >>> known = np.zeros((10, 20), dtype=np.int32)
    >>> path = np.array([[[2, 3]], [[2, 4]]])
    >>> frame = render_frame(truth, known, path, 1, scale=4)
    >>> frame.shape, frame.dtype.name
    ((40, 80, 3), 'uint8')
    >>> tuple(int(v) for v in frame[2 * 4 + 1, 4 * 4 + 1]) == robot_colour(0)
    True
    """
    trace = _check_trace(truth, first_known, positions, alive)
    tick = _check_tick(trace, tick)
    if trail is not None and trail < 0:
        raise MrexploreInputError(f"trail must be >= 0 ticks, got {trail}")
    pixels, stride = _geometry(trace.occupied.shape, scale)
    result: UInt8Array = _PALETTE[_frame_indices(trace, tick, trail, pixels, stride)]
    return result


# ---------------------------------------------------------------------------- GIF


def frame_ticks(last_tick: int, max_frames: int) -> IntArray:
    """At most ``max_frames`` ticks from ``0..last_tick``, evenly spread, last included.

    >>> frame_ticks(20, 7).tolist()
    [0, 3, 7, 10, 13, 17, 20]
    >>> frame_ticks(5, 100).tolist()
    [0, 1, 2, 3, 4, 5]
    >>> frame_ticks(9, 1).tolist()
    [9]
    """
    if max_frames < 1:
        raise MrexploreInputError(f"max_frames must be >= 1, got {max_frames}")
    if last_tick < 0:
        raise MrexploreInputError(f"last_tick must be >= 0, got {last_tick}")
    if max_frames == 1:
        return np.array([last_tick], dtype=np.intp)
    count = min(max_frames, last_tick + 1)
    # floor(x + 0.5), not np.round: ticks spaced >= 1 apart then stay distinct.
    spread = np.floor(np.linspace(0, last_tick, count) + 0.5).astype(np.intp)
    ticks: IntArray = np.unique(spread)
    return ticks


def save_gif(
    path: str | os.PathLike[str],
    truth: npt.ArrayLike,
    first_known: npt.ArrayLike,
    positions: npt.ArrayLike,
    *,
    max_frames: int = 200,
    fps: int = 10,
    alive: npt.ArrayLike | None = None,
    scale: int | None = None,
    trail: int | None = None,
    hold_last_ms: int = 1500,
) -> Path:
    """Write an animated GIF of the run, one frame per sampled tick.

    Ticks are taken by :func:`frame_ticks` (at most ``max_frames``, evenly spread,
    first and last always included); frames are those of :func:`render_frame` with
    the same ``scale``, ``trail`` and ``alive``. The last frame stays on screen for
    ``hold_last_ms`` (at least one frame time). The GIF loops forever.

    Frames share one fixed palette, so they are written exactly, without dithering
    or quantization. Pillow merges a frame identical to the one before it into that
    one (adding up their durations), so a run where nothing moves between sampled
    ticks yields fewer frames, and stores each later frame as its changes only
    (unchanged pixels transparent), which makes the file about ten times smaller.

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    if fps < 1:
        raise MrexploreInputError(f"fps must be >= 1, got {fps}")
    if trail is not None and trail < 0:
        raise MrexploreInputError(f"trail must be >= 0 ticks, got {trail}")
    trace = _check_trace(truth, first_known, positions, alive)
    pixels, stride = _geometry(trace.occupied.shape, scale)
    ticks = frame_ticks(trace.last_tick, max_frames)

    frames = (_frame_indices(trace, int(tick), trail, pixels, stride) for tick in ticks)
    return write_indexed_gif(Path(path), frames, fps, hold_last_ms)


def write_indexed_gif(out: Path, frames: Iterable[UInt8Array], fps: int, hold_last_ms: int) -> Path:
    """Write frames of indices into the shared palette as a looping GIF; returns ``out``.

    The GIF writer of :func:`save_gif` and :func:`mrexplore.viz.animate.save_animation`:
    every frame ``1000 / fps`` ms (at least 20 ms, as browsers slow shorter delays
    down), the last held ``hold_last_ms`` (at least one frame time).
    """
    from PIL import Image

    palette_bytes = _PALETTE.tobytes()
    images: list[Image.Image] = []
    for indices in frames:
        contiguous = np.ascontiguousarray(indices)
        image = Image.frombytes(
            "P", (contiguous.shape[1], contiguous.shape[0]), contiguous.tobytes()
        )
        image.putpalette(palette_bytes)
        images.append(image)
    frame_ms = max(20, round(1000 / fps))  # browsers slow down GIF delays under 20 ms
    durations = [frame_ms] * len(images)
    durations[-1] = max(frame_ms, hold_last_ms)
    images[0].save(
        out,
        format="GIF",
        save_all=True,
        append_images=images[1:],
        duration=durations,
        loop=0,
        optimize=True,
    )
    return out


# ------------------------------------------------------------------------ figures


def _rgb_float(colour: RGB) -> tuple[float, float, float]:
    return (colour[0] / 255, colour[1] / 255, colour[2] / 255)


def _known_map_rgb(trace: _Trace, tick: int) -> UInt8Array:
    classes = trace.occupied + 2 * (trace.known_from <= tick).view(np.uint8)
    result: UInt8Array = _PALETTE[classes]
    return result


def _truth_rgb(trace: _Trace, explorable: BoolArray | None) -> UInt8Array:
    image = np.full((*trace.occupied.shape, 3), 255, dtype=np.uint8)
    image[trace.occupied != 0] = KNOWN_OCCUPIED_RGB
    if explorable is not None:
        # Free cells that cannot be reached from the start: not part of the task.
        image[(trace.occupied == 0) & ~explorable] = _UNREACHABLE_RGB
    return image


def _legend_layout(handles: list[Any], max_columns: int) -> tuple[list[Any], int, float]:
    """Order ``handles`` to read row by row (matplotlib fills legends column by
    column) and return them with the column count and the height in inches."""
    rows = math.ceil(len(handles) / max_columns)
    columns = math.ceil(len(handles) / rows)
    ordered = [
        handles[row * columns + column]
        for column in range(columns)
        for row in range(rows)
        if row * columns + column < len(handles)
    ]
    return ordered, columns, 0.05 + 0.22 * rows


def _check_explorable(explorable: npt.ArrayLike | None, shape: tuple[int, ...]) -> BoolArray | None:
    if explorable is None:
        return None
    arr = np.asarray(explorable, dtype=bool)
    if arr.shape != shape:
        raise MrexploreInputError(f"explorable has shape {arr.shape}, truth has {shape}")
    return arr


def save_final_png(
    path: str | os.PathLike[str],
    truth: npt.ArrayLike,
    first_known: npt.ArrayLike,
    positions: npt.ArrayLike,
    *,
    title: str = "",
    credit: str = "",
    alive: npt.ArrayLike | None = None,
    explorable: npt.ArrayLike | None = None,
    estimated_positions: npt.ArrayLike | None = None,
    dpi: int = 110,
) -> Path:
    """Write a summary PNG: ground truth beside the team's final map and paths.

    Left panel: the ground truth (black = occupied; with ``explorable``, free cells
    unreachable from the start are tinted) and each robot's start. Right panel: the
    team's map at the last tick in the frame colours (white/black known, light/dark
    grey not known), every robot's full path as a line in its colour, its start
    (circle), its final position (square) and, when ``alive`` says it failed, an
    ``x``. Wide maps are stacked top and bottom instead of side by side. A legend
    sits under the panels and ``credit`` (required wherever someone else's map is
    shown) in small print at the very bottom.

    With ``estimated_positions`` (``(T+1) x N x 2``, the cell each robot believed it
    was on: the trace of a run with odometry drift), each live robot whose believed
    cell at the last tick is not its true one also gets a hollow square in its
    colour on the believed cell, joined to its final position by a thin line, and
    the legend a "believed position" entry.

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    fig = _final_figure(
        truth,
        first_known,
        positions,
        title=title,
        credit=credit,
        alive=alive,
        explorable=explorable,
        estimated_positions=estimated_positions,
        dpi=dpi,
    )
    out = Path(path)
    fig.savefig(out, format="png", dpi=dpi)
    return out


def _final_figure(
    truth: npt.ArrayLike,
    first_known: npt.ArrayLike,
    positions: npt.ArrayLike,
    *,
    title: str,
    credit: str,
    alive: npt.ArrayLike | None,
    explorable: npt.ArrayLike | None,
    estimated_positions: npt.ArrayLike | None,
    dpi: int,
) -> Any:
    """The figure of :func:`save_final_png`; its axes are the ground truth, then
    the team's map (``fig.axes[1]``, in cell coordinates: x = column, y = row)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from mrexplore.viz.noise import estimated_positions as checked_estimates

    trace = _check_trace(truth, first_known, positions, alive)
    explorable_arr = _check_explorable(explorable, trace.occupied.shape)
    believed = (
        checked_estimates(
            {"estimated_positions": estimated_positions}, trace.positions, trace.occupied.shape
        )
        if estimated_positions is not None
        else None
    )
    height, width = trace.occupied.shape
    last = trace.last_tick
    n_robots = trace.n_robots

    # ---- layout, in inches
    stacked = width > 1.7 * height
    panel_long = 4.6
    if width >= height:
        panel_w, panel_h = panel_long, max(0.4, panel_long * height / width)
    else:
        panel_w, panel_h = max(0.4, panel_long * width / height), panel_long
    if stacked:
        panel_w, panel_h = 7.5, max(0.4, 7.5 * height / width)
    gap, side_margin = 0.3, 0.25
    panel_title_h = 0.3
    top_h = 0.12 + (0.35 if title else 0.0) + panel_title_h
    if stacked:
        fig_w = max(panel_w + 2 * side_margin, 6.0)
        body_h = 2 * panel_h + panel_title_h + gap
    else:
        fig_w = max(2 * panel_w + gap + 2 * side_margin, 6.0)
        body_h = panel_h

    # Two legends under the panels: one row (or more) of robots, then the key.
    robot_handles: list[Any] = []
    if n_robots <= 2 * len(ROBOT_COLOURS):
        robot_handles.extend(
            Line2D([], [], color=_rgb_float(robot_colour(robot)), lw=2.5, label=f"robot {robot}")
            for robot in range(n_robots)
        )
    else:
        robot_handles.append(
            Line2D([], [], color="0.4", lw=2.5, label=f"{n_robots} robot paths (colours cycle)")
        )
    key_handles: list[Any] = [
        Line2D([], [], marker=marker, ls="none", mfc="white", mec="black", ms=7, label=label)
        for marker, label in (("o", "start"), ("s", "final position"))
    ]
    failed = (
        np.flatnonzero(~trace.alive[-1]) if trace.alive is not None else np.array([], dtype=int)
    )
    if failed.size:
        key_handles.append(
            Line2D([], [], ls="none", marker="x", color="black", mew=2, ms=8, label="failed")
        )
    if believed is not None:
        key_handles.append(
            # Hollow and grey, on a line: unlike the white-filled "final position".
            Line2D(
                [],
                [],
                color="0.45",
                lw=0.8,
                marker="s",
                mfc="none",
                mec="0.45",
                mew=1.5,
                ms=7,
                label="believed position",
            )
        )
    key_handles.extend(
        Patch(facecolor=_rgb_float(rgb), edgecolor="0.5", label=label)
        for rgb, label in (
            (KNOWN_FREE_RGB, "known free"),
            (KNOWN_OCCUPIED_RGB, "known occupied"),
            (UNKNOWN_FREE_RGB, "unknown free"),
            (UNKNOWN_OCCUPIED_RGB, "unknown occupied"),
        )
    )
    if explorable_arr is not None and np.any((trace.occupied == 0) & ~explorable_arr):
        key_handles.append(
            Patch(facecolor=_rgb_float(_UNREACHABLE_RGB), edgecolor="0.5", label="unreachable")
        )
    legends = [
        _legend_layout(group, max(1, int(fig_w / inches_per_entry)))
        for group, inches_per_entry in ((robot_handles, 1.0), (key_handles, 1.3))
        if group
    ]
    legend_h = 0.1 + sum(height_in for _, _, height_in in legends)
    credit_text = "\n".join(textwrap.wrap(credit, width=int(fig_w * 17))) if credit else ""
    credit_h = 0.08 + 0.14 * (credit_text.count("\n") + 1) if credit_text else 0.08
    bottom_h = legend_h + credit_h + 0.1
    fig_h = top_h + body_h + bottom_h

    fig = Figure(figsize=(fig_w, fig_h), dpi=dpi)
    FigureCanvasAgg(fig)

    def axes_at(left_in: float, bottom_in: float) -> Any:
        return fig.add_axes((left_in / fig_w, bottom_in / fig_h, panel_w / fig_w, panel_h / fig_h))

    if stacked:
        left_x = (fig_w - panel_w) / 2
        ax_truth = axes_at(left_x, bottom_h + panel_h + panel_title_h + gap)
        ax_known = axes_at(left_x, bottom_h)
    else:
        left_x = (fig_w - 2 * panel_w - gap) / 2
        ax_truth = axes_at(left_x, bottom_h)
        ax_known = axes_at(left_x + panel_w + gap, bottom_h)

    # Enlarged maps look best with crisp cells; reduced ones need smoothing so that
    # thin walls do not flicker in and out.
    panel_px = max(panel_w, panel_h) * dpi
    interpolation = "nearest" if max(height, width) <= panel_px else "antialiased"
    ax_truth.imshow(_truth_rgb(trace, explorable_arr), interpolation=interpolation)
    ax_known.imshow(_known_map_rgb(trace, last), interpolation=interpolation)

    cell_pt = min(panel_w / width, panel_h / height) * 72
    line_w = float(np.clip(cell_pt * 0.45, 0.8, 2.5))
    marker_pt = float(np.clip(cell_pt * 1.2, 5.0, 9.0))
    rows = trace.positions[..., 0]
    cols = trace.positions[..., 1]
    for robot in range(n_robots):
        colour = _rgb_float(robot_colour(robot))
        ax_known.plot(
            cols[:, robot],
            rows[:, robot],
            color=colour,
            lw=line_w,
            alpha=0.9,
            solid_joinstyle="round",
            solid_capstyle="round",
        )
        for ax in (ax_truth, ax_known):
            ax.plot(
                cols[0, robot],
                rows[0, robot],
                marker="o",
                ls="none",
                mfc=colour,
                mec="black",
                mew=0.8,
                ms=marker_pt,
            )
        ax_known.plot(
            cols[-1, robot],
            rows[-1, robot],
            marker="s",
            ls="none",
            mfc=colour,
            mec="black",
            mew=0.8,
            ms=marker_pt,
        )
    if believed is not None:
        _draw_believed_final(ax_known, trace, believed, line_w, marker_pt)
    for robot in failed:
        ax_known.plot(
            cols[-1, robot],
            rows[-1, robot],
            marker="x",
            ls="none",
            color="black",
            mew=2.2,
            ms=marker_pt * 1.5,
        )

    known_cells = trace.known_from <= last
    if explorable_arr is not None and explorable_arr.any():
        share = np.count_nonzero(known_cells & explorable_arr) / np.count_nonzero(explorable_arr)
        known_note = f", {100 * share:.1f}% of explorable area known"
    else:
        known_note = ""
    ax_truth.set_title(f"Ground truth ({width} x {height} cells)", fontsize=10)
    ax_known.set_title(f"Team map and paths at tick {last}{known_note}", fontsize=10)
    for ax in (ax_truth, ax_known):
        ax.set_xlim(-0.5, width - 0.5)
        ax.set_ylim(height - 0.5, -0.5)
        ax.set_xticks([])
        ax.set_yticks([])

    if title:
        fig.text(0.5, 1 - 0.12 / fig_h, title, ha="center", va="top", fontsize=12)
    legend_top = bottom_h - 0.05
    for group, columns, height_in in legends:
        fig.legend(
            handles=group,
            loc="upper center",
            bbox_to_anchor=(0.5, legend_top / fig_h),
            ncol=columns,
            fontsize=8,
            frameon=False,
            handlelength=1.6,
            columnspacing=1.2,
            borderaxespad=0.0,
        )
        legend_top -= height_in
    if credit_text:
        fig.text(0.5, 0.06 / fig_h, credit_text, ha="center", va="bottom", fontsize=7, color="0.3")
    return fig


def _draw_believed_final(
    ax: Any, trace: _Trace, believed: IntArray, line_w: float, marker_pt: float
) -> None:
    """Each live robot's believed cell at the last tick: a hollow square in its
    colour, a thin line to its true cell (nothing where the two are the same)."""
    last = trace.last_tick
    for robot in range(trace.n_robots):
        if trace.alive is not None and not trace.alive[last, robot]:
            continue
        (true_row, true_col), (row, col) = trace.positions[last, robot], believed[last, robot]
        if (row, col) == (true_row, true_col):
            continue
        colour = _rgb_float(robot_colour(robot))
        ax.plot([true_col, col], [true_row, row], color=colour, lw=max(0.6, line_w / 2))
        ax.plot(col, row, marker="s", ls="none", mfc="none", mec=colour, mew=1.5, ms=marker_pt)


def coverage_plot_png(
    path: str | os.PathLike[str],
    curve: npt.ArrayLike,
    *,
    title: str = "",
    labels: Sequence[str] | None = None,
    dpi: int = 110,
) -> Path:
    """Plot explored fraction (0..1) against tick and write it as a PNG.

    ``curve`` is one curve (length ``T+1``, index = tick) or several as the rows of
    a 2-D array, named by ``labels`` in a legend.

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import PercentFormatter

    curves = np.asarray(curve, dtype=float)
    if curves.ndim == 1:
        curves = curves[None, :]
    if curves.ndim != 2 or curves.shape[1] == 0:
        raise MrexploreInputError(
            f"curve must be 1-D (ticks) or 2-D (curves x ticks), got shape {curves.shape}"
        )
    if labels is not None and len(labels) != curves.shape[0]:
        raise MrexploreInputError(f"{len(labels)} labels for {curves.shape[0]} curves")

    fig = Figure(figsize=(6.4, 3.6), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ticks = np.arange(curves.shape[1])
    for index, row in enumerate(curves):
        label = labels[index] if labels is not None else None
        ax.plot(ticks, row, lw=1.8, label=label, color=_rgb_float(robot_colour(index)))
    ax.set_ylim(0, 1.02)
    ax.set_xlim(0, max(1, curves.shape[1] - 1))
    ax.yaxis.set_major_formatter(PercentFormatter(xmax=1))
    ax.set_xlabel("tick")
    ax.set_ylabel("explored")
    ax.grid(alpha=0.3)
    if labels is not None:
        ax.legend(fontsize=8, loc="lower right")
    if title:
        ax.set_title(title, fontsize=11)
    out = Path(path)
    fig.savefig(out, format="png", dpi=dpi)
    return out
