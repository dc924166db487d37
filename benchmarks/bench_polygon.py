"""Bytes, approximation error and cost of the ``polygon`` sharing mechanism.

One robot explores the Intel lab map (the catalogue map ``intel``; ``--map`` takes
another catalogue name or a map file) at 0.1 m cells with a 30-cell sensor by a
nearest-frontier walk (go to the closest frontier cell of its own map, one cell
per tick, re-plan on arrival). The walk is computed once; the same observation
sequence is then replayed through :class:`~mrexplore.comm.polygon.PolygonSharing`
for each split rate, with a second robot receiving every package. Printed per
split rate:

* ``polygon B``: bytes of every package the robot sent (header included), and
  the part of them that were periodic full resyncs (``resync B``);
* ``raw scan B``: one laser scan per tick, ``360`` beams of
  ``SCAN_BEAM_BYTES`` plus the header (the centralized approach of §5.3);
* ``full B``: the ``full`` mechanism, 5 bytes per newly observed cell plus the
  header per tick with new cells;
* ``error``: final :meth:`~PolygonSharing.approximation_error` and its mean over
  the ticks (sampled every 10 ticks);
* ``agree``: share of the sender's observed cells on which the receiver's belief
  equals the sender's observation at the end;
* ``ms/observe``, ``ms/tick``, ``ms/receive``: mean time of ``on_observe``, of
  ``on_tick`` and of the receiver's ``on_receive_all``.

Usage::

    .venv/bin/python benchmarks/bench_polygon.py [--ticks 1500] [--split-rates 0.1 1 10]
        [--resync-every 50] [--epsilon 1.0]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import HEADER_BYTES, SCAN_BEAM_BYTES, cell_updates_size
from mrexplore.comm.polygon import PolygonSharing
from mrexplore.comm.polygon_packages import Resync
from mrexplore.comm.sharing import Observation
from mrexplore.grid import largest_free_component, load_map
from mrexplore.grid.catalogue import resolve_map_name
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, new_belief
from mrexplore.planning import distance_field, extract_path, frontier_mask
from mrexplore.sensing import visible_cells

SCAN_BEAMS = 360
SENSOR_RANGE_CELLS = 30.0


def frontier_walk(
    occupied: npt.NDArray[np.bool_], start: tuple[int, int], ticks: int
) -> list[Observation]:
    """Observations of a nearest-frontier walk of at most ``ticks`` ticks."""
    belief = new_belief(occupied.shape)
    truth_state = np.where(occupied, OCCUPIED, FREE).astype(np.int8)
    position = start
    path: npt.NDArray[np.int32] | None = None
    step = 0
    observations = []
    for _ in range(ticks):
        rows, cols = visible_cells(occupied, position, SENSOR_RANGE_CELLS)
        values = truth_state[rows, cols]
        was_unknown = belief[rows, cols] == UNKNOWN
        belief[rows, cols] = values
        observations.append(Observation(rows, cols, values, was_unknown))
        if path is None or step >= len(path) - 1:
            frontier = frontier_mask(belief)
            frontier[position] = False
            if not frontier.any():
                break
            dist = distance_field(belief == FREE, position)
            reachable = np.where(frontier, dist, np.inf)
            target = np.unravel_index(int(np.argmin(reachable)), reachable.shape)
            if not np.isfinite(reachable[target]):
                break
            path = extract_path(dist, (int(target[0]), int(target[1])))
            step = 0
        step += 1
        position = (int(path[step, 0]), int(path[step, 1]))
    return observations


def replay(
    shape: tuple[int, int],
    observations: list[Observation],
    split_rate: float,
    resync_every: int,
    epsilon: float = 1.0,
) -> dict[str, float]:
    sharing = PolygonSharing(split_rate=split_rate, resync_every=resync_every, epsilon=epsilon)
    sharing.bind(2, shape)
    sender_belief = new_belief(shape)
    receiver_belief = new_belief(shape)
    team = [frozenset({0, 1})]
    beliefs = [sender_belief, receiver_belief]
    total = resync = 0
    by_type: dict[str, int] = {}
    observe_s = tick_s = receive_s = 0.0
    errors = []
    for tick, observation in enumerate(observations):
        started = time.perf_counter()
        messages = sharing.on_tick(tick, team, beliefs)
        tick_s += time.perf_counter() - started
        sender_belief[observation.rows, observation.cols] = observation.values
        started = time.perf_counter()
        messages += sharing.on_observe(0, tick, observation, sender_belief)
        observe_s += time.perf_counter() - started
        started = time.perf_counter()
        sharing.on_receive_all(1, receiver_belief, messages)
        receive_s += time.perf_counter() - started
        for message in messages:
            total += message.size_bytes
            by_type[message.type] = by_type.get(message.type, 0) + message.size_bytes
            if isinstance(message.payload, Resync):
                resync += message.size_bytes
        if tick % 10 == 0:
            errors.append(sharing.approximation_error(0))
    own = sharing.own_map(0)
    observed = own != UNKNOWN
    n = len(observations)
    return {
        "bytes": total,
        "resync": resync,
        "error": sharing.approximation_error(0),
        "mean_error": float(np.mean(errors)),
        "agree": float(np.mean(receiver_belief[observed] == own[observed])),
        "vertices": sum(int(r.points.shape[0]) for r in sharing.polygons(0)),
        "observe_ms": 1e3 * observe_s / n,
        "tick_ms": 1e3 * tick_s / n,
        "receive_ms": 1e3 * receive_s / n,
        **{f"bytes_{kind}": float(value) for kind, value in by_type.items()},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ticks", type=int, default=1500, help="length of the walk")
    parser.add_argument("--split-rates", nargs="+", type=float, default=[0.1, 1.0, 10.0])
    parser.add_argument("--resync-every", type=int, default=50, help="ticks; 0 = never")
    parser.add_argument("--epsilon", type=float, default=0.5, help="DP tolerance, cells")
    parser.add_argument("--map", default="intel", help="catalogue map name or map file")
    args = parser.parse_args()
    map_path = resolve_map_name(args.map) or Path(args.map)
    grid = load_map(map_path, cell_size_m=0.1)
    occupied = grid.occupied
    free_cells = np.argwhere(largest_free_component(occupied))
    centre = free_cells[np.argmin(np.abs(free_cells - free_cells.mean(axis=0)).sum(axis=1))]
    observations = frontier_walk(occupied, (int(centre[0]), int(centre[1])), args.ticks)
    n_ticks = len(observations)
    raw_scan = n_ticks * (HEADER_BYTES + SCAN_BEAMS * SCAN_BEAM_BYTES)
    full = sum(
        cell_updates_size(int(o.was_unknown.sum())) for o in observations if o.was_unknown.any()
    )
    observed = int(sum(o.rows.size for o in observations))
    print(
        f"map {map_path.name} {occupied.shape[0]}x{occupied.shape[1]} cells at 0.1 m, "
        f"sensor {SENSOR_RANGE_CELLS:g} cells, {n_ticks} ticks, {observed} cells observed, "
        f"resync every {args.resync_every} ticks, epsilon {args.epsilon:g} cells"
    )
    replay(occupied.shape, observations[:20], 1.0, args.resync_every)  # compile the kernels
    header = (
        f"{'SR/s':>6}{'polygon B':>11}{'resync B':>10}{'raw scan B':>12}{'full B':>10}"
        f"{'error':>8}{'mean err':>9}{'agree':>8}{'verts':>7}"
        f"{'ms/observe':>12}{'ms/tick':>9}{'ms/receive':>12}"
    )
    print(header)
    print("-" * len(header))
    rows = []
    for split_rate in args.split_rates:
        result = replay(occupied.shape, observations, split_rate, args.resync_every, args.epsilon)
        rows.append((split_rate, result))
        print(
            f"{split_rate:>6g}{result['bytes']:>11.0f}{result['resync']:>10.0f}"
            f"{raw_scan:>12d}{full:>10d}{100 * result['error']:>7.2f}%"
            f"{100 * result['mean_error']:>8.2f}%{100 * result['agree']:>7.2f}%"
            f"{result['vertices']:>7.0f}{result['observe_ms']:>12.2f}"
            f"{result['tick_ms']:>9.2f}{result['receive_ms']:>12.2f}"
        )
    print()
    print("bytes by package type (% of polygon bytes; B includes resyncs)")
    for split_rate, result in rows:
        shares = "  ".join(
            f"{kind} {100 * result.get(f'bytes_{kind}', 0.0) / max(result['bytes'], 1):5.1f}"
            for kind in ("ES", "B", "VP", "EP")
        )
        print(f"  SR {split_rate:g}: {shares}")


if __name__ == "__main__":
    main()
