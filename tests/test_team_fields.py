"""The compiled team paths of issue 20 (burgard, market-occupancy) equal the plain
formulations they replace, on random maps: costs from every robot to every target,
paths in reused buffers, reachability by a flood, line of sight to a few targets,
burgard's assignment and market-occupancy's row."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np
import numpy.typing as npt
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import robot_view
from mrexplore.comm.bytes import float32_on_wire
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import distance_field, frontier_mask, path_to
from mrexplore.planning.distance import FieldCounter
from mrexplore.planning.team_fields import (
    Components,
    reachable,
    team_costs,
    workspace,
    workspace_path,
)
from mrexplore.planning.visibility import in_sight_kernel
from mrexplore.sensing import visible_cells_flat
from mrexplore.strategies import market_occupancy as market
from mrexplore.strategies.base import RobotView
from mrexplore.strategies.burgard import assign_greedy
from mrexplore.strategies.market_occupancy import MarketOccupancy
from mrexplore.strategies.utility import coverage_probability, discount

U, F, W = UNKNOWN, FREE, OCCUPIED
Cell = tuple[int, int]


@st.composite
def beliefs(draw: st.DrawFn) -> npt.NDArray[np.int8]:
    """Small random maps, and tall mostly free ones (where a search that stops early
    touches only some of the rows: the buffers are reset by rows)."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if draw(st.booleans()):
        height, width = draw(st.integers(1, 25)), draw(st.integers(1, 25))
        weights = rng.dirichlet(np.ones(3) * 0.7)
    else:
        height, width = draw(st.integers(30, 120)), draw(st.integers(1, 8))
        weights = np.array([0.05, 0.85, 0.1])
    return rng.choice(np.array([U, F, W], dtype=np.int8), size=(height, width), p=weights)


def _cells(belief: npt.NDArray[np.int8], picks: list[int]) -> list[Cell]:
    return [(int(r), int(c)) for r, c in (divmod(p % belief.size, belief.shape[1]) for p in picks)]


def _workspace_is_clean(n_cells: int) -> bool:
    space = workspace(n_cells)
    return bool(np.isinf(space.dist).all() and not space.state.any() and not space.targets.any())


@settings(max_examples=300, deadline=None)
@given(beliefs(), st.lists(st.integers(0, 100_000), min_size=0, max_size=6), st.booleans())
def test_team_costs_equal_one_distance_field_per_source(
    belief: npt.NDArray[np.int8], picks: list[int], frontier_targets: bool
) -> None:
    passable = belief == FREE
    sources = _cells(belief, picks)  # any cells: passable or not, repeated or not
    if frontier_targets:
        targets = frontier_mask(belief)
    else:  # any cells, passable or not
        rng = np.random.default_rng(len(picks))
        targets = rng.random(belief.shape) < 0.3
    index = np.flatnonzero(targets)
    with FieldCounter() as counter:
        got = team_costs(passable, sources, index)
    assert counter.count == len(sources)
    assert got.shape == (len(sources), index.size)
    rows, cols = np.divmod(index, belief.shape[1])
    for i, source in enumerate(sources):
        want = distance_field(passable, source, targets=targets)[rows, cols]
        np.testing.assert_array_equal(got[i], want)  # bit for bit, inf included
    assert _workspace_is_clean(belief.size)
    np.testing.assert_array_equal(passable, belief == FREE)  # restored


@settings(max_examples=300, deadline=None)
@given(beliefs(), st.integers(0, 100_000), st.integers(0, 100_000))
def test_workspace_path_equals_path_to(
    belief: npt.NDArray[np.int8], pick_start: int, pick_goal: int
) -> None:
    passable = belief == FREE
    start, goal = _cells(belief, [pick_start, pick_goal])
    want = path_to(passable, start, goal)
    with FieldCounter() as counter:
        got = workspace_path(passable, start, goal)
    assert counter.count == 1
    if want is None:
        assert got is None
    else:
        assert got is not None
        np.testing.assert_array_equal(got, want)
    assert _workspace_is_clean(belief.size)


@settings(max_examples=300, deadline=None)
@given(beliefs(), st.integers(0, 10_000), st.floats(0.5, 12.0))
def test_in_sight_kernel_equals_the_viewers_disk(
    belief: npt.NDArray[np.int8], pick: int, radius: float
) -> None:
    occupied = belief == OCCUPIED
    (row, col) = _cells(belief, [pick])[0]
    rows, cols = np.divmod(np.arange(belief.size, dtype=np.int64), belief.shape[1])
    candidates = np.hypot(rows - row, cols - col) < radius
    seen = np.empty(belief.size, dtype=np.bool_)
    n_seen = in_sight_kernel(occupied, row, col, rows, cols, candidates, seen)
    disk = np.zeros(belief.size, dtype=bool)
    disk[visible_cells_flat(occupied, (row, col), radius)] = True
    np.testing.assert_array_equal(seen, disk & candidates)
    assert n_seen == int(seen.sum())


def reference_discount(
    utility: npt.NDArray[np.float64],
    target_rows: npt.NDArray[np.int64],
    target_cols: npt.NDArray[np.int64],
    goal: Cell,
    max_range: float,
    occupied: npt.NDArray[np.bool_] | None = None,
) -> None:
    """utility.discount as it was: the goal's whole visible disk."""
    d = np.hypot(target_rows - goal[0], target_cols - goal[1])
    reduction = coverage_probability(d, max_range)
    if occupied is not None and reduction.any():
        seen = np.zeros(occupied.size, dtype=bool)
        seen[visible_cells_flat(occupied, goal, max_range)] = True
        reduction = np.where(seen[target_rows * occupied.shape[1] + target_cols], reduction, 0.0)
    utility -= reduction


def reference_assign_greedy(
    robots: list[int],
    positions: Mapping[int, Cell],
    held_goals: Mapping[int, Cell],
    belief_passable: npt.NDArray[np.bool_],
    frontier: npt.NDArray[np.bool_],
    *,
    beta: float,
    max_range: float,
    normalize_cost: bool,
    unreachable: Mapping[int, Iterable[Cell]] | None = None,
    occupied: npt.NDArray[np.bool_] | None = None,
) -> dict[int, Cell]:
    """burgard.assign_greedy as it was (protocol=positions): a field per robot."""
    rows, cols = np.nonzero(frontier)
    utility = np.ones(rows.size, dtype=np.float64)
    for goal in held_goals.values():
        reference_discount(utility, rows, cols, goal, max_range, occupied)
    costs: dict[int, npt.NDArray[np.float64]] = {}
    for robot in robots:
        dist = distance_field(belief_passable, positions[robot], targets=frontier)
        cost = dist[rows, cols]
        cost[(rows == positions[robot][0]) & (cols == positions[robot][1])] = np.inf
        for cell in (unreachable or {}).get(robot, ()):
            cost[(rows == cell[0]) & (cols == cell[1])] = np.inf
        if normalize_cost:
            finite = cost[np.isfinite(cost)]
            if finite.size and finite.max() > 0:
                cost = cost / finite.max()
        costs[robot] = cost
    assigned: dict[int, Cell] = {}
    remaining = [r for r in robots if np.isfinite(costs[r]).any()]
    while remaining and rows.size:
        best_value = -np.inf
        best: tuple[int, int] | None = None
        for robot in remaining:
            value = utility - beta * costs[robot]
            index = int(np.argmax(value))
            if np.isfinite(value[index]) and value[index] > best_value:
                best_value, best = float(value[index]), (robot, index)
        if best is None:
            break
        robot, index = best
        goal = (int(rows[index]), int(cols[index]))
        assigned[robot] = goal
        reference_discount(utility, rows, cols, goal, max_range, occupied)
        remaining.remove(robot)
    return assigned


@settings(max_examples=300, deadline=None)
@given(
    beliefs(),
    st.lists(st.integers(0, 10_000), min_size=1, max_size=5),
    st.lists(st.integers(0, 10_000), max_size=3),
    st.floats(1.0, 10.0),
    st.booleans(),
    st.booleans(),
    st.sampled_from([0.5, 1.0, 3.0]),
)
def test_assign_greedy_equals_the_field_per_robot_formulation(
    belief: npt.NDArray[np.int8],
    picks: list[int],
    held: list[int],
    max_range: float,
    visibility: bool,
    normalize: bool,
    beta: float,
) -> None:
    robots = list(range(len(picks)))
    positions = dict(zip(robots, _cells(belief, picks), strict=True))
    held_goals = {100 + i: cell for i, cell in enumerate(_cells(belief, held))}
    frontier = frontier_mask(belief)
    unreachable = {0: _cells(belief, held[:1])}
    kwargs = {
        "beta": beta,
        "max_range": max_range,
        "normalize_cost": normalize,
        "unreachable": unreachable,
        "occupied": belief == OCCUPIED if visibility else None,
    }
    want = reference_assign_greedy(
        robots, positions, held_goals, belief == FREE, frontier, **kwargs
    )
    got = assign_greedy(robots, positions, held_goals, belief == FREE, frontier, **kwargs)
    assert got == want
    assert list(got) == list(want)  # the same order of assignment


@settings(max_examples=300, deadline=None)
@given(beliefs(), st.integers(0, 10_000), st.floats(0.5, 10.0), st.booleans())
def test_discount_equals_the_whole_disk_formulation(
    belief: npt.NDArray[np.int8], pick: int, max_range: float, visibility: bool
) -> None:
    goal = _cells(belief, [pick])[0]
    rows, cols = np.divmod(np.arange(belief.size, dtype=np.int64), belief.shape[1])
    occupied = belief == OCCUPIED if visibility else None
    want = np.ones(belief.size)
    reference_discount(want, rows, cols, goal, max_range, occupied)
    got = np.ones(belief.size)
    discount(got, rows, cols, goal, max_range, occupied)
    np.testing.assert_array_equal(got, want)


@settings(max_examples=300, deadline=None)
@given(beliefs(), st.integers(0, 100_000), st.booleans())
def test_reachable_equals_a_finite_distance(
    belief: npt.NDArray[np.int8], pick: int, frontier_targets: bool
) -> None:
    passable = belief == FREE
    source = _cells(belief, [pick])[0]  # passable or not
    if frontier_targets:
        targets = frontier_mask(belief)
    else:
        targets = np.random.default_rng(pick).random(belief.shape) < 0.3
    index = np.flatnonzero(targets)
    rows, cols = np.divmod(index, belief.shape[1])
    want = np.isfinite(distance_field(passable, source, targets=targets)[rows, cols])
    with FieldCounter() as counter:
        got = reachable(passable, source, index)
    assert counter.count == 0  # a flood, not a distance field
    np.testing.assert_array_equal(got, want)
    assert _workspace_is_clean(belief.size)


def reference_row(
    strategy: MarketOccupancy, view: RobotView, points: npt.NDArray[np.int64]
) -> npt.NDArray[np.float32]:
    """MarketOccupancy.row as it was: a distance field to the points, every time."""
    r = strategy.r or view.sensor_range
    r_f = strategy.r_f or 2.0 * view.sensor_range
    lambda_f = strategy.lambda_f or r_f
    others = [q for robot, q in sorted(strategy.assigned.items()) if robot != strategy.robot_id]
    reach = np.zeros(points.shape[0])
    if points.shape[0]:
        targets = np.zeros(view.belief.shape, dtype=bool)
        targets[points[:, 0], points[:, 1]] = True
        dist = distance_field(view.belief == FREE, view.position, targets=targets)
        reach = dist[points[:, 0], points[:, 1]]
    c = np.where(np.isfinite(reach), reach, 0.0) if strategy.cost == "path" else None
    w = market.weight(
        market.cost(view.position, points) if c is None else c,
        market.utility(view.belief, points, r, strategy.lambda_u),
        market.occupancy(points, others, r_f, lambda_f),
    )
    if points.shape[0]:
        w = np.where(np.isfinite(reach) & (reach > 0), w, market.INFEASIBLE)
    return float32_on_wire(np.minimum(w, market.INFEASIBLE))


@settings(max_examples=200, deadline=None)
@given(
    beliefs(),
    st.integers(0, 100_000),
    st.lists(st.integers(0, 100_000), max_size=8),
    st.sampled_from(["euclidean", "path"]),
    st.booleans(),
)
def test_market_row_equals_a_field_per_row(
    belief: npt.NDArray[np.int8], pick: int, picks: list[int], cost: str, detect_first: bool
) -> None:
    position = _cells(belief, [pick])[0]
    view = robot_view(
        belief, position, n_robots=2, tick=7, subnetwork=frozenset({0, 1}), sensor_range=3.0
    )
    strategy = MarketOccupancy(0, 2, cost=cost)
    strategy.assigned = {1: _cells(belief, picks[:1] or [0])[0]}
    if detect_first:  # the requester's own row: read from its detection of this tick
        points = strategy.frontier_points(view)
    else:  # another robot's points: any cells, repeated or not
        points = np.array(_cells(belief, picks), dtype=np.int64).reshape(-1, 2)
    np.testing.assert_array_equal(strategy.row(view, points), reference_row(strategy, view, points))


@settings(max_examples=200, deadline=None)
@given(beliefs(), st.lists(st.integers(0, 100_000), min_size=1, max_size=6), st.integers(0, 3))
def test_kept_components_answer_as_a_flood_while_the_map_changes(
    belief: npt.NDArray[np.int8], picks: list[int], lose_every: int
) -> None:
    """Cells become free step by step (and, every few steps, some stop being free):
    the kept union-find answers what a fresh flood answers."""
    rng = np.random.default_rng(len(picks) + belief.size)
    passable = belief == FREE
    components = Components()
    for step, pick in enumerate(picks):
        source = _cells(belief, [pick])[0]
        index = np.flatnonzero(rng.random(belief.shape) < 0.3)
        want = reachable(passable, source, index)
        np.testing.assert_array_equal(components.reachable(passable, source, index), want)
        passable = passable | (rng.random(belief.shape) < 0.2)
        if lose_every and step % lose_every == 0:
            passable = passable & (rng.random(belief.shape) < 0.9)
