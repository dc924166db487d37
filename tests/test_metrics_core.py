"""The run metrics of ``mrexplore.metrics.core`` against plain formulations."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from hypothesis import given, settings
from hypothesis import strategies as st

from mrexplore.metrics.core import group_diameter


def all_pairs_diameter(positions: npt.NDArray[np.int32]) -> npt.NDArray[np.float64]:
    """Every pair's distance at every tick at once, then the largest."""
    diff = positions[:, :, None, :].astype(np.float64) - positions[:, None, :, :]
    return np.sqrt((diff**2).sum(axis=-1)).max(axis=(1, 2))


@settings(max_examples=60, deadline=None)
@given(
    ticks=st.integers(1, 40),
    robots=st.integers(2, 12),
    side=st.integers(1, 2000),
    seed=st.integers(0, 2**32 - 1),
)
def test_group_diameter_is_the_largest_pair_distance_to_the_bit(
    ticks: int, robots: int, side: int, seed: int
) -> None:
    positions = np.random.default_rng(seed).integers(0, side, (ticks, robots, 2)).astype(np.int32)
    assert np.array_equal(group_diameter(positions), all_pairs_diameter(positions))


def test_group_diameter_of_one_robot_is_zero() -> None:
    positions = np.zeros((5, 1, 2), dtype=np.int32)
    assert np.array_equal(group_diameter(positions), np.zeros(5))


def test_group_diameter_of_a_known_team() -> None:
    positions = np.array([[[0, 0], [3, 4], [1, 1]], [[0, 0], [0, 0], [6, 8]]], dtype=np.int32)
    assert group_diameter(positions).tolist() == [5.0, 10.0]
