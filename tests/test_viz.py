"""Tests of mrexplore.viz on a small synthetic trace."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest
from PIL import Image

from mrexplore.errors import MrexploreInputError
from mrexplore.viz import (
    KNOWN_FREE_RGB,
    KNOWN_OCCUPIED_RGB,
    UNKNOWN_FREE_RGB,
    UNKNOWN_OCCUPIED_RGB,
    coverage_plot_png,
    frame_ticks,
    render_frame,
    robot_colour,
    save_final_png,
    save_gif,
)

HEIGHT, WIDTH, N_ROBOTS, LAST_TICK = 30, 40, 3, 20
SENSOR_RANGE = 3


class Trace:
    """A tiny run: robots walking along the free corridors of a walled grid."""

    def __init__(self) -> None:
        truth = np.zeros((HEIGHT, WIDTH), dtype=np.uint8)
        truth[0, :] = truth[-1, :] = truth[:, 0] = truth[:, -1] = 1
        truth[10, 5:30] = 1  # an inner wall
        self.truth = truth
        # Each robot moves one cell right every tick along its own row.
        starts = np.array([[3, 2], [15, 5], [25, 10]])
        steps = np.arange(LAST_TICK + 1)
        positions = np.repeat(starts[None], LAST_TICK + 1, axis=0)
        positions[:, :, 1] += steps[:, None]
        self.positions = positions
        first_known = np.full((HEIGHT, WIDTH), -1, dtype=np.int32)
        rows, cols = np.mgrid[0:HEIGHT, 0:WIDTH]
        for tick in range(LAST_TICK + 1):
            for row, col in positions[tick]:
                seen = (rows - row) ** 2 + (cols - col) ** 2 <= SENSOR_RANGE**2
                first_known[seen & (first_known < 0)] = tick
        self.first_known = first_known
        self.alive = np.ones((LAST_TICK + 1, N_ROBOTS), dtype=bool)
        self.alive[12:, 1] = False


@pytest.fixture(scope="module")
def trace() -> Trace:
    return Trace()


def rgb(pixel: npt.NDArray[np.uint8]) -> tuple[int, ...]:
    return tuple(int(value) for value in pixel)


def test_frame_shape_and_dtype(trace: Trace) -> None:
    frame = render_frame(trace.truth, trace.first_known, trace.positions, 5, scale=3)
    assert frame.shape == (HEIGHT * 3, WIDTH * 3, 3)
    assert frame.dtype == np.uint8


def test_auto_scale_gives_a_picture_of_about_500_px(trace: Trace) -> None:
    frame = render_frame(trace.truth, trace.first_known, trace.positions, 5)
    scale = frame.shape[0] // HEIGHT
    assert frame.shape == (HEIGHT * scale, WIDTH * scale, 3)
    assert 400 <= max(frame.shape[:2]) <= 600


@pytest.mark.parametrize("scale", [1, 2, 8])
def test_robot_pixel_has_its_colour(trace: Trace, scale: int) -> None:
    tick = 7
    frame = render_frame(trace.truth, trace.first_known, trace.positions, tick, scale=scale)
    for robot, (row, col) in enumerate(trace.positions[tick]):
        centre = frame[row * scale + scale // 2, col * scale + scale // 2]
        assert rgb(centre) == robot_colour(robot)


def test_map_classes_have_their_colours(trace: Trace) -> None:
    tick = 10
    frame = render_frame(trace.truth, trace.first_known, trace.positions, tick, scale=1, trail=0)
    known = (trace.first_known >= 0) & (trace.first_known <= tick)
    # Cells far from every robot, so no robot square covers them.
    far = np.ones_like(known)
    for row, col in trace.positions[tick]:
        far[max(row - 3, 0) : row + 4, max(col - 3, 0) : col + 4] = False
    expected = {
        (False, False): UNKNOWN_FREE_RGB,
        (False, True): UNKNOWN_OCCUPIED_RGB,
        (True, False): KNOWN_FREE_RGB,
        (True, True): KNOWN_OCCUPIED_RGB,
    }
    for (is_known, occupied), colour in expected.items():
        cells = far & (known == is_known) & ((trace.truth == 1) == occupied)
        assert cells.any()
        assert all(rgb(pixel) == colour for pixel in frame[cells])


def test_trail_is_drawn_and_can_be_limited(trace: Trace) -> None:
    tick, scale = 15, 2
    args = (trace.truth, trace.first_known, trace.positions, tick)
    full = render_frame(*args, scale=scale)
    short = render_frame(*args, scale=scale, trail=3)
    row, col = trace.positions[2, 0]  # robot 0's cell at tick 2: long behind it
    pixel = (row * scale, col * scale)
    assert rgb(full[pixel]) == robot_colour(0)
    assert rgb(short[pixel]) == KNOWN_FREE_RGB


def test_big_map_is_reduced_without_losing_robots() -> None:
    size = 1500
    truth = np.zeros((size, size), dtype=np.uint8)
    first_known = np.full((size, size), -1, dtype=np.int32)
    positions = np.array([[[1, 1], [777, 1001], [1499, 1499]]])
    frame = render_frame(truth, first_known, positions, 0)
    assert 400 <= max(frame.shape[:2]) <= 600
    stride = -(-size // frame.shape[0])
    for robot, (row, col) in enumerate(positions[0]):
        assert rgb(frame[row // stride, col // stride]) == robot_colour(robot)


def test_failed_robot_is_crossed_out(trace: Trace) -> None:
    tick, scale = 15, 10
    args = (trace.truth, trace.first_known, trace.positions, tick)
    plain = render_frame(*args, scale=scale)
    marked = render_frame(*args, scale=scale, alive=trace.alive)
    row, col = trace.positions[tick, 1]
    box = (slice(row * scale, (row + 1) * scale), slice(col * scale, (col + 1) * scale))
    assert not np.array_equal(plain[box], marked[box])
    others = trace.positions[tick, 0]
    other_box = (slice(others[0] * scale, (others[0] + 1) * scale), slice(others[1] * scale, None))
    assert np.array_equal(plain[other_box], marked[other_box])


def test_bad_input_is_reported(trace: Trace) -> None:
    with pytest.raises(MrexploreInputError, match="tick"):
        render_frame(trace.truth, trace.first_known, trace.positions, LAST_TICK + 1)
    with pytest.raises(MrexploreInputError, match="first_known"):
        render_frame(trace.truth, trace.first_known[:-1], trace.positions, 0)
    outside = trace.positions.copy()
    outside[3, 0] = (HEIGHT, 0)
    with pytest.raises(MrexploreInputError, match="leave"):
        render_frame(trace.truth, trace.first_known, outside, 0)


def test_frame_ticks_are_even_and_end_at_the_last_tick() -> None:
    for last_tick in (0, 1, 7, 20, 199, 200, 1001):
        for max_frames in (1, 2, 3, 50, 200, 500):
            ticks = frame_ticks(last_tick, max_frames)
            assert len(ticks) == min(max_frames, last_tick + 1)
            assert ticks[-1] == last_tick
            assert np.all(np.diff(ticks) > 0)
            if max_frames > 1:
                assert ticks[0] == 0


def gif_frames(path: Path) -> list[npt.NDArray[np.uint8]]:
    frames = []
    with Image.open(path) as gif:
        assert gif.format == "GIF"
        for index in range(getattr(gif, "n_frames", 1)):
            gif.seek(index)
            frames.append(np.asarray(gif.convert("RGB")))
    return frames


def test_gif_has_every_tick_when_allowed(trace: Trace, tmp_path: Path) -> None:
    out = save_gif(tmp_path / "run.gif", trace.truth, trace.first_known, trace.positions)
    assert out == tmp_path / "run.gif"
    with Image.open(out) as gif:
        assert getattr(gif, "n_frames", 1) == LAST_TICK + 1
        assert gif.info.get("loop") == 0


def test_gif_respects_max_frames_and_ends_on_the_last_tick(trace: Trace, tmp_path: Path) -> None:
    args = (trace.truth, trace.first_known, trace.positions)
    out = save_gif(tmp_path / "run.gif", *args, max_frames=7, fps=5, scale=4, alive=trace.alive)
    frames = gif_frames(out)
    assert len(frames) == 7
    last = render_frame(*args, LAST_TICK, scale=4, alive=trace.alive)
    assert np.array_equal(frames[-1], last)
    first = render_frame(*args, 0, scale=4, alive=trace.alive)
    assert np.array_equal(frames[0], first)


def test_final_png_opens(trace: Trace, tmp_path: Path) -> None:
    explorable = trace.truth == 0
    out = save_final_png(
        tmp_path / "final.png",
        trace.truth,
        trace.first_known,
        trace.positions,
        title="synthetic run",
        credit="Map: synthetic test grid",
        alive=trace.alive,
        explorable=explorable,
    )
    with Image.open(out) as image:
        assert image.format == "PNG"
        width, height = image.size
    assert width > 300 and height > 200
    assert out.stat().st_size < 1_000_000


def test_coverage_plot_opens(tmp_path: Path) -> None:
    curve = np.minimum(1.0, np.linspace(0, 1.3, 50))
    out = coverage_plot_png(tmp_path / "coverage.png", curve, title="coverage")
    with Image.open(out) as image:
        assert image.format == "PNG"
    both = np.stack([curve, curve**2])
    out = coverage_plot_png(tmp_path / "two.png", both, labels=["a", "b"])
    with Image.open(out) as image:
        assert image.format == "PNG"


def test_import_does_not_load_matplotlib() -> None:
    code = (
        "import sys, mrexplore.viz\n"
        "loaded = sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib')\n"
        "assert not loaded, loaded\n"
    )
    # Whatever made mrexplore importable here (installed or on sys.path) is passed on.
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    result = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=False
    )
    assert result.returncode == 0, result.stderr
