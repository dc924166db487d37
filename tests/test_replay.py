"""The HTML replay: what it embeds, that it needs no network, and that it plays.

The browser test opens ``replay.html`` in headless Chromium (Debian's ``chromium``
and ``chromium-driver``, installed by ``make browser-deps``) through Selenium, and
is skipped, saying why, when either is missing.
"""

from __future__ import annotations

import base64
import json
import re
import time
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mrexplore.cli import main
from mrexplore.sim import Scenario
from mrexplore.sim.engine import Simulation
from mrexplore.trace import OPTIONAL_TRACE_ARRAYS, load_trace
from mrexplore.viz.replay import replay_data, replay_html, write_replay

CHROMIUM = Path("/usr/bin/chromium")
CHROMEDRIVER = Path("/usr/bin/chromedriver")
DTYPES = {
    "u1": np.uint8,
    "i1": np.int8,
    "u2": np.uint16,
    "i2": np.int16,
    "u4": np.uint32,
    "i4": np.int32,
    "f4": np.float32,
    "f8": np.float64,
}


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short run with partitions and a failure, saved as `mrexplore run --out` does."""
    scenario = Scenario(
        map="sheng40",
        robots=4,
        strategy="nearest-frontier",
        seed=2,
        comm_range=8,
        fail=[(2, 15)],
        max_ticks=120,
    )
    record = Simulation(scenario, record_beliefs=True).run()
    folder = tmp_path_factory.mktemp("run")
    record.save(folder)  # data only: result.json, trace.npz
    return folder


def unpack(spec: dict[str, Any]) -> np.ndarray:
    raw = zlib.decompress(base64.b64decode(spec["z"]))
    array = np.frombuffer(raw, dtype=np.dtype(DTYPES[spec["dtype"]]).newbyteorder("<"))
    if spec.get("bits"):
        count = int(np.prod(spec["shape"]))
        return np.unpackbits(array, count=count).reshape(spec["shape"])
    return array.reshape(spec["shape"])


def test_embedded_arrays_decode_to_the_trace(run_dir: Path) -> None:
    trace = load_trace(run_dir / "trace.npz")
    data = replay_data(trace, json.loads((run_dir / "result.json").read_text()))
    meta, arrays = data["meta"], data["arrays"]
    positions = np.asarray(meta["start"])[None] + np.cumsum(unpack(arrays["positions"]), axis=0)
    assert np.array_equal(positions, trace["positions"])
    goals = np.asarray(meta["goal_start"])[None] + np.cumsum(unpack(arrays["goals"]), axis=0)
    assert np.array_equal(goals, trace["goals"])
    assert np.array_equal(unpack(arrays["first_known"]).astype(int) - 1, trace["first_known"])
    assert np.array_equal(unpack(arrays["truth"]), trace["truth"])
    assert np.array_equal(unpack(arrays["component"]), trace["component"])
    assert np.array_equal(unpack(arrays["link_bits"]), trace["link_bits"])
    assert np.array_equal(unpack(arrays["robot_known"]).astype(int) - 1, trace["robot_first_known"])
    assert np.allclose(unpack(arrays["coverage"]), trace["coverage"], atol=1e-6)
    assert np.array_equal(unpack(arrays["bytes"]), np.cumsum(trace["bytes_per_tick"]))
    assert meta["fail_tick"] == [-1, -1, 15, -1]
    assert meta["last_tick"] == trace["positions"].shape[0] - 1
    assert "nearest-frontier" in meta["title"]


def test_page_is_self_contained(run_dir: Path) -> None:
    page = write_replay(run_dir).read_text()
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "<link" not in page and "@import" not in page
    # The embedded data cannot close its <script> element early.
    assert page.count("</script>") == 2
    assert 'id="tick"' in page and 'id="coverage"' in page


def test_data_that_looks_like_markup_stays_inside_its_script(run_dir: Path) -> None:
    trace = load_trace(run_dir / "trace.npz")
    page = replay_html(trace, {"strategy": "</script><script>alert(1)</script>"})
    assert page.count("</script>") == 2


def test_old_trace_without_the_new_arrays_still_replays(run_dir: Path, tmp_path: Path) -> None:
    trace = load_trace(run_dir / "trace.npz")
    old = {k: v for k, v in trace.items() if k not in (*OPTIONAL_TRACE_ARRAYS, "goals", "alive")}
    np.savez_compressed(tmp_path / "trace.npz", **old)
    assert main(["replay", str(tmp_path)]) == 0
    data = replay_data(load_trace(tmp_path / "trace.npz"))
    assert not {"component", "link_bits", "robot_known", "goals"} & set(data["arrays"])


def test_cli_replay_writes_the_page_and_rejects_bad_input(
    run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "page.html"
    assert main(["replay", str(run_dir), "--out", str(out)]) == 0
    assert out.stat().st_size > 1000
    assert main(["replay", str(tmp_path / "missing")]) == 2
    assert "not a run folder" in capsys.readouterr().err
    (tmp_path / "empty").mkdir()
    assert main(["replay", str(tmp_path / "empty")]) == 2
    assert "no trace.npz" in capsys.readouterr().err


# ------------------------------------------------------------------- the browser


def _browser_or_skip() -> Any:
    if not CHROMIUM.exists() or not CHROMEDRIVER.exists():
        pytest.skip(
            "headless Chromium is not installed (/usr/bin/chromium and /usr/bin/chromedriver "
            "come from Debian's chromium and chromium-driver: `make browser-deps`)"
        )
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        pytest.skip("selenium is not installed (pip install -e '.[dev]')")
    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for argument in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--disable-gpu",
        "--window-size=1280,1000",
    ):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    try:
        return webdriver.Chrome(options=options, service=Service(str(CHROMEDRIVER)))
    except Exception as error:  # any start-up failure means "no usable browser"
        pytest.skip(f"headless Chromium would not start: {error}")


def _wait(driver: Any, script: str, timeout: float = 10.0) -> Any:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for: {script}")


def test_replay_plays_and_seeks_in_headless_chromium(run_dir: Path, tmp_path: Path) -> None:
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    page = write_replay(run_dir, tmp_path / "replay.html")
    last_tick = load_trace(run_dir / "trace.npz")["positions"].shape[0] - 1
    driver = _browser_or_skip()
    try:
        driver.get(page.resolve().as_uri())
        state = _wait(driver, "return document.body.dataset.ready || document.body.dataset.error")
        assert state == "1", f"the page failed: {state}"
        tick = driver.find_element(By.ID, "tick")
        coverage = driver.find_element(By.ID, "coverage")
        assert tick.text == "0"
        start_coverage = coverage.text

        # Play: the tick and the coverage move on by themselves.
        driver.execute_script("document.getElementById('speed').value = '50'")
        driver.find_element(By.ID, "play").click()
        _wait(driver, "return Number(document.getElementById('tick').textContent) >= 10", 5)
        driver.find_element(By.ID, "play").click()  # pause
        assert coverage.text != start_coverage

        # The slider: Home goes back to the start, End to the last tick.
        slider = driver.find_element(By.ID, "slider")
        slider.send_keys(Keys.HOME)
        assert tick.text == "0" and coverage.text == start_coverage
        slider.send_keys(Keys.END)
        assert tick.text == str(last_tick)
        assert coverage.text != start_coverage
        slider.send_keys(Keys.ARROW_LEFT)
        assert tick.text == str(last_tick - 1)

        # Robot beliefs open one panel per robot; the failed robot says so.
        driver.find_element(By.ID, "show-beliefs").click()
        panels = driver.find_elements(By.CSS_SELECTOR, "#beliefs .panel canvas")
        assert len(panels) == 4
        assert "failed" in driver.find_element(By.ID, "beliefs").text
        for toggle in ("show-links", "show-targets", "show-trails"):
            driver.find_element(By.ID, toggle).click()
        assert driver.find_element(By.ID, "failed").text == "1"

        # The keyboard: space plays and pauses, arrows step.
        slider.send_keys(Keys.HOME)
        driver.find_element(By.ID, "map").click()  # the focus leaves the controls
        keys = ActionChains(driver)
        keys.send_keys(Keys.SPACE).perform()
        assert driver.execute_script("return replay.playing")
        keys.send_keys(Keys.SPACE).perform()
        assert not driver.execute_script("return replay.playing")
        driver.execute_script("replay.seek(5)")
        ActionChains(driver).send_keys(Keys.ARROW_RIGHT).perform()
        assert tick.text == "6"

        driver.execute_script(f"replay.seek({last_tick})")
        shot = tmp_path / "replay.png"
        assert driver.save_screenshot(str(shot))
        assert shot.stat().st_size > 10_000
        errors = [e for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
        assert errors == []
    finally:
        driver.quit()


def test_browser_dependencies_are_documented_in_the_makefile() -> None:
    makefile = (Path(__file__).resolve().parents[1] / "Makefile").read_text()
    assert "browser-deps" in makefile.split("\ntest:", 1)[1].splitlines()[0]
    assert "chromium-driver" in makefile


# ------------------------------------------------------------- a big run (slow)


def synthetic_trace(
    size: int = 1000, n_ticks: int = 5001, n_robots: int = 16, sensor: int = 10
) -> dict[str, np.ndarray]:
    """A 1000 x 1000, 5,000-tick record of robots wandering (random headings, one cell
    per tick, bouncing off the border) with a sensor disk.

    Not a simulation: arrays of the right shapes, with realistic change rates and
    irregular known areas (they compress like real runs), to measure the replay.
    """
    rng = np.random.default_rng(7)
    truth = np.zeros((size, size), dtype=np.uint8)
    truth[[0, -1], :] = truth[:, [0, -1]] = 1
    truth[::100, :] = 1
    truth[:, ::125] = 1
    truth[::100, 50::100] = 0  # doors
    truth[50::100, ::125] = 0
    walls = rng.random((size, size)) < 0.01  # clutter
    truth[walls] = 1
    positions = np.zeros((n_ticks, n_robots, 2), dtype=np.int32)
    here = rng.integers(sensor, size - sensor, size=(n_robots, 2))
    heading = rng.integers(-1, 2, size=(n_robots, 2))
    for tick in range(n_ticks):
        turn = rng.random(n_robots) < 0.02
        heading[turn] = rng.integers(-1, 2, size=(int(turn.sum()), 2))
        step = here + heading
        bounce = (step < 1) | (step > size - 2)
        heading[bounce] *= -1
        here = np.clip(here + heading, 1, size - 2)
        positions[tick] = here
    offsets = np.array(
        [(dr, dc) for dr in range(-sensor, sensor + 1) for dc in range(-sensor, sensor + 1)]
    )
    offsets = offsets[(offsets**2).sum(axis=1) <= sensor**2]
    robot_known = np.full((n_robots, size, size), -1, dtype=np.int32)
    for tick in range(n_ticks - 1, -1, -1):  # backwards: the earliest tick wins
        cells = positions[tick][:, None, :] + offsets[None]
        rows = np.clip(cells[..., 0], 0, size - 1)
        cols = np.clip(cells[..., 1], 0, size - 1)
        robot_known[np.arange(n_robots)[:, None], rows, cols] = tick
    never = np.iinfo(np.int32).max
    first_known = np.where(robot_known >= 0, robot_known, never).min(axis=0)
    first_known = np.where(first_known == never, -1, first_known).astype(np.int32)
    alive = np.ones((n_ticks, n_robots), dtype=bool)
    alive[n_ticks // 2 :, 3] = False
    goals = np.roll(positions, -20, axis=0)
    goals[-20:] = -1
    distance2 = ((positions[:, :, None] - positions[:, None]) ** 2).sum(-1)
    linked = (distance2 <= 150**2) & alive[:, :, None] & alive[:, None, :]
    low, high = np.triu_indices(n_robots, k=1)
    link_bits = np.packbits(linked[:, low, high], axis=1)
    component = np.full((n_ticks, n_robots), -1, dtype=np.int16)
    for tick in range(n_ticks):
        label = 0
        for robot in range(n_robots):
            if alive[tick, robot] and component[tick, robot] < 0:
                members = np.flatnonzero(linked[tick, robot]) if linked[tick, robot].any() else []
                component[tick, [robot, *members]] = label
                label += 1
    counts = np.bincount(first_known[first_known >= 0], minlength=n_ticks)[:n_ticks]
    free = truth == 0
    return {
        "truth": truth,
        "explorable": free,
        "first_known": first_known,
        "positions": positions,
        "alive": alive,
        "goals": goals,
        "component": component,
        "link_bits": link_bits,
        "subnetworks": (component.max(axis=1) + 1).astype(np.int64),
        "robot_first_known": robot_known,
        "coverage": np.cumsum(counts) / np.count_nonzero(free),
        "bytes_per_tick": np.full(n_ticks, 1000, dtype=np.int64),
    }


@pytest.mark.slow
def test_replay_of_a_1000_by_1000_map_over_5000_ticks_stays_small_and_fluid(
    tmp_path: Path,
) -> None:
    trace = synthetic_trace()
    started = time.perf_counter()
    page = tmp_path / "replay.html"
    page.write_text(replay_html(trace, {"strategy": "synthetic"}))
    seconds = time.perf_counter() - started
    size_mb = page.stat().st_size / 1e6
    print(f"\nreplay.html: {size_mb:.1f} MB written in {seconds:.1f} s")
    assert size_mb < 20
    driver = _browser_or_skip()
    try:
        started = time.perf_counter()
        driver.get(page.resolve().as_uri())
        state = _wait(
            driver, "return document.body.dataset.ready || document.body.dataset.error", 60
        )
        assert state == "1", f"the page failed: {state}"
        print(f"loaded in the browser in {time.perf_counter() - started:.1f} s")
        timing = driver.execute_script("return replay.benchmark(250)")
        print(f"frame time over 250 seeks: {timing}")
        driver.find_element("id", "show-beliefs").click()
        with_beliefs = driver.execute_script("return replay.benchmark(100)")
        print(f"... with 16 belief panels: {with_beliefs}")
        driver.execute_script("replay.seek(2500)")
        driver.save_screenshot(str(tmp_path / "big.png"))
        # Playing forward draws only what changed: well under a 60 Hz frame budget.
        assert timing["forwardMs"] < 100
    finally:
        driver.quit()
