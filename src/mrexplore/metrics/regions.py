"""Regional waiting-time and exploration-percentage variances (Wu, Puig & Garcia, §V.B).

L. Wu, D. Puig, M. A. Garcia, "Balanced multi-robot exploration through a global
optimization strategy", Journal of Physical Agents 4(1), 2010, §V.B, eqs. (8)-(10).
The paper judges a method by how evenly it serves the regions of the map: a
victim should not wait much longer in one region than in another.

The map is cut into ``N`` equal rectangles (:func:`split_regions`). At tick ``t``
a region ``R`` holds ``n`` known and ``m`` unknown cells, and

==================  ========================================  =====================  ========
symbol (paper)      definition                                code                   unit
==================  ========================================  =====================  ========
``w``               tick the cell became known                ``first_known``        tick
``w'``              ``t + e``, ``e = g / speed`` (choice 1)   :func:`waiting_times`  tick
``w_R`` (8)         ``(sum_i w_i + sum_j w'_j) / (m + n)``    —                      tick
``WTV`` (9)         ``sigma^2(w_R_i), i = 1..N``              :func:`wtv`            tick²
``awt_R``           ``(1/n) sum_i w_i`` once all is known     —                      tick
``WTV_final`` (10)  ``sigma^2(awt_R_i)``                      :func:`final_wtv`      tick²
``EP_R``            ``100 n / (m + n)``                       —                      percent
``EPV``             ``sigma^2(EP_R_i)`` (no equation number)  :func:`epv`            percent²
==================  ========================================  =====================  ========

Where the paper leaves a choice, this module takes the following one.

1. **Estimated waiting time.** The paper sets ``w' = e + t`` with ``e`` "the number
   of estimated steps from a closest robot to the unknown cell (the distance
   divided by the cell size)". Here ``e = g / speed``: ``g`` is the straight-line
   (Euclidean) distance in cells between the cell's centre and the closest robot,
   walls ignored (the same geometric distance ``g`` the paper uses in §IV.B for
   places no known path reaches), and ``speed`` is the robots' speed in cells
   per tick, so with the paper's one cell per step ``e`` is the paper's. ``e`` is
   not rounded to whole ticks, and the sensor range is not subtracted (the paper
   measures the distance to the cell, not to where it would be sensed from).
2. **Closest robot** means the closest robot alive at tick ``t`` (the paper has no
   failures). If no robot is alive, the estimate is taken from where the robots
   stopped, so a dead team still gets a finite, comparable number.
3. **Which cells.** Only *explorable* cells count (free cells reachable from the
   start cells, the cells coverage counts). The paper counts every cell, "no
   matter if it is found free or occupied", but the inside of thick walls and
   enclosed rooms is never sensed, so it would carry an estimate forever and
   make ``w_R`` depend on how thick the walls are drawn.
4. **Variance.** ``sigma^2`` is the plain population variance (divide by ``N``),
   not normalised: WTV is in ticks², EPV in percent² (the paper's "exploration
   percentage"; divide by 10⁴ for fractions).
5. **Empty regions.** A region without an explorable cell has no ``w_R`` and no
   ``EP_R``; it is left out and ``N`` counts the others (this also covers a
   map too small for the tiling). With fewer than two regions left the
   variance is 0.
6. **Final WTV.** Eq. (10) is eq. (9) at the end of a run in which every cell is
   known (then ``w_R = awt_R``). A run may stop earlier (coverage threshold,
   ``max_ticks``, stall); its unknown cells then get ``w'`` as in eq. (8), so
   :func:`final_wtv` is WTV at the last tick.
7. **Ticks.** ``positions[t]`` and ``alive[t]`` are the state at the end of tick
   ``t``, and a cell is known at ``t`` when ``0 <= first_known <= t``.
8. **Tiling.** The paper only says "equal-sized regions". Each doubling of the
   region count halves the rectangles along their longer side (rows on a tie):
   a square map gives 2 = 2x1, 4 = 2x2, 8 = 4x2, 16 = 4x4, 32 = 8x4, 64 = 8x8
   (rows x columns); see :func:`region_tiling`.

Example: a 4x4 map explored at tick 4 except two cells, one robot at (3, 0),
two regions (top and bottom halves).

>>> import numpy as np
>>> first_known = np.array(
...     [[0, 0, 0, 0], [0, 0, 0, 0], [2, 2, 4, 4], [2, 2, -1, -1]], dtype=np.int32
... )
>>> explorable = np.ones((4, 4), dtype=bool)
>>> regions = split_regions((4, 4), 2)
>>> robots = np.array([[3, 0]])
>>> # top: w_R = 0; bottom: (2+2+4+4 + 2+2 + (4+2) + (4+3)) / 8 = 29/8 = 3.625
>>> wtv(first_known, explorable, robots, 4, 1.0, regions)  # ((3.625 / 2) ** 2)
3.28515625
>>> epv(first_known, explorable, 4, regions)  # EP 100 and 75
156.25
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.errors import MrexploreInputError

REGION_COUNTS = (2, 4, 8, 16, 32, 64)
"""The region counts of the paper (§V.B: "2, 4, 8, 16, 32, 64 equal-sized regions")."""

# Up to this many robots, one vectorised pass per robot over the cells beats a
# KD-tree query (measured: 35k cells, 8 robots, 1 ms against 12 ms).
_BRUTE_FORCE_MAX_ROBOTS = 64


def region_tiling(shape: tuple[int, int], n_regions: int) -> tuple[int, int]:
    """Rows and columns of rectangles that :func:`split_regions` cuts the map into.

    ``n_regions`` must be a power of two. Starting from the whole map, each
    doubling halves the rectangles along their longer side (rows on a tie), so
    a square map gives 2 = 2x1, 4 = 2x2, 8 = 4x2, 16 = 4x4, 32 = 8x4, 64 = 8x8
    and a wide map splits its columns first. On a map with fewer rows (columns)
    than bands some rectangles are empty; the variances leave them out.

    >>> region_tiling((200, 200), 8)
    (4, 2)
    >>> region_tiling((100, 300), 8)
    (2, 4)
    """
    height, width = int(shape[0]), int(shape[1])
    if n_regions < 1 or n_regions & (n_regions - 1):
        raise MrexploreInputError(f"regions: {n_regions} is not a power of two (2, 4, 8, ...)")
    rows, cols = 1, 1
    while rows * cols < n_regions:
        if height / rows >= width / cols:
            rows *= 2
        else:
            cols *= 2
    return rows, cols


def split_regions(shape: tuple[int, int], n_regions: int) -> npt.NDArray[np.int64]:
    """Label each cell of an ``H x W`` map with its region, ``0 .. n_regions - 1``.

    The regions are the rectangles of :func:`region_tiling`, numbered row-major.
    Their heights (and widths) differ by at most one cell, and are equal when the
    map's side divides evenly. On a map smaller than the tiling some labels are
    not used.

    >>> split_regions((4, 4), 4)
    array([[0, 0, 1, 1],
           [0, 0, 1, 1],
           [2, 2, 3, 3],
           [2, 2, 3, 3]])
    """
    rows, cols = region_tiling(shape, n_regions)
    height, width = int(shape[0]), int(shape[1])
    row_band = (np.arange(height, dtype=np.int64) * rows) // height
    col_band = (np.arange(width, dtype=np.int64) * cols) // width
    return row_band[:, None] * cols + col_band[None, :]


def waiting_times(
    first_known: npt.NDArray[np.integer[Any]],
    explorable: npt.NDArray[np.bool_],
    positions_at_t: npt.NDArray[np.integer[Any]],
    t: int,
    speed: float = 1.0,
) -> npt.NDArray[np.float64]:
    """Waiting time of every explorable cell at tick ``t``; NaN elsewhere (§V.B).

    A cell known by ``t`` gets its stamp ``w = first_known``; an unknown one gets
    ``w' = t + g / speed``, with ``g`` the Euclidean distance in cells to the
    closest robot of ``positions_at_t`` (``N x 2`` row, col: pass the robots alive
    at ``t``).
    """
    _check_maps(first_known, explorable)
    _check_tick_and_speed(t, speed)
    waits = np.full(explorable.shape, np.nan, dtype=np.float64)
    known = explorable & (first_known >= 0) & (first_known <= t)
    waits[known] = first_known[known]
    unknown = explorable & ~known
    if unknown.any():
        robots = _check_robots(positions_at_t)
        rows, cols = np.nonzero(unknown)
        waits[unknown] = t + _closest_robot_distance(rows, cols, robots) / speed
    return waits


def wtv(
    first_known: npt.NDArray[np.integer[Any]],
    explorable: npt.NDArray[np.bool_],
    positions_at_t: npt.NDArray[np.integer[Any]],
    t: int,
    speed: float,
    regions: npt.NDArray[np.integer[Any]],
) -> float:
    """Waiting time variance WTV at tick ``t``, eqs. (8)-(9), in ticks².

    ``w_R`` (8) is the mean of the :func:`waiting_times` of region ``R``'s
    explorable cells, and WTV (9) the population variance of ``w_R`` over the
    regions of ``regions`` (``H x W`` labels, e.g. from :func:`split_regions`)
    that hold an explorable cell.
    """
    _check_regions(regions, explorable)
    waits = waiting_times(first_known, explorable, positions_at_t, t, speed)
    labels = regions[explorable].astype(np.int64)
    n_regions = int(regions.max()) + 1 if regions.size else 1
    sums = np.bincount(labels, weights=waits[explorable], minlength=n_regions)
    sizes = np.bincount(labels, minlength=n_regions)
    return _variance_of_shares(sums, sizes)


def epv(
    first_known: npt.NDArray[np.integer[Any]],
    explorable: npt.NDArray[np.bool_],
    t: int,
    regions: npt.NDArray[np.integer[Any]],
) -> float:
    """Exploration percentage variance EPV at tick ``t`` (§V.B), in percent².

    ``EP_R`` is the percentage of region ``R``'s explorable cells known by ``t``;
    EPV the population variance of ``EP_R`` over the regions that hold an
    explorable cell.
    """
    _check_maps(first_known, explorable)
    _check_regions(regions, explorable)
    _check_tick_and_speed(t, 1.0)
    labels = regions[explorable].astype(np.int64)
    stamps = first_known[explorable]
    known = (stamps >= 0) & (stamps <= t)
    n_regions = int(regions.max()) + 1 if regions.size else 1
    known_counts = np.bincount(labels[known], minlength=n_regions)
    sizes = np.bincount(labels, minlength=n_regions)
    return _variance_of_shares(100.0 * known_counts, sizes)


def region_curves(
    trace: Mapping[str, Any],
    region_counts: Iterable[int] = REGION_COUNTS,
    every: int = 1,
) -> dict[str, npt.NDArray[Any]]:
    """WTV and EPV of a run at ticks ``0, every, 2 every, ...`` and the last tick.

    ``trace`` holds the arrays of ``trace.npz`` (``first_known``, ``explorable``,
    ``positions``, optionally ``alive`` and ``speed``). Returns ``tick`` and, for
    each ``n`` of ``region_counts``, ``wtv_<n>`` (eqs. 8-9) and ``epv_<n>``, all of
    the same length. Equal to calling :func:`wtv` and :func:`epv` tick by tick.
    """
    if every < 1:
        raise MrexploreInputError(f"every={every}: must be a positive number of ticks")
    last = int(np.asarray(trace["positions"]).shape[0]) - 1
    ticks = np.arange(0, last + 1, every, dtype=np.int64)
    if ticks[-1] != last:
        ticks = np.append(ticks, last)
    return _curves_at(trace, ticks, tuple(region_counts))


def final_wtv(trace: Mapping[str, Any], n_regions: int = 8) -> float:
    """WTV_final, eq. (10): WTV over ``n_regions`` regions at the run's last tick.

    Cells still unknown then get the estimate ``w'`` (see the module docstring).
    """
    curves = _curves_at(trace, _last_tick(trace), (n_regions,))
    return float(curves[f"wtv_{n_regions}"][0])


def final_epv(trace: Mapping[str, Any], n_regions: int = 8) -> float:
    """EPV over ``n_regions`` regions at the run's last tick, in percent²."""
    curves = _curves_at(trace, _last_tick(trace), (n_regions,))
    return float(curves[f"epv_{n_regions}"][0])


def _last_tick(trace: Mapping[str, Any]) -> npt.NDArray[np.int64]:
    return np.array([np.asarray(trace["positions"]).shape[0] - 1], dtype=np.int64)


def _curves_at(
    trace: Mapping[str, Any], ticks: npt.NDArray[np.int64], region_counts: tuple[int, ...]
) -> dict[str, npt.NDArray[Any]]:
    """WTV and EPV at ``ticks`` (increasing) for each region count.

    The explorable cells are sorted by the tick they became known, so at any
    tick the known ones are a prefix of that order and the unknown ones the rest;
    only the rest needs the closest-robot distances. The cells are also grouped
    into *atoms*, the sets of cells that share their region under every region
    count, so each tick sums over the cells once (two ``bincount``) and then
    only over the few atoms for each region count.
    """
    first_known = np.asarray(trace["first_known"])
    explorable = np.asarray(trace["explorable"], dtype=bool)
    positions = np.asarray(trace["positions"])
    alive = np.asarray(trace["alive"], dtype=bool) if "alive" in trace else None
    speed = float(trace.get("speed", 1.0))
    _check_maps(first_known, explorable)
    _check_tick_and_speed(0, speed)
    if positions.ndim != 3 or positions.shape[1] < 1 or positions.shape[2] != 2:
        raise MrexploreInputError(
            f"trace: positions has shape {positions.shape}, expected (ticks, robots, 2)"
        )
    if alive is not None and alive.shape != positions.shape[:2]:
        raise MrexploreInputError(
            f"trace: alive has shape {alive.shape}, positions {positions.shape}"
        )
    shape = (int(explorable.shape[0]), int(explorable.shape[1]))

    cells = np.flatnonzero(explorable)
    stamps = first_known.ravel()[cells].astype(np.int64)
    never = np.iinfo(np.int64).max
    order_key = np.where(stamps >= 0, stamps, never)
    order = np.argsort(order_key, kind="stable")
    cells, order_key = cells[order], order_key[order]
    known_waits = order_key.astype(np.float64)  # only the known prefix is ever read
    cell_rows, cell_cols = np.divmod(cells, shape[1])

    # Atoms: a mixed-radix key of the cell's label under every region count.
    atom_key = np.zeros(cells.size, dtype=np.int64)
    labels = {}
    for n in region_counts:
        labels[n] = split_regions(shape, n).ravel()[cells]
        atom_key = atom_key * n + labels[n]
    _, first_cell, atom_of_cell = np.unique(atom_key, return_index=True, return_inverse=True)
    atom_of_cell = atom_of_cell.ravel()
    n_atoms = first_cell.size
    atom_sizes = np.bincount(atom_of_cell, minlength=n_atoms)
    region_of_atom = {n: labels[n][first_cell] for n in region_counts}
    sizes = {n: np.bincount(region_of_atom[n], atom_sizes, minlength=n) for n in region_counts}

    out: dict[str, npt.NDArray[Any]] = {"tick": ticks.copy()}
    for n in region_counts:
        out[f"wtv_{n}"] = np.empty(ticks.size, dtype=np.float64)
        out[f"epv_{n}"] = np.empty(ticks.size, dtype=np.float64)
    for i, tick in enumerate(ticks.tolist()):
        n_known = int(np.searchsorted(order_key, tick, side="right"))
        robots = positions[tick]
        if alive is not None and alive[tick].any():
            robots = robots[alive[tick]]
        estimates = tick + (
            _closest_robot_distance(cell_rows[n_known:], cell_cols[n_known:], robots) / speed
        )
        waits = np.concatenate((known_waits[:n_known], estimates))
        atom_waits = np.bincount(atom_of_cell, weights=waits, minlength=n_atoms)
        atom_known = np.bincount(atom_of_cell[:n_known], minlength=n_atoms)
        for n in region_counts:
            sums = np.bincount(region_of_atom[n], weights=atom_waits, minlength=n)
            known_counts = np.bincount(region_of_atom[n], weights=atom_known, minlength=n)
            out[f"wtv_{n}"][i] = _variance_of_shares(sums, sizes[n])
            out[f"epv_{n}"][i] = _variance_of_shares(100.0 * known_counts, sizes[n])
    return out


def _closest_robot_distance(
    rows: npt.NDArray[np.integer[Any]],
    cols: npt.NDArray[np.integer[Any]],
    robots: npt.NDArray[np.integer[Any]],
) -> npt.NDArray[np.float64]:
    """Euclidean distance (cells) from each cell ``(rows[k], cols[k])`` to the closest robot."""
    if rows.size == 0:
        return np.zeros(0, dtype=np.float64)
    robot_rc = robots.astype(np.float64)
    if len(robot_rc) > _BRUTE_FORCE_MAX_ROBOTS:
        from scipy.spatial import cKDTree  # here: teams this large are rare, the import slow

        cells = np.column_stack((rows, cols)).astype(np.float64)
        distance, _ = cKDTree(robot_rc).query(cells)
        return np.asarray(distance, dtype=np.float64)
    row_f, col_f = rows.astype(np.float64), cols.astype(np.float64)
    best = np.full(rows.size, np.inf)
    for robot_row, robot_col in robot_rc:  # a loop over robots, each pass vectorised
        np.minimum(best, (row_f - robot_row) ** 2 + (col_f - robot_col) ** 2, out=best)
    return np.sqrt(best)


def _variance_of_shares(
    totals: npt.NDArray[np.floating[Any]] | npt.NDArray[np.integer[Any]],
    sizes: npt.NDArray[np.integer[Any]],
) -> float:
    """Population variance of ``totals / sizes`` over the regions with ``sizes > 0``."""
    keep = sizes > 0
    if np.count_nonzero(keep) < 2:
        return 0.0
    shares = totals[keep] / sizes[keep]
    deviations = shares - shares.mean()  # np.var, without its overhead on tiny arrays
    return float(deviations @ deviations) / deviations.size


def _check_maps(first_known: npt.NDArray[Any], explorable: npt.NDArray[Any]) -> None:
    if first_known.ndim != 2 or first_known.shape != explorable.shape:
        raise MrexploreInputError(
            f"first_known has shape {first_known.shape} but explorable {explorable.shape}; "
            "both must be the same H x W map"
        )


def _check_regions(regions: npt.NDArray[Any], explorable: npt.NDArray[Any]) -> None:
    if regions.shape != explorable.shape:
        raise MrexploreInputError(
            f"regions has shape {regions.shape} but the map {explorable.shape}"
        )
    if regions.size and int(regions.min()) < 0:
        raise MrexploreInputError("regions: labels must be 0, 1, 2, ...")


def _check_tick_and_speed(t: int, speed: float) -> None:
    if t < 0:
        raise MrexploreInputError(f"tick {t}: must be 0 or more")
    if not np.isfinite(speed) or speed <= 0:
        raise MrexploreInputError(f"speed {speed}: must be a positive number of cells per tick")


def _check_robots(positions_at_t: npt.NDArray[Any]) -> npt.NDArray[Any]:
    robots = np.asarray(positions_at_t)
    if robots.ndim != 2 or robots.shape[1] != 2 or robots.shape[0] < 1:
        raise MrexploreInputError(
            f"positions_at_t has shape {robots.shape}; expected (robots, 2) with a robot "
            "to estimate the waiting time of unknown cells from"
        )
    return robots
