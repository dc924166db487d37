"""Resolve a :class:`Scenario` into a world: the map, start cells and ranges in cells."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
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
from mrexplore.grid.catalogue import CATALOGUE, resolve_map_name, user_maps
from mrexplore.sim.scenario import Cell, Scenario, parse_length

_MAP_SUFFIXES = {".yaml", ".yml", ".pgm", ".png", ".bmp", ".map", ".json"}


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
    if path.suffix.lower() in _MAP_SUFFIXES or path.exists():
        if not path.exists():
            raise MapFileError(path, "no such file")
        return path
    raise UnknownIdError(
        "map (generator, catalogue map or file)",
        name,
        [*GENERATORS, *(entry.name for entry in CATALOGUE), *user_maps()],
    )


def load_scenario_map(scenario: Scenario) -> GridMap:
    """Generate or load the scenario's map."""
    path = resolve_map(scenario.map)
    if path is None:
        width, height = scenario.size if scenario.size is not None else (None, None)
        map_seed = scenario.seed if scenario.map_seed is None else scenario.map_seed
        return generate_map(scenario.map, width, height, seed=map_seed)
    return load_map(path, cell_size_m=scenario.cell_size)


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


def build_world(scenario: Scenario, starts_rng: np.random.Generator) -> World:
    """Load the map, convert ranges to cells and place the robots."""
    scenario.validate()
    grid = load_scenario_map(scenario)
    sensor_range = cells_from_length(scenario.sensor_range, grid, "--sensor-range")
    if sensor_range < 1:
        raise ScenarioError(
            f"--sensor-range {scenario.sensor_range}: is {sensor_range:.2f} cells; need >= 1"
        )
    starts = choose_starts(scenario, grid.occupied, starts_rng)
    explorable = free_component_of(grid.occupied, list(starts))
    return World(grid, starts, explorable, sensor_range)
