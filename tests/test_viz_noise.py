"""Pictures of noisy runs (issue 19): believed positions and distorted beliefs.

The traces are a real short run with the three optional arrays of a noisy run added
by hand (``estimated_positions``, ``localisation_error``, ``robot_belief``), and tiny
hand-made traces where a pixel can be checked against a known cell.
"""

from __future__ import annotations

import base64
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from PIL import Image

from mrexplore.errors import MrexploreInputError
from mrexplore.sim import Scenario
from mrexplore.sim.engine import Simulation
from mrexplore.sim.record import RunRecord
from mrexplore.viz import (
    BELIEF_WRONG_FREE_RGB,
    BELIEF_WRONG_OCCUPIED_RGB,
    KNOWN_FREE_RGB,
    KNOWN_OCCUPIED_RGB,
    UNKNOWN_FREE_RGB,
    RunAnimator,
    replay_html,
    robot_colour,
    save_animation,
    save_final_png,
)
from mrexplore.viz import animate as animate_module
from mrexplore.viz.noise import belief_codes, block_belief_codes
from mrexplore.viz.render import _final_figure
from mrexplore.viz.replay import replay_data

Trace = dict[str, Any]
OFFSET = np.array([2, 3])  # the believed cell, from the true one (rows, columns)


@pytest.fixture(scope="module")
def record() -> RunRecord:
    scenario = Scenario(map="sheng40", robots=3, strategy="nearest-frontier", seed=2, max_ticks=60)
    return Simulation(scenario, record_beliefs=True).run()


def noisy(trace: Trace) -> Trace:
    """``trace`` with a noisy run's arrays: each robot believes it is ``OFFSET`` cells
    from where it is (held inside the map), and robot 0 believes every wall it knows
    two rows lower than it is."""
    height, width = trace["truth"].shape
    estimated = trace["positions"] + OFFSET
    estimated[..., 0] = estimated[..., 0].clip(0, height - 1)
    estimated[..., 1] = estimated[..., 1].clip(0, width - 1)
    known = trace["robot_first_known"] >= 0
    belief = np.where(known, np.where(trace["truth"] != 0, 100, 0), -1).astype(np.int8)
    belief[0] = np.where(known[0], np.roll(np.where(belief[0] == 100, 100, 0), 2, axis=0), -1)
    offset = (estimated - trace["positions"]).astype(float)
    return {
        **trace,
        "estimated_positions": estimated.astype(np.int32),
        "localisation_error": np.hypot(offset[..., 0], offset[..., 1]),
        "robot_belief": belief,
    }


def rgb(pixel: npt.NDArray[np.uint8]) -> tuple[int, ...]:
    return tuple(int(value) for value in pixel)


def colours_near(frame: npt.NDArray[np.uint8], y: float, x: float, radius: int) -> set[Any]:
    """The RGB colours in the square of ``radius`` pixels around pixel (x, y)."""
    row, col = round(y), round(x)
    window = frame[row - radius : row + radius + 1, col - radius : col + radius + 1]
    return {rgb(pixel) for pixel in window.reshape(-1, 3)}


def one_robot(estimated: list[list[int]] | None) -> Trace:
    """One robot on an empty 30 x 30 map, at (5, 5) for two ticks."""
    truth = np.zeros((30, 30), dtype=np.uint8)
    trace: Trace = {
        "truth": truth,
        "first_known": np.zeros_like(truth, dtype=np.int32),
        "positions": np.array([[[5, 5]], [[5, 5]]], dtype=np.int32),
    }
    if estimated is not None:
        trace["estimated_positions"] = np.array([[cell] for cell in estimated], dtype=np.int32)
    return trace


# ------------------------------------------------------------------ the animation


def test_frames_render_with_and_without_the_noise_arrays(record: RunRecord) -> None:
    trace = record.trace_arrays()
    for arrays in (trace, noisy(trace)):
        for panels in (False, True):
            animator = RunAnimator(arrays, belief_panels=panels)
            frame = animator.frame(record.ticks)
            assert frame.shape == (animator.height, animator.width, 3)
    # The localisation error gets its own header line.
    assert RunAnimator(noisy(trace)).map_top > RunAnimator(trace).map_top


def test_believed_cell_is_a_hollow_square_of_the_robot_colour() -> None:
    animator = RunAnimator(one_robot([[5, 5], [15, 20]]), scale=8)
    frame = animator.frame(1)
    y, x = animator._centre(np.array([15, 20]))[::-1]
    half = animator_side(animator) / 2 + 1
    colour = robot_colour(0)
    # Its bottom and right sides (the line from the robot comes in from the top left).
    assert colour in colours_near(frame, y + half, x, 1)
    assert colour in colours_near(frame, y, x + half, 1)
    # Hollow: inside, the map shows through.
    assert rgb(frame[round(y) + 2, round(x) - 2]) == KNOWN_FREE_RGB
    # The thin line: halfway between the robot and its believed cell.
    robot_y, robot_x = animator._centre(np.array([5, 5]))[::-1]
    assert colour in colours_near(frame, (y + robot_y) / 2, (x + robot_x) / 2, 1)
    # At tick 0 the robot is where it believes it is: nothing but the robot.
    assert colour not in colours_near(animator.frame(0), y + half, x, 1)
    plain = RunAnimator(one_robot(None), scale=8)
    plain_y = y - animator.map_top + plain.map_top
    assert colour not in colours_near(plain.frame(1), plain_y + half, x, 1)
    # Below the header (one line longer: the localisation error), the same picture.
    assert np.array_equal(animator.frame(0)[animator.map_top :], plain.frame(0)[plain.map_top :])


def animator_side(animator: RunAnimator) -> int:
    return animate_module._robot_side(animator.scale)


def test_believed_positions_can_be_turned_off_and_are_checked() -> None:
    trace = one_robot([[5, 5], [15, 20]])
    off = RunAnimator(trace, scale=8, believed=False)
    plain = RunAnimator(one_robot(None), scale=8)
    assert np.array_equal(off.frame(1)[off.map_top :], plain.frame(1)[plain.map_top :])
    with pytest.raises(MrexploreInputError, match="estimated_positions leave the 30 x 30 map"):
        RunAnimator(one_robot([[5, 5], [15, 30]]))
    with pytest.raises(MrexploreInputError, match="estimated_positions has shape"):
        RunAnimator({**trace, "estimated_positions": np.zeros((1, 1, 2), dtype=np.int32)})


def test_failed_robots_show_no_believed_cell() -> None:
    trace = {**one_robot([[5, 5], [15, 20]]), "alive": np.array([[True], [False]])}
    animator = RunAnimator(trace, scale=8)
    y, x = animator._centre(np.array([15, 20]))[::-1]
    half = animator_side(animator) / 2 + 1
    assert robot_colour(0) not in colours_near(animator.frame(1), y + half, x, 1)


def test_gif_of_a_noisy_run_with_belief_panels(record: RunRecord, tmp_path: Path) -> None:
    trace = noisy(record.trace_arrays())
    path = save_animation(tmp_path / "run.gif", trace, max_frames=6, belief_panels=True)
    with Image.open(path) as gif:
        gif.seek(gif.n_frames - 1)
        last = np.asarray(gif.convert("RGB"))
    assert np.array_equal(last, RunAnimator(trace, belief_panels=True).frame(record.ticks))


# ------------------------------------------------------------------ belief panels


def walls_moved() -> Trace:
    """One robot that knows the whole 30 x 30 map from tick 0 except cell (20, 20),
    known at tick 5, and believes the true wall of row 12 (columns 5-14) is on row 10,
    and the free cell (20, 20) a wall."""
    truth = np.zeros((30, 30), dtype=np.uint8)
    truth[12, 5:15] = 1
    robot_known = np.zeros((1, 30, 30), dtype=np.int32)
    robot_known[0, 20, 20] = 5
    belief = np.zeros((1, 30, 30), dtype=np.int8)
    belief[0, 10, 5:15] = 100
    belief[0, 20, 20] = 100
    return {
        "truth": truth,
        "first_known": robot_known[0],
        "positions": np.full((6, 1, 2), 25, dtype=np.int32),
        "robot_first_known": robot_known,
        "robot_belief": belief,
    }


def panel_pixel(animator: RunAnimator, frame: npt.NDArray[np.uint8], cell: tuple[int, int]) -> Any:
    """The colour of ``cell`` in robot 0's belief panel."""
    left, top = animator.panel_boxes[0]
    row, col = animator._panel_pixel(np.array(cell))
    border = animate_module._BORDER
    return rgb(frame[top + animate_module._CAPTION_H + border + row, left + border + col])


def test_belief_panels_show_the_robots_own_belief_and_its_errors() -> None:
    trace = walls_moved()
    animator = RunAnimator(trace, belief_panels=True, scale=4)
    frame = animator.frame(5)
    assert panel_pixel(animator, frame, (10, 8)) == BELIEF_WRONG_OCCUPIED_RGB  # wall moved here
    assert panel_pixel(animator, frame, (12, 8)) == BELIEF_WRONG_FREE_RGB  # ... from here
    assert panel_pixel(animator, frame, (20, 20)) == BELIEF_WRONG_OCCUPIED_RGB
    assert panel_pixel(animator, frame, (5, 5)) == KNOWN_FREE_RGB  # right, and free
    # A cell shows from the tick the robot first knew it (with its final value).
    assert panel_pixel(animator, animator.frame(4), (20, 20)) == UNKNOWN_FREE_RGB
    # Without robot_belief the panel is coloured by the truth, as before.
    truthful = {k: v for k, v in trace.items() if k != "robot_belief"}
    plain = RunAnimator(truthful, belief_panels=True, scale=4)
    assert panel_pixel(plain, plain.frame(5), (10, 8)) == KNOWN_FREE_RGB
    assert panel_pixel(plain, plain.frame(5), (12, 8)) == KNOWN_OCCUPIED_RGB


def test_a_right_wall_in_the_belief_is_black() -> None:
    trace = walls_moved()
    trace["robot_belief"][0, 12, 5:15] = 100  # the robot also holds the true wall
    animator = RunAnimator(trace, belief_panels=True, scale=4)
    assert panel_pixel(animator, animator.frame(5), (12, 8)) == KNOWN_OCCUPIED_RGB


def test_without_first_known_ticks_the_panels_show_the_final_belief_throughout() -> None:
    trace = {k: v for k, v in walls_moved().items() if k != "robot_first_known"}
    animator = RunAnimator(trace, belief_panels=True, scale=4)
    frame = animator.frame(0)
    assert panel_pixel(animator, frame, (20, 20)) == BELIEF_WRONG_OCCUPIED_RGB
    assert panel_pixel(animator, frame, (12, 8)) == BELIEF_WRONG_FREE_RGB


def test_belief_codes_reduce_to_the_worst_cell_of_a_block() -> None:
    trace = walls_moved()
    codes = belief_codes(trace, trace["truth"])
    assert codes is not None
    reduced = block_belief_codes(codes, 2)
    assert reduced.shape == (1, 15, 15)
    assert reduced[0, 5, 3] == 5 and reduced[0, 6, 3] == 4 and reduced[0, 2, 2] == 2


# ------------------------------------------------------------------ final picture


def final_figure(trace: Trace, **options: Any) -> Any:
    return _final_figure(
        trace["truth"],
        trace["first_known"],
        trace["positions"],
        title="",
        credit="",
        alive=trace.get("alive"),
        explorable=None,
        dpi=110,
        **options,
    )


def figure_colours_near(figure: Any, cell: tuple[int, int], radius: int) -> list[Any]:
    """The RGB colours drawn within ``radius`` pixels of ``cell`` on the team map."""
    figure.canvas.draw()
    image = np.asarray(figure.canvas.buffer_rgba())[..., :3]
    x, y = figure.axes[1].transData.transform((cell[1], cell[0]))
    row, col = round(image.shape[0] - y), round(x)
    window = image[row - radius : row + radius + 1, col - radius : col + radius + 1]
    return [rgb(pixel) for pixel in window.reshape(-1, 3)]


def close_to(colours: list[Any], wanted: tuple[int, int, int], tolerance: int = 40) -> bool:
    return any(sum(abs(a - b) for a, b in zip(c, wanted, strict=True)) < tolerance for c in colours)


def test_final_picture_marks_the_believed_cell() -> None:
    trace = one_robot([[5, 5], [15, 20]])
    estimated = trace.pop("estimated_positions")
    marked = figure_colours_near(final_figure(trace, estimated_positions=estimated), (15, 20), 8)
    assert close_to(marked, robot_colour(0))
    plain = figure_colours_near(final_figure(trace, estimated_positions=None), (15, 20), 8)
    assert not close_to(plain, robot_colour(0))
    legend = final_figure(trace, estimated_positions=estimated).legends[-1]
    assert "believed position" in [text.get_text() for text in legend.get_texts()]


def test_final_png_of_a_noisy_run(record: RunRecord, tmp_path: Path) -> None:
    trace = noisy(record.trace_arrays())
    out = save_final_png(
        tmp_path / "final.png",
        trace["truth"],
        trace["first_known"],
        trace["positions"],
        alive=trace["alive"],
        estimated_positions=trace["estimated_positions"],
    )
    with Image.open(out) as image:
        assert image.format == "PNG"


# ------------------------------------------------------------------ the replay


def unpack(spec: dict[str, Any]) -> np.ndarray:
    dtypes = {"u1": np.uint8, "u2": np.uint16, "i1": np.int8, "i2": np.int16, "i4": np.int32}
    raw = zlib.decompress(base64.b64decode(spec["z"]))
    return np.frombuffer(raw, dtype=np.dtype(dtypes[spec["dtype"]]).newbyteorder("<")).reshape(
        spec["shape"]
    )


def test_replay_embeds_the_believed_positions_errors_and_beliefs(record: RunRecord) -> None:
    trace = noisy(record.trace_arrays())
    data = replay_data(trace)
    meta, arrays = data["meta"], data["arrays"]
    deltas = unpack(arrays["estimated_positions"])
    estimated = np.asarray(meta["estimated_start"])[None] + np.cumsum(deltas, axis=0)
    assert np.array_equal(estimated, trace["estimated_positions"])
    tenths = unpack(arrays["localisation_error"]) / 10
    assert np.allclose(tenths, trace["localisation_error"], atol=0.05)
    codes = belief_codes(trace, trace["truth"])
    assert np.array_equal(unpack(arrays["panel_belief"]), codes)
    assert (unpack(arrays["panel_belief"])[0] == 5).any()  # robot 0's moved walls
    page = replay_html(trace)
    assert 'id="show-believed"' in page and "believed position" in page
    plain = replay_data(record.trace_arrays())["arrays"]
    assert not {"estimated_positions", "localisation_error", "panel_belief"} & set(plain)


def test_replay_of_beliefs_without_first_known_ticks(record: RunRecord) -> None:
    trace = noisy(record.trace_arrays())
    del trace["robot_first_known"]
    arrays = replay_data(trace)["arrays"]
    known = unpack(arrays["robot_known"]).astype(int) - 1
    assert np.array_equal(known, np.where(trace["robot_belief"] >= 0, 0, -1))


def test_replay_draws_believed_positions_and_wrong_beliefs_in_chromium(tmp_path: Path) -> None:
    from test_replay import _browser_or_skip, _wait

    trace = {**walls_moved(), "estimated_positions": np.full((6, 1, 2), 25, dtype=np.int32)}
    trace["estimated_positions"][5] = [15, 20]
    page = tmp_path / "replay.html"
    page.write_text(replay_html(trace))
    driver = _browser_or_skip()
    try:
        driver.get(page.resolve().as_uri() + "#tick=5&beliefs=1")
        state = _wait(driver, "return document.body.dataset.ready || document.body.dataset.error")
        assert state == "1", f"the page failed: {state}"
        # Pixels of the map canvas around the believed cell, and of the panel at a cell.
        read_map = """
            const canvas = document.getElementById("map");
            const k = canvas.width / 30, x = (20 + 0.5) * k, y = (15 + 0.5) * k;
            const r = Math.ceil(Math.max(7, Math.min(k / devicePixelRatio, 16)) * 0.5
              * devicePixelRatio) + 3;
            const d = canvas.getContext("2d").getImageData(x - r, y - r, 2 * r + 1, 2 * r + 1);
            const seen = new Set();
            for (let i = 0; i < d.data.length; i += 4)
              seen.add([d.data[i], d.data[i + 1], d.data[i + 2]].join(","));
            return [...seen];
        """
        colour = ",".join(str(v) for v in robot_colour(0))
        assert colour in driver.execute_script(read_map)
        read_panel = """
            const canvas = document.querySelector("#beliefs .panel canvas");
            const k = canvas.width / 30;
            const pixel = (r, c) => Array.from(canvas.getContext("2d")
              .getImageData((c + 0.5) * k, (r + 0.5) * k, 1, 1).data.slice(0, 3));
            return [pixel(10, 8), pixel(12, 8), pixel(5, 5)];
        """
        moved, missed, free = driver.execute_script(read_panel)
        assert tuple(moved) == BELIEF_WRONG_OCCUPIED_RGB
        assert tuple(missed) == BELIEF_WRONG_FREE_RGB
        assert tuple(free) == KNOWN_FREE_RGB
        # The believed cell is (10, 5) cells from the true one.
        assert driver.find_element("id", "localisation").text == "11.2 / 11.2"
        driver.find_element("id", "show-believed").click()  # off: the marker goes
        assert colour not in driver.execute_script(read_map)
        errors = [e for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
        assert errors == []
    finally:
        driver.quit()
