"""Compiled kernels of the polygon map-sharing mechanism (:mod:`mrexplore.comm.polygon`).

Everything here works on raw numpy arrays and trusts its inputs; the mechanism
validates at its edge. Coordinates: a contour point is a flat cell index
``row * width + col``; a polygon vertex is the centre of a cell, stored as
``(x, y) = (col, row)`` int32 pairs. Distances are in cells.

* :func:`trace_contours`: Suzuki & Abe (1985) border following, the algorithm
  of OpenCV's ``findContours`` (8-connected foreground, 4-connected holes, every
  border pixel listed in order, ``CHAIN_APPROX_NONE``), with a 64-bit hash of
  each contour so unchanged contours are recognised in O(1).
* :func:`match_vertices`: where the vertices of the previous approximation lie
  on the new contours (Meier et al. §3, cases 1 and 3).
* :func:`edge_deviations`: for every polygon edge, the contour point between its
  two end vertices farthest from the edge (the Douglas-Peucker split point).
* :func:`rasterise`: even-odd fill of a set of polygons plus their edges
  (Bresenham), clipped to a window.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

IntArray = npt.NDArray[np.int64]
FloatArray = npt.NDArray[np.float64]

# Neighbour offsets (d_row, d_col) in counter-clockwise order as seen on screen
# (row 0 at the top): E, NE, N, NW, W, SW, S, SE. Same order as OpenCV.
_D_ROW = np.array([0, -1, -1, -1, 0, 1, 1, 1], dtype=np.int64)
_D_COL = np.array([1, 1, 0, -1, -1, -1, 0, 1], dtype=np.int64)

_HASH_MULTIPLIER = np.uint64(0x9E3779B97F4A7C15)
_HASH_SEED = np.uint64(0xCBF29CE484222325)


@numba.njit(cache=True, nogil=True)
def trace_contours_kernel(
    mask: npt.NDArray[np.bool_],
    labels: npt.NDArray[np.int32],
    points: IntArray,
    offsets: IntArray,
    holes: npt.NDArray[np.bool_],
    hashes: npt.NDArray[np.uint64],
    row0: int,
    col0: int,
    grid_width: int,
) -> int:
    """All borders of the 8-connected components of ``mask`` (Suzuki & Abe, 1985).

    Args:
        mask: ``H x W`` boolean grid, ``True`` = foreground; the window of a larger
            grid ``grid_width`` cells wide whose cell ``[0, 0]`` is grid cell
            ``(row0, col0)``.
        labels: scratch of ``(H + 2) * (W + 2)`` int32, any content.
        points, offsets, holes, hashes: output buffers (see :func:`trace_contours`);
            ``offsets``, ``holes`` and ``hashes`` must hold one entry per
            foreground cell (plus one for ``offsets``), ``points`` any size.
            Points are flat indices of the larger grid.

    Returns:
        The number of contours, or ``-1`` when ``points`` was too small.
    """
    height, width = mask.shape
    padded_width = width + 2
    labels[: padded_width + 1] = 0
    for r in range(height):
        base = (r + 1) * padded_width + 1
        for c in range(width):
            labels[base + c] = 1 if mask[r, c] else 0
        labels[base + width] = 0
        labels[base + width + 1] = 0
    labels[(height + 1) * padded_width :] = 0
    deltas = _D_ROW * padded_width + _D_COL
    capacity = points.size
    n_points = 0
    n_contours = 0
    offsets[0] = 0
    nbd = 1
    for r in range(1, height + 1):
        for c in range(1, width + 1):
            start = r * padded_width + c
            value = labels[start]
            if value == 0:
                continue
            if value == 1 and labels[start - 1] == 0:
                hole = False
                from_dir = 4  # the west neighbour
            elif value >= 1 and labels[start + 1] == 0:
                hole = True
                from_dir = 0  # the east neighbour
            else:
                continue
            nbd += 1
            # 3.1: clockwise from the background neighbour, the first foreground pixel.
            first_dir = -1
            for k in range(8):
                d = (from_dir - k) & 7
                if labels[start + deltas[d]] != 0:
                    first_dir = d
                    break
            if first_dir < 0:  # an isolated pixel
                labels[start] = -nbd
                if n_points >= capacity:
                    return -1
                points[n_points] = start
                n_points += 1
            else:
                first = start + deltas[first_dir]
                current = start
                back_dir = first_dir  # direction from ``current`` to the previous pixel
                while True:
                    # 3.3: counter-clockwise from the previous pixel, the next one.
                    step = back_dir + 1
                    while labels[current + deltas[step & 7]] == 0:
                        step += 1
                    found = step & 7
                    # 3.4: the east neighbour was examined and is background.
                    if step > 8:
                        labels[current] = -nbd
                    elif labels[current] == 1:
                        labels[current] = nbd
                    if n_points >= capacity:
                        return -1
                    points[n_points] = current  # padded index, converted below
                    n_points += 1
                    following = current + deltas[found]
                    if following == start and current == first:
                        break
                    current = following
                    back_dir = (found + 4) & 7
            holes[n_contours] = hole
            n_contours += 1
            offsets[n_contours] = n_points
    for g in range(n_points):
        padded = points[g]
        row = padded // padded_width - 1 + row0
        points[g] = row * grid_width + padded % padded_width - 1 + col0
    for k in range(n_contours):
        h = _HASH_SEED ^ np.uint64(1 if holes[k] else 0)
        for g in range(offsets[k], offsets[k + 1]):
            h = (h ^ np.uint64(points[g])) * _HASH_MULTIPLIER
            h ^= h >> np.uint64(29)
        hashes[k] = h
    return n_contours


def trace_contours(
    mask: npt.NDArray[np.bool_],
    scratch: npt.NDArray[np.int32] | None = None,
    origin: tuple[int, int] = (0, 0),
    grid_width: int | None = None,
) -> tuple[IntArray, IntArray, npt.NDArray[np.bool_], npt.NDArray[np.uint64]]:
    """All borders of the 8-connected components of ``mask`` (Suzuki & Abe, 1985).

    Args:
        mask: ``H x W`` boolean grid, ``True`` = foreground.
        scratch: optional int32 buffer of at least ``(H + 2) * (W + 2)`` entries,
            reused between calls to spare an allocation.
        origin, grid_width: ``mask`` is the window of a grid ``grid_width`` cells
            wide (default: ``W``) whose cell ``[0, 0]`` is grid cell ``origin``
            (row, col); points are flat indices of that grid. A window that holds
            every foreground cell of the grid gives the grid's contours, in the
            same order (the scan meets the foreground cells in the same order).

    Returns:
        ``(points, offsets, is_hole, hashes)``: contour ``k`` is
        ``points[offsets[k]:offsets[k + 1]]`` (flat indices ``row * W + col``, in
        border-following order, a pixel repeated where the border passes it
        twice); ``is_hole[k]`` says whether it borders a hole (else an outer
        border); ``hashes[k]`` is a 64-bit hash of ``(is_hole, points)``.

    >>> import numpy as np
    >>> mask = np.zeros((4, 5), dtype=bool)
    >>> mask[1:3, 1:4] = True
    >>> points, offsets, is_hole, _ = trace_contours(mask)
    >>> [divmod(int(p), 5) for p in points], offsets.tolist(), is_hole.tolist()
    ([(1, 1), (2, 1), (2, 2), (2, 3), (1, 3), (1, 2)], [0, 6], [False])
    """
    mask = np.ascontiguousarray(mask, dtype=np.bool_)
    n_padded = (mask.shape[0] + 2) * (mask.shape[1] + 2)
    if scratch is None or scratch.size < n_padded:
        scratch = np.empty(n_padded, dtype=np.int32)
    n_foreground = int(np.count_nonzero(mask))
    offsets = np.empty(n_foreground + 1, dtype=np.int64)
    holes = np.empty(n_foreground, dtype=np.bool_)
    hashes = np.empty(n_foreground, dtype=np.uint64)
    capacity = 2 * n_foreground + 64
    while True:
        points = np.empty(capacity, dtype=np.int64)
        n_contours = int(
            trace_contours_kernel(
                mask,
                scratch[:n_padded],
                points,
                offsets,
                holes,
                hashes,
                origin[0],
                origin[1],
                mask.shape[1] if grid_width is None else grid_width,
            )
        )
        if n_contours >= 0:
            break
        capacity *= 2
    n_points = int(offsets[n_contours])
    return (
        points[:n_points].copy(),
        offsets[: n_contours + 1].copy(),
        holes[:n_contours].copy(),
        hashes[:n_contours].copy(),
    )


@numba.njit(cache=True, nogil=True)
def match_vertices(
    contour_points: IntArray,
    contour_offsets: IntArray,
    eligible: npt.NDArray[np.bool_],
    head: IntArray,
    vertex_cells: IntArray,
    polygon_offsets: IntArray,
    out_contour: IntArray,
    out_index: IntArray,
) -> None:
    """Place the vertices of old polygons on new contours.

    Every vertex whose cell lies on one of the contours is given a contour and a
    position on it; the others get contour ``-1`` (they vanished, case 1 of the
    paper). A cell may lie on several contours (a one-cell-thick ring is on its
    outer and its hole border) or several times on one (a thin spur is walked
    out and back): a vertex goes to the candidate contour that holds the most
    vertices of its old polygon (ties: the lower contour number), and to the
    occurrence that comes first after the previous vertex of its polygon on that
    contour, so the old order is kept where it can be.

    Args:
        contour_points, contour_offsets: the new contours (see
            :func:`trace_contours`).
        eligible: per contour, whether vertices may be placed on it (contours
            that did not change keep their own polygon and take no others).
        head: scratch, ``H * W`` int64 filled with ``-1``; restored on return.
        vertex_cells: flat cell of every old vertex, polygon after polygon, each
            polygon's vertices in order.
        polygon_offsets: polygon ``q`` owns ``vertex_cells[polygon_offsets[q]:
            polygon_offsets[q + 1]]``.
        out_contour, out_index: results, one per vertex (filled in place).
    """
    n_contours = contour_offsets.size - 1
    n_points = contour_points.size
    contour_of = np.empty(n_points, dtype=np.int64)
    for k in range(n_contours):
        for g in range(contour_offsets[k], contour_offsets[k + 1]):
            contour_of[g] = k
    following = np.empty(n_points, dtype=np.int64)
    for g in range(n_points - 1, -1, -1):
        if not eligible[contour_of[g]]:
            continue
        cell = contour_points[g]
        following[g] = head[cell]
        head[cell] = g
    votes = np.zeros(n_contours, dtype=np.int64)
    last_voter = np.full(n_contours, -1, dtype=np.int64)
    previous = np.full(n_contours, -1, dtype=np.int64)
    n_polygons = polygon_offsets.size - 1
    for q in range(n_polygons):
        lo = polygon_offsets[q]
        hi = polygon_offsets[q + 1]
        for v in range(lo, hi):
            g = head[vertex_cells[v]]
            while g >= 0:
                k = contour_of[g]
                if last_voter[k] != v:
                    last_voter[k] = v
                    votes[k] += 1
                g = following[g]
        for v in range(lo, hi):
            best = -1
            g = head[vertex_cells[v]]
            while g >= 0:
                k = contour_of[g]
                if best < 0 or votes[k] > votes[best] or (votes[k] == votes[best] and k < best):
                    best = k
                g = following[g]
            out_contour[v] = best
            if best < 0:
                out_index[v] = -1
                continue
            base = contour_offsets[best]
            length = contour_offsets[best + 1] - base
            chosen = -1
            chosen_gap = length + 1
            g = head[vertex_cells[v]]
            while g >= 0:
                if contour_of[g] == best:
                    index = g - base
                    if previous[best] < 0:
                        gap = index
                    else:
                        gap = (index - previous[best] - 1) % length
                    if gap < chosen_gap:
                        chosen_gap = gap
                        chosen = index
                g = following[g]
            out_index[v] = chosen
            previous[best] = chosen
        # Reset the per-polygon scratch for the contours this polygon touched.
        for v in range(lo, hi):
            g = head[vertex_cells[v]]
            while g >= 0:
                k = contour_of[g]
                votes[k] = 0
                last_voter[k] = -1
                previous[k] = -1
                g = following[g]
    for g in range(n_points):
        head[contour_points[g]] = -1


@numba.njit(cache=True, nogil=True, inline="always")
def _segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    dx = bx - ax
    dy = by - ay
    length2 = dx * dx + dy * dy
    if length2 == 0.0:
        return float(np.hypot(px - ax, py - ay))
    t = ((px - ax) * dx + (py - ay) * dy) / length2
    if t < 0.0:
        t = 0.0
    elif t > 1.0:
        t = 1.0
    return float(np.hypot(px - (ax + t * dx), py - (ay + t * dy)))


@numba.njit(cache=True, nogil=True)
def edge_deviation(contour: IntArray, width: int, start: int, end: int) -> tuple[float, int]:
    """Farthest contour point of the edge from ``contour[start]`` to ``contour[end]``.

    The edge's contour points are ``start, start + 1, ..., end`` walking forward
    (cyclically); ``start == end`` means the whole contour (a one-vertex polygon).

    Returns:
        ``(distance, index)``: the largest distance (cells) of those points from
        the segment and the contour index of the first point attaining it.
    """
    n = contour.size
    ay = float(contour[start] // width)
    ax = float(contour[start] % width)
    by = float(contour[end] // width)
    bx = float(contour[end] % width)
    span = (end - start) % n
    if span == 0:
        span = n
    best = 0.0
    best_index = start
    for step in range(1, span):
        index = (start + step) % n
        cell = contour[index]
        d = _segment_distance(float(cell % width), float(cell // width), ax, ay, bx, by)
        if d > best:
            best = d
            best_index = index
    return best, best_index


@numba.njit(cache=True, nogil=True)
def edge_deviations(
    contour: IntArray, width: int, anchors: IntArray
) -> tuple[FloatArray, IntArray]:
    """:func:`edge_deviation` of every edge ``anchors[i] -> anchors[i + 1]`` (cyclic)."""
    m = anchors.size
    deviation = np.zeros(m, dtype=np.float64)
    farthest = np.zeros(m, dtype=np.int64)
    for i in range(m):
        d, index = edge_deviation(contour, width, anchors[i], anchors[(i + 1) % m])
        deviation[i] = d
        farthest[i] = index
    return deviation, farthest


@numba.njit(cache=True, nogil=True)
def farthest_point(contour: IntArray, width: int, index: int) -> int:
    """Contour index of the point farthest (Euclidean) from ``contour[index]``."""
    ry = contour[index] // width
    rx = contour[index] % width
    best = -1
    best_index = index
    for g in range(contour.size):
        dy = contour[g] // width - ry
        dx = contour[g] % width - rx
        d = dx * dx + dy * dy
        if d > best:
            best = d
            best_index = g
    return best_index


@numba.njit(cache=True, nogil=True)
def _draw_line(
    out: npt.NDArray[np.bool_], x0: int, y0: int, x1: int, y1: int, row0: int, col0: int
) -> None:
    """Bresenham line between two cell centres, clipped to the window ``out``."""
    height, width = out.shape
    dx = abs(x1 - x0)
    dy = -abs(y1 - y0)
    sx = 1 if x0 < x1 else -1
    sy = 1 if y0 < y1 else -1
    err = dx + dy
    x = x0
    y = y0
    while True:
        r = y - row0
        c = x - col0
        if 0 <= r < height and 0 <= c < width:
            out[r, c] = True
        if x == x1 and y == y1:
            break
        e2 = 2 * err
        if e2 >= dy:
            err += dy
            x += sx
        if e2 <= dx:
            err += dx
            y += sy


@numba.njit(cache=True, nogil=True)
def _crossed_rows(ya: int, yb: int, row0: int, row1: int) -> tuple[int, int]:
    """The rows ``first .. last - 1`` of the window ``row0 .. row1 - 1`` whose centre
    line the edge from row ``ya`` to row ``yb`` crosses (half-open: ``min .. max - 1``)."""
    return max(min(ya, yb), row0), min(max(ya, yb), row1)


@numba.njit(cache=True, nogil=True)
def rasterise(
    xy: npt.NDArray[np.int32],
    offsets: IntArray,
    row0: int,
    col0: int,
    out: npt.NDArray[np.bool_],
) -> None:
    """OR the polygons ``xy[offsets[q]:offsets[q + 1]]`` into the window ``out``.

    A cell is set when its centre is inside the polygons under the even-odd rule
    (a cell inside an odd number of them: holes cancel their outer border) or
    when an edge passes through it (Bresenham line between the cell centres of
    two consecutive vertices). A one-vertex polygon marks its cell; a
    two-vertex polygon marks the line between them.

    Args:
        xy: ``n x 2`` int32 vertices, ``(x, y) = (col, row)`` of cell centres.
        offsets: polygon boundaries in ``xy`` (length ``n_polygons + 1``).
        row0, col0: grid cell of ``out[0, 0]``.
        out: the window, modified in place.
    """
    height, width = out.shape
    row1 = row0 + height
    n_polygons = offsets.size - 1
    if n_polygons < 1:
        return
    first_vertex = offsets[0]
    end_vertex = offsets[n_polygons]
    # following[i]: the vertex after i on its polygon's boundary, which closes (the
    # last vertex of xy[offsets[q]:offsets[q + 1]] is followed by the first).
    following = np.empty(end_vertex, dtype=np.int64)
    for q in range(n_polygons):
        for i in range(offsets[q], offsets[q + 1]):
            following[i] = i + 1 if i + 1 < offsets[q + 1] else offsets[q]
    # Scanline crossings, bucketed per window row: count, then fill.
    counts = np.zeros(height + 1, dtype=np.int64)
    for i in range(first_vertex, end_vertex):
        j = following[i]
        first, last = _crossed_rows(int(xy[i, 1]), int(xy[j, 1]), row0, row1)
        for y in range(first, last):
            counts[y - row0 + 1] += 1
    for r in range(height):
        counts[r + 1] += counts[r]
    crossings = np.empty(counts[height], dtype=np.float64)
    fill = counts[:height].copy()
    for i in range(first_vertex, end_vertex):
        j = following[i]
        xa = int(xy[i, 0])
        ya = int(xy[i, 1])
        xb = int(xy[j, 0])
        yb = int(xy[j, 1])
        if ya != yb:  # a horizontal edge crosses no row's centre line
            first, last = _crossed_rows(ya, yb, row0, row1)
            slope = (xb - xa) / (yb - ya)
            for y in range(first, last):
                crossings[fill[y - row0]] = xa + (y - ya) * slope
                fill[y - row0] += 1
        # The edge's own cells (single vertices too), so thin and degenerate
        # polygons keep their cells; cells are only ever set, so in any order.
        if not (
            max(xa, xb) < col0
            or min(xa, xb) >= col0 + width
            or max(ya, yb) < row0
            or min(ya, yb) >= row1
        ):
            _draw_line(out, xa, ya, xb, yb, row0, col0)
    for r in range(height):
        lo = counts[r]
        hi = counts[r + 1]
        if hi - lo < 2:
            continue
        row_crossings = np.sort(crossings[lo:hi])
        for p in range(0, hi - lo - 1, 2):
            c_first = int(np.ceil(row_crossings[p])) - col0
            c_last = int(np.floor(row_crossings[p + 1])) - col0
            if c_first < 0:
                c_first = 0
            if c_last > width - 1:
                c_last = width - 1
            for c in range(c_first, c_last + 1):
                out[r, c] = True


@numba.njit(cache=True, nogil=True)
def paint_box(
    rasters: npt.NDArray[np.bool_],
    slots: IntArray,
    own: npt.NDArray[np.int8],
    belief: npt.NDArray[np.int8],
    box: tuple[int, int, int, int],
    free_value: int,
    occupied_value: int,
    unknown_value: int,
) -> int:
    """Write the union of several senders' rasters into ``belief`` inside ``box``.

    Args:
        rasters: ``n x 2 x H x W``; ``rasters[s, 0]`` a sender's observed layer,
            ``rasters[s, 1]`` its obstacle layer.
        slots: the senders, as indices into ``rasters``.
        own: ``H x W``, the cells the robot observed itself (``unknown_value``
            elsewhere); those cells are left alone.
        belief: ``H x W``, written in place.
        box: ``(row_min, row_max, col_min, col_max)``, inclusive, inside the grid.

    A cell becomes ``occupied_value`` where any obstacle layer holds it, else
    ``free_value`` where any observed layer does, else ``unknown_value``.

    Returns:
        The number of cells of ``belief`` whose value changed.
    """
    row0, row1, col0, col1 = box
    n_cols = col1 - col0 + 1
    free = np.empty(n_cols, dtype=np.bool_)
    occupied = np.empty(n_cols, dtype=np.bool_)
    n_changed = 0
    for r in range(row0, row1 + 1):
        # Row by row, each sender's row read in one sweep.
        free[:] = False
        occupied[:] = False
        for s in slots:
            free_row = rasters[s, 0, r]
            occupied_row = rasters[s, 1, r]
            for i in range(n_cols):
                free[i] |= free_row[col0 + i]
                occupied[i] |= occupied_row[col0 + i]
        for i in range(n_cols):
            c = col0 + i
            if own[r, c] != unknown_value:
                continue
            if occupied[i]:
                value = occupied_value
            elif free[i]:
                value = free_value
            else:
                value = unknown_value
            if belief[r, c] != value:
                belief[r, c] = value
                n_changed += 1
    return n_changed
