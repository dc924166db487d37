"""Time the planning and sensing kernels on office-like grids.

Usage::

    .venv/bin/python benchmarks/bench_kernels.py [--sizes 200 500 2000] [--repeats 7]

Each kernel is called once to compile (numba) and warm caches, then timed
``--repeats`` times; the table shows the median in milliseconds. The maps are
built here with numpy (rooms, walls, doors, furniture) so the script depends on
nothing but the planning and sensing modules.
"""

from __future__ import annotations

import argparse
import itertools
import statistics
import time
from collections.abc import Callable

import numpy as np
import numpy.typing as npt

from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN
from mrexplore.planning import (
    distance_field,
    extract_path,
    frontier_clusters,
    frontier_mask,
    information_gain,
    ray_table,
)
from mrexplore.sensing import observe


def office_grid(size: int, rng: np.random.Generator) -> npt.NDArray[np.bool_]:
    """A ``size x size`` office: rooms of 15-40 cells, 1-cell walls, doors, furniture.

    Returns the ground truth, ``True`` = occupied.
    """
    occupied = np.zeros((size, size), dtype=bool)
    occupied[[0, -1], :] = True
    occupied[:, [0, -1]] = True

    def cuts(length: int) -> list[int]:
        positions, at = [], 0
        while True:
            at += int(rng.integers(15, 41))
            if at >= length - 10:
                return positions
            positions.append(at)

    row_walls, col_walls = cuts(size), cuts(size)
    for r in row_walls:
        occupied[r, :] = True
    for c in col_walls:
        occupied[:, c] = True
    # A door of 2-4 cells in every wall segment between two rooms.
    row_edges = [0, *row_walls, size - 1]
    col_edges = [0, *col_walls, size - 1]
    for r in row_walls:
        for left, right in itertools.pairwise(col_edges):
            if right - left > 6:
                start = int(rng.integers(left + 1, right - 4))
                occupied[r, start : start + int(rng.integers(2, 5))] = False
    for c in col_walls:
        for top, bottom in itertools.pairwise(row_edges):
            if bottom - top > 6:
                start = int(rng.integers(top + 1, bottom - 4))
                occupied[start : start + int(rng.integers(2, 5)), c] = False
    # Furniture: small blocks away from the walls.
    for _ in range(size * size // 400):
        r, c = int(rng.integers(2, size - 6)), int(rng.integers(2, size - 6))
        occupied[r : r + int(rng.integers(1, 4)), c : c + int(rng.integers(1, 4))] = True
    return occupied


def median_ms(call: Callable[[], object], repeats: int) -> float:
    """Median wall time of ``call`` in ms, after one untimed warm-up call."""
    call()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1e3


def bench_size(size: int, repeats: int, rng: np.random.Generator) -> list[tuple[str, float, str]]:
    """Rows ``(kernel, median ms, note)`` for one map size."""
    occupied = office_grid(size, rng)
    passable = ~occupied
    free_cells = np.argwhere(passable)
    center = free_cells[np.argmin(((free_cells - size // 2) ** 2).sum(axis=1))]
    source = (int(center[0]), int(center[1]))
    rows: list[tuple[str, float, str]] = []

    full = distance_field(passable, source)
    reachable = np.isfinite(full)
    rows.append(
        (
            "distance_field full",
            median_ms(lambda: distance_field(passable, source), repeats),
            f"{int(reachable.sum())} cells reached",
        )
    )
    # A few targets at a quarter of the map's reach, as nearby frontier cells would be.
    near = np.argwhere(reachable & (full <= 0.25 * full[reachable].max()))
    targets = np.zeros_like(passable)
    picks = near[rng.choice(len(near), size=5, replace=False)]
    targets[picks[:, 0], picks[:, 1]] = True
    early = distance_field(passable, source, targets=targets)
    rows.append(
        (
            "distance_field 5 targets",
            median_ms(lambda: distance_field(passable, source, targets=targets), repeats),
            f"{int(np.isfinite(early).sum())} cells settled",
        )
    )
    farthest_flat = int(np.argmax(np.where(reachable, full, -1.0)))
    farthest = (farthest_flat // size, farthest_flat % size)
    path = extract_path(full, farthest)
    rows.append(
        (
            "extract_path farthest",
            median_ms(lambda: extract_path(full, farthest), repeats),
            f"{len(path)} cells",
        )
    )

    # A belief that knows everything within a third of the reach from the source.
    known = reachable & (full <= full[reachable].max() / 3)
    known[1:, :] |= known[:-1, :]
    known[:-1, :] |= known[1:, :]
    known[:, 1:] |= known[:, :-1]
    known[:, :-1] |= known[:, 1:]
    belief = np.where(known, np.where(occupied, OCCUPIED, FREE), UNKNOWN).astype(np.int8)
    mask = frontier_mask(belief)
    rows.append(
        (
            "frontier_mask",
            median_ms(lambda: frontier_mask(belief), repeats),
            f"{int(mask.sum())} frontier cells",
        )
    )
    clusters = frontier_clusters(mask)
    rows.append(
        (
            "frontier_clusters",
            median_ms(lambda: frontier_clusters(mask), repeats),
            f"{len(clusters)} clusters",
        )
    )
    frontier_cells = np.argwhere(mask)
    for n_candidates in (50, 2000):
        candidates = frontier_cells[rng.choice(len(frontier_cells), n_candidates)]
        rows.append(
            (
                f"information_gain {n_candidates} r=20",
                median_ms(lambda c=candidates: information_gain(belief, c, 20.0), repeats),
                "",
            )
        )
    candidates = frontier_cells[rng.choice(len(frontier_cells), 50)]
    rows.append(
        (
            "information_gain 50 r=20 LOS",
            median_ms(
                lambda: information_gain(belief, candidates, 20.0, line_of_sight=True), repeats
            ),
            "",
        )
    )

    for radius in (4.0, 20.0, 50.0):
        fresh = np.full(occupied.shape, UNKNOWN, dtype=np.int8)
        ray_table(radius)  # built once per process, not part of a sensing step
        new_rows = observe(fresh.copy(), occupied, source, radius)[0]
        rows.append(
            (
                f"observe r={radius:g}",
                median_ms(lambda b=fresh, r=radius: observe(b, occupied, source, r), repeats),
                f"{len(new_rows)} cells seen",
            )
        )
    # Worst case for the sensor: nothing blocks any ray.
    open_world = np.zeros_like(occupied)
    open_belief = np.full(occupied.shape, UNKNOWN, dtype=np.int8)
    middle = (size // 2, size // 2)
    rows.append(
        (
            "observe r=50 open floor",
            median_ms(lambda: observe(open_belief, open_world, middle, 50.0), repeats),
            "7845 cells in the disk",
        )
    )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[200, 500, 2000])
    parser.add_argument("--repeats", type=int, default=7, help="timed calls per kernel")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    for size in args.sizes:
        repeats = args.repeats if size <= 500 else max(3, args.repeats // 2)
        print(f"\n{size} x {size} office map (median of {repeats}, ms)")
        for name, ms, note in bench_size(size, repeats, rng):
            print(f"  {name:<32} {ms:>10.3f}  {note}")


if __name__ == "__main__":
    main()
