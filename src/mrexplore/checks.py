"""Checkers that ship: re-check a run from its trace, and check a strategy plugin.

* :func:`check_trace` re-checks a run from the arrays of ``trace.npz`` alone
  (DESIGN §8): moves are legal, no robot crossed a wall or shared a cell, every
  cell the team knew was in sensor range and sight of a robot when it became
  known, and (given ``result.json``) the metrics follow from the trace.
* :func:`check_strategy` runs a registered strategy through small scenarios and
  checks the contract any strategy must keep (as Gymnasium's ``check_env``).
* :func:`check_determinism` runs a scenario twice and compares the traces.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from mrexplore.errors import MrexploreInputError, StrategyError
from mrexplore.metrics import json_safe, summarize
from mrexplore.planning import distance_field
from mrexplore.sensing import visible_cells

SQRT2 = math.sqrt(2.0)


def check_trace(trace: Mapping[str, Any], result: Mapping[str, Any] | None = None) -> list[str]:
    """Every violation of the run contract found in ``trace`` (empty list = valid)."""
    problems: list[str] = []
    truth = np.asarray(trace["truth"]).astype(bool)
    positions = np.asarray(trace["positions"])
    first_known = np.asarray(trace["first_known"])
    alive = np.asarray(trace["alive"]) if "alive" in trace else None
    radius = float(trace["sensor_range"])
    speed = float(trace["speed"])
    height, width = truth.shape
    n_ticks, n_robots, _ = positions.shape
    rows, cols = positions[..., 0], positions[..., 1]
    if (rows < 0).any() or (rows >= height).any() or (cols < 0).any() or (cols >= width).any():
        return ["a robot left the map"]
    if truth[rows, cols].any():
        tick, robot = np.argwhere(truth[rows, cols])[0]
        problems.append(f"robot {robot} is inside a wall at tick {tick}")
    for tick in range(n_ticks):
        cells = {tuple(p) for p in positions[tick]}
        if len(cells) != n_robots:
            problems.append(f"two robots share a cell at tick {tick}")
            break
    free = ~truth
    max_step = speed + SQRT2 + 1e-9
    steps = np.diff(positions, axis=0)
    for tick, robot in np.argwhere(np.abs(steps).max(axis=2) > 0):
        start, end = positions[tick, robot], positions[tick + 1, robot]
        d_row, d_col = (int(v) for v in end - start)
        if max(abs(d_row), abs(d_col)) == 1:
            side_a = truth[start[0] + d_row, start[1]]
            side_b = truth[start[0], start[1] + d_col]
            if not (d_row and d_col and (side_a or side_b)):
                continue  # a legal single step
        # Several steps in one tick (speed, or budget carried over): a path over free
        # cells no longer than the largest budget must exist.
        reach = distance_field(free, (int(start[0]), int(start[1])), max_distance=max_step)
        if not reach[end[0], end[1]] <= max_step:
            problems.append(
                f"robot {robot} moved illegally {start.tolist()} -> {end.tolist()} "
                f"at tick {tick + 1} (wall, corner or too far)"
            )
    if "distance" in trace:
        distance = np.asarray(trace["distance"])
        increments = np.diff(distance, axis=0)
        octile = np.abs(steps).max(axis=2) + (SQRT2 - 1) * np.abs(steps).min(axis=2)
        if (increments < octile - 1e-9).any():
            problems.append("recorded distance is shorter than the moves")
    for tick in np.unique(first_known[first_known >= 0]):
        known = first_known == tick
        seen = np.zeros_like(known)
        for robot in range(n_robots):
            if alive is not None and not alive[tick, robot]:
                continue
            cell = (int(positions[tick, robot, 0]), int(positions[tick, robot, 1]))
            vis_rows, vis_cols = visible_cells(truth, cell, radius)
            seen[vis_rows, vis_cols] = True
        if (known & ~seen).any():
            r, c = np.argwhere(known & ~seen)[0]
            problems.append(
                f"cell ({r}, {c}) became known at tick {tick} out of every robot's sight"
            )
    if "robot_complete" in trace and "robot_first_known" in trace:
        explorable = np.asarray(trace["explorable"], dtype=bool)
        for robot, done in enumerate(np.asarray(trace["robot_complete"])):
            own = np.asarray(trace["robot_first_known"][robot])[explorable]
            held = (own >= 0).all() and own.size > 0
            # a belief may forget cells (polygon sharing): only a completion the robot's
            # first_known cannot have reached is a violation
            if done >= 0 and held and int(own.max()) > done:
                problems.append(
                    f"robot {robot} held the whole map at tick {done}, but its own first_known "
                    f"reaches tick {int(own.max())}"
                )
            if done < 0 and held:
                problems.append(f"robot {robot} held the whole map but robot_complete is -1")
    if result is not None:
        expected = json_safe(summarize(dict(trace)))
        for key, value in expected.items():
            if key in result and not _close(result[key], value):
                problems.append(f"result.json {key}={result[key]!r} but the trace gives {value!r}")
        if "ticks" in result and result["ticks"] != n_ticks - 1:
            problems.append(f"result.json ticks={result['ticks']} but the trace has {n_ticks - 1}")
    return problems


def _close(a: Any, b: Any) -> bool:
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_close(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, int | float) and isinstance(b, int | float):
        return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-9)
    return bool(a == b)


def check_determinism(scenario: Any) -> list[str]:
    """Run ``scenario`` twice; report any trace array that differs."""
    from mrexplore.sim.engine import simulate

    first = simulate(scenario).trace_arrays()
    second = simulate(scenario).trace_arrays()
    return [
        f"trace array {name!r} differs between two runs of the same scenario"
        for name in first
        if not np.array_equal(first[name], second[name])
    ]


def check_strategy(name: str, *, max_ticks: int = 3000) -> None:
    """Raise :class:`StrategyError` listing every way strategy ``name`` breaks the contract.

    Runs it with 1 and 3 robots on ``sheng40`` and a small ``office`` (twice each,
    to check determinism), checks that each run completes and that its trace is
    valid, that every parameter's default lies in its declared range, and that an
    unknown parameter is refused as bad input.
    """
    from mrexplore.sim.engine import simulate
    from mrexplore.sim.scenario import Scenario
    from mrexplore.strategies.registry import get_strategy

    cls = get_strategy(name)
    problems: list[str] = []
    if cls.id != name:
        problems.append(f"registered as {name!r} but its id is {cls.id!r}")
    if not cls.summary:
        problems.append("has no one-line summary")
    for param, spec in cls.params.items():
        if not isinstance(spec.default, bool | int | float | str):
            problems.append(f"parameter {param!r} has a default that is not bool/int/float/str")
        elif not spec.accepts(spec.default):
            problems.append(
                f"parameter {param!r} has a default {spec.default!r} outside its declared "
                f"range ({spec.describe()})"
            )
    try:
        cls(0, 1, **{"no_such_parameter_xyz": 1})
        problems.append("accepted an unknown parameter")
    except MrexploreInputError:
        pass
    for map_name, size, robots in (("sheng40", None, 1), ("office", (48, 36), 3)):
        scenario = Scenario(
            map=map_name, size=size, robots=robots, strategy=name, seed=3, max_ticks=max_ticks
        )
        try:
            record = simulate(scenario)
        except StrategyError as error:
            problems.append(f"{map_name} with {robots} robots: {error}")
            continue
        if record.status != "complete":
            problems.append(f"{map_name} with {robots} robots ended {record.status!r}")
        problems += [
            f"{map_name} with {robots} robots: {p}"
            for p in check_trace(record.trace_arrays(), record.result())
        ]
        problems += [f"{map_name} with {robots} robots: {p}" for p in check_determinism(scenario)]
    if problems:
        raise StrategyError(f"strategy {name!r}: " + "; ".join(problems))
