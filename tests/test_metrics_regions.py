"""Regional waiting-time and exploration-percentage variances (Wu, Puig & Garcia §V.B)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from mrexplore.checks import check_trace
from mrexplore.errors import MrexploreInputError
from mrexplore.metrics import (
    REGION_COUNTS,
    epv,
    final_epv,
    final_wtv,
    region_curves,
    region_tiling,
    split_regions,
    waiting_times,
    wtv,
)
from mrexplore.sim import Scenario, simulate

# 4x4 map, every cell explorable. Known by tick 4 except the two bottom-right cells.
FIRST_KNOWN = np.array(
    [
        [0, 0, 0, 0],
        [0, 0, 0, 0],
        [2, 2, 4, 4],
        [2, 2, -1, -1],
    ],
    dtype=np.int32,
)
ALL = np.ones((4, 4), dtype=bool)


# ---------------------------------------------------------------- regions


def test_tiling_of_a_square_map_splits_rows_first() -> None:
    tilings = {n: region_tiling((200, 200), n) for n in REGION_COUNTS}
    assert tilings == {2: (2, 1), 4: (2, 2), 8: (4, 2), 16: (4, 4), 32: (8, 4), 64: (8, 8)}


def test_tiling_splits_the_longer_side_first() -> None:
    assert region_tiling((100, 300), 2) == (1, 2)
    assert region_tiling((100, 300), 8) == (2, 4)
    assert region_tiling((300, 100), 8) == (4, 2)


@pytest.mark.parametrize("n_regions", [0, 3, 6, -4])
def test_region_count_must_be_a_power_of_two(n_regions: int) -> None:
    with pytest.raises(MrexploreInputError, match="power of two"):
        split_regions((16, 16), n_regions)


@settings(max_examples=60, deadline=None)
@given(
    n_regions=st.sampled_from(REGION_COUNTS),
    height=st.sampled_from((64, 128, 192)),
    width=st.sampled_from((64, 128, 192)),
)
def test_regions_tile_a_divisible_map_into_equal_rectangles(
    n_regions: int, height: int, width: int
) -> None:
    # Sides that are multiples of 64 divide by any tiling of at most 64 regions.
    labels = split_regions((height, width), n_regions)
    assert labels.shape == (height, width)
    sizes = np.bincount(labels.ravel(), minlength=n_regions)
    assert sizes.size == n_regions
    assert (sizes == height * width // n_regions).all()
    _assert_rectangles(labels)


@settings(max_examples=60, deadline=None)
@given(
    n_regions=st.sampled_from(REGION_COUNTS),
    height=st.integers(8, 70),
    width=st.integers(8, 70),
)
def test_regions_of_any_map_are_nearly_equal_rectangles(
    n_regions: int, height: int, width: int
) -> None:
    labels = split_regions((height, width), n_regions)
    rows, cols = region_tiling((height, width), n_regions)
    assert rows * cols == n_regions
    _assert_rectangles(labels)
    if rows <= height and cols <= width:
        assert set(np.unique(labels).tolist()) == set(range(n_regions))
        band_heights = np.bincount(labels[:, 0] // cols)
        band_widths = np.bincount(labels[0, :] % cols)
        assert band_heights.max() - band_heights.min() <= 1
        assert band_widths.max() - band_widths.min() <= 1


def _assert_rectangles(labels: np.ndarray) -> None:
    for label in np.unique(labels):
        rows, cols = np.nonzero(labels == label)
        box = (rows.max() - rows.min() + 1) * (cols.max() - cols.min() + 1)
        assert box == rows.size, f"region {label} is not a rectangle"


# ---------------------------------------------------------------- hand-checked cases


def test_waiting_times_by_hand() -> None:
    # Robot at (3, 0), tick 4, speed 1: the unknown (3, 2) and (3, 3) are 2 and 3
    # cells away, so w' = 4 + 2 = 6 and 4 + 3 = 7; known cells keep first_known.
    waits = waiting_times(FIRST_KNOWN, ALL, np.array([[3, 0]]), 4, 1.0)
    expected = FIRST_KNOWN.astype(float)
    expected[3, 2:] = [6.0, 7.0]
    np.testing.assert_allclose(waits, expected)


def test_two_regions_by_hand() -> None:
    regions = split_regions((4, 4), 2)  # rows 0-1 = region 0, rows 2-3 = region 1
    robots = np.array([[3, 0]])
    # eq. (8): w_R0 = 0; w_R1 = (2 + 2 + 4 + 4 + 2 + 2 + 6 + 7) / 8 = 29/8 = 3.625.
    # eq. (9): the variance of two values is (difference / 2)^2 = 1.8125^2.
    assert wtv(FIRST_KNOWN, ALL, robots, 4, 1.0, regions) == pytest.approx(1.8125**2)
    # EP = 100 % and 6/8 = 75 %: EPV = (25 / 2)^2 = 156.25.
    assert epv(FIRST_KNOWN, ALL, 4, regions) == pytest.approx(156.25)


def test_four_regions_by_hand() -> None:
    regions = split_regions((4, 4), 4)  # 2x2 blocks: TL, TR, BL, BR
    robots = np.array([[3, 0]])
    # w_R = 0, 0, (2+2+2+2)/4 = 2, (4+4+6+7)/4 = 5.25; mean 1.8125;
    # squared deviations 3.28515625 (x2), 0.03515625, 11.81640625; sum / 4 = 4.60546875.
    assert wtv(FIRST_KNOWN, ALL, robots, 4, 1.0, regions) == pytest.approx(4.60546875)
    # EP = 100, 100, 100, 50; mean 87.5; (3 * 12.5^2 + 37.5^2) / 4 = 468.75.
    assert epv(FIRST_KNOWN, ALL, 4, regions) == pytest.approx(468.75)


def test_earlier_tick_with_speed_and_a_wall_by_hand() -> None:
    explorable = ALL.copy()
    explorable[0, 3] = False  # a wall: left out of both regions
    regions = split_regions((4, 4), 2)
    robots = np.array([[2, 1]])
    # Tick 2, speed 2. Top: 7 known cells at 0 -> w_R0 = 0. Bottom: 4 known at 2, and
    # (2,2), (2,3), (3,2), (3,3) at distances 1, 2, sqrt 2, sqrt 5 -> w' = 2 + d / 2.
    bottom = (4 * 2 + 4 * 2 + (1 + 2 + math.sqrt(2) + math.sqrt(5)) / 2) / 8
    assert wtv(FIRST_KNOWN, explorable, robots, 2, 2.0, regions) == pytest.approx((bottom / 2) ** 2)
    assert epv(FIRST_KNOWN, explorable, 2, regions) == pytest.approx(25.0**2)  # 100 % vs 50 %


def test_regions_without_explorable_cells_are_left_out() -> None:
    explorable = ALL.copy()
    explorable[:, 2:] = False  # regions TR and BR of the 2x2 tiling are empty
    regions = split_regions((4, 4), 4)
    robots = np.array([[3, 0]])
    # Left: TL w_R = 0 and EP 100, BL w_R = 2 and EP 100.
    assert wtv(FIRST_KNOWN, explorable, robots, 4, 1.0, regions) == pytest.approx(1.0)
    assert epv(FIRST_KNOWN, explorable, 4, regions) == 0.0
    explorable[2:, :] = False  # one region left: nothing to vary
    assert wtv(FIRST_KNOWN, explorable, robots, 4, 1.0, regions) == 0.0


def test_final_wtv_is_eq_10_once_everything_is_known() -> None:
    rng = np.random.default_rng(3)
    first_known = rng.integers(0, 50, size=(16, 16)).astype(np.int32)
    trace = _trace(first_known, np.ones((16, 16), dtype=bool), ticks=50, robots=2)
    regions = split_regions((16, 16), 8)
    awt = [first_known[regions == r].mean() for r in range(8)]  # awt_R
    assert final_wtv(trace, 8) == pytest.approx(np.var(awt))
    assert final_epv(trace, 8) == 0.0


def test_dead_robots_do_not_estimate_and_a_dead_team_falls_back() -> None:
    first_known = FIRST_KNOWN
    trace = _trace(first_known, ALL, ticks=4, robots=2)
    trace["positions"][:, 0] = [3, 3]  # robot 0 sits beside the unknown cells
    trace["positions"][:, 1] = [0, 0]
    regions = split_regions((4, 4), 2)
    near, far = np.array([[3, 3]]), np.array([[0, 0]])
    curves = region_curves(trace, region_counts=(2,))
    assert curves["wtv_2"][-1] == pytest.approx(wtv(first_known, ALL, near, 4, 1.0, regions))
    trace["alive"][:, 0] = False
    curves = region_curves(trace, region_counts=(2,))
    assert curves["wtv_2"][-1] == pytest.approx(wtv(first_known, ALL, far, 4, 1.0, regions))
    trace["alive"][:] = False  # nobody left: estimate from where they stopped
    curves = region_curves(trace, region_counts=(2,))
    both = np.array([[3, 3], [0, 0]])
    assert curves["wtv_2"][-1] == pytest.approx(wtv(first_known, ALL, both, 4, 1.0, regions))


def test_many_robots_use_the_kd_tree_and_agree_with_brute_force() -> None:
    rng = np.random.default_rng(7)
    first_known = np.full((40, 40), -1, dtype=np.int32)
    robots = rng.integers(0, 40, size=(100, 2))
    waits = waiting_times(first_known, np.ones((40, 40), dtype=bool), robots, 3, 1.5)
    rows, cols = np.indices((40, 40))
    distance = np.sqrt(
        (rows[..., None] - robots[:, 0]) ** 2 + (cols[..., None] - robots[:, 1]) ** 2
    ).min(axis=-1)
    np.testing.assert_allclose(waits, 3 + distance / 1.5)


def test_bad_inputs_raise() -> None:
    regions = split_regions((4, 4), 2)
    with pytest.raises(MrexploreInputError, match="shape"):
        wtv(FIRST_KNOWN, np.ones((4, 5), dtype=bool), np.array([[0, 0]]), 1, 1.0, regions)
    with pytest.raises(MrexploreInputError, match="speed"):
        wtv(FIRST_KNOWN, ALL, np.array([[0, 0]]), 1, 0.0, regions)
    with pytest.raises(MrexploreInputError, match="positions_at_t"):
        wtv(FIRST_KNOWN, ALL, np.zeros((0, 2), dtype=int), 1, 1.0, regions)
    with pytest.raises(MrexploreInputError, match="every"):
        region_curves(_trace(FIRST_KNOWN, ALL, ticks=4, robots=1), every=0)


# ---------------------------------------------------------------- properties


@settings(max_examples=60, deadline=None)
@given(
    n_regions=st.sampled_from((2, 4, 8, 16)),
    block=hnp.arrays(np.int32, (3, 2), elements=st.integers(-1, 20)),
    t=st.integers(0, 25),
)
def test_epv_is_zero_when_every_region_is_equally_explored(
    n_regions: int, block: np.ndarray, t: int
) -> None:
    rows, cols = region_tiling((3 * 64, 2 * 64), n_regions)
    shape = (3 * rows, 2 * cols)
    assert region_tiling(shape, n_regions) == (rows, cols)
    first_known = np.tile(block, (rows, cols))  # the same pattern in every region
    explorable = np.ones(shape, dtype=bool)
    regions = split_regions(shape, n_regions)
    assert epv(first_known, explorable, t, regions) == pytest.approx(0.0, abs=1e-9)


_maps = st.tuples(st.integers(2, 20), st.integers(2, 20)).flatmap(
    lambda shape: st.tuples(
        hnp.arrays(np.int32, shape, elements=st.integers(-1, 30)),
        hnp.arrays(np.bool_, shape),
        hnp.arrays(
            np.int64,
            st.tuples(st.integers(1, 5), st.just(2)),
            elements=st.integers(0, min(shape) - 1),
        ),
    )
)


@settings(max_examples=80, deadline=None)
@given(
    arrays=_maps,
    t=st.integers(0, 40),
    speed=st.floats(0.25, 4.0),
    n_regions=st.sampled_from(REGION_COUNTS),
)
def test_variances_are_bounded(
    arrays: tuple[np.ndarray, np.ndarray, np.ndarray], t: int, speed: float, n_regions: int
) -> None:
    first_known, explorable, robots = arrays
    regions = split_regions(first_known.shape, n_regions)
    assert wtv(first_known, explorable, robots, t, speed, regions) >= 0.0
    # EP lies in [0, 100], so its variance is at most 50^2.
    assert 0.0 <= epv(first_known, explorable, t, regions) <= 2500.0 + 1e-9


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    every=st.integers(1, 7),
    speed=st.floats(0.5, 3.0),
)
def test_curves_agree_with_wtv_and_epv_tick_by_tick(seed: int, every: int, speed: float) -> None:
    rng = np.random.default_rng(seed)
    shape, ticks, robots = (12, 18), 20, 3
    first_known = rng.integers(-1, ticks + 1, size=shape).astype(np.int32)
    explorable = rng.random(shape) < 0.8
    trace = _trace(first_known, explorable, ticks=ticks, robots=robots, rng=rng)
    trace["speed"] = np.array(speed)
    trace["alive"][ticks // 2 :, 0] = False
    curves = region_curves(trace, region_counts=(2, 8), every=every)
    assert curves["tick"][0] == 0 and curves["tick"][-1] == ticks
    assert (np.diff(curves["tick"]) > 0).all()
    for i, tick in enumerate(curves["tick"].tolist()):
        live = trace["positions"][tick][trace["alive"][tick]]
        for n in (2, 8):
            regions = split_regions(shape, n)
            assert curves[f"wtv_{n}"][i] == pytest.approx(
                wtv(first_known, explorable, live, tick, speed, regions)
            )
            assert curves[f"epv_{n}"][i] == pytest.approx(
                epv(first_known, explorable, tick, regions)
            )


def _trace(
    first_known: np.ndarray,
    explorable: np.ndarray,
    *,
    ticks: int,
    robots: int,
    rng: np.random.Generator | None = None,
) -> dict[str, Any]:
    rng = rng or np.random.default_rng(0)
    height, width = first_known.shape
    positions = np.stack(
        [
            rng.integers(0, height, size=(ticks + 1, robots)),
            rng.integers(0, width, (ticks + 1, robots)),
        ],
        axis=-1,
    ).astype(np.int32)
    return {
        "first_known": first_known,
        "explorable": explorable,
        "positions": positions,
        "alive": np.ones((ticks + 1, robots), dtype=bool),
        "speed": np.array(1.0),
    }


# ---------------------------------------------------------------- a real run


def test_real_run_curves_and_result() -> None:
    record = simulate(Scenario(map="sheng40", robots=3, strategy="nearest-frontier", seed=1))
    trace = record.trace_arrays()
    n_ticks = trace["positions"].shape[0]
    curves = region_curves(trace)
    assert set(curves) == {"tick"} | {f"{m}_{n}" for m in ("wtv", "epv") for n in REGION_COUNTS}
    for name, values in curves.items():
        assert values.shape == (n_ticks,), name
        assert np.isfinite(values).all(), name
    np.testing.assert_array_equal(curves["tick"], np.arange(n_ticks))
    sampled = region_curves(trace, every=10)
    assert sampled["tick"][-1] == n_ticks - 1
    np.testing.assert_allclose(sampled["wtv_8"], curves["wtv_8"][sampled["tick"]])
    result = record.result()
    assert math.isfinite(result["wtv_8_final"]) and result["wtv_8_final"] >= 0
    assert math.isfinite(result["epv_8_final"]) and result["epv_8_final"] >= 0
    assert result["wtv_8_final"] == pytest.approx(curves["wtv_8"][-1])
    assert check_trace(trace, result) == []
