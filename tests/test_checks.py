"""The trace checker catches broken runs (so the checks elsewhere can fail)."""

from __future__ import annotations

import numpy as np
import pytest

from mrexplore.checks import check_trace
from mrexplore.sim import Scenario, simulate


@pytest.fixture(scope="module")
def trace() -> dict[str, np.ndarray]:
    record = simulate(Scenario(map="office", size=(50, 40), robots=3, seed=2))
    arrays = record.trace_arrays()
    assert check_trace(arrays, record.result()) == []
    return arrays


def tampered(trace: dict[str, np.ndarray], **changes: np.ndarray) -> dict[str, np.ndarray]:
    out = {name: np.array(value, copy=True) for name, value in trace.items()}
    out.update(changes)
    return out


def test_a_robot_inside_a_wall_is_caught(trace: dict[str, np.ndarray]) -> None:
    positions = trace["positions"].copy()
    wall = np.argwhere(trace["truth"] == 1)[0]
    positions[5, 0] = wall
    problems = check_trace(tampered(trace, positions=positions))
    assert any("inside a wall" in p for p in problems)


def test_a_teleport_is_caught(trace: dict[str, np.ndarray]) -> None:
    positions = trace["positions"].copy()
    free = np.argwhere((trace["truth"] == 0) & trace["explorable"])
    far = max(
        free.tolist(), key=lambda c: abs(c[0] - positions[9, 0, 0]) + abs(c[1] - positions[9, 0, 1])
    )
    positions[10, 0] = far
    problems = check_trace(tampered(trace, positions=positions))
    assert any("moved illegally" in p for p in problems)


def test_two_robots_in_one_cell_are_caught(trace: dict[str, np.ndarray]) -> None:
    positions = trace["positions"].copy()
    positions[3, 1] = positions[3, 0]
    assert any("share a cell" in p for p in check_trace(tampered(trace, positions=positions)))


def test_knowledge_out_of_sight_is_caught(trace: dict[str, np.ndarray]) -> None:
    first_known = trace["first_known"].copy()
    start = trace["positions"][0, 0]
    far = np.unravel_index(
        np.argmax(np.hypot(*np.indices(first_known.shape) - start[:, None, None])),
        first_known.shape,
    )
    first_known[far] = 0
    problems = check_trace(tampered(trace, first_known=first_known))
    assert any("out of every robot's sight" in p for p in problems)


def test_metrics_that_do_not_follow_from_the_trace_are_caught(trace: dict[str, np.ndarray]) -> None:
    record_result = {"total_distance": -1.0, "ticks": len(trace["positions"]) - 1}
    problems = check_trace(trace, record_result)
    assert any("total_distance" in p for p in problems)
