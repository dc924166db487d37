"""The run animation (GIF/MP4) and the record arrays it is drawn from."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from mrexplore.checks import check_trace
from mrexplore.cli import main
from mrexplore.errors import MrexploreInputError
from mrexplore.sim import Scenario
from mrexplore.sim.engine import Simulation
from mrexplore.sim.record import RunRecord
from mrexplore.trace import OPTIONAL_TRACE_ARRAYS, load_trace, pack_links, unpack_links
from mrexplore.viz import RunAnimator, robot_colour, save_animation
from mrexplore.viz import animate as animate_module

COMM_RANGE = 8


@pytest.fixture(scope="module")
def record() -> RunRecord:
    scenario = Scenario(
        map="sheng40",
        robots=4,
        strategy="nearest-frontier",
        seed=2,
        comm_range=COMM_RANGE,
        fail=[(2, 15)],
        max_ticks=120,
    )
    return Simulation(scenario, record_beliefs=True).run()


# ----------------------------------------------------------------- record arrays


def test_new_arrays_have_their_documented_shapes(record: RunRecord) -> None:
    trace = record.trace_arrays()
    n_ticks, n_robots = trace["positions"].shape[:2]
    height, width = trace["truth"].shape
    assert trace["component"].shape == (n_ticks, n_robots)
    assert trace["component"].dtype == np.int16
    assert trace["link_bits"].shape == (n_ticks, math.ceil(n_robots * (n_robots - 1) / 2 / 8))
    assert trace["robot_first_known"].shape == (n_robots, height, width)
    assert trace["robot_first_known"].dtype == np.int32
    assert check_trace(trace, record.result()) == []


def test_components_and_links_agree_with_the_range_model(record: RunRecord) -> None:
    trace = record.trace_arrays()
    positions, alive = trace["positions"], trace["alive"]
    component, links = trace["component"], unpack_links(trace["link_bits"], 4)
    assert np.array_equal(component < 0, ~alive)
    assert np.array_equal(component.max(axis=1) + 1, trace["subnetworks"])
    assert (component[:, 2][15:] == -1).all()
    assert trace["subnetworks"].max() > 1  # the range really splits the team
    for tick in range(1, positions.shape[0]):
        # Links in force during tick t: positions at the end of t - 1, robots alive at t.
        cells = positions[tick - 1].astype(float)
        close = ((cells[:, None] - cells[None]) ** 2).sum(-1) <= COMM_RANGE**2
        expected = close & alive[tick][:, None] & alive[tick][None, :]
        np.fill_diagonal(expected, False)
        assert np.array_equal(links[tick], expected), tick
        linked_a, linked_b = np.nonzero(links[tick])
        assert (component[tick, linked_a] == component[tick, linked_b]).all()


def test_each_robot_knows_what_it_sensed_and_the_team_knows_the_union(record: RunRecord) -> None:
    trace = record.trace_arrays()
    robot_known = trace["robot_first_known"]
    never = np.iinfo(np.int32).max
    earliest = np.where(robot_known >= 0, robot_known, never).min(axis=0)
    team = trace["first_known"]
    assert np.array_equal(np.where(earliest == never, -1, earliest), team)
    # Knowledge is never lost, and a failed robot learns nothing after it failed.
    assert (robot_known[2][robot_known[2] >= 0] < 15).all()


def test_pack_and_unpack_links_round_trip() -> None:
    rng = np.random.default_rng(0)
    for n_robots in (2, 3, 9, 17):
        pairs = [(a, b) for a in range(n_robots) for b in range(a + 1, n_robots)]
        chosen = [p for p in pairs if rng.random() < 0.4]
        matrix = unpack_links(pack_links(chosen, n_robots), n_robots)
        assert {(int(a), int(b)) for a, b in zip(*np.nonzero(np.triu(matrix)), strict=True)} == set(
            chosen
        )


def test_beliefs_are_optional_and_old_traces_load(record: RunRecord, tmp_path: Path) -> None:
    scenario = Scenario(map="sheng40", robots=2, seed=1, max_ticks=20)
    without = Simulation(scenario, record_beliefs=False).run().trace_arrays()
    assert "robot_first_known" not in without and "component" in without
    old = {k: v for k, v in record.trace_arrays().items() if k not in OPTIONAL_TRACE_ARRAYS}
    np.savez_compressed(tmp_path / "trace.npz", **old)
    loaded = load_trace(tmp_path / "trace.npz")
    assert set(loaded) == set(old)
    assert check_trace(loaded) == []


# --------------------------------------------------------------------- frames


def test_frame_shows_header_map_and_belief_panels(record: RunRecord) -> None:
    trace = record.trace_arrays()
    plain = RunAnimator(trace)
    panels = RunAnimator(trace, belief_panels=True, title="a title")
    assert panels.width > plain.width
    assert panels.map_top > plain.map_top
    frame = panels.frame(60)
    assert frame.shape == (panels.height, panels.width, 3)
    # Every robot has a framed panel in its colour.
    for robot, (left, top) in enumerate(panels.panel_boxes):
        border = frame[top + animate_module._CAPTION_H, left + 5]
        assert tuple(int(v) for v in border) == robot_colour(robot)


def test_links_are_drawn_in_the_colour_of_their_subnetwork_leader() -> None:
    truth = np.zeros((30, 60), dtype=np.uint8)
    positions = np.array([[[10, 5], [10, 50], [25, 50]]] * 2)
    trace = {
        "truth": truth,
        "first_known": np.zeros_like(truth, dtype=np.int32),
        "positions": positions,
        "component": np.array([[0, 1, 1]] * 2, dtype=np.int16),
        "link_bits": np.stack([pack_links([(1, 2)], 3)] * 2),
    }
    animator = RunAnimator(trace, scale=4)
    frame = animator.frame(1)
    x, y = animator._centre(np.array([18, 50]))  # halfway between robots 1 and 2
    assert tuple(int(v) for v in frame[round(y), round(x)]) == robot_colour(1)
    x, y = animator._centre(np.array([10, 28]))  # robots 0 and 1 are not linked
    assert tuple(int(v) for v in frame[round(y), round(x)]) == (255, 255, 255)


def test_targets_are_rings_of_the_robot_colour() -> None:
    truth = np.zeros((30, 30), dtype=np.uint8)
    trace = {
        "truth": truth,
        "first_known": np.zeros_like(truth, dtype=np.int32),
        "positions": np.array([[[5, 5]]]),
        "goals": np.array([[[20, 20]]], dtype=np.int32),
    }
    animator = RunAnimator(trace, scale=8)
    indices = animator.frame_indices(0)
    x, y = animator._centre(np.array([20, 20]))
    ring = indices[round(y) - 12 : round(y) + 13, round(x) - 12 : round(x) + 13]
    colours = {tuple(int(v) for v in animate_module.PALETTE[i]) for i in np.unique(ring)}
    assert robot_colour(0) in colours


def test_belief_panels_need_the_beliefs(record: RunRecord) -> None:
    trace = {k: v for k, v in record.trace_arrays().items() if k != "robot_first_known"}
    with pytest.raises(MrexploreInputError, match="belief-panels"):
        RunAnimator(trace, belief_panels=True)


# ------------------------------------------------------------------ animations


def test_gif_skips_frames_and_ends_on_the_last_tick(record: RunRecord, tmp_path: Path) -> None:
    trace = record.trace_arrays()
    path = save_animation(tmp_path / "run.gif", trace, max_frames=12, belief_panels=True)
    with Image.open(path) as gif:
        assert 2 <= gif.n_frames <= 12
        gif.seek(gif.n_frames - 1)
        last = np.asarray(gif.convert("RGB"))
    expected = RunAnimator(trace, belief_panels=True).frame(record.ticks)
    assert np.array_equal(last, expected)


def test_mp4_needs_ffmpeg(
    record: RunRecord, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(animate_module, "ffmpeg_path", lambda: None)
    with pytest.raises(MrexploreInputError, match="ffmpeg"):
        save_animation(tmp_path / "run.mp4", record.trace_arrays())


def test_the_viz_extra_ships_an_encoder_without_a_system_ffmpeg(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PATH", str(tmp_path))  # no ffmpeg there
    found = animate_module.ffmpeg_path()
    assert found is not None and Path(found).is_file()  # imageio-ffmpeg's own binary


def test_mp4_is_written(record: RunRecord, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PATH", str(tmp_path))  # the extra's encoder, not a system one
    path = save_animation(tmp_path / "run.mp4", record.trace_arrays(), max_frames=10)
    head = path.read_bytes()[:12]
    assert head[4:8] == b"ftyp" and path.stat().st_size > 1000  # an MP4 container


def test_cli_run_mp4_without_ffmpeg_is_bad_input(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(animate_module, "ffmpeg_path", lambda: None)  # no encoder at all
    code = main(["run", "--map", "sheng40", "--robots", "2", "--mp4", "--out", str(tmp_path)])
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "ffmpeg" in err


def test_cli_run_gif_with_belief_panels_and_replay(tmp_path: Path) -> None:
    out = tmp_path / "run"
    args = ["run", "--map", "sheng40", "--robots", "3", "--max-ticks", "30", "--out", str(out)]
    assert main([*args, "--gif", "--belief-panels", "--comm-range", "10"]) == 0
    assert (out / "run.gif").stat().st_size > 1000
    assert "robot_first_known" in load_trace(out / "trace.npz")
    assert main(["replay", str(out), "--gif", "--max-frames", "5"]) == 0
    assert (out / "replay.html").exists()
