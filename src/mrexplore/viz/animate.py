"""Animations of a whole run, drawn from its record: GIF and MP4.

A frame shows, at one tick:

* the map: ground truth faint (light grey free, dark grey walls) under the team's
  known map (white free, black walls), as in :func:`mrexplore.viz.render_frame`;
* each robot in its colour (:data:`~mrexplore.viz.ROBOT_COLOURS`) with its path so
  far, its current target as a ring of its colour, and an ``X`` once it has failed;
* the communication links in force during the tick, each drawn in the colour of
  the lowest-id robot of its sub-network (the robot that coordinates a
  "centralised" method there), so every sub-network has one colour;
* a header with the tick, the coverage of the explorable cells, the number of
  sub-networks and of failed robots;
* optionally (``belief_panels=True``) one small panel per robot with the map that
  robot itself knew at that tick (framed in its colour), to see the maps of two
  sub-networks drift apart after a partition (Sheng et al., Fig. 9).

Everything comes from the arrays of ``trace.npz`` (:mod:`mrexplore.trace`);
links, targets and belief panels appear only when the trace has ``link_bits`` and
``component``, ``goals`` and ``robot_first_known``. A belief panel shows which cells
the robot knew, coloured by ground truth.

Noisy runs (odometry drift, sensor noise: :mod:`mrexplore.viz.noise`) add:

* with ``estimated_positions``: each live robot's believed cell as a hollow square
  in its colour, joined to the robot by a thin line, on the map and in its belief
  panel (nothing extra where the two cells are the same), and a header line with
  the mean and largest localisation error of the live robots (``localisation_error``,
  else the distance between the two cells);
* with ``robot_belief``: the belief panels colour each cell the robot knows by the
  robot's own belief instead of the truth, so a wall it mapped in the wrong place
  shows there, and a cell whose belief disagrees with the truth is tinted red
  (:data:`~mrexplore.viz.render.BELIEF_WRONG_FREE_RGB`: held free, a wall in truth;
  :data:`~mrexplore.viz.render.BELIEF_WRONG_OCCUPIED_RGB`: held a wall, free in
  truth). The trace keeps only the final belief: a cell appears at the tick the
  robot first knew it (``robot_first_known``), drawn with the value the robot held
  at the end of the run, not the one it held at that tick. A cell the robot no
  longer holds at the end shows as unknown. Without ``robot_first_known`` the
  panels show the final belief in every frame.

Frames are palette images (the palette of :mod:`mrexplore.viz.render`), so a GIF
is written exactly, without quantization. An MP4 needs an ffmpeg binary: the one
``imageio-ffmpeg`` ships (``pip install 'mrexplore[viz]'``) or ``ffmpeg`` on ``PATH``.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreError, MrexploreInputError
from mrexplore.trace import n_link_pairs
from mrexplore.viz.noise import (
    belief_codes,
    belief_first_known,
    block_belief_codes,
    estimated_positions,
    localisation_errors,
)
from mrexplore.viz.render import (
    _BELIEF_CODE_INDEX,
    _I_BODY0,
    _I_KNOWN_FREE,
    _I_OUTLINE,
    _PALETTE,
    ROBOT_COLOURS,
    UInt8Array,
    _block_any,
    _block_min_ticks,
    _check_tick,
    _check_trace,
    _cross_out,
    _draw_robots,
    _geometry,
    _map_and_trails,
    _robot_side,
    _Trace,
    frame_ticks,
    write_indexed_gif,
)

#: Default number of frames of an animation (evenly spread over the run).
DEFAULT_MAX_FRAMES = 300
#: Default frame rate: 300 frames play in 20 s.
DEFAULT_FPS = 15
_GAP = 6
_FONT_PX = 13
_LINE_H = 18
_CAPTION_H = 15
_BORDER = 2
_PANEL_AREA_MIN_PX = 240
_PANEL_ROBOT_PX = 5
_LINK_PX = 2
_BELIEVED_PX = 2
_PANEL_BELIEVED_PX = _PANEL_ROBOT_PX + 4


FFMPEG_MISSING = (
    "an MP4 needs an ffmpeg encoder: pip install 'mrexplore[viz]' (imageio-ffmpeg, which "
    "ships one), or put ffmpeg on PATH"
)


def ffmpeg_path() -> str | None:
    """The ``ffmpeg`` program to encode MP4s with, or ``None`` if there is none.

    The binary that ``imageio-ffmpeg`` ships (the ``viz`` extra) comes first: the same
    encoder, with H.264, on every machine. Without it, ``ffmpeg`` on ``PATH``.
    """
    try:
        import imageio_ffmpeg
    except ImportError:
        return shutil.which("ffmpeg")
    try:
        return str(imageio_ffmpeg.get_ffmpeg_exe())
    except RuntimeError:  # the package is there but its binary is not (e.g. an sdist build)
        return shutil.which("ffmpeg")


def _font(size: int) -> Any:
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except (TypeError, ValueError, ImportError, OSError):  # Pillow without FreeType
        return ImageFont.load_default()


class RunAnimator:
    """Renders frames of one run from its trace arrays.

    Args:
        trace: the arrays of ``trace.npz`` (a dict, an ``NpzFile`` or
            :meth:`RunRecord.trace_arrays`); needs ``truth``, ``first_known`` and
            ``positions``, uses ``alive``, ``goals``, ``component``, ``link_bits``,
            ``robot_first_known``, ``coverage`` (or ``explorable``) and, from noisy
            runs, ``estimated_positions``, ``localisation_error`` and
            ``robot_belief`` when present.
        scale: pixels per cell of the main map (``None``: longer side about 500 px,
            large maps reduced, as in :func:`~mrexplore.viz.render_frame`).
        trail: ticks of path drawn behind each robot (``None``: the whole path).
        links, targets: draw communication links and current targets.
        believed: draw each robot's believed cell (when the trace has
            ``estimated_positions``).
        belief_panels: add one panel per robot with its own belief (needs
            ``robot_first_known`` or ``robot_belief`` in the trace).
        title: a line above the header (e.g. strategy, team size and map).
    """

    def __init__(
        self,
        trace: Mapping[str, Any],
        *,
        scale: int | None = None,
        trail: int | None = None,
        links: bool = True,
        targets: bool = True,
        believed: bool = True,
        belief_panels: bool = False,
        title: str = "",
    ) -> None:
        for name in ("truth", "first_known", "positions"):
            if name not in trace:
                raise MrexploreInputError(f"the trace has no {name!r} array")
        self.trace: _Trace = _check_trace(
            trace["truth"], trace["first_known"], trace["positions"], trace.get("alive")
        )
        if trail is not None and trail < 0:
            raise MrexploreInputError(f"trail must be >= 0 ticks, got {trail}")
        self.trail = trail
        self.title = title
        n_ticks, n_robots = self.trace.positions.shape[:2]
        height, width = self.trace.occupied.shape
        self.scale, self.stride = _geometry((height, width), scale)
        self.goals = self._optional(trace, "goals", (n_ticks, n_robots, 2)) if targets else None
        self.component = self._optional(trace, "component", (n_ticks, n_robots))
        self.link_pairs: list[npt.NDArray[np.intp]] | None = None
        if links and "link_bits" in trace and self.component is not None:
            link_bits = np.asarray(trace["link_bits"])
            # With unlimited range every pair is linked: lines would only hide the map.
            if not every_pair_linked(link_bits, self.component):
                self.link_pairs = _link_pairs(link_bits, n_robots, n_ticks)
        estimated = estimated_positions(trace, self.trace.positions, (height, width))
        self.estimated = estimated if believed else None
        self.localisation = localisation_errors(trace, self.trace.positions, estimated)
        self.robot_known: npt.NDArray[Any] | None = None
        self.belief: npt.NDArray[np.uint8] | None = None
        if belief_panels:
            robot_known = belief_first_known(trace)
            if robot_known is None:
                raise MrexploreInputError(
                    "belief panels need robot_first_known (or robot_belief) in the trace: "
                    "run with --belief-panels (Simulation(..., record_beliefs=True))"
                )
            name = "robot_first_known" if "robot_first_known" in trace else "robot_belief"
            self.robot_known = self._shaped(name, robot_known, (n_robots, height, width))
            codes = belief_codes(trace, self.trace.occupied)
            if codes is not None:
                self.belief = self._shaped("robot_belief", codes, (n_robots, height, width))
        self.coverage = _coverage(trace, self.trace)
        self.font = _font(_FONT_PX)
        self._layout()

    @classmethod
    def _optional(cls, trace: Mapping[str, Any], name: str, shape: tuple[int, ...]) -> Any:
        if name not in trace:
            return None
        return cls._shaped(name, np.asarray(trace[name]), shape)

    @staticmethod
    def _shaped(name: str, array: Any, shape: tuple[int, ...]) -> Any:
        if array.shape != shape:
            raise MrexploreInputError(f"{name} has shape {array.shape}, expected {shape}")
        return array

    # ------------------------------------------------------------------ layout
    def _layout(self) -> None:
        height, width = self.trace.occupied.shape
        self.map_h = -(-height // self.stride) * self.scale
        self.map_w = -(-width // self.stride) * self.scale
        header_lines = 1 + bool(self.title) + (self.localisation is not None)
        self.header_h = _LINE_H * header_lines + 4
        self.map_top = self.header_h
        total_w, total_h = self.map_w, self.map_h
        self.panel_boxes: list[tuple[int, int]] = []
        if self.robot_known is not None:
            n_robots = self.trace.n_robots
            columns = math.ceil(math.sqrt(n_robots))
            rows = math.ceil(n_robots / columns)
            area_h = max(self.map_h, _PANEL_AREA_MIN_PX)
            avail_h = max((area_h - (rows - 1) * _GAP) // rows - _CAPTION_H - 2 * _BORDER, 8)
            factor = min(avail_h / height, 1.5 * avail_h / width)
            self.panel_h = max(8, round(height * factor))
            self.panel_w = max(8, round(width * factor))
            # Reduce by whole blocks first (a block is known from its earliest known
            # cell on, a wall if it holds one), then sample to the panel's size.
            panel_stride = max(1, math.floor(1 / factor))
            reduced_h, reduced_w = -(-height // panel_stride), -(-width // panel_stride)
            pick_rows = ((np.arange(self.panel_h) * reduced_h) // self.panel_h)[:, None]
            pick_cols = ((np.arange(self.panel_w) * reduced_w) // self.panel_w)[None, :]
            known = _block_min_ticks(self.robot_known, panel_stride)
            self.panel_known = known[:, pick_rows, pick_cols]
            occupied = _block_any(self.trace.occupied != 0, panel_stride)
            self.panel_occupied = occupied[pick_rows, pick_cols].astype(np.uint8)
            # The palette index of each panel cell once known: the truth's, or with
            # robot_belief the robot's own final belief (wrong cells tinted red).
            self.panel_known_index = np.broadcast_to(
                self.panel_occupied + _I_KNOWN_FREE, (n_robots, self.panel_h, self.panel_w)
            )
            if self.belief is not None:
                codes = block_belief_codes(self.belief, panel_stride)[:, pick_rows, pick_cols]
                self.panel_known_index = _BELIEF_CODE_INDEX[codes]
            box_w = self.panel_w + 2 * _BORDER
            box_h = self.panel_h + 2 * _BORDER + _CAPTION_H
            left0 = self.map_w + 2 * _GAP
            for robot in range(n_robots):
                row, column = divmod(robot, columns)
                self.panel_boxes.append(
                    (left0 + column * (box_w + _GAP), self.map_top + row * (box_h + _GAP))
                )
            total_w = left0 + columns * box_w + (columns - 1) * _GAP
            total_h = max(total_h, rows * box_h + (rows - 1) * _GAP)
        self.width = total_w
        self.height = self.map_top + total_h

    @property
    def last_tick(self) -> int:
        return self.trace.last_tick

    # ----------------------------------------------------------------- drawing
    def _centre(self, cell: npt.NDArray[np.intp]) -> tuple[float, float]:
        """Pixel (x, y) of a cell's centre on the main map (frame coordinates)."""
        reduced = cell // self.stride
        return (
            float(reduced[1] * self.scale + (self.scale - 1) / 2),
            float(self.map_top + reduced[0] * self.scale + (self.scale - 1) / 2),
        )

    def frame_indices(self, tick: int) -> UInt8Array:
        """The frame at ``tick`` as indices into :data:`PALETTE` (``height x width``)."""
        from PIL import Image, ImageDraw

        tick = _check_tick(self.trace, tick)
        trace = self.trace
        canvas = np.full((self.height, self.width), _I_KNOWN_FREE, dtype=np.uint8)
        main = _map_and_trails(trace, tick, self.trail, self.scale, self.stride, light_trails=True)
        canvas[self.map_top : self.map_top + self.map_h, : self.map_w] = main
        image = Image.frombuffer("P", (self.width, self.height), canvas.tobytes(), "raw", "P", 0, 1)
        draw = ImageDraw.Draw(image)
        colour_of = np.arange(trace.n_robots) % len(ROBOT_COLOURS)
        positions = trace.positions[tick]
        if self.link_pairs is not None and self.component is not None:
            labels = self.component[tick]
            leaders = {
                int(label): int(np.flatnonzero(labels == label)[0])
                for label in np.unique(labels[labels >= 0])
            }
            for a, b in self.link_pairs[tick]:
                leader = leaders.get(int(labels[a]), int(a))
                _link_line(
                    draw,
                    self._centre(positions[a]),
                    self._centre(positions[b]),
                    int(_I_BODY0 + colour_of[leader]),
                )
        if self.estimated is not None:
            self._believed(draw, tick)
        if self.goals is not None:
            radius = _robot_side(self.scale) / 2 + 2
            alive = trace.alive[tick] if trace.alive is not None else None
            for robot, goal in enumerate(self.goals[tick]):
                if goal[0] < 0 or (alive is not None and not alive[robot]):
                    continue
                x, y = self._centre(np.asarray(goal, dtype=np.intp))
                box = (x - radius, y - radius, x + radius, y + radius)
                draw.ellipse(box, outline=_I_OUTLINE, width=3)
                draw.ellipse(box, outline=int(_I_BODY0 + colour_of[robot]), width=2)
        drawn = np.asarray(image, dtype=np.uint8).copy()
        robots_layer = drawn[self.map_top : self.map_top + self.map_h, : self.map_w]
        _draw_robots(robots_layer, trace, tick, self.scale, self.stride)
        if self.robot_known is not None:
            for robot, (left, top) in enumerate(self.panel_boxes):
                self._panel(drawn, robot, tick, left, top)
        image = Image.frombuffer("P", (self.width, self.height), drawn.tobytes(), "raw", "P", 0, 1)
        self._text(ImageDraw.Draw(image), tick)
        result: UInt8Array = np.asarray(image, dtype=np.uint8).copy()
        return result

    def _believed(self, draw: Any, tick: int) -> None:
        """Each live robot's believed cell: a hollow square in its colour and a thin
        line to the robot (drawn before the robots, which then sit on top)."""
        assert self.estimated is not None
        trace = self.trace
        half = _robot_side(self.scale) / 2 + 1
        for robot, (cell, believed) in enumerate(
            zip(trace.positions[tick], self.estimated[tick], strict=True)
        ):
            if (trace.alive is not None and not trace.alive[tick, robot]) or (
                cell // self.stride == believed // self.stride
            ).all():
                continue
            colour = int(_I_BODY0 + robot % len(ROBOT_COLOURS))
            x, y = self._centre(believed)
            draw.line((self._centre(cell), (x, y)), fill=colour, width=1)
            box = (round(x - half), round(y - half), round(x + half), round(y + half))
            draw.rectangle(box, outline=colour, width=_BELIEVED_PX)

    def _panel_pixel(self, cell: npt.NDArray[np.intp]) -> tuple[int, int]:
        """The pixel (row, column) of a cell's centre in a belief panel."""
        height, width = self.trace.occupied.shape
        return (
            (2 * int(cell[0]) + 1) * self.panel_h // (2 * height),
            (2 * int(cell[1]) + 1) * self.panel_w // (2 * width),
        )

    def _panel(self, canvas: UInt8Array, robot: int, tick: int, left: int, top: int) -> None:
        assert self.robot_known is not None
        trace = self.trace
        known = self.panel_known[robot]
        known_now = (known >= 0) & (known <= tick)
        image = np.where(known_now, self.panel_known_index[robot], self.panel_occupied)
        colour = int(_I_BODY0 + robot % len(ROBOT_COLOURS))
        box_top = top + _CAPTION_H
        canvas[
            box_top : box_top + self.panel_h + 2 * _BORDER,
            left : left + self.panel_w + 2 * _BORDER,
        ] = colour
        inner = canvas[
            box_top + _BORDER : box_top + _BORDER + self.panel_h,
            left + _BORDER : left + _BORDER + self.panel_w,
        ]
        inner[:] = image
        centre = self._panel_pixel(trace.positions[tick, robot])
        alive = trace.alive is None or bool(trace.alive[tick, robot])
        if self.estimated is not None and alive:
            believed = self._panel_pixel(self.estimated[tick, robot])
            if believed != centre:
                _pixel_line(inner, centre, believed, colour)
                _hollow_square(inner, believed, _PANEL_BELIEVED_PX, colour)
        side = _PANEL_ROBOT_PX
        top_px, left_px = centre[0] - side // 2, centre[1] - side // 2
        inner[max(top_px - 1, 0) : top_px + side + 1, max(left_px - 1, 0) : left_px + side + 1] = (
            _I_OUTLINE
        )
        inner[max(top_px, 0) : top_px + side, max(left_px, 0) : left_px + side] = colour
        if trace.alive is not None and not trace.alive[tick, robot]:
            _cross_out(inner, top_px, left_px, side)

    def _text(self, draw: Any, tick: int) -> None:
        trace = self.trace
        lines = [self.title] if self.title else []
        status = f"tick {tick} / {self.last_tick}    coverage {100 * self.coverage[tick]:.1f}%"
        if self.component is not None:
            labels = self.component[tick]
            status += f"    sub-networks {len(np.unique(labels[labels >= 0]))}"
        if trace.alive is not None:
            failed = int(np.count_nonzero(~trace.alive[tick]))
            if failed:
                status += f"    failed {failed}"
        lines.append(status)
        if self.localisation is not None:
            live = (
                self.localisation[tick]
                if trace.alive is None
                else self.localisation[tick][trace.alive[tick]]
            )
            if live.size:
                lines.append(
                    f"localisation error: mean {live.mean():.1f}, max {live.max():.1f} cells"
                )
            else:
                lines.append("localisation error: no live robot")
        for index, line in enumerate(lines):
            draw.text((4, 2 + index * _LINE_H), line, fill=_I_OUTLINE, font=self.font)
        for robot, (left, top) in enumerate(self.panel_boxes):
            caption = f"robot {robot}"
            if trace.alive is not None and not trace.alive[tick, robot]:
                caption += " (failed)"
            draw.text(
                (left, top),
                caption,
                fill=int(_I_BODY0 + robot % len(ROBOT_COLOURS)),
                font=self.font,
            )

    def frame(self, tick: int) -> UInt8Array:
        """The frame at ``tick`` as an RGB image (``height x width x 3`` uint8)."""
        result: UInt8Array = _PALETTE[self.frame_indices(tick)]
        return result


#: The colours of a frame's palette indices (RGB, uint8).
PALETTE: UInt8Array = _PALETTE


def _pixel_line(image: UInt8Array, start: tuple[int, int], end: tuple[int, int], fill: int) -> None:
    """A 1 px line from pixel ``start`` to ``end`` (row, column), clipped to ``image``."""
    steps = max(abs(end[0] - start[0]), abs(end[1] - start[1])) + 1
    rows = np.rint(np.linspace(start[0], end[0], steps)).astype(np.intp)
    cols = np.rint(np.linspace(start[1], end[1], steps)).astype(np.intp)
    inside = (rows >= 0) & (rows < image.shape[0]) & (cols >= 0) & (cols < image.shape[1])
    image[rows[inside], cols[inside]] = fill


def _hollow_square(image: UInt8Array, centre: tuple[int, int], side: int, fill: int) -> None:
    """The 1 px outline of a ``side`` px square centred on pixel ``centre``, clipped."""
    top, left = centre[0] - side // 2, centre[1] - side // 2
    bottom, right = top + side - 1, left + side - 1
    height, width = image.shape
    rows = slice(max(top, 0), min(bottom + 1, height))
    cols = slice(max(left, 0), min(right + 1, width))
    for row in (top, bottom):
        if 0 <= row < height:
            image[row, cols] = fill
    for col in (left, right):
        if 0 <= col < width:
            image[rows, col] = fill


def _link_line(draw: Any, start: tuple[float, float], end: tuple[float, float], fill: int) -> None:
    """A link: a line in the sub-network's colour (paths are drawn lighter)."""
    draw.line((start, end), fill=fill, width=_LINK_PX)


def every_pair_linked(link_bits: npt.NDArray[Any], component: npt.NDArray[Any]) -> bool:
    """Whether at every tick every two live robots were linked (unlimited range).

    >>> from mrexplore.trace import pack_links
    >>> bits = np.stack([pack_links([(0, 1)], 3), pack_links([(0, 1)], 3)])
    >>> every_pair_linked(bits, np.array([[0, 0, -1], [0, 0, 1]]))
    False
    """
    alive = np.count_nonzero(np.asarray(component) >= 0, axis=1)
    linked = np.unpackbits(np.asarray(link_bits, dtype=np.uint8), axis=1).sum(axis=1)
    return bool(np.array_equal(linked, alive * (alive - 1) // 2))


def _link_pairs(
    link_bits: npt.NDArray[Any], n_robots: int, n_ticks: int
) -> list[npt.NDArray[np.intp]]:
    """Per tick, the linked pairs ``(a, b)``, ``a < b``, as a ``K x 2`` array."""
    n_pairs = n_link_pairs(n_robots)
    expected = (n_ticks, -(-n_pairs // 8))
    if link_bits.shape != expected:
        raise MrexploreInputError(f"link_bits has shape {link_bits.shape}, expected {expected}")
    flags = np.unpackbits(link_bits.astype(np.uint8), axis=1, count=n_pairs).astype(bool)
    low, high = np.triu_indices(n_robots, k=1)
    pairs = np.stack([low, high], axis=1)
    return [pairs[row] for row in flags]


def _coverage(trace: Mapping[str, Any], checked: _Trace) -> npt.NDArray[np.float64]:
    """Coverage per tick: the trace's own curve, else computed from ``first_known``."""
    n_ticks = checked.last_tick + 1
    if "coverage" in trace and np.asarray(trace["coverage"]).shape == (n_ticks,):
        return np.asarray(trace["coverage"], dtype=np.float64)
    from mrexplore.metrics import coverage_curve

    explorable = (
        np.asarray(trace["explorable"], dtype=bool)
        if "explorable" in trace
        else checked.occupied == 0
    )
    first_known = np.asarray(trace["first_known"])
    return coverage_curve(first_known, explorable, n_ticks)


def save_animation(
    path: str | os.PathLike[str],
    trace: Mapping[str, Any],
    *,
    max_frames: int = DEFAULT_MAX_FRAMES,
    fps: int = DEFAULT_FPS,
    hold_last_ms: int = 1500,
    **options: Any,
) -> Path:
    """Write an animation of the run: a GIF, or an MP4 when ``path`` ends in ``.mp4``.

    Ticks are taken by :func:`~mrexplore.viz.frame_ticks`: at most ``max_frames``,
    evenly spread, the first and the last included, so a 5,000-tick run gives a
    file of the same size as a 300-tick one. ``options`` go to :class:`RunAnimator`
    (``scale``, ``trail``, ``links``, ``targets``, ``believed``, ``belief_panels``,
    ``title``).
    The GIF loops forever and holds its last frame ``hold_last_ms``.

    Raises:
        MrexploreInputError: bad arguments, or an MP4 without an ffmpeg (:func:`ffmpeg_path`).

    Returns:
        The path written, as a :class:`~pathlib.Path`.
    """
    if fps < 1:
        raise MrexploreInputError(f"fps must be >= 1, got {fps}")
    out = Path(path)
    mp4 = out.suffix.lower() == ".mp4"
    ffmpeg = ffmpeg_path() if mp4 else None
    if mp4 and ffmpeg is None:
        raise MrexploreInputError(FFMPEG_MISSING)
    animator = RunAnimator(trace, **options)
    ticks = frame_ticks(animator.last_tick, max_frames)
    if ffmpeg is not None:
        return _write_mp4(out, animator, ticks, fps, ffmpeg)
    return _write_gif(out, animator, ticks, fps, hold_last_ms)


def _write_gif(
    out: Path, animator: RunAnimator, ticks: npt.NDArray[np.intp], fps: int, hold_last_ms: int
) -> Path:
    frames = (animator.frame_indices(int(tick)) for tick in ticks)
    return write_indexed_gif(out, frames, fps, hold_last_ms)


def _write_mp4(
    out: Path, animator: RunAnimator, ticks: npt.NDArray[np.intp], fps: int, ffmpeg: str
) -> Path:
    # H.264 in yuv420p needs even sides: pad with white.
    height, width = animator.height + animator.height % 2, animator.width + animator.width % 2
    command = [
        ffmpeg,
        "-y",
        "-loglevel",
        "error",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgb24",
        "-s",
        f"{width}x{height}",
        "-r",
        str(fps),
        "-i",
        "-",
        "-c:v",
        "libx264",
        "-pix_fmt",
        "yuv420p",
        "-movflags",
        "+faststart",
        str(out),
    ]
    padded = np.full((height, width, 3), 255, dtype=np.uint8)
    # ffmpeg's messages go to a file: a pipe nobody reads could fill up and block it.
    with tempfile.TemporaryFile() as messages:
        process = subprocess.Popen(command, stdin=subprocess.PIPE, stderr=messages)
        assert process.stdin is not None
        try:
            for tick in ticks:
                padded[: animator.height, : animator.width] = animator.frame(int(tick))
                process.stdin.write(padded.tobytes())
        except BrokenPipeError:
            pass  # ffmpeg stopped early; its message follows
        finally:
            process.stdin.close()
        code = process.wait()
        messages.seek(0)
        stderr = messages.read().decode(errors="replace")
    if code != 0:
        last_line = (stderr.strip().splitlines() or ["no message"])[-1]
        raise MrexploreError(f"ffmpeg failed writing {out}: {last_line}")
    return out
