"""The memory budget of a run (issue 13 A): refused before anything large is allocated."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import mrexplore.sim.world as world_module
from mrexplore.cli import main
from mrexplore.grid import GridMap, downsample
from mrexplore.sim import budget
from mrexplore.sim.engine import Simulation
from mrexplore.sim.scenario import Scenario
from mrexplore.sim.world import load_scenario_map

GB = 10**9


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str], *needles: str) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    line = lines[0]
    assert line.startswith("mrexplore: error: "), line
    assert "Traceback" not in err and "internal error" not in err
    for needle in needles:
        assert needle in line, (needle, line)
    return line


@pytest.fixture
def eight_gb(monkeypatch: pytest.MonkeyPatch) -> None:
    """A machine with 8 GB available, whatever this one has."""
    monkeypatch.setattr(budget, "available_memory_bytes", lambda: 8 * GB)


@pytest.fixture
def no_allocation(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail loudly (instead of eating the machine's memory) if a check lets a run through."""

    def boom(*args: object, **kwargs: object) -> None:
        raise AssertionError("the memory check let the run through")

    monkeypatch.setattr(world_module, "generate_map", boom)
    monkeypatch.setattr(world_module, "choose_starts", boom)


# --------------------------------------------------------------------------- CLI


def test_huge_generated_map_is_refused_before_generating(
    capsys: pytest.CaptureFixture[str], eight_gb: None, no_allocation: None
) -> None:
    # Before: ended in "internal error: MemoryError" after 35 s (or ran for hours).
    line = _refused(
        ["run", "--map", "blank", "--size", "10000x10000", "--robots", "1"],
        capsys,
        "--size 10000x10000 with 1 robot needs about",
        "GB, more than the 8 GB available",
        "smaller --size",
    )
    needed = float(line.split("needs about ")[1].split(" GB")[0])
    assert 20 < needed < 60  # 1e8 cells x (14 + 2 + 150) B + the trace of ~12e6 ticks


def test_many_robots_on_a_file_map_are_refused(
    capsys: pytest.CaptureFixture[str], eight_gb: None, no_allocation: None
) -> None:
    _refused(
        ["run", "--map", "intel", "--robots", "10000"],
        capsys,
        "--map intel (685x744 cells of 0.05 m) with 10000 robots needs about",
        "more than the 8 GB available",
        "fewer robots",
    )


def test_pooled_size_is_checked_before_pooling(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, no_allocation: None
) -> None:
    monkeypatch.setattr(budget, "available_memory_bytes", lambda: 10 * 10**6)
    pooled: list[object] = []
    monkeypatch.setattr(world_module, "resample_to_cell_size", lambda *a: pooled.append(a))
    _refused(
        ["run", "--map", "intel", "--cell-size", "0.1", "--robots", "2"],
        capsys,
        "--cell-size 0.1 on the map intel (343x372 cells) with 2 robots needs about",
        "MB available",
    )
    assert not pooled


def test_cell_size_larger_than_the_map_is_a_clear_error(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # Before: downsample padded to (factor x map) cells and tried to allocate 3.6 TiB.
    line = _refused(
        ["run", "--map", "intel", "--cell-size", "1e5"],
        capsys,
        "--cell-size 100000: the map intel is 34.25 m x 37.2 m",
        "1x1 cells",
        "use a cell size below",
    )
    assert "robots" not in line


def test_cell_size_that_leaves_no_free_cell_does_not_blame_the_robots(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # Before: "--robots 4: more robots than free start cells (the largest free region has 0)".
    for size in ("50", "10"):
        line = _refused(
            ["run", "--map", "intel", "--cell-size", size], capsys, f"--cell-size {size}: "
        )
        assert "more robots than free start cells" not in line
    _refused(
        ["run", "--map", "intel", "--cell-size", "10"],
        capsys,
        "the map intel at 10 m per cell has no free cell (every 10 m cell holds a wall)",
        "use a smaller cell size",
    )


def test_cell_size_that_leaves_fewer_free_cells_than_robots(
    capsys: pytest.CaptureFixture[str],
) -> None:
    _refused(
        ["run", "--map", "intel", "--cell-size", "2", "--robots", "50"],
        capsys,
        "--cell-size 2: the map intel at 2 m per cell has only 1 free cell in its largest "
        "free region, fewer than the 50 robots",
    )


def test_unknown_available_memory_refuses_nothing(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(budget, "available_memory_bytes", lambda: None)
    estimate = budget.estimate_run_bytes((10_000, 10_000), 1000)
    budget.check_run_memory("--size 10000x10000", estimate, 1000, "advice")  # no error


# --------------------------------------------------------------------------- the pooling


def test_downsample_with_a_huge_factor_allocates_no_more_than_the_map() -> None:
    occupied = np.ones((700, 700), dtype=bool)
    occupied[1:-1, 1:-1] = False
    tracemalloc.start()
    try:
        coarse = downsample(GridMap(occupied, resolution_m=0.05), 2_000_000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert coarse.occupied.shape == (1, 1) and coarse.occupied.all()
    assert peak < occupied.nbytes


def test_downsample_equals_padding_with_walls() -> None:
    rng = np.random.default_rng(7)
    for _ in range(300):
        height, width = (int(v) for v in rng.integers(1, 25, size=2))
        factor = int(rng.integers(1, 30))
        occupied = rng.random((height, width)) < 0.2
        coarse_h, coarse_w = -(-height // factor), -(-width // factor)
        padded = np.ones((coarse_h * factor, coarse_w * factor), dtype=bool)
        padded[:height, :width] = occupied
        expected = padded.reshape(coarse_h, factor, coarse_w, factor).any(axis=(1, 3))
        assert np.array_equal(downsample(GridMap(occupied), factor).occupied, expected)


# --------------------------------------------------------------------------- the estimate


def _estimate_of(scenario: Scenario, monkeypatch: pytest.MonkeyPatch) -> budget.MemoryEstimate:
    seen: list[budget.MemoryEstimate] = []
    monkeypatch.setattr(budget, "check_run_memory", lambda _w, estimate, *_a: seen.append(estimate))
    load_scenario_map(scenario)
    return seen[-1]


@pytest.mark.parametrize(
    ("scenario", "limit_gb"),
    [
        (Scenario(map="warehouse", robots=32), 1.0),  # benchmarks/bench_suite.py
        (Scenario(map="intel", robots=8, sensor_range=40), 0.3),
        (Scenario(map="office", size=(200, 200), robots=8, strategy="burgard"), 0.1),
        (
            Scenario(
                map="cityblock",
                size=(1000, 1000),
                robots=64,
                comm_range=50.0,
                sharing="sheng-sync",
            ),
            1.0,
        ),
        (Scenario(map="office", size=(2000, 2000), robots=64, sensor_range=10, max_ticks=60), 1.5),
    ],
)
def test_benchmark_runs_are_estimated_modestly(
    scenario: Scenario, limit_gb: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert _estimate_of(scenario, monkeypatch).total < limit_gb * GB


def test_recorded_beliefs_and_strategies_add_their_arrays() -> None:
    base = budget.estimate_run_bytes((1000, 1000), 4)
    recorded = budget.estimate_run_bytes((1000, 1000), 4, record_beliefs=True)
    assert recorded.total - base.total == 4 * 10**6 * 4
    zlot = budget.estimate_run_bytes((1000, 1000), 4, strategy="zlot-market")
    assert zlot.total - base.total == 23 * 10**6 * 4
    linked = budget.estimate_run_bytes((10, 10), 1000)
    apart = budget.estimate_run_bytes((10, 10), 1000, linked_share=0.0)
    assert linked.total - apart.total == 520 * 1000 * 999 // 2


def test_estimate_tracks_the_allocations_of_a_run(monkeypatch: pytest.MonkeyPatch) -> None:
    """The estimate against what numpy and Python really allocate (tracemalloc peak)."""
    scenario = Scenario(map="blank", size=(600, 600), robots=1, max_ticks=30)
    estimate = _estimate_of(scenario, monkeypatch)
    tracemalloc.start()
    try:
        record = Simulation(scenario).run()
        record.result()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    counted = estimate.total - estimate.fixed_bytes  # modules and kernels are not traced
    assert 0.6 * counted < peak < 1.5 * counted, (peak, counted)


def test_ticks_estimate_stays_below_real_runs() -> None:
    # blank 300x300 with 1 robot, sensor 8: complete in 14007 ticks (measured)
    ticks = budget.estimate_ticks(298 * 298, 1, sensor_range_cells=8, speed=1.0)
    assert 5000 < ticks < 14007
    assert budget.estimate_ticks(10**6, 1, sensor_range_cells=8, speed=1, max_ticks=50) == 51
    assert budget.estimate_ticks(10**6, 1, sensor_range_cells=None, speed=1) == 1


# --------------------------------------------------------------------------- available memory


def test_meminfo_is_read_in_kib(tmp_path: Path) -> None:
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:       32000000 kB\nMemAvailable:   22000000 kB\n")
    assert budget._meminfo_available(str(meminfo)) == 22000000 * 1024
    meminfo.write_text("MemTotal: 1 kB\n")
    assert budget._meminfo_available(str(meminfo)) is None
    assert budget._meminfo_available(str(tmp_path / "missing")) is None


def test_cgroup_limit_lowers_the_available_memory(tmp_path: Path) -> None:
    (tmp_path / "memory.max").write_text("4000000000\n")
    (tmp_path / "memory.current").write_text("1000000000\n")
    assert budget._cgroup_headroom(str(tmp_path)) == 3 * GB
    (tmp_path / "memory.max").write_text("max\n")
    assert budget._cgroup_headroom(str(tmp_path)) is None


def test_available_memory_is_a_positive_number_here() -> None:
    available = budget.available_memory_bytes()
    assert available is None or available > 0


def test_format_bytes_never_prints_two_equal_numbers() -> None:
    assert budget.format_bytes(41 * GB) == "41 GB"
    assert budget.format_bytes(350 * 10**6) == "350 MB"
    assert budget.format_bytes(int(22.3 * GB), int(22.1 * GB)) == "22.3 GB"
    assert budget.format_bytes(int(22.1 * GB), int(22.3 * GB)) == "22.1 GB"
