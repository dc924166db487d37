"""Resolve a :class:`Scenario` into a world: the map, start cells and ranges in cells."""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MapFileError, ScenarioError, UnknownIdError
from mrexplore.grid import (
    GENERATORS,
    GridMap,
    free_component_of,
    generate_map,
    largest_free_component,
    load_map,
)
from mrexplore.grid.catalogue import CATALOGUE, MAP_SUFFIXES, resolve_map_name, user_maps
from mrexplore.grid.generators import MAX_GENERATED_SIDE, MIN_GENERATED_SIDE
from mrexplore.grid.io import resample_to_cell_size
from mrexplore.sim import budget
from mrexplore.sim.scenario import Cell, Scenario, is_unlimited, parse_length


@dataclass(frozen=True)
class World:
    """A scenario resolved against its map."""

    grid: GridMap
    starts: tuple[Cell, ...]
    explorable: npt.NDArray[np.bool_]
    sensor_range_cells: float

    @property
    def n_explorable(self) -> int:
        return int(np.count_nonzero(self.explorable))


def resolve_map(name: str) -> Path | None:
    """The file ``--map NAME`` stands for, or ``None`` for a generator.

    A generator name wins, then a catalogue map, then a map of the user's
    ``$MREXPLORE_MAPS`` folders, then a file path.

    Raises:
        MapFileError: ``name`` looks like a file path (it has an extension) that
            does not exist.
        UnknownIdError: ``name`` is neither a generator, a map name nor a file.
    """
    if name in GENERATORS:
        return None
    named = resolve_map_name(name)
    if named is not None:
        return named
    path = Path(name)
    if path.suffix.lower() in MAP_SUFFIXES or path.exists():
        if not path.exists():
            raise MapFileError(path, "no such file")
        return path
    raise UnknownIdError(
        "map (generator, catalogue map or file)",
        name,
        [*GENERATORS, *(entry.name for entry in CATALOGUE), *user_maps()],
    )


def load_scenario_map(scenario: Scenario, *, record_beliefs: bool | None = None) -> GridMap:
    """Generate or load the scenario's map, refusing a run that cannot fit in memory.

    The memory a run needs (:func:`mrexplore.sim.budget.estimate_run_bytes`) is
    checked before the map is generated (from ``--size``), and for a file map
    before it is pooled to ``--cell-size`` (from the file's size and the pooling
    factor; the file itself is bounded by :data:`mrexplore.grid.io.MAX_CELLS`).
    ``record_beliefs`` is the :class:`~mrexplore.sim.engine.Simulation` option of
    that name (it adds 4 bytes per robot and cell).

    Raises:
        ScenarioError: the run would need more memory than is available; or
            ``--cell-size`` leaves the map without a free cell, or with fewer free
            cells (in its largest free region) than robots.
    """
    path = resolve_map(scenario.map)
    if path is None:
        info = GENERATORS[scenario.map]
        width, height = scenario.size if scenario.size is not None else info.default_size
        if all(MIN_GENERATED_SIDE <= side <= MAX_GENERATED_SIDE for side in (width, height)):
            # generate_map refuses other sizes itself, with a better message
            inner = max(width - 2, 1) * max(height - 2, 1)
            _check_memory(
                scenario,
                (height, width),
                inner,
                None,
                record_beliefs,
                f"--size {width}x{height}"
                if scenario.size is not None
                else f"--map {scenario.map} at its default size {width}x{height}",
                "use a smaller --size or fewer robots",
            )
        map_seed = scenario.seed if scenario.map_seed is None else scenario.map_seed
        given_width, given_height = scenario.size if scenario.size is not None else (None, None)
        return generate_map(scenario.map, given_width, given_height, seed=map_seed)
    grid = load_map(path)
    if scenario.cell_size is not None:
        if grid.resolution_m is None:  # a unitless map takes the cell size as resolution
            return _checked_file_map(
                scenario, replace(grid, resolution_m=float(scenario.cell_size)), record_beliefs
            )
        grid = _pooled(scenario, grid, record_beliefs)
        return _checked_file_map(scenario, grid, record_beliefs, pooled=True)
    return _checked_file_map(scenario, grid, record_beliefs)


def _length_cells(value: float | str, option: str, resolution_m: float | None) -> float | None:
    """A range in cells, or ``None`` when it cannot be told (yet)."""
    try:
        amount, in_metres = parse_length(value, option)
    except ScenarioError:
        return None
    if not in_metres:
        return amount
    return None if resolution_m is None else amount / resolution_m


def _check_memory(
    scenario: Scenario,
    shape: tuple[int, int],
    free_cells: int,
    resolution_m: float | None,
    record_beliefs: bool | None,
    what: str,
    advice: str,
) -> None:
    """:func:`~mrexplore.sim.budget.check_run_memory` for a map of ``shape`` cells.

    ``free_cells`` is the map's number of free cells, or an upper bound on it. A team
    larger than that is left to the start-cell checks, whose message says so (the
    memory such a team would need is beside the point).
    """
    from mrexplore.errors import MrexploreInputError
    from mrexplore.sim.record import BELIEF_CELLS_AUTO
    from mrexplore.strategies.registry import get_strategy

    if scenario.robots > free_cells:
        return
    cells = shape[0] * shape[1]
    sharing = scenario.sharing
    if sharing is None:
        try:
            sharing = get_strategy(scenario.strategy).default_sharing
        except MrexploreInputError:  # reported by the caller, with its own message
            sharing = "full"
    if record_beliefs is None:
        record_beliefs = scenario.robots * cells <= BELIEF_CELLS_AUTO
    linked_share = 1.0
    if not is_unlimited(scenario.comm_range):
        # robots spread evenly: the share of pairs closer than the range
        comm_range = _length_cells(scenario.comm_range, "--comm-range", resolution_m)
        if comm_range is not None:
            linked_share = min(1.0, math.pi * comm_range * comm_range / max(free_cells, 1))
    ticks = budget.estimate_ticks(
        free_cells,
        scenario.robots,
        sensor_range_cells=_length_cells(scenario.sensor_range, "--sensor-range", resolution_m),
        speed=scenario.speed,
        coverage_threshold=scenario.coverage_threshold,
        max_ticks=scenario.max_ticks,
    )
    estimate = budget.estimate_run_bytes(
        shape,
        scenario.robots,
        strategy=scenario.strategy,
        sharing=sharing,
        record_beliefs=record_beliefs,
        ticks=ticks,
        linked_share=linked_share,
        noisy=scenario.noisy,
    )
    budget.check_run_memory(what, estimate, scenario.robots, advice)


def _map_label(grid: GridMap, resolution_m: float | None) -> str:
    at = "" if resolution_m is None else f" at {resolution_m:g} m per cell"
    return f"the map {grid.name}{at}"


def _pooled(scenario: Scenario, grid: GridMap, record_beliefs: bool | None) -> GridMap:
    """``grid`` pooled to ``--cell-size``, after checking the pooled map's size and memory."""
    assert scenario.cell_size is not None and grid.resolution_m is not None
    cell_size, resolution = float(scenario.cell_size), grid.resolution_m
    option = f"--cell-size {scenario.cell_size:g}"
    if cell_size < resolution * (1 - 1e-6):
        raise ScenarioError(
            f"{option}: finer than the resolution {resolution:g} m of the map {grid.name}; "
            "only coarser cells are supported"
        )
    factor = max(1, round(cell_size / resolution))
    height, width = grid.shape
    shape = (-(-height // factor), -(-width // factor))
    if min(shape) < 3:  # only the occupied outer ring is left: no room for a free cell
        largest = math.ceil(min(height, width) / 2) - 1  # the largest factor leaving 3 cells
        raise ScenarioError(
            f"{option}: the map {grid.name} is {width * resolution:g} m x "
            f"{height * resolution:g} m, so {factor * resolution:g} m cells leave it "
            f"{shape[1]}x{shape[0]} cells, all of them walls; use a cell size below "
            f"{(largest + 0.5) * resolution:g} m"
        )
    free_fine = int(np.count_nonzero(~grid.occupied))
    _check_memory(
        scenario,
        shape,
        free_fine // (factor * factor),  # a coarse free cell holds factor^2 free cells
        factor * resolution,
        record_beliefs,
        f"{option} on the map {grid.name} ({shape[1]}x{shape[0]} cells)",
        "use a larger --cell-size or fewer robots",
    )
    return resample_to_cell_size(grid, cell_size)


def _checked_file_map(
    scenario: Scenario, grid: GridMap, record_beliefs: bool | None, *, pooled: bool = False
) -> GridMap:
    """``grid``, after checking that it fits in memory and, if pooled, has room to start."""
    height, width = grid.shape
    if not pooled:
        resolution = grid.resolution_m
        cells = (
            f" ({width}x{height} cells)"
            if resolution is None
            else (f" ({width}x{height} cells of {resolution:g} m)")
        )
        _check_memory(
            scenario,
            grid.shape,
            int(np.count_nonzero(~grid.occupied)),
            resolution,
            record_beliefs,
            f"--map {scenario.map}{cells}",
            "use a smaller map, a larger --cell-size or fewer robots",
        )
        return grid
    option = f"--cell-size {scenario.cell_size:g}"
    label = _map_label(grid, grid.resolution_m)
    if grid.occupied.all():
        size = f"{grid.resolution_m:g} m"
        raise ScenarioError(
            f"{option}: {label} has no free cell (every {size} cell holds a wall); "
            "use a smaller cell size"
        )
    if isinstance(scenario.start, str):
        region = int(np.count_nonzero(largest_free_component(grid.occupied)))
        if region < scenario.robots:
            raise ScenarioError(
                f"{option}: {label} has only {region} free cell"
                f"{'' if region == 1 else 's'} in its largest free region, fewer than the "
                f"{scenario.robots} robots; use a smaller cell size or fewer robots"
            )
    return grid


def cells_from_length(value: float | str, grid: GridMap, option: str) -> float:
    """A range in cells from a number of cells or a string in metres."""
    amount, in_metres = parse_length(value, option)
    if not in_metres:
        return amount
    if grid.resolution_m is None:
        raise ScenarioError(
            f"{option} {value}: metres need a map with a resolution; {grid.name} has none"
        )
    return amount / grid.resolution_m


def choose_starts(
    scenario: Scenario, occupied: npt.NDArray[np.bool_], rng: np.random.Generator
) -> tuple[Cell, ...]:
    """Start cells: given, together (adjacent cells) or separate (random cells)."""
    height, width = occupied.shape
    n_robots = scenario.robots
    if not isinstance(scenario.start, str):
        cells = [(int(r), int(c)) for r, c in scenario.start]
        if len(cells) != n_robots:
            raise ScenarioError(f"--start: {len(cells)} cells given for {n_robots} robots")
        for row, col in cells:
            if not (0 <= row < height and 0 <= col < width):
                raise ScenarioError(f"--start {row},{col}: outside the {width}x{height} map")
            if occupied[row, col]:
                raise ScenarioError(f"--start {row},{col}: start cell is inside a wall")
        if len(set(cells)) != len(cells):
            raise ScenarioError("--start: two robots cannot start in the same cell")
        return tuple(cells)
    region = largest_free_component(occupied)
    region_rows, region_cols = np.nonzero(region)
    if region_rows.size < n_robots:
        raise ScenarioError(
            f"--robots {n_robots}: more robots than free start cells "
            f"(the largest free region has {region_rows.size})"
        )
    if scenario.start == "separate":
        picks = rng.choice(region_rows.size, size=n_robots, replace=False)
        return tuple((int(region_rows[i]), int(region_cols[i])) for i in np.sort(picks))
    seed_index = int(rng.integers(region_rows.size))
    return _nearest_free_cells(
        region, (int(region_rows[seed_index]), int(region_cols[seed_index])), n_robots
    )


def _nearest_free_cells(region: npt.NDArray[np.bool_], seed: Cell, count: int) -> tuple[Cell, ...]:
    """``count`` cells of ``region`` in breadth-first order from ``seed`` (4-connected)."""
    height, width = region.shape
    seen = {seed}
    order: list[Cell] = []
    queue = deque([seed])
    while queue and len(order) < count:
        row, col = queue.popleft()
        order.append((row, col))
        for d_row, d_col in ((-1, 0), (0, 1), (1, 0), (0, -1)):
            nxt = (row + d_row, col + d_col)
            if 0 <= nxt[0] < height and 0 <= nxt[1] < width and region[nxt] and nxt not in seen:
                seen.add(nxt)
                queue.append(nxt)
    return tuple(order)


def build_world(
    scenario: Scenario, starts_rng: np.random.Generator, *, record_beliefs: bool | None = None
) -> World:
    """Load the map, convert ranges to cells and place the robots.

    ``record_beliefs`` (as :class:`~mrexplore.sim.engine.Simulation` takes it) only
    enters the memory check of :func:`load_scenario_map`.

    Raises the errors of :meth:`Scenario.check_fields`, of the map and of the start
    cells (:class:`~mrexplore.errors.MrexploreInputError`).
    """
    scenario.check_fields()
    grid = load_scenario_map(scenario, record_beliefs=record_beliefs)
    sensor_range = cells_from_length(scenario.sensor_range, grid, "--sensor-range")
    if sensor_range < 1:
        raise ScenarioError(
            f"--sensor-range {scenario.sensor_range}: is {sensor_range:.2f} cells; need >= 1"
        )
    starts = choose_starts(scenario, grid.occupied, starts_rng)
    explorable = free_component_of(grid.occupied, list(starts))
    return World(grid, starts, explorable, sensor_range)
