"""Checkers that ship: re-check a run from its trace, and check a strategy plugin.

* :func:`check_trace` re-checks a run from the arrays of ``trace.npz`` alone
  (DESIGN §8): moves are legal, no robot crossed a wall or shared a cell, every
  cell the team knew was in sensor range and sight of a robot when it became
  known, and (given ``result.json``) the metrics follow from the trace.
* :func:`check_strategy` runs a registered strategy through small scenarios and
  checks the contract any strategy must keep (as Gymnasium's ``check_env``).
* :func:`check_comm_model` drives a registered communication model through a
  script of moves, sends and a failure, checks the protocol of
  :class:`~mrexplore.comm.models.CommModel`, then runs it in small scenarios.
* :func:`check_determinism` runs a scenario twice and compares the traces.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from mrexplore.errors import CommModelError, MrexploreError, MrexploreInputError, StrategyError
from mrexplore.metrics import json_safe, summarize
from mrexplore.params import Param
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
    # With odometry drift a robot writes what it sees at its estimated pose (turned by
    # its heading error): only the reach of its sensor around the cell it believes it
    # is on can be checked, R plus the rounding of the estimate and of each cell.
    estimated = (
        np.asarray(trace["estimated_positions"]) if "estimated_positions" in trace else positions
    )
    drift = (
        np.asarray(trace["localisation_error"]) > 0
        if "localisation_error" in trace
        else np.zeros(positions.shape[:2], dtype=bool)
    )
    grid_rows, grid_cols = np.ogrid[:height, :width]
    for tick in np.unique(first_known[first_known >= 0]):
        known = first_known == tick
        seen = np.zeros_like(known)
        for robot in range(n_robots):
            if alive is not None and not alive[tick, robot]:
                continue
            cell = (int(positions[tick, robot, 0]), int(positions[tick, robot, 1]))
            believed = (int(estimated[tick, robot, 0]), int(estimated[tick, robot, 1]))
            if believed != cell or drift[tick, robot]:
                sight = radius + SQRT2
                seen |= (grid_rows - believed[0]) ** 2 + (grid_cols - believed[1]) ** 2 <= (
                    sight * sight
                )
                continue
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
    from mrexplore.sim.scenario import Scenario
    from mrexplore.strategies.registry import get_strategy

    cls = get_strategy(name)
    problems = _declaration_problems(name, cls.id, cls.summary, cls.params)
    try:
        cls(0, 1, **{"no_such_parameter_xyz": 1})
        problems.append("accepted an unknown parameter")
    except MrexploreInputError:
        pass
    for map_name, size, robots in (("sheng40", None, 1), ("office", (48, 36), 3)):
        scenario = Scenario(
            map=map_name, size=size, robots=robots, strategy=name, seed=3, max_ticks=max_ticks
        )
        problems += _run_problems(scenario, f"{map_name} with {robots} robots")
    if problems:
        raise StrategyError(f"strategy {name!r}: " + "; ".join(problems))


def _declaration_problems(
    name: str, declared_id: str, summary: str, params: Mapping[str, Param]
) -> list[str]:
    """What is wrong with a registered class's id, summary and parameter table."""
    problems: list[str] = []
    if declared_id != name:
        problems.append(f"registered as {name!r} but its id is {declared_id!r}")
    if not summary:
        problems.append("has no one-line summary")
    for param, spec in params.items():
        if not isinstance(spec.default, bool | int | float | str):
            problems.append(f"parameter {param!r} has a default that is not bool/int/float/str")
        elif not spec.accepts(spec.default):
            problems.append(
                f"parameter {param!r} has a default {spec.default!r} outside its declared "
                f"range ({spec.describe()})"
            )
    return problems


def _run_problems(scenario: Any, label: str) -> list[str]:
    """Run ``scenario``: it must complete with a valid trace, the same twice."""
    from mrexplore.sim.engine import simulate

    try:
        record = simulate(scenario)
    except (StrategyError, CommModelError) as error:
        return [f"{label}: {error}"]
    problems = []
    if record.status != "complete":
        problems.append(f"{label} ended {record.status!r}")
    problems += [f"{label}: {p}" for p in check_trace(record.trace_arrays(), record.result())]
    problems += [f"{label}: {p}" for p in check_determinism(scenario)]
    return problems


#: The scripted check of :func:`check_comm_model`: robots on a line whose spacing
#: (cells) changes every few ticks, so that a ranged model splits and merges.
_SPACINGS = (1, 1, 3, 3, 6, 6, 10, 10, 2, 2, 8, 8, 1, 1, 20, 20, 5, 5, 40, 40, 12, 12, 2, 2)
_CHECK_ROBOTS = 5
_CHECK_RANGE = 8.0
_CHECK_DEATH = (4, 9)  # robot 4 fails at tick 9
_DRAIN_TICKS = 60


def check_comm_model(name: str, *, max_ticks: int = 3000) -> None:
    """Raise :class:`CommModelError` listing every way communication model ``name``
    breaks the protocol.

    Checks the id, summary and parameter declarations; that an unknown parameter is
    refused as bad input; then drives the model directly through a script of five
    robots moving apart and together, one of them failing, each sending a broadcast
    and a unicast every tick (with a range of 8 cells, or unlimited if the model
    refuses a range), and checks that

    * links join two different live robots ``(a, b)`` with ``a < b``, and the
      sub-networks are the connected components of the links over the live robots;
    * every delivered message reaches a live robot of its sender's sub-network as it
      was when the message was sent, not the sender, at a later tick, at most once,
      and a unicast only its destination;
    * nothing stays in flight long after the last message, the ledger's per-robot
      bytes sum to its total, :meth:`~mrexplore.comm.models.CommModel.stats` has one
      sub-network count per update, and the same seed gives the same deliveries;

    and finally runs ``nearest-frontier`` over it with 1 and 3 robots on ``sheng40``
    and a small ``office`` (each must complete with a valid trace, twice the same).
    """
    from mrexplore.comm.models import COMM_MODELS, make_comm_model
    from mrexplore.sim.scenario import Scenario

    cls = COMM_MODELS.get(name)
    problems = _declaration_problems(name, cls.id, cls.summary, cls.params)
    comm_range = _CHECK_RANGE
    try:
        make_comm_model(name, _check_setup(5, comm_range))
    except MrexploreInputError:  # a model may refuse settings it does not honour
        comm_range = math.inf
    try:
        make_comm_model(name, _check_setup(5, comm_range), {"no_such_parameter_xyz": 1})
        problems.append("accepted an unknown parameter")
    except MrexploreInputError:
        pass
    try:
        first, protocol = _drive(name, _check_setup(5, comm_range))
        problems += protocol
        again, _ = _drive(name, _check_setup(5, comm_range))
        if first != again:
            problems.append("two runs with the same seed delivered different messages")
    except MrexploreError as error:
        problems.append(f"scripted check: {type(error).__name__}: {error}")
    if not problems:  # full runs only for a model that keeps the protocol
        for map_name, size, robots in (("sheng40", None, 1), ("office", (48, 36), 3)):
            scenario = Scenario(
                map=map_name,
                size=size,
                robots=robots,
                comm_model=name,
                seed=3,
                max_ticks=max_ticks,
            )
            problems += _run_problems(scenario, f"{map_name} with {robots} robots")
    if problems:
        raise CommModelError(f"communication model {name!r}: " + "; ".join(problems))


def _check_setup(seed: int, comm_range: float) -> Any:
    """Five robots on an open 20 x 200 cell map of 1 m cells."""
    from mrexplore.comm.models import CommSetup

    occupied = np.zeros((20, 200), dtype=bool)
    occupied[0, :] = occupied[-1, :] = occupied[:, 0] = occupied[:, -1] = True
    return CommSetup(
        n_robots=_CHECK_ROBOTS,
        occupied=occupied,
        rng=np.random.default_rng(seed),
        comm_range=comm_range,
        metres_per_cell=1.0,
    )


def _drive(name: str, setup: Any) -> tuple[list[tuple[int, int, Any]], list[str]]:
    """Run the script on a fresh model; return ``(deliveries, problems)`` where a
    delivery is ``(tick, receiver, payload)``."""
    from mrexplore.comm.bytes import BROADCAST, HEADER_BYTES
    from mrexplore.comm.links import components
    from mrexplore.comm.messages import Message
    from mrexplore.comm.models import make_comm_model

    model = make_comm_model(name, setup)
    n = setup.n_robots
    problems: list[str] = []
    deliveries: list[tuple[int, int, Any]] = []
    reach: dict[Any, frozenset[int]] = {}  # payload -> who may receive it
    dest_of: dict[Any, int] = {}
    sent_at: dict[Any, int] = {}
    received: set[tuple[Any, int]] = set()
    alive = frozenset(range(n))
    updates = 0
    last_send = len(_SPACINGS) - 1
    tick = 0
    for tick in range(last_send + 1 + _DRAIN_TICKS):
        if tick == _CHECK_DEATH[1]:
            alive = alive - {_CHECK_DEATH[0]}
        spacing = _SPACINGS[min(tick, last_send)]
        positions = {r: (10, 2 + r * spacing) for r in range(n)}
        model.update(tick, positions, alive)
        updates += 1
        links = model.links()
        groups = model.subnetworks()
        if any(not (a < b and a in alive and b in alive) for a, b in links):
            problems.append(f"tick {tick}: a link that is not (a, b), a < b, both alive")
        if sorted(map(sorted, groups)) != sorted(map(sorted, components(alive, links))):
            problems.append(f"tick {tick}: sub-networks are not the components of the links")
        if tick > 0:
            for receiver, inbox in sorted(model.deliver(tick).items()):
                for message in inbox:
                    key = message.payload
                    deliveries.append((tick, receiver, key))
                    if key not in reach:
                        problems.append(f"tick {tick}: delivered a message nobody sent")
                    elif receiver not in reach[key] or receiver not in alive:
                        problems.append(
                            f"tick {tick}: robot {receiver} got a message from outside its "
                            "sender's sub-network, from itself, or while dead"
                        )
                    elif dest_of[key] != BROADCAST and dest_of[key] != receiver:
                        problems.append(f"tick {tick}: a unicast reached robot {receiver}")
                    elif sent_at[key] >= tick:
                        problems.append(f"tick {tick}: a message arrived at the tick it was sent")
                    elif (key, receiver) in received:
                        problems.append(f"tick {tick}: robot {receiver} got a message twice")
                    received.add((key, receiver))
        if tick <= last_send:
            for sender in sorted(alive):
                group = model.subnetwork_of(sender) - {sender}
                for dest, size in ((BROADCAST, HEADER_BYTES + 8), ((sender + 1) % n, 40)):
                    key = (sender, tick, dest)
                    message = Message("status", sender, dest, size, key, tick_sent=tick)
                    reach[key], dest_of[key], sent_at[key] = group, dest, tick
                    model.send(message, tick)
        model.flush(tick)
        if tick > last_send and model.in_flight() == 0:
            break
    if model.in_flight():
        problems.append(
            f"{model.in_flight()} messages still in flight {_DRAIN_TICKS} ticks "
            "after the last send (with unlimited bandwidth)"
        )
    ledger = model.ledger
    if int(ledger.bytes_by_robot.sum()) != ledger.total:
        problems.append("the ledger's bytes per robot do not sum to its total")
    if deliveries and ledger.total <= 0:
        problems.append("messages were delivered but no byte was counted")
    stats = model.stats()
    if len(stats.subnetwork_counts) != updates:
        problems.append(
            f"stats() has {len(stats.subnetwork_counts)} sub-network counts for {updates} updates"
        )
    if min(stats.partition_events, stats.merge_events) < 0 or not (
        math.isfinite(stats.queue_delay_mean) and stats.queue_delay_mean >= 0
    ):
        problems.append("stats() has negative counts or a queue delay that is not >= 0")
    if not isinstance(model.describe(), str) or not model.describe():
        problems.append("describe() gave no description")
    return deliveries, problems
